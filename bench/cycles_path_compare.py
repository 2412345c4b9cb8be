#!/usr/bin/python3
"""Prism's `path` integrator against Blender Cycles' path tracing on three scenes
(docs/cycles-path.md). One command, rerunnable:

    /usr/bin/python3 bench/cycles_path_compare.py [--out /tmp/cycles-path] [--max-depth 8]
        [--cycles-spp 512] [--prism-spp 512] [--scenes cornell,sweep,asset]
        [--images docs/images] [--skip-blender] [--noise]
    /usr/bin/python3 bench/cycles_path_compare.py --equal-error [--scenes cornell]
        [--equal-error-res WxH] [--reference-spp 4096] [--test-spp 128] [--repeats 5]

Scenes, each one .glb (or .gltf) read by both renderers:
- cornell: scenes/cornell.gltf, lit by its emissive ceiling panel only, black world. Its
  materials are exactly Lambertian in glTF (metallic 0, roughness 1, specularFactor 0), which
  Blender's importer turns into a Principled BSDF whose diffuse lobe is Disney's, not
  Lambert's; Cycles renders it both as imported and with Diffuse BSDFs (--lambert).
- sweep: written here, ten UV spheres (roughness 0.1, 0.3, 0.5, 0.7, 0.9; metallic 0 in the
  top row, 1 in the bottom row), under OUT/sky.exr, an equirectangular sky + ground + sun
  blob written here with NumPy and OpenImageIO.
- asset: assimp-testmodels' BoxTextured.glb (base-colour PNG texture) with a camera added and
  the sampler's minFilter set to LINEAR (Cycles does not mip-map), under the same sky.
- asset_lambert (a control): the same file with specularFactor 0 (glTF's BRDF is then
  exactly rho/pi), against Cycles with Diffuse BSDFs.
- furnace (a smaller experiment, with --scenes furnace): the sweep with base colour 1
  under a uniform map of radiance 1 (OUT/uniform.exr).
The env-lit files hold one directional light of intensity 0, so that neither renderer
adds its default key light to a scene without lights.

Cycles (bench/peers/cycles_render.py --max-bounces B): B = max-depth - 1 bounces (Cycles'
0 is direct light only, Prism's max-depth 1), no glossy filter, no clamping, caustics on,
single-scattering GGX, 1-pixel box filter, fixed samples, no denoising, 2 threads.
Prism: `prism render FILE --integrator path --spp N --max-depth D [--environment
OUT/sky.exr] --res WxH --threads 2`.

Metric, on Rec.709 luminance Y of the linear images: mean over pixels of
|Y_P - Y_C| / (Y_C + 0.01) ("mean rel"), over all pixels and over the pixels Prism's alpha
says are covered by geometry; the same on 4x4 block means (the per-pixel noise of both
renderers mostly averages out); and (mean Y_P - mean Y_C) / mean Y_C ("image mean").
Writes OUT/results.json and docs/images/cycles-path-SCENE.png (Cycles | Prism | difference:
red Prism brighter, blue darker, full colour at 10 %).
"""
import argparse
import json
import math
import os
import statistics
import struct
import sys
import time

import numpy
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from benchlib import run_logged  # noqa: E402
from blender_compare import find_prism, write_png  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CYCLES_SCRIPT = os.path.join(ROOT, "bench/peers/cycles_render.py")
BOX_TEXTURED = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"
LUMA = numpy.array([0.2126, 0.7152, 0.0722])
EPSILON = 0.01
BLOCK = 4
SWEEP_ROUGHNESS = (0.1, 0.3, 0.5, 0.7, 0.9)


def run(cmd, log):
    text, seconds = run_logged(cmd, log)
    print("  %.1f s: %s" % (seconds, " ".join(cmd)))
    return text, seconds


def read_rgba(path):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    pixels = buf.get_pixels(oiio.FLOAT)
    names = list(spec.channelnames)
    pick = []
    for c in "RGBA":
        pick.append(next(i for i, n in enumerate(names) if n == c or n.endswith("." + c)))
    return pixels[..., pick]


def write_sky(path, width=512):
    """Sky: blue-white gradient above the horizon, brownish ground below, a sun blob of
    radius 4 degrees and radiance 40 at elevation 35 degrees, azimuth 60 degrees from +X
    towards +Z (Prism's map convention, docs/lights.md: row 0 = +Y, middle column = +X)."""
    height = width // 2
    v = (numpy.arange(height) + 0.5) / height
    u = (numpy.arange(width) + 0.5) / width
    theta = v * math.pi  # from +Y
    phi = (u - 0.5) * 2 * math.pi  # 0 at the middle column (+X), +pi/2 a quarter right (+Z)
    phi, theta = numpy.meshgrid(phi, theta)
    d = numpy.stack([numpy.sin(theta) * numpy.cos(phi), numpy.cos(theta),
                     numpy.sin(theta) * numpy.sin(phi)], axis=-1)
    up = d[..., 1:2]
    sky = numpy.where(up > 0, (1 - up) * numpy.array([0.9, 0.95, 1.0]) * 1.2
                      + up * numpy.array([0.25, 0.45, 0.9]),
                      numpy.array([0.30, 0.22, 0.15]) * (1 + 0.5 * up))
    e, a = math.radians(35), math.radians(60)
    sun = numpy.array([math.cos(e) * math.cos(a), math.sin(e), math.cos(e) * math.sin(a)])
    near = (d @ sun) > math.cos(math.radians(4))
    sky[near] = numpy.array([40.0, 38.0, 34.0])
    buf = oiio.ImageBuf(oiio.ImageSpec(width, height, 3, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(), numpy.ascontiguousarray(sky, dtype=numpy.float32))
    if not buf.write(path):
        sys.exit("cannot write %s: %s" % (path, buf.geterror()))


def look_at_quaternion(eye, target):
    """glTF camera rotation (x, y, z, w) looking from eye at target, +Y up."""
    f = numpy.subtract(target, eye, dtype=float)
    f /= numpy.linalg.norm(f)
    r = numpy.cross(f, [0.0, 1.0, 0.0])
    r /= numpy.linalg.norm(r)
    u = numpy.cross(r, f)
    m = numpy.stack([r, u, -f], axis=1)  # columns: camera x, y, z in the world
    w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    return [(m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w),
            (m[1, 0] - m[0, 1]) / (4 * w), w]


def zero_light(root):
    """One directional light of intensity 0: a scene 'with lights', so neither renderer adds
    its default key light; it lights nothing."""
    root.setdefault("extensionsUsed", []).append("KHR_lights_punctual")
    root.setdefault("extensions", {})["KHR_lights_punctual"] = {
        "lights": [{"name": "none", "type": "directional", "intensity": 0.0}]}
    root["nodes"].append({"name": "none", "extensions": {"KHR_lights_punctual": {"light": 0}}})
    root["scenes"][root.get("scene", 0)]["nodes"].append(len(root["nodes"]) - 1)


def add_camera(root, eye, target, yfov, aspect):
    root.setdefault("cameras", []).append(
        {"name": "view", "type": "perspective",
         "perspective": {"yfov": yfov, "aspectRatio": aspect, "znear": 0.05}})
    root["nodes"].append({"name": "view", "camera": len(root["cameras"]) - 1,
                          "translation": list(map(float, eye)),
                          "rotation": look_at_quaternion(eye, target)})
    root["scenes"][root.get("scene", 0)]["nodes"].append(len(root["nodes"]) - 1)


def write_glb(path, root, binary):
    binary += b"\0" * (-len(binary) % 4)
    if binary:
        root["buffers"] = [{"byteLength": len(binary)}]
    text = json.dumps(root).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary:
        body += struct.pack("<II", len(binary), 0x004E4942) + binary
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def read_glb(path):
    data = open(path, "rb").read()
    length = struct.unpack("<I", data[12:16])[0]
    root = json.loads(data[20:20 + length])
    rest = data[20 + length:]
    binary = rest[8:8 + struct.unpack("<I", rest[:4])[0]] if rest else b""
    return root, binary


def uv_sphere(radius, rings=48, segments=96):
    theta = numpy.linspace(0, math.pi, rings + 1)
    phi = numpy.linspace(0, 2 * math.pi, segments + 1)
    phi, theta = numpy.meshgrid(phi, theta)
    n = numpy.stack([numpy.sin(theta) * numpy.cos(phi), numpy.cos(theta),
                     -numpy.sin(theta) * numpy.sin(phi)], axis=-1).reshape(-1, 3)
    index = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            if i > 0:
                index.append((a, b, a + 1))
            if i < rings - 1:
                index.append((a + 1, b, b + 1))
    return (radius * n).astype(numpy.float32), n.astype(numpy.float32), \
        numpy.array(index, dtype=numpy.uint32)


def write_uniform(path):
    """A map of radiance 1 everywhere (a furnace)."""
    buf = oiio.ImageBuf(oiio.ImageSpec(64, 32, 3, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(), numpy.ones((32, 64, 3), dtype=numpy.float32))
    if not buf.write(path):
        sys.exit("cannot write %s: %s" % (path, buf.geterror()))


def write_sweep(path, width, height, white=False):
    """Ten spheres, radius 0.8, 1.9 apart: roughness across, metallic 0 (grey 0.5) on top,
    metallic 1 (gold-like base colour) below; camera 14 m away on +Z. `white`: base colour 1
    for all (the furnace scene: a white metal's Fresnel is 1 in both renderers)."""
    positions, normals, indices = uv_sphere(0.8)
    binary = b""
    views = []
    for array, target in ((positions, 34962), (normals, 34962), (indices, 34963)):
        views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": array.nbytes,
                      "target": target})
        binary += array.tobytes()
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
         "min": positions.min(axis=0).tolist(), "max": positions.max(axis=0).tolist()},
        {"bufferView": 1, "componentType": 5126, "count": len(normals), "type": "VEC3"},
        {"bufferView": 2, "componentType": 5125, "count": indices.size, "type": "SCALAR"}]
    root = {"asset": {"version": "2.0", "generator": "bench/cycles_path_compare.py"},
            "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
            "accessors": accessors, "bufferViews": views}
    for row, metallic in enumerate((0.0, 1.0)):
        for column, roughness in enumerate(SWEEP_ROUGHNESS):
            colour = [0.5, 0.5, 0.5, 1.0] if metallic == 0 else [1.0, 0.78, 0.34, 1.0]
            if white:
                colour = [1.0, 1.0, 1.0, 1.0]
            root["materials"].append({"name": "m%g r%g" % (metallic, roughness),
                                      "pbrMetallicRoughness": {
                                          "baseColorFactor": colour,
                                          "metallicFactor": metallic,
                                          "roughnessFactor": roughness}})
            root["meshes"].append({"name": "sphere m%g r%g" % (metallic, roughness),
                                   "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1},
                                                   "indices": 2,
                                                   "material": len(root["materials"]) - 1}]})
            root["nodes"].append({"name": "sphere m%g r%g" % (metallic, roughness),
                                  "mesh": len(root["meshes"]) - 1,
                                  "translation": [1.9 * (column - 2), 1.0 - 2.0 * row, 0.0]})
            root["scenes"][0]["nodes"].append(len(root["nodes"]) - 1)
    add_camera(root, (0.0, 0.0, 14.0), (0.0, 0.0, 0.0), 0.4, width / height)
    zero_light(root)
    write_glb(path, root, binary)


def write_asset(path, width, height, lambert=False):
    """`lambert`: specularFactor 0 on the material as well (exactly rho/pi in glTF, the
    control against Cycles' Diffuse BSDF)."""
    root, binary = read_glb(BOX_TEXTURED)
    if lambert:
        root.setdefault("extensionsUsed", []).append("KHR_materials_specular")
        for material in root["materials"]:
            material.setdefault("extensions", {})["KHR_materials_specular"] = {
                "specularFactor": 0.0}
    for sampler in root.get("samplers", []):
        sampler["minFilter"] = 9729  # LINEAR: Cycles filters the full image only
    add_camera(root, (1.9, 1.5, 2.5), (0.0, -0.05, 0.0), 0.6, width / height)
    zero_light(root)
    write_glb(path, root, binary)


def luminance(rgba):
    return rgba[..., :3] @ LUMA


def blocks(y):
    h, w = (s - s % BLOCK for s in y.shape)
    return y[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).mean(axis=(1, 3))


def compare(prism, cycles):
    yp, yc = luminance(prism), luminance(cycles)
    covered = prism[..., 3] > 0.999
    rel = numpy.abs(yp - yc) / (yc + EPSILON)
    block_covered = blocks(covered.astype(float)) > 0.999
    block_rel = numpy.abs(blocks(yp) - blocks(yc)) / (blocks(yc) + EPSILON)
    return {"mean_rel_all": float(rel.mean()),
            "mean_rel_covered": float(rel[covered].mean()) if covered.any() else None,
            "mean_rel_4x4_all": float(block_rel.mean()),
            "mean_rel_4x4_covered": float(block_rel[block_covered].mean())
            if block_covered.any() else None,
            "image_mean_diff": float((yp.mean() - yc.mean()) / yc.mean()),
            "covered_mean_diff": float((yp[covered].mean() - yc[covered].mean())
                                       / yc[covered].mean()) if covered.any() else None,
            "covered_pixels": int(covered.sum())}


def sphere_ratios(prism, cycles):
    """For the sweep and furnace scenes: each sphere's mean luminance, Prism / Cycles, over a
    disc of 0.8 times its projected radius (silhouettes left out)."""
    h, w = cycles.shape[:2]
    scale = (h / 2) / (14.0 * math.tan(0.2))  # pixels per metre at the spheres' plane
    yy, xx = numpy.mgrid[0:h, 0:w] + 0.5
    yp, yc = luminance(prism), luminance(cycles)
    ratios = {}
    for row, metallic in enumerate((0, 1)):
        for column, roughness in enumerate(SWEEP_ROUGHNESS):
            cx, cy = w / 2 + 1.9 * (column - 2) * scale, h / 2 - (1.0 - 2.0 * row) * scale
            disc = (xx - cx) ** 2 + (yy - cy) ** 2 < (0.8 * 0.8 * scale) ** 2
            ratios["metallic %d roughness %g" % (metallic, roughness)] = \
                float(yp[disc].mean() / yc[disc].mean())
    return ratios


def side_by_side(path, cycles, prism):
    yp, yc = luminance(prism), luminance(cycles)
    relative = (yp - yc) / (yc + EPSILON)
    t = numpy.clip(numpy.abs(relative) / 0.10, 0.0, 1.0)
    heat = numpy.ones(relative.shape + (3,))
    heat[..., 1] = 1.0 - t
    heat[..., 0] = numpy.where(relative > 0, 1.0, 1.0 - t)
    heat[..., 2] = numpy.where(relative > 0, 1.0 - t, 1.0)

    def srgb(x):
        x = numpy.clip(x[..., :3], 0.0, 1.0)
        return numpy.where(x <= 0.0031308, 12.92 * x, 1.055 * numpy.power(x, 1 / 2.4) - 0.055)

    gap = numpy.ones((cycles.shape[0], 4, 3))
    write_png(path, numpy.concatenate([srgb(cycles), gap, srgb(prism), gap, heat], axis=1))


def rel_mse(image, reference):
    """prism diff's relMSE (docs/metrics.md): mean over pixels and RGB of
    (a - b)^2 / (b^2 + 0.01)."""
    a, b = image[..., :3], reference[..., :3]
    return float(numpy.mean((a - b) ** 2 / (b * b + 0.01)))


def equal_error(args, prism, out, name, glb, environment, extra, results, res):
    """Each renderer against its own high-spp reference, at `res`: relMSE at
    --test-spp and the render time. relMSE falls as 1/time for an unbiased renderer, so
    the time to equal error is proportional to relMSE * time; the ratio of the two is
    Prism time / Cycles time at equal error. The test renders are timed --repeats times,
    Prism and Cycles in turn, and the medians kept (a render of a few seconds on a shared
    machine varies by tens of per cent from one run to the next).

    With --prism-target-error each round also renders both adaptively (Prism's
    --target-error, Cycles' noise threshold, at most --adaptive-max-spp samples a pixel),
    in the same interleaved rounds as the fixed-sample renders, so that each renderer's
    best mode can be set against the other's from one run."""

    modes = ["fixed"] + (["adaptive"] if args.prism_target_error > 0 else [])

    def cycles_cmd(exr, spp, seed, mode="fixed"):
        cmd = ["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python",
               CYCLES_SCRIPT, "--", glb, exr, "--res", res, "--spp", str(spp), "--threads",
               str(args.threads), "--max-bounces", str(args.max_depth - 1), "--no-key-light",
               "--seed", seed] + extra
        if mode == "adaptive":
            cmd += ["--adaptive-threshold", str(args.cycles_adaptive_threshold),
                    "--adaptive-min-samples", str(args.adaptive_min_spp)]
        return cmd + (["--environment", environment] if environment else [])

    def prism_cmd(exr, spp, seed=None, mode="fixed"):
        cmd = [prism, "render", glb, "-o", exr, "--integrator", "path", "--spp", str(spp),
               "--max-depth", str(args.max_depth), "--res", res, "--threads",
               str(args.threads), "--verbose"]
        if mode == "adaptive":
            cmd += ["--target-error", str(args.prism_target_error), "--min-spp",
                    str(args.adaptive_min_spp), "--error-goal", args.prism_error_goal]
        if seed is not None:
            cmd += ["--seed", seed]
        return cmd + (["--environment", environment] if environment else [])

    def test_spp(mode):
        return args.adaptive_max_spp if mode == "adaptive" else args.test_spp

    def cycles_seconds(text):
        return float(next(l.split()[1] for l in text.splitlines()
                          if l.startswith("PEER_RENDER_TIME")))

    def prism_total_seconds(text):
        # "render time  R s (load + build L s, total T s)": load, BVH and render, the scope of
        # Cycles' render call (which leaves Blender's start-up and glTF import out).
        line = next(l for l in text.splitlines() if l.startswith("render time"))
        return float(line.split("total ")[1].split(" s")[0])

    def prism_mean_spp(text):
        # "... path, 100x100, 1024 spp max, 129 mean, 25 rounds, ..." of an adaptive render.
        line = next((l for l in text.splitlines() if " spp max, " in l), None)
        return float(line.split(" spp max, ")[1].split()[0]) if line else None

    # Prism's samples are a pure function of (pixel, sample): a reference of the same seed
    # holds the test render's own samples, and an error measured against it would leave their
    # noise out (by 1 - 2 N / M of the variance, 22 % at 256 against 2048). With fixed samples
    # alone the reference's other M - N samples are taken, (M R - N T) / (M - N), since each
    # pixel is the mean of its samples; an adaptive render's samples differ from pixel to
    # pixel, so with it the reference is drawn from another seed, as Cycles' is.
    independent_seed = len(modes) > 1
    references = {}
    exr = os.path.join(out, "ee_cycles_%s_%d.exr" % (name, args.reference_spp))
    run(cycles_cmd(exr, args.reference_spp, "7"), exr + ".log")
    references["cycles"] = read_rgba(exr)
    exr = os.path.join(out, "ee_prism_%s_%d%s.exr" % (name, args.reference_spp,
                                                    "_seed7" if independent_seed else ""))
    run(prism_cmd(exr, args.reference_spp, "7" if independent_seed else None), exr + ".log")
    references["prism"] = read_rgba(exr)

    times = {(who, mode): [] for who in ("prism", "cycles", "prism_total") for mode in modes}
    images, mean_spp = {}, {}
    for _ in range(args.repeats):
        for mode in modes:
            suffix = "_adaptive" if mode == "adaptive" else ""
            exr = os.path.join(out, "ee_cycles_%s_%d%s.exr" % (name, test_spp(mode), suffix))
            text, _ = run(cycles_cmd(exr, test_spp(mode), "0", mode), exr + ".log")
            times[("cycles", mode)].append(cycles_seconds(text))
            images[("cycles", mode)] = read_rgba(exr)
            exr = os.path.join(out, "ee_prism_%s_%d%s.exr" % (name, test_spp(mode), suffix))
            text, seconds = run(prism_cmd(exr, test_spp(mode), mode=mode), exr + ".log")
            times[("prism", mode)].append(seconds)
            times[("prism_total", mode)].append(prism_total_seconds(text))
            mean_spp[mode] = prism_mean_spp(text)
            images[("prism", mode)] = read_rgba(exr)

    products = {}
    for mode in modes:
        row = {"res": res, "test_spp": test_spp(mode), "reference_spp": args.reference_spp,
               "repeats": args.repeats}
        reference = references["prism"]
        if independent_seed:
            row["prism_reference"] = "seed 7, %d spp" % args.reference_spp
        else:
            m, n = float(args.reference_spp), float(args.test_spp)
            reference = reference.copy()
            reference[..., :3] = (m * reference[..., :3] -
                                  n * images[("prism", mode)][..., :3]) / (m - n)
            row["prism_reference"] = "the other %d samples of the same seed" % (
                args.reference_spp - args.test_spp)
        if mode == "adaptive":
            row.update({"prism_target_error": args.prism_target_error,
                        "prism_error_goal": args.prism_error_goal,
                        "cycles_adaptive_threshold": args.cycles_adaptive_threshold,
                        "adaptive_min_spp": args.adaptive_min_spp,
                        "prism_mean_spp": mean_spp[mode]})
        row["prism_rel_mse"] = rel_mse(images[("prism", mode)], reference)
        row["cycles_rel_mse"] = rel_mse(images[("cycles", mode)], references["cycles"])
        for who in ("prism", "cycles", "prism_total"):
            row[who + "_seconds"] = statistics.median(times[(who, mode)])
            row[who + "_seconds_all"] = times[(who, mode)]
        for who in ("prism", "cycles"):
            products[(who, mode)] = row[who + "_rel_mse"] * row[who + "_seconds"]
        products[("prism_total", mode)] = row["prism_rel_mse"] * row["prism_total_seconds"]
        row["time_to_equal_error_prism_over_cycles"] = (
            products[("prism", mode)] / products[("cycles", mode)])
        row["time_to_equal_error_render_calls"] = (
            products[("prism_total", mode)] / products[("cycles", mode)])
        print("%s equal error at %s, %s, %d spp%s against %d spp of each: Prism relMSE %.4g in "
              "%.2f s (whole process; %.2f s load, BVH and render)%s, Cycles relMSE %.4g in %.2f s "
              "(medians of %d): Prism time / Cycles time = %.3f (whole process), %.3f (render "
              "calls)" %
              (name, res, mode, test_spp(mode), " at most" if mode == "adaptive" else "",
               args.reference_spp, row["prism_rel_mse"], row["prism_seconds"],
               row["prism_total_seconds"],
               ", %.4g spp mean" % mean_spp[mode] if mode == "adaptive" else "",
               row["cycles_rel_mse"], row["cycles_seconds"], args.repeats,
               row["time_to_equal_error_prism_over_cycles"],
               row["time_to_equal_error_render_calls"]))
        results[name + " equal error" + (" adaptive" if mode == "adaptive" else "")] = row
    if len(modes) > 1:
        # Each renderer in whichever of its modes reaches the error sooner.
        best = {who: min(modes, key=lambda m: products[(who, m)]) for who in ("prism", "cycles")}
        row = {"prism_mode": best["prism"], "cycles_mode": best["cycles"],
               "time_to_equal_error_prism_over_cycles":
                   products[("prism", best["prism"])] / products[("cycles", best["cycles"])],
               "time_to_equal_error_render_calls":
                   products[("prism_total", best["prism"])] / products[("cycles", best["cycles"])]}
        print("%s equal error, each at its best (Prism %s, Cycles %s): Prism time / Cycles time "
              "= %.3f (whole process), %.3f (render calls)" %
              (name, row["prism_mode"], row["cycles_mode"],
               row["time_to_equal_error_prism_over_cycles"], row["time_to_equal_error_render_calls"]))
        results[name + " equal error best"] = row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="/tmp/cycles-path")
    parser.add_argument("--max-depth", type=int, default=8)
    parser.add_argument("--cycles-spp", type=int, default=512)
    parser.add_argument("--prism-spp", type=int, default=512)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--scenes", default="cornell,sweep,asset")
    parser.add_argument("--images", default=os.path.join(ROOT, "docs/images"))
    parser.add_argument("--noise", action="store_true",
                        help="also render Cycles with seed 1: the metric between the two "
                             "Cycles seeds is the noise floor at that spp")
    parser.add_argument("--equal-error", action="store_true",
                        help="only the time-to-equal-error runs (Cornell with Cycles' Diffuse "
                             "BSDFs) at --equal-error-res")
    parser.add_argument("--equal-error-res", default="",
                        help="default: half the scene's resolution each way")
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--test-spp", type=int, default=128)
    parser.add_argument("--repeats", type=int, default=5,
                        help="times each test render is timed (medians), Prism and Cycles "
                             "in turn")
    parser.add_argument("--prism-target-error", type=float, default=0.0,
                        help="with --equal-error: adaptive test renders too, Prism with this "
                             "--target-error and Cycles with --cycles-adaptive-threshold")
    parser.add_argument("--prism-error-goal", choices=("pixel", "image"), default="pixel",
                        help="what Prism's --target-error bounds (prism render --error-goal)")
    parser.add_argument("--cycles-adaptive-threshold", type=float, default=0.01)
    parser.add_argument("--adaptive-max-spp", type=int, default=1024,
                        help="the most samples a pixel takes in the adaptive test renders")
    parser.add_argument("--adaptive-min-spp", type=int, default=16,
                        help="the samples every pixel takes in both adaptive test renders")
    parser.add_argument("--skip-blender", action="store_true",
                        help="reuse the Cycles renders already in --out")
    args = parser.parse_args()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    prism = find_prism()
    sky = os.path.join(out, "sky.exr")
    write_sky(sky)
    uniform = os.path.join(out, "uniform.exr")
    write_uniform(uniform)

    scenes = {"cornell": (os.path.join(ROOT, "scenes/cornell.gltf"), "200x200", None),
              "sweep": (os.path.join(out, "sweep.glb"), "320x192", sky),
              "asset": (os.path.join(out, "asset.glb"), "240x240", sky),
              "asset_lambert": (os.path.join(out, "asset_lambert.glb"), "240x240", sky),
              "furnace": (os.path.join(out, "furnace.glb"), "320x192", uniform)}
    results = {}
    path = os.path.join(out, "results.json")
    if os.path.exists(path):
        results = json.load(open(path))
    for name in args.scenes.split(","):
        glb, res, environment = scenes[name]
        width, height = (int(v) for v in res.split("x"))
        if args.equal_error:
            if name == "sweep":
                write_sweep(glb, width, height)
            elif name in ("asset", "asset_lambert"):
                write_asset(glb, width, height, lambert=name == "asset_lambert")
            extra = ["--lambert"] if name in ("cornell", "asset_lambert") else []
            equal_error(args, prism, out, name, glb, environment, extra, results,
                        args.equal_error_res or "%dx%d" % (width // 2, height // 2))
            with open(path, "w") as f:
                json.dump(results, f, indent=1)
            continue
        if name == "sweep":
            write_sweep(glb, width, height)
        elif name == "furnace":
            write_sweep(glb, width, height, white=True)
        elif name in ("asset", "asset_lambert"):
            write_asset(glb, width, height, lambert=name == "asset_lambert")
        variants = [("", [])] if name != "asset_lambert" else []
        if name in ("cornell", "asset_lambert"):
            variants.append(("lambert", ["--lambert"]))
        if args.noise:
            variants += [(v + "_seed1" if v else "seed1", e + ["--seed", "1"])
                         for v, e in variants]
        cycles = {}
        for variant, extra in variants:
            exr = os.path.join(out, "cycles_%s%s.exr" % (name, "_" + variant if variant else ""))
            timing = exr + ".time"
            if not args.skip_blender:
                cmd = ["blender", "-b", "--factory-startup", "--python-exit-code", "1",
                       "--python", CYCLES_SCRIPT, "--", glb, exr, "--res", res, "--spp",
                       str(args.cycles_spp), "--threads", str(args.threads),
                       "--max-bounces", str(args.max_depth - 1), "--no-key-light"] + extra
                if environment:
                    cmd += ["--environment", environment]
                text, _ = run(cmd, exr + ".log")
                seconds = float(next(l.split()[1] for l in text.splitlines()
                                     if l.startswith("PEER_RENDER_TIME")))
                open(timing, "w").write("%.4f\n" % seconds)
            cycles[variant] = (read_rgba(exr), float(open(timing).read()))
        exr = os.path.join(out, "prism_%s.exr" % name)
        cmd = [prism, "render", glb, "-o", exr, "--integrator", "path", "--spp",
               str(args.prism_spp), "--max-depth", str(args.max_depth), "--res", res,
               "--threads", str(args.threads), "--quiet"]
        if environment:
            cmd += ["--environment", environment]
        _, prism_seconds = run(cmd, exr + ".log")
        image = read_rgba(exr)
        for variant, (reference, cycles_seconds) in cycles.items():
            key = name + (" vs Cycles " + variant if variant else "")
            s = compare(image, reference)
            if "seed1" in variant:
                seed0 = cycles[variant.replace("_seed1", "").replace("seed1", "")][0]
                floor = reference.copy()
                floor[..., 3] = image[..., 3]  # Prism's coverage for the covered mask
                s["cycles_seed1_vs_seed0"] = compare(floor, seed0)
            s.update({"prism_seconds_wall": prism_seconds, "cycles_render_seconds": cycles_seconds,
                      "prism_spp": args.prism_spp, "cycles_spp": args.cycles_spp,
                      "max_depth": args.max_depth, "res": res})
            results[key] = s
            print("%-24s mean rel %.2f%% (covered %s), 4x4 %.2f%% (covered %s), image mean "
                  "%+.2f%%, Prism %.1f s / Cycles %.1f s" %
                  (key, 100 * s["mean_rel_all"],
                   "-" if s["mean_rel_covered"] is None else "%.2f%%" % (100 * s["mean_rel_covered"]),
                   100 * s["mean_rel_4x4_all"],
                   "-" if s["mean_rel_4x4_covered"] is None
                   else "%.2f%%" % (100 * s["mean_rel_4x4_covered"]),
                   100 * s["image_mean_diff"], prism_seconds, cycles_seconds))
            if name in ("sweep", "furnace"):
                s["sphere_ratio_prism_over_cycles"] = sphere_ratios(image, reference)
                print("  per sphere, Prism / Cycles mean luminance: " + ", ".join(
                    "%s %.4f" % (k.replace("metallic ", "m").replace(" roughness ", " r"), v)
                    for k, v in s["sphere_ratio_prism_over_cycles"].items()))
            if "cycles_seed1_vs_seed0" in s:
                n = s["cycles_seed1_vs_seed0"]
                print("  noise floor, Cycles seed 1 vs seed 0: mean rel %.2f%% (covered %.2f%%), "
                      "4x4 %.2f%% (covered %.2f%%), image mean %+.2f%%" %
                      (100 * n["mean_rel_all"], 100 * n["mean_rel_covered"],
                       100 * n["mean_rel_4x4_all"], 100 * n["mean_rel_4x4_covered"],
                       100 * n["image_mean_diff"]))
            for d in [out] + ([os.path.abspath(args.images)]
                              if args.images and "seed1" not in variant else []):
                os.makedirs(d, exist_ok=True)
                side_by_side(os.path.join(d, "cycles-path-%s%s.png" %
                                          (name, "-" + variant if variant else "")),
                             reference, image)
        with open(path, "w") as f:
            json.dump(results, f, indent=1)
    print("wrote %s" % path)


if __name__ == "__main__":
    main()
