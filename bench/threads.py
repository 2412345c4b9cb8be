#!/usr/bin/python3
"""Thread scaling: the same `prism render` with --threads 1, 2 and every core (when the
machine has more than 2), repeated and interleaved so that load from other jobs hits each
thread count alike; prints a Markdown table of the median render time and the speed-up over
one thread.

    /usr/bin/python3 bench/threads.py [--generated DIR] [--out DIR] [--reps 3] [--spp 8]

Scenes: 2CylinderEngine and scenes/spheres.gltf, plus the generated sphere field and
terrain when --generated names their directory. Render time is Prism's own `render time`
(tracing only, after load and BVH build), which is the part that runs in parallel.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

from benchlib import ROOT, find_prism
ENGINE = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"




def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--generated", help="directory of bench/make_bench_scenes.py's scenes")
    parser.add_argument("--out", default="/tmp/prism-threads")
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--spp", type=int, default=8)
    parser.add_argument("--integrator", default="whitted")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    prism = find_prism("threads.py")
    cores = os.cpu_count()
    counts = [1, 2] + ([cores] if cores > 2 else [])
    scenes = [ENGINE, os.path.join(ROOT, "scenes/spheres.gltf")]
    if args.generated:
        scenes += [os.path.join(args.generated, "sphere_field.gltf"),
                   os.path.join(args.generated, "terrain.glb")]
    commands = []
    print("Integrator `%s`, %d spp, default resolution; median of %d interleaved runs; "
          "%d cores." % (args.integrator, args.spp, args.reps, cores))
    print()
    print("| scene | threads | render s (median) | runs | rays/s | speed-up vs 1 thread | "
          "efficiency |")
    print("| --- | ---: | ---: | --- | ---: | ---: | ---: |")
    for scene in scenes:
        tag = os.path.splitext(os.path.basename(scene))[0]
        times = {n: [] for n in counts}
        rays = {}
        for rep in range(args.reps):
            for n in counts:
                out = os.path.join(args.out, "%s_t%d.exr" % (tag, n))
                cmd = [prism, "render", scene, "-o", out, "--integrator", args.integrator,
                       "--spp", str(args.spp), "--threads", str(n)]
                proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                      text=True)
                with open("%s.rep%d.log" % (out, rep), "w") as f:
                    f.write(" ".join(cmd) + "\n" + proc.stdout)
                if proc.returncode != 0:
                    sys.exit("failed: %s\n%s" % (" ".join(cmd), proc.stdout[-2000:]))
                if rep == 0:
                    commands.append(" ".join(cmd))
                times[n].append(float(re.search(r"render time\s+([0-9.]+) s",
                                                proc.stdout).group(1)))
                rays[n] = int(re.search(r"rays\s+camera .* total ([0-9,]+)",
                                        proc.stdout).group(1).replace(",", ""))
        base = statistics.median(times[1])
        for n in counts:
            t = statistics.median(times[n])
            print("| %s | %d | %.3f | %s | %.3g | %.2f | %.0f%% |" % (
                os.path.basename(scene), n, t, ", ".join("%.3f" % x for x in times[n]),
                rays[n] / t, base / t, 100.0 * base / t / n), flush=True)
    with open(os.path.join(args.out, "commands.txt"), "w") as f:
        f.write("\n".join(commands) + "\n")


if __name__ == "__main__":
    main()
