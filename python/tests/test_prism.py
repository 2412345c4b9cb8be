"""The Python module against the command line it must agree with: same pixels, same errors.

Run by CTest (python.module) with PYTHONPATH at the build tree's python/ folder and PRISM_EXE
the prism executable of the same build.
"""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import prism

SOURCE = pathlib.Path(__file__).resolve().parents[2]
SPHERES = str(SOURCE / "scenes" / "spheres.gltf")
WHITTED = str(SOURCE / "scenes" / "whitted.gltf")
PRISM = os.environ.get("PRISM_EXE", str(SOURCE / "build" / "apps" / "prism"))


def run_prism(*args):
    return subprocess.run([PRISM, *args], capture_output=True, text=True)


@pytest.fixture(scope="module")
def session():
    return prism.Session(SPHERES, threads=2)


def test_integrators_list_the_registry_with_parameter_tables():
    table = {i["name"]: i for i in prism.integrators()}
    assert {"phong", "shadow", "whitted"} <= set(table)
    depth = [p for p in table["whitted"]["parameters"] if p["name"] == "max-depth"]
    assert len(depth) == 1 and depth[0]["type"] == "integer"
    assert depth[0]["min"] <= depth[0]["default"] <= depth[0]["max"]
    # The command line offers exactly these integrators.
    help_text = run_prism("render", "--help").stdout
    for name in table:
        assert name + ":" in help_text


def test_render_is_the_command_lines_image_bit_for_bit(session, tmp_path):
    render = session.render(integrator="whitted", spp=4, resolution=(64, 48), max_depth=3)
    assert render.image.shape == (48, 64, 4)
    assert render.image.dtype == np.float32
    assert (render.width, render.height, render.spp) == (64, 48, 4)
    assert render.parameters["max-depth"] == 3
    out = tmp_path / "cli.exr"
    cli = run_prism("render", SPHERES, "-o", str(out), "--integrator", "whitted", "--spp", "4",
                    "--res", "64x48", "--max-depth", "3", "-q")
    assert cli.returncode == 0, cli.stderr
    assert np.array_equal(prism.read_exr(str(out)), render.image)
    # Something was rendered: lit pixels, and every camera ray counted.
    assert render.image[..., :3].max() > 0.0
    assert render.rays["camera"] == 64 * 48 * 4
    assert render.rays_per_second > 0.0


def test_a_session_loads_once_and_reuses_its_bvh(session):
    first = session.render(integrator="phong", resolution=(32, 24))
    second = session.render(integrator="shadow", resolution=(32, 24))
    assert second.build_seconds == 0.0
    assert first.integrator == "phong" and second.integrator == "shadow"
    # phong casts no shadow rays, shadow does: the two really are different integrators.
    assert first.rays["shadow"] == 0 and second.rays["shadow"] > 0


def test_integrator_parameters_change_the_image(tmp_path):
    session = prism.Session(WHITTED, threads=2)
    shallow = session.render(integrator="whitted", resolution=(48, 36), max_depth=1)
    deep = session.render(integrator="whitted", resolution=(48, 36), max_depth=5)
    assert shallow.rays["reflection"] + shallow.rays["refraction"] < (
        deep.rays["reflection"] + deep.rays["refraction"])
    assert not np.array_equal(shallow.image, deep.image)


def test_thread_count_does_not_change_pixels():
    one = prism.Session(SPHERES, threads=1).render(integrator="shadow", spp=4, resolution=(40, 30))
    two = prism.Session(SPHERES, threads=2).render(integrator="shadow", spp=4, resolution=(40, 30))
    assert np.array_equal(one.image, two.image)


def test_request_errors_carry_the_command_lines_message(session, tmp_path):
    with pytest.raises(prism.RequestError) as caught:
        session.render(camera="nope", resolution=(8, 8))
    assert caught.value.field == "camera"
    cli = run_prism("render", SPHERES, "-o", str(tmp_path / "x.exr"), "--camera", "nope")
    assert cli.returncode == 2
    assert cli.stderr.strip() == f"prism: error: --{caught.value.field} {caught.value}"
    assert isinstance(caught.value, ValueError)


@pytest.mark.parametrize("kwargs, field", [
    ({"spp": 0}, "spp"),
    ({"min_spp": -3}, "min-spp"),
    ({"seed": -1}, "seed"),
    ({"seed": 2 ** 31}, "seed"),
    ({"target_error": float("nan")}, "target-error"),
    ({"time_limit": -1.0}, "time-limit"),
    ({"resolution": (0, 10)}, "res"),
    ({"integrator": "bogus"}, "integrator"),
    ({"working_space": "srgb"}, "working-space"),
    ({"spheres": "cubes"}, "spheres"),
    ({"build_quality": "best"}, "build-quality"),
    ({"max_depth": 2.5}, "max-depth"),
    ({"no_such_parameter": 1}, "no-such-parameter"),
    ({"background": -1.0}, "background"),
    ({"background": (1.0, 2.0)}, "background"),
    ({"environment_intensity": float("nan")}, "environment-intensity"),
    ({"environment_rotation": float("inf")}, "environment-rotation"),
    ({"look_from": (1.0, 2.0)}, "look-from"),
    ({"look_at": (0.0, float("nan"), 0.0)}, "look-at"),
    ({"fov": 180.0}, "fov"),
    ({"region": (10, 0, 5, 4)}, "region"),
    ({"region": (0, 0, 100000, 4)}, "region"),
])
def test_bad_options_name_their_field(session, kwargs, field):
    with pytest.raises(prism.RequestError) as caught:
        session.render(**kwargs)
    assert caught.value.field == field
    assert "\n" not in str(caught.value) and str(caught.value)


def test_a_broken_scene_is_a_load_error_naming_the_file(tmp_path):
    broken = tmp_path / "broken.gltf"
    broken.write_text('{"asset": {"version": "2.0"}, '
                      '"buffers": [{"byteLength": 100, "uri": "missing.bin"}]}')
    with pytest.raises(prism.LoadError) as caught:
        prism.Session(str(broken))
    assert str(broken) in str(caught.value)
    cli = run_prism("info", str(broken))
    assert cli.returncode != 0
    assert str(caught.value) in cli.stderr


def test_write_is_prism_renders_files(session, tmp_path):
    render = session.render(integrator="whitted", spp=2, resolution=(32, 24))
    exr, png = tmp_path / "out.exr", tmp_path / "out.png"
    render.write(str(exr), preview=str(png))
    assert np.array_equal(prism.read_exr(str(exr)), render.image)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # An output in a folder that does not exist is refused before anything is written.
    with pytest.raises(prism.RequestError) as caught:
        render.write(str(tmp_path / "missing" / "out.exr"))
    assert caught.value.field == "output"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.exr", "out.png"]


def test_compare_images_agrees_with_prism_diff(session, tmp_path):
    a = session.render(integrator="phong", resolution=(32, 24))
    b = session.render(integrator="whitted", resolution=(32, 24))
    assert prism.compare_images(a.image, a.image)["rmse"] == 0.0
    error = prism.compare_images(a.image, b.image)
    assert error["rmse"] > 0.0 and error["compared_pixels"] == 32 * 24
    a.write(str(tmp_path / "a.exr"))
    b.write(str(tmp_path / "b.exr"))
    diff = run_prism("diff", str(tmp_path / "a.exr"), str(tmp_path / "b.exr"), "--metric", "rmse")
    printed = float(diff.stdout.split()[-1])
    assert printed == pytest.approx(error["rmse"], rel=1e-5)
    with pytest.raises(ValueError):
        prism.compare_images(a.image, b.image[:10])


def test_a_reference_gives_the_error_after_every_pass(session, tmp_path):
    reference = session.render(integrator="shadow", spp=16, resolution=(24, 16))
    reference.write(str(tmp_path / "ref.exr"))
    render = session.render(integrator="shadow", spp=4, resolution=(24, 16),
                            reference=str(tmp_path / "ref.exr"))
    errors = render.pass_errors
    assert [e["samples"] for e in errors] == [1, 2, 3, 4]
    last = prism.compare_images(render.image, reference.image)
    assert errors[-1]["rmse"] == pytest.approx(last["rmse"], rel=1e-6)


def test_lighting_and_camera_options_are_the_command_lines(session, tmp_path):
    kwargs = dict(integrator="path", spp=2, resolution=(32, 24), background=(0.5, 0.25, 0.125),
                  camera="auto", look_from=(0.0, 2.0, 9.0), fov=40.0)
    render = session.render(**kwargs)
    out = tmp_path / "cli.exr"
    cli = run_prism("render", SPHERES, "-o", str(out), "--integrator", "path", "--spp", "2",
                    "--res", "32x24", "--background", "0.5,0.25,0.125", "--camera", "auto",
                    "--look-from", "0,2,9", "--fov", "40", "-q")
    assert cli.returncode == 0, cli.stderr
    assert np.array_equal(prism.read_exr(str(out)), render.image)
    # The camera really moved: the file's own camera sees another image.
    assert not np.array_equal(session.render(integrator="path", spp=2, resolution=(32, 24),
                                             background=(0.5, 0.25, 0.125)).image, render.image)
    # The background is seen by rays that miss unless hidden; hidden, those pixels are 0.
    hidden = session.render(**kwargs, hide_environment=True)
    misses = hidden.image[..., 3] == 0.0
    assert misses.any()
    assert np.all(hidden.image[misses][:, :3] == 0.0)
    assert np.all(render.image[misses][:, :3] > 0.0)


def test_a_region_is_the_command_lines_region(session, tmp_path):
    render = session.render(integrator="whitted", spp=4, resolution=(64, 48), region=(9, 5, 41, 30))
    whole = session.render(integrator="whitted", spp=4, resolution=(64, 48))
    inside = render.image[5:30, 9:41]
    assert np.array_equal(inside, whole.image[5:30, 9:41])
    assert inside[..., 3].max() > 0.0
    outside = render.image.copy()
    outside[5:30, 9:41] = 0.0
    assert not outside.any()
    exr = tmp_path / "region.exr"
    render.write(str(exr))
    cli = tmp_path / "cli.exr"
    run = run_prism("render", SPHERES, "-o", str(cli), "--integrator", "whitted", "--spp", "4",
                    "--res", "64x48", "--region", "9,5,41,30", "-q")
    assert run.returncode == 0, run.stderr
    # Both store the region alone, as their data window: the same pixels.
    assert np.array_equal(prism.read_exr(str(exr)), prism.read_exr(str(cli)))
    assert prism.read_exr(str(exr)).shape == (25, 32, 4)


def test_a_seed_is_the_command_lines_seed(session, tmp_path):
    kwargs = dict(integrator="path", spp=4, resolution=(48, 32))
    default = session.render(**kwargs)
    assert np.array_equal(session.render(**kwargs, seed=0).image, default.image)
    seeded = session.render(**kwargs, seed=7)
    # Another stream: most lit pixels differ (path tracing is noisy at 4 spp).
    lit = default.image[..., 3] > 0.0
    differ = np.any(seeded.image[..., :3] != default.image[..., :3], axis=-1)
    assert differ[lit].mean() > 0.5
    out = tmp_path / "cli.exr"
    cli = run_prism("render", SPHERES, "-o", str(out), "--integrator", "path", "--spp", "4",
                    "--res", "48x32", "--seed", "7", "-q")
    assert cli.returncode == 0, cli.stderr
    assert np.array_equal(prism.read_exr(str(out)), seeded.image)
