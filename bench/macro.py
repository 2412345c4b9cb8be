#!/usr/bin/python3
"""Macro benchmark: renders a fixed set of scenes with `prism render` and prints a Markdown
table of load + BVH build time, render time, rays per second, peak resident memory and the
error against a high-spp reference of the same scene with the same integrator.

    /usr/bin/python3 bench/macro.py --generated DIR [--out DIR] [--spp 8] [--ref-spp 128]
                                    [--integrator whitted] [--threads N]

DIR holds the generated scenes (bench/make_bench_scenes.py writes them: sphere_field.gltf,
terrain.glb); bench/run_all.sh makes them. Needs /usr/bin/time (GNU time, Debian's `time`
package) for the peak RSS. Prism is $PRISM, else build-bench/apps/prism, else
build/apps/prism.

Per scene: one reference render (--ref-spp), then the measured render (--spp) under
`/usr/bin/time -v`; `prism diff --metric all` gives RMSE and relMSE of the measured image
against the reference. The reference's own noise adds to the error: with 128 spp against 8,
the RMSE printed is about sqrt(1 + 8/128) = 1.03 times the error against the true image.
"""
import argparse
import os
import re
import subprocess
import sys

from benchlib import ROOT, find_prism
ASSIMP = "/usr/share/assimp/models/glTF2"




def scenes(generated):
    shipped = sorted(os.path.join(ROOT, "scenes", f)
                     for f in os.listdir(os.path.join(ROOT, "scenes")) if f.endswith(".gltf"))
    return shipped + [
        ASSIMP + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
        ASSIMP + "/BoxTextured-glTF/BoxTextured.gltf",
        os.path.join(generated, "sphere_field.gltf"),
        os.path.join(generated, "terrain.glb"),
    ]


def run(cmd, log):
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n" + proc.stdout)
    if proc.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (proc.returncode, " ".join(cmd), proc.stdout[-3000:]))
    return proc.stdout


def number(pattern, text, cast=float):
    m = re.search(pattern, text)
    if not m:
        sys.exit("macro.py: no match for %r in:\n%s" % (pattern, text[-2000:]))
    return cast(m.group(1).replace(",", ""))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--generated", required=True, help="directory of the generated scenes")
    parser.add_argument("--out", default="/tmp/prism-macro")
    parser.add_argument("--spp", type=int, default=8)
    parser.add_argument("--ref-spp", type=int, default=128)
    parser.add_argument("--integrator", default="whitted")
    parser.add_argument("--threads", type=int, default=os.cpu_count())
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    prism = find_prism("macro.py")
    commands = []
    rows = []
    for scene in scenes(args.generated):
        if not os.path.exists(scene):
            sys.exit("macro.py: missing scene " + scene)
        tag = os.path.splitext(os.path.basename(scene))[0]
        common = ["--integrator", args.integrator, "--threads", str(args.threads)]
        ref = os.path.join(args.out, tag + "_ref.exr")
        cmd = [prism, "render", scene, "-o", ref, "--spp", str(args.ref_spp), "--quiet"] + common
        run(cmd, ref + ".log")
        commands.append(" ".join(cmd))
        image = os.path.join(args.out, tag + ".exr")
        cmd = ["/usr/bin/time", "-v", prism, "render", scene, "-o", image, "--spp",
               str(args.spp), "--verbose"] + common
        text = run(cmd, image + ".log")
        commands.append(" ".join(cmd))
        # The --verbose line (stderr): "... N triangles (...), M spheres (...), ..., WxH, ...
        # loaded and built in X s".
        triangles = number(r"([0-9]+) triangles", text, int)
        spheres = number(r"([0-9]+) spheres", text, int)
        resolution = re.search(r"camera '[^']*', ([0-9]+x[0-9]+)", text).group(1)
        load = number(r"loaded and built in ([0-9.]+) s", text)
        render = number(r"render time\s+([0-9.]+) s", text)
        total = number(r"total ([0-9.]+) s\)", text)
        rays = number(r"rays\s+camera .* total ([0-9,]+)", text, int)
        rate = number(r"rays/second\s+([0-9.e+]+)", text)
        rss_kb = number(r"Maximum resident set size \(kbytes\): ([0-9]+)", text, int)
        diff = subprocess.run([prism, "diff", image, ref, "--metric", "all"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True).stdout
        with open(image + ".diff", "w") as f:
            f.write(diff)
        m = re.search(r"^RGB\s+(\S+)\s+(\S+)", diff, re.M)
        rmse, relmse = (float(m.group(1)), float(m.group(2))) if m else (float("nan"),) * 2
        rows.append((tag + os.path.splitext(scene)[1], triangles, spheres, resolution, load,
                     render, total, rays, rate, rss_kb / 1024.0, rmse, relmse))
        print("%-22s load %.3f s render %.3f s rays/s %.3g RSS %.0f MB RMSE %.4g" % (
            rows[-1][0], load, render, rate, rss_kb / 1024.0, rmse), file=sys.stderr, flush=True)

    print("Integrator `%s`, %d spp, %d threads; reference %d spp, same integrator and "
          "resolution." % (args.integrator, args.spp, args.threads, args.ref_spp))
    print()
    print("| scene | triangles | spheres | resolution | load + build s | render s | total s | "
          "rays | rays/s | peak RSS MB | RMSE vs ref | relMSE vs ref |")
    print("| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in rows:
        print("| %s | %d | %d | %s | %.3f | %.3f | %.3f | %d | %.3g | %.0f | %.4g | %.4g |" % r)
    with open(os.path.join(args.out, "commands.txt"), "w") as f:
        f.write("\n".join(commands) + "\n")


if __name__ == "__main__":
    main()
