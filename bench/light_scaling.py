#!/usr/bin/env python3
"""What each light costs in render time, from 1 to 64 lights (docs/benchmarks.md, "Many
lights"):

    python3 bench/light_scaling.py WORK_DIR [--rounds 9] [--lights 0,1,2,4,8,16,32,64]
                                   [--kind point|spot] [--res 1280x960] [--spp 1] [--threads 1]

Writes the scenes of bench/make_light_scene.py into WORK_DIR (if missing), then renders
them with `shadow` (1 spp unless --spp says more: more samples make each light's cost large
against the 1 ms the `render time` line resolves and the noise of a shared machine), each round taking every light count once in turn (interleaved,
so a slow spell of a shared machine falls on every count alike). It keeps the in-process
`render time` prism prints, so neither start-up nor the EXR write counts. The cost per light
is (t(N) - t(0)) / N, t(0) being one light of intensity 0; each round gives its own, and the
table shows their medians over the rounds (and the fastest run), with the spread of the
medians from 1 to 64 lights as max / min. Writes WORK_DIR/light_scaling.json.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys

from benchlib import ROOT, find_prism

RENDER_TIME = re.compile(r"^render time\s+([0-9.]+) s", re.M)


def render_seconds(prism, scene, args, out):
    proc = subprocess.run([prism, "render", scene, "--integrator", "shadow", "--spp", str(args.spp),
                           "--res", args.res, "--threads", str(args.threads), "-o", out],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        sys.exit("failed: %s\n%s" % (scene, proc.stdout[-2000:]))
    match = RENDER_TIME.search(proc.stdout)
    if not match:
        sys.exit("no `render time` line for %s:\n%s" % (scene, proc.stdout[-2000:]))
    return float(match.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("work")
    parser.add_argument("--rounds", type=int, default=9)
    parser.add_argument("--lights", default="0,1,2,4,8,16,32,64")
    parser.add_argument("--kind", choices=("point", "spot"), default="point")
    parser.add_argument("--res", default="1280x960")
    parser.add_argument("--spp", type=int, default=1)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    counts = [int(n) for n in args.lights.split(",")]
    if counts[0] != 0:
        sys.exit("--lights must start with 0 (the cost of everything but the lights)")
    prism = find_prism("light_scaling.py")
    os.makedirs(args.work, exist_ok=True)
    scenes = {}
    for n in counts:
        path = os.path.join(args.work, "%s%d.gltf" % (args.kind, n))
        if not os.path.exists(path):
            extra = ["--kind", "spot", "--range", "6"] if args.kind == "spot" else []
            subprocess.run([sys.executable, os.path.join(ROOT, "bench/make_light_scene.py"),
                            "--lights", str(n), "-o", path] + extra, check=True)
        scenes[n] = path
    out = os.path.join(args.work, "out.exr")
    for n in counts:  # warm-up: the file cache and the CPU's clock
        render_seconds(prism, scenes[n], args, out)
    times = {n: [] for n in counts}
    for _ in range(args.rounds):
        for n in counts:
            times[n].append(render_seconds(prism, scenes[n], args, out))
    per_light = {n: [(times[n][r] - times[0][r]) / n * 1000.0 for r in range(args.rounds)]
                 for n in counts if n > 0}
    print("| lights | render time, median | fastest | per light, median of rounds | "
          "per light, fastest runs |")
    print("| ---: | ---: | ---: | ---: | ---: |")
    for n in counts:
        row = "| %d | %.3f s | %.3f s |" % (n, statistics.median(times[n]), min(times[n]))
        if n > 0:
            row += " %.1f ms | %.1f ms |" % (statistics.median(per_light[n]),
                                             (min(times[n]) - min(times[0])) / n * 1000.0)
        else:
            row += " | |"
        print(row)
    medians = [statistics.median(v) for v in per_light.values()]
    print("per light from %d to %d lights: %.1f to %.1f ms, max / min %.3f" %
          (min(per_light), max(per_light), min(medians), max(medians), max(medians) / min(medians)))
    with open(os.path.join(args.work, "light_scaling.json"), "w") as f:
        json.dump({"prism": prism, "args": vars(args), "times": times,
                   "per_light_ms": per_light}, f, indent=1)


if __name__ == "__main__":
    main()
