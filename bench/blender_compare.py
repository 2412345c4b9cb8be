#!/usr/bin/python3
"""Blender -> glTF -> Prism, against Blender Cycles' direct-light render of the same scene
(issue 6, docs/blender-comparison.md). One command, rerunnable:

    /usr/bin/python3 bench/blender_compare.py [--out DIR] [--res 400x300] [--cycles-spp 512]
        [--prism-spp 256] [--images docs/images] [--quick]

1. bench/peers/blender_asset.py builds the scene in Blender, exports DIR/asset.glb and
   renders it with Cycles twice (seeds 0 and 1) plus once with Diffuse BSDFs (--lambert).
2. Prism renders DIR/asset.glb with `--integrator shadow --background 0` at the same
   resolution, and again with `--detect-spheres`, and two edited copies: without the
   normal map (tells whether this Prism build reads normal maps) and with the samplers'
   minFilter LINEAR instead of the exporter's LINEAR_MIPMAP_LINEAR (Cycles does not
   mip-map), to separate texture filtering from shading.
3. The linear EXRs are compared. The reference is the mean of the two Cycles seeds. The
   "lit" mask holds the pixels whose reference mean-RGB radiance exceeds LIT_FRACTION of
   the image mean; per-object masks are the lit pixels whose 3x3 neighbourhood in Cycles'
   object-index pass is one object (silhouettes excluded). For each mask it prints the mean
   of |prism - cycles| / cycles (mean RGB per pixel), the ratio of the summed radiances, and
   Cycles' own noise: half the mean relative difference of its two seeds (the noise of their
   mean).
Previews (sRGB PNGs, clamped) and a relative-difference map go to --images.

Needs Blender 3.4, python3-numpy and python3-openimageio (`bash scripts/setup-bench.sh`) and
a prism binary: $PRISM, else build-blender/, build-bench/ or build/.
"""
import argparse
import json
import os
import struct
import subprocess
import sys
import time

import numpy
import OpenImageIO as oiio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ASSET_SCRIPT = os.path.join(ROOT, "bench/peers/blender_asset.py")
LIT_FRACTION = 0.2
OBJECTS = {1: "floor (checker)", 2: "cube (bricks, normal map)", 3: "sphere (stripes, glossy)"}
NORMAL_MAPPED = 2


def find_prism():
    if os.environ.get("PRISM"):
        return os.environ["PRISM"]
    for d in ("build-blender", "build-bench", "build"):
        p = os.path.join(ROOT, d, "apps/prism")
        if os.path.exists(p):
            return p
    sys.exit("blender_compare.py: no prism binary (build it, or set $PRISM)")


def run(cmd, log):
    start = time.perf_counter()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n" + proc.stdout)
    if proc.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (proc.returncode, " ".join(cmd), proc.stdout[-3000:]))
    print("  %.1f s: %s" % (time.perf_counter() - start, " ".join(cmd)))
    return proc.stdout


def read_channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    pixels = buf.get_pixels(oiio.FLOAT)
    index = [spec.channelnames.index(n) for n in names]
    return pixels[..., index]


def gltf_json(path):
    data = open(path, "rb").read()
    length = struct.unpack("<I", data[12:16])[0]
    return json.loads(data[20:20 + length])


def write_glb_variant(source, target, edit):
    """Copies a .glb with edit(json) applied to its JSON chunk."""
    data = open(source, "rb").read()
    length = struct.unpack("<I", data[12:16])[0]
    root = json.loads(data[20:20 + length])
    edit(root)
    text = json.dumps(root).encode()
    text += b" " * (-len(text) % 4)
    rest = data[20 + length:]
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + rest
    with open(target, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def srgb_preview(path, rgb):
    x = numpy.clip(rgb, 0.0, 1.0)
    x = numpy.where(x <= 0.0031308, 12.92 * x, 1.055 * numpy.power(x, 1 / 2.4) - 0.055)
    write_png(path, x)


def write_png(path, rgb):
    h, w, _ = rgb.shape
    buf = oiio.ImageBuf(oiio.ImageSpec(w, h, 3, oiio.UINT8))
    buf.set_pixels(oiio.ROI(), numpy.ascontiguousarray(rgb, dtype=numpy.float32))
    if not buf.write(path):
        sys.exit("cannot write %s: %s" % (path, buf.geterror()))


def difference_map(path, relative, lit):
    """Blue = Prism darker, red = Prism brighter, full colour at 10 %; unlit pixels grey."""
    t = numpy.clip(numpy.abs(relative) / 0.10, 0.0, 1.0)
    rgb = numpy.ones(relative.shape + (3,))
    brighter = relative > 0
    rgb[..., 1] = 1.0 - t
    rgb[..., 0] = numpy.where(brighter, 1.0, 1.0 - t)
    rgb[..., 2] = numpy.where(brighter, 1.0 - t, 1.0)
    rgb[~lit] = 0.25
    write_png(path, rgb)


def eroded(ids, value):
    """Pixels whose 3x3 neighbourhood (edge-replicated) is all `value`."""
    padded = numpy.pad(ids, 1, mode="edge")
    h, w = ids.shape
    ok = numpy.ones_like(ids, dtype=bool)
    for dy in range(3):
        for dx in range(3):
            ok &= padded[dy:dy + h, dx:dx + w] == value
    return ok


def stats(prism, cycles, cycles_a, cycles_b, mask):
    p, c = prism.mean(axis=-1)[mask], cycles.mean(axis=-1)[mask]
    a, b = cycles_a.mean(axis=-1)[mask], cycles_b.mean(axis=-1)[mask]
    return {"pixels": int(mask.sum()),
            "mean_rel": float(numpy.mean(numpy.abs(p - c) / c)),
            "median_rel": float(numpy.median(numpy.abs(p - c) / c)),
            "ratio": float(p.sum() / c.sum()),
            "noise": float(0.5 * numpy.mean(numpy.abs(a - b) / c))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="/tmp/prism-blender")
    parser.add_argument("--res", default="400x300")
    parser.add_argument("--cycles-spp", type=int, default=512)
    parser.add_argument("--prism-spp", type=int, default=256)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--images", default=os.path.join(ROOT, "docs/images"),
                        help="where the PNG previews go ('' = only into --out)")
    parser.add_argument("--quick", action="store_true", help="64/16 spp: a smoke run")
    parser.add_argument("--skip-blender", action="store_true",
                        help="reuse the asset and Cycles renders already in --out")
    args = parser.parse_args()
    if args.quick:
        args.cycles_spp, args.prism_spp = 64, 16
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    prism = find_prism()

    if not args.skip_blender:
        run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python",
             ASSET_SCRIPT, "--", out, "--res", args.res, "--spp", str(args.cycles_spp),
             "--seeds", "0,1", "--threads", str(args.threads), "--lambert"],
            os.path.join(out, "blender.log"))
    glb = os.path.join(out, "asset.glb")
    renders = {}
    for name, extra in (("prism", []), ("prism_detect", ["--detect-spheres"])):
        exr = os.path.join(out, name + ".exr")
        text = run([prism, "render", glb, "-o", exr, "--integrator", "shadow", "--spp",
                    str(args.prism_spp), "--res", args.res, "--background", "0", "--threads",
                    str(args.threads), "--quiet"] + extra, exr + ".log")
        renders[name] = read_channels(exr, ["R", "G", "B"])
        if extra:
            print("  " + "\n  ".join(l for l in text.splitlines() if "sphere" in l))
    run([prism, "info", glb], os.path.join(out, "prism_info.txt"))
    # Whether this build reads normal maps: the same render of the file without them.
    def drop_normal_maps(root):
        for m in root.get("materials", []):
            m.pop("normalTexture", None)

    # Cycles filters textures bilinearly from the full image only; the exporter asks for
    # trilinear mip-mapping (minFilter LINEAR_MIPMAP_LINEAR), which Prism honours.
    def no_mip_maps(root):
        for sampler in root.get("samplers", []):
            sampler["minFilter"] = 9729  # LINEAR

    for name, edit in (("no_normal_map", drop_normal_maps), ("no_mip_maps", no_mip_maps)):
        variant = os.path.join(out, "asset_%s.glb" % name)
        write_glb_variant(glb, variant, edit)
        exr = os.path.join(out, "prism_%s.exr" % name)
        run([prism, "render", variant, "-o", exr, "--integrator", "shadow", "--spp",
             str(args.prism_spp), "--res", args.res, "--background", "0", "--threads",
             str(args.threads), "--quiet"], exr + ".log")
        renders["prism_" + name] = read_channels(exr, ["R", "G", "B"])
    normal_map_used = not numpy.array_equal(renders["prism_no_normal_map"], renders["prism"])

    combined = ["ViewLayer.Combined." + c for c in "RGB"]
    cycles_a = read_channels(os.path.join(out, "cycles_seed0.exr"), combined)
    cycles_b = read_channels(os.path.join(out, "cycles_seed1.exr"), combined)
    lambert = read_channels(os.path.join(out, "cycles_lambert_seed0.exr"), combined)
    ids = numpy.round(read_channels(os.path.join(out, "cycles_seed0.exr"),
                                    ["ViewLayer.IndexOB.X"])[..., 0]).astype(int)
    cycles = 0.5 * (cycles_a + cycles_b)
    luminance = cycles.mean(axis=-1)
    lit = luminance > LIT_FRACTION * luminance.mean()
    masks = [("all lit pixels", lit),
             ("lit, without the normal-mapped cube", lit & ~eroded(ids, NORMAL_MAPPED)
              & (ids != NORMAL_MAPPED))]
    masks += [("lit " + label, lit & eroded(ids, k)) for k, label in OBJECTS.items()]

    gltf = gltf_json(glb)
    spec_lights = gltf_json(os.path.join(out, "asset_spec.glb"))
    blender_lights = json.load(open(os.path.join(out, "blender_lights.json")))
    print("\nLights: Blender -> glTF (COMPAT export, used) and the exporter's default SPEC")
    print("| light | Blender | glTF COMPAT | glTF SPEC (default) |")
    print("| --- | --- | ---: | ---: |")
    for l, s in zip(gltf["extensions"]["KHR_lights_punctual"]["lights"],
                    spec_lights["extensions"]["KHR_lights_punctual"]["lights"]):
        b = blender_lights[l["name"]]
        unit = ("W/m^2", "lx") if b["type"] == "SUN" else ("W", "cd")
        print("| %s (%s) | %g %s | %.6g %s | %.6g %s |" % (l["name"], l["type"], b["energy"],
                                                         unit[0], l["intensity"], unit[1],
                                                         s["intensity"], unit[1]))

    head = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                          stdout=subprocess.PIPE, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                           stdout=subprocess.PIPE, text=True).stdout.strip()
    print("\nPrism: %s (tree at %s%s), %d spp; Cycles: Blender 3.4, %d spp x 2 seeds; %s; "
          "lit = mean RGB above %.2f x the image mean (%.4g)" %
          (prism, head, ", with uncommitted changes" if dirty else "", args.prism_spp,
           args.cycles_spp, args.res, LIT_FRACTION, LIT_FRACTION * luminance.mean()))
    print("normal map used by this Prism build: %s (its render of the file without "
          "normalTexture %s)" % (("yes", "differs") if normal_map_used else ("no", "is identical")))
    print("\n| Prism render | region | pixels | mean rel. diff | median rel. diff | "
          "Prism/Cycles sum | Cycles noise |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: |")
    results = {}
    rows = [("prism", renders["prism"], cycles, "Cycles"),
            ("prism --detect-spheres", renders["prism_detect"], cycles, "Cycles"),
            ("prism, minFilter LINEAR", renders["prism_no_mip_maps"], cycles, "Cycles"),
            ("prism, minFilter LINEAR", renders["prism_no_mip_maps"], lambert,
             "Cycles, Diffuse BSDF"),
            ("prism", renders["prism"], lambert, "Cycles, Diffuse BSDF")]
    for label, image, reference, ref_name in rows:
        for region, mask in masks:
            if ref_name != "Cycles":
                noise_a = noise_b = reference  # one seed only: noise not measured
            else:
                noise_a, noise_b = cycles_a, cycles_b
            s = stats(image, reference, noise_a, noise_b, mask)
            results[f"{label} vs {ref_name}: {region}"] = s
            print("| %s vs %s | %s | %d | %.2f%% | %.2f%% | %.4f | %s |" %
                  (label, ref_name, region, s["pixels"], 100 * s["mean_rel"],
                   100 * s["median_rel"], s["ratio"],
                   "%.2f%%" % (100 * s["noise"]) if ref_name == "Cycles" else "n/a"))
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)

    relative = numpy.zeros_like(luminance)
    relative[lit] = (renders["prism"].mean(axis=-1)[lit] - luminance[lit]) / luminance[lit]
    for d in [out] + ([os.path.abspath(args.images)] if args.images else []):
        os.makedirs(d, exist_ok=True)
        srgb_preview(os.path.join(d, "blender-cycles.png"), cycles)
        srgb_preview(os.path.join(d, "blender-prism.png"), renders["prism"])
        difference_map(os.path.join(d, "blender-difference.png"), relative, lit)
    print("\nwrote %s/{results.json,*.exr,*.png}%s" %
          (out, " and previews in " + args.images if args.images else ""))


if __name__ == "__main__":  # also imported by cycles_path_compare.py for its helpers
    main()
