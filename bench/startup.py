#!/usr/bin/env python3
"""What a user waits for outside the render itself (docs/benchmarks.md, "Start-up"):

    python3 bench/startup.py [--rounds 15] [--res 320x240] [--spp 4] [--vs OTHER_PRISM]

Each round runs, in turn (interleaved, so a slow spell of a shared machine falls on every
command alike): a C++ hello world built here with g++ -O2, `prism --help`, and `prism
render` of an untextured asset (2CylinderEngine) and of a textured one (BoxTextured, a PNG).
A render's start-up is its whole-process wall time minus the `total` prism itself reports
(load, build, render and write, timed from main): dynamic linking, static constructors and
exit. The table gives medians over the rounds; "over hello" subtracts the hello world's
median wall time, the cost of any process at all. The goal of the start-up work: `--help`
and both renders within 20 ms of hello, and a small textured render's wall time within 1.3x
of the total prism reports. With --vs, every round also runs the same prism commands with
another build's binary (before a change, say), and a last table gives this build's wall
time over the other's, as the median of the rounds' ratios.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

from benchlib import find_prism, run_logged

ASSETS = "/usr/share/assimp/models/glTF2"
SCENES = {
    "untextured": ASSETS + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
    "textured": ASSETS + "/BoxTextured-glTF/BoxTextured.gltf",
}
TOTAL = re.compile(r"total ([0-9.]+) s\)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--res", default="320x240")
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--vs", metavar="OTHER_PRISM", help="another prism binary to compare")
    args = parser.parse_args()
    prism = find_prism("startup.py")
    for path in SCENES.values():
        if not os.path.exists(path):
            sys.exit("startup.py: %s is missing (Debian's assimp-testmodels)" % path)

    with tempfile.TemporaryDirectory() as work:
        hello = os.path.join(work, "hello")
        with open(hello + ".cpp", "w") as f:
            f.write('#include <cstdio>\nint main() { std::puts("hello"); }\n')
        subprocess.run(["g++", "-O2", hello + ".cpp", "-o", hello], check=True)
        commands = {"hello world": [hello]}
        binaries = {"": prism}
        if args.vs:
            binaries[" (vs)"] = args.vs
        for label, binary in binaries.items():
            commands["prism --help" + label] = [binary, "--help"]
            for kind, scene in SCENES.items():
                commands["prism render " + kind + label] = [
                    binary, "render", scene, "--res", args.res, "--spp", str(args.spp), "-o",
                    os.path.join(work, kind + ".exr")]
        walls = {name: [] for name in commands}
        outside = {name: [] for name in commands if name.startswith("prism render")}
        totals = {name: [] for name in outside}
        log = os.path.join(work, "last.log")
        for name, cmd in commands.items():  # one warm-up each: the page cache, not counted
            run_logged(cmd, log)
        for _ in range(args.rounds):
            for name, cmd in commands.items():
                output, wall = run_logged(cmd, log)
                walls[name].append(wall)
                if name in outside:
                    match = TOTAL.search(output)
                    if not match:
                        sys.exit("no `total` in the output of %s:\n%s" % (" ".join(cmd), output))
                    total = float(match.group(1))
                    totals[name].append(total)
                    outside[name].append(wall - total)

    hello_wall = statistics.median(walls["hello world"])
    print("%d rounds, medians; %s%s; res %s, %d spp" %
          (args.rounds, prism, " (vs) " + args.vs if args.vs else "", args.res, args.spp))
    print("| command | wall ms | prism's total ms | outside it ms | over hello ms | wall / total |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name in commands:
        wall = statistics.median(walls[name]) * 1e3
        if name in outside:
            total = statistics.median(totals[name]) * 1e3
            out = statistics.median(outside[name]) * 1e3
            ratio = statistics.median(w / t for w, t in zip(walls[name], totals[name]))
            print("| %s | %.1f | %.1f | %.1f | %.1f | %.3f |" %
                  (name, wall, total, out, out - hello_wall * 1e3, ratio))
        else:
            over = "" if name == "hello world" else "%.1f" % (wall - hello_wall * 1e3)
            print("| %s | %.1f | | | %s | |" % (name, wall, over))
    if args.vs:
        print("\n| command | wall, this / vs (median of rounds) | outside total, this / vs |")
        print("| --- | ---: | ---: |")
        for name in commands:
            if name + " (vs)" not in commands:
                continue
            other = name + " (vs)"
            ratio = statistics.median(a / b for a, b in zip(walls[name], walls[other]))
            out = ""
            if name in outside:
                out = "%.3f" % statistics.median(a / b for a, b in zip(outside[name], outside[other]))
            print("| %s | %.3f | %s |" % (name, ratio, out))


if __name__ == "__main__":
    main()
