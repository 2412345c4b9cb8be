#!/usr/bin/python3
"""Renders the same scenes with Prism and its peers and prints Markdown tables
(bench/peers/README.md). Run from the repository root with Debian's Python:

    /usr/bin/python3 bench/peers/run_peers.py [--out DIR] [--quick]

Needs build/apps/prism (or $PRISM), povray, blender, python3-numpy, python3-openimageio.

Comparisons:
  whitted  scenes/whitted.gltf, Prism `whitted` (uniform, and adaptive: --target-error
           0.05 and 0.03, --min-spp 4) vs POV-Ray 3.7 on bench/peers/whitted.pov
  whitted  scenes/whitted.gltf, Prism `shadow` (--spheres mesh:4) vs Cycles, direct light
  engine   2CylinderEngine.glb,  Prism `shadow`  vs Cycles, direct light

Each renderer's error is measured against its OWN converged render of the same scene (the
highest sample count): that is convergence error per second, free of model differences.
Agreement between renderers is a separate table: the converged renders against each other.
"""
import argparse
import os
import re
import sys

import numpy
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from benchlib import run_logged  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PRISM = os.environ.get("PRISM", os.path.join(ROOT, "build/apps/prism"))
ENGINE = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"
WHITTED = os.path.join(ROOT, "scenes/whitted.gltf")
WHITTED_POV = os.path.join(ROOT, "bench/peers/whitted.pov")
CYCLES_SCRIPT = os.path.join(ROOT, "bench/peers/cycles_render.py")
THREADS = 2
ADAPTIVE = ", adaptive"  # renderer-name suffix of adaptive rows
ADAPTIVE_TARGETS = [0.05, 0.03]
ADAPTIVE_MIN_SPP = 4
EPS = 1e-2  # relative MSE: (x - r)^2 / (r^2 + EPS)
LIT = 0.02  # a pixel is "lit" when both converged renders exceed this mean RGB radiance




def prism(scene, out, res, spp, integrator, extra=()):
    cmd = [PRISM, "render", scene, "-o", out, "--integrator", integrator, "--spp", str(spp),
           "--res", res, "--threads", str(THREADS)] + list(extra)
    text, wall = run_logged(cmd, out + ".log")
    render = float(re.search(r"render time\s+([0-9.]+) s", text).group(1))
    return render, wall, cmd, text


def mean_spp(text):
    """The mean samples per pixel an adaptive render reports ("256 spp max, 4.411 mean")."""
    return float(re.search(r"spp max, ([0-9.]+) mean", text).group(1))


def povray(scene, out, res, samples_root):
    w, h = res.split("x")
    aa = ["-A"] if samples_root == 1 else ["+AM1", "+A0.0", "+R%d" % samples_root, "-J"]
    cmd = ["povray", "-D", "-V", "+I" + scene, "+O" + out, "+FE", "+W" + w, "+H" + h,
           "+WT%d" % THREADS] + aa
    text, wall = run_logged(cmd, out + ".log")
    trace = float(re.search(r"Trace Time:.*\(([0-9.]+) seconds\)", text).group(1))
    parse = float(re.search(r"Parse Time:.*\(([0-9.]+) seconds\)", text).group(1))
    return parse + trace, wall, cmd


def cycles(scene, out, res, spp, lambert=False):
    cmd = ["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python",
           CYCLES_SCRIPT, "--", scene, out, "--res", res, "--spp", str(spp),
           "--threads", str(THREADS)] + (["--lambert"] if lambert else [])
    text, wall = run_logged(cmd, out + ".log")
    render = float(re.search(r"PEER_RENDER_TIME ([0-9.]+)", text).group(1))
    return render, wall, cmd


def load(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit(buf.geterror())
    return buf.get_pixels(oiio.FLOAT)[:, :, :3].astype(numpy.float64)


def errors(image, reference):
    """RMSE, RMSE of the images clamped to [0, 1] (point-light highlights on mirrors reach
    hundreds and dominate plain RMSE), and relative MSE."""
    d = image - reference
    c = numpy.clip(image, 0, 1) - numpy.clip(reference, 0, 1)
    return (float(numpy.sqrt(numpy.mean(d * d))), float(numpy.sqrt(numpy.mean(c * c))),
            float(numpy.mean(d * d / (reference * reference + EPS))))


def agreement(a, b):
    """a against b: RMSE, relMSE, and the mean and median |a - b| / b of mean-RGB radiance
    over the pixels where both are lit."""
    rmse, clamped, rel = errors(a, b)
    la, lb = a.mean(axis=2), b.mean(axis=2)
    lit = (la > LIT) & (lb > LIT)
    r = numpy.abs(la[lit] - lb[lit]) / lb[lit]
    return rmse, clamped, rel, float(r.mean()), float(numpy.median(r)), float(lit.mean())


def patch(image, x, y, size=8):
    return float(image[y:y + size, x:x + size].mean())


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default="/tmp/prism-peers")
    parser.add_argument("--quick", action="store_true", help="small references, for a smoke test")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    o = lambda name: os.path.join(args.out, name)  # noqa: E731

    counts = [1, 4, 16, 64]
    # POV-Ray AA method 1, threshold 0, no jitter: an R x R grid per pixel (+R is at most 9)
    pov_roots = [1, 2, 4, 8]
    ref_spp, ref_root, ref_cycles = (64, 8, 64) if args.quick else (256, 9, 512)

    rows = {}  # comparison -> list of (renderer, samples, render s, wall s, image)
    commands = []

    def record(key, renderer, samples, result, image):
        render, wall, cmd = result[:3]
        rows.setdefault(key, []).append((renderer, samples, render, wall, image))
        commands.append(" ".join(cmd))
        print("%-28s %-22s %6g spp  render %8.3f s  wall %8.3f s" % (key, renderer, samples,
                                                                   render, wall), flush=True)

    # 1. Whitted: Prism vs POV-Ray, 640x480.
    key, res = "whitted: Prism vs POV-Ray", "640x480"
    for spp in sorted(set(counts + [ref_spp])):
        f = o("w_prism_%d.exr" % spp)
        record(key, "Prism whitted", spp, prism(WHITTED, f, res, spp, "whitted"), f)
    # Adaptive sampling (docs/sampling.md), capped at the reference's spp; its error is
    # measured against the uniform Prism reference. The row's samples are its mean spp.
    for target in ADAPTIVE_TARGETS:
        f = o("w_prism_adaptive_%g.exr" % target)
        result = prism(WHITTED, f, res, ref_spp, "whitted",
                       ["--target-error", str(target), "--min-spp", str(ADAPTIVE_MIN_SPP)])
        record(key, "Prism whitted" + ADAPTIVE, mean_spp(result[3]), result, f)
    for root in sorted(set(pov_roots + [ref_root])):
        f = o("w_pov_%d.exr" % (root * root))
        record(key, "POV-Ray 3.7", root * root, povray(WHITTED_POV, f, res, root), f)

    # 2. and 3. Direct light: Prism shadow vs Cycles.
    for key, scene, res, extra in [
            ("whitted: Prism vs Cycles", WHITTED, "320x240", ["--spheres", "mesh:4"]),
            ("engine: Prism vs Cycles", ENGINE, "320x320", [])]:
        tag = key.split(":")[0]
        for spp in sorted(set(counts + [ref_cycles])):
            f = o("%s_prism_%d.exr" % (tag, spp))
            record(key, "Prism shadow", spp, prism(scene, f, res, spp, "shadow", extra), f)
        for spp in sorted(set(counts + [ref_cycles])):
            f = o("%s_cycles_%d.exr" % (tag, spp))
            record(key, "Cycles", spp, cycles(scene, f, res, spp), f)
        f = o("%s_cycles_lambert_%d.exr" % (tag, ref_cycles))
        record(key + " (Lambert)", "Cycles, Diffuse BSDF", ref_cycles,
               cycles(scene, f, res, ref_cycles, lambert=True), f)

    print()
    print("| comparison | renderer | samples/pixel | render s | wall s | RMSE vs own ref | "
          "RMSE clamped [0,1] | relMSE vs own ref |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    refs = {}
    for key, entries in rows.items():
        if key.endswith("(Lambert)"):
            continue
        for renderer in dict.fromkeys(e[0] for e in entries):
            mine = [e for e in entries if e[0] == renderer]
            if renderer.endswith(ADAPTIVE):  # against the same renderer's uniform reference
                ref_image = refs[(key, renderer[:-len(ADAPTIVE)])]
                ref_path = None
            else:
                ref_path = max(mine, key=lambda e: e[1])[4]
                ref_image = refs[(key, renderer)] = load(ref_path)
            for _, samples, render, wall, image in mine:
                if image == ref_path:
                    err = ("reference",) * 3
                else:
                    err = tuple("%.4g" % e for e in errors(load(image), ref_image))
                print("| %s | %s | %g | %.3f | %.3f | %s | %s | %s |" % (
                    (key, renderer, samples, render, wall) + err))

    print()
    print("| scene | A (converged) | B (converged) | RMSE | RMSE clamped | relMSE | "
          "mean rel. diff, lit | median rel. diff, lit | lit fraction |")
    print("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    pairs = [("whitted: Prism vs POV-Ray", "Prism whitted", "POV-Ray 3.7", None),
             ("whitted: Prism vs Cycles", "Prism shadow", "Cycles", None),
             ("whitted: Prism vs Cycles", "Prism shadow", "Cycles, Diffuse BSDF",
              "whitted: Prism vs Cycles (Lambert)"),
             ("engine: Prism vs Cycles", "Prism shadow", "Cycles", None),
             ("engine: Prism vs Cycles", "Prism shadow", "Cycles, Diffuse BSDF",
              "engine: Prism vs Cycles (Lambert)")]
    for key, a, b, bkey in pairs:
        ia = refs[(key, a)]
        ib = refs[(key, b)] if bkey is None else load(rows[bkey][0][4])
        rmse, clamped, rel, mean, median, frac = agreement(ia, ib)
        print("| %s | %s | %s | %.4g | %.4g | %.4g | %.2f%% | %.2f%% | %.2f |" % (
            key.split(":")[0], a, b, rmse, clamped, rel, 100 * mean, 100 * median, frac))

    print()
    print("Diffuse-floor patches (8x8 pixels, mean RGB radiance of the converged renders):")
    print()
    print("| scene | patch (x, y) | Prism | peer | peer / Prism |")
    print("| --- | --- | ---: | ---: | ---: |")
    for key, a, b, bkey, spots in [
            ("whitted: Prism vs POV-Ray", "Prism whitted", "POV-Ray 3.7", None,
             [(300, 420), (40, 300), (560, 330)]),
            ("whitted: Prism vs Cycles", "Prism shadow", "Cycles, Diffuse BSDF",
             "whitted: Prism vs Cycles (Lambert)", [(150, 210), (20, 150), (280, 165)]),
            ("whitted: Prism vs Cycles", "Prism shadow", "Cycles", None,
             [(150, 210), (20, 150), (280, 165)])]:
        ia = refs[(key, a)]
        ib = refs[(key, b)] if bkey is None else load(rows[bkey][0][4])
        for x, y in spots:
            pa, pb = patch(ia, x, y), patch(ib, x, y)
            print("| %s | (%d, %d) | %.5f | %.5f (%s) | %.4f |" % (
                key.split(":")[0], x, y, pa, pb, b, pb / pa))

    with open(o("commands.txt"), "w") as f:
        f.write("\n".join(commands) + "\n")
    print()
    print("images, logs and commands.txt in", args.out)


if __name__ == "__main__":
    main()
