#!/usr/bin/env python3
"""Whole-process time and memory of two prism binaries on the same renders, interleaved:

    python3 bench/before_after.py --old OLD/prism [--new NEW/prism] [--runs 5] WORK_DIR

Renders a textured game level (bench/make_textured_level.py), 2CylinderEngine (from Debian's
assimp-testmodels), the 1M-triangle terrain and a 16M-triangle height field
(bench/make_bench_scenes.py), making the generated scenes in WORK_DIR if they are missing.
Each round runs old then new on every scene (one warm-up round is not counted); the table
gives medians of wall, CPU (user + sys) and peak memory, and new / old as the median of the
per-round ratios. Both binaries get the same explicit options (integrator, spp, resolution),
since defaults differ between commits. Writes WORK_DIR/before_after.json and prints a
Markdown table.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

from benchlib import ROOT, find_prism

ENGINE = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"


def scenes(work):
    level = os.path.join(work, "level", "level.gltf")
    terrain = os.path.join(work, "terrain.glb")
    mesh16m = os.path.join(work, "mesh16m.glb")
    if not os.path.exists(level):
        subprocess.run([sys.executable, os.path.join(ROOT, "bench/make_textured_level.py"),
                        os.path.dirname(level)], check=True, stdout=subprocess.DEVNULL)
    for path, side in ((terrain, 710), (mesh16m, 2829)):
        if not os.path.exists(path):
            subprocess.run([sys.executable, os.path.join(ROOT, "bench/make_bench_scenes.py"),
                            "--mesh", path, "--mesh-side", str(side)], check=True)
    return [
        ("textured level (24 PNGs), 1 spp whitted", level, ["--res", "640x480", "--spp", "1"]),
        ("2CylinderEngine, 16 spp shadow", ENGINE,
         ["--res", "480x480", "--spp", "16", "--integrator", "shadow"]),
        ("terrain (1M triangles), 16 spp shadow", terrain,
         ["--res", "853x480", "--spp", "16", "--integrator", "shadow"]),
        ("16M triangles, 1 spp whitted", mesh16m, ["--res", "640x480", "--spp", "1"]),
    ]


def run(cmd):
    """Wall seconds, CPU seconds and peak MiB of one whole process."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), err[-2000:]))
    return {"wall": wall, "cpu": usage.ru_utime + usage.ru_stime,
            "peak_mib": usage.ru_maxrss / 1024.0}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("work", help="folder for generated scenes, images and the results")
    parser.add_argument("--old", required=True, help="the prism binary to compare against")
    parser.add_argument("--new", default=None, help="default: this tree's build")
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    new = args.new or find_prism("before_after.py")
    os.makedirs(args.work, exist_ok=True)
    todo = scenes(args.work)
    binaries = {"old": args.old, "new": new}
    results = {name: {"old": [], "new": []} for name, _, _ in todo}
    for round_index in range(args.runs + 1):
        for name, scene, options in todo:
            for which, prism in binaries.items():
                out = os.path.join(args.work, "%s-%d.exr" % (which, todo.index((name, scene,
                                                                               options))))
                figures = run([prism, "render", scene, "-o", out, "-q"] + options)
                if round_index > 0:  # the first round warms the page cache
                    results[name][which].append(figures)
    rows = []
    print("| render | new wall s | old wall s | new / old wall | new / old CPU | "
          "new / old peak |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, _, _ in todo:
        r = results[name]
        ratio = {k: statistics.median(n[k] / o[k] for n, o in zip(r["new"], r["old"]))
                 for k in ("wall", "cpu", "peak_mib")}
        med = {w: {k: statistics.median(x[k] for x in r[w]) for k in ("wall", "cpu", "peak_mib")}
               for w in ("old", "new")}
        rows.append({"render": name, "median": med, "ratio": ratio, "runs": r})
        print("| %s | %.3f | %.3f | **%.3f** | %.3f | %.3f (%.0f / %.0f MiB) |" % (
            name, med["new"]["wall"], med["old"]["wall"], ratio["wall"], ratio["cpu"],
            ratio["peak_mib"], med["new"]["peak_mib"], med["old"]["peak_mib"]))
    with open(os.path.join(args.work, "before_after.json"), "w") as f:
        json.dump({"old": args.old, "new": new, "runs": args.runs, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
