#!/usr/bin/python3
"""Uniform against adaptive sampling: the render time and the rays needed to reach a given
error against a high-spp reference, on the compare scenes.

    /usr/bin/python3 bench/adaptive.py [--out DIR] [--res WxH|default] [--reference-spp 512]
        [--threads N] [--scenes spheres,engine] [--keep-reference] [--extra "ARGS"]

For each scene: a uniform reference at --reference-spp, uniform renders at 4..128 spp and
adaptive renders (--target-error 0.2 .. 0.01, --spp 1024 as the cap), each measured with
`prism diff --metric all` (RMSE and relMSE, colour channels). For each goal error, the time
and the rays each method needs are read off its error curve (log-log interpolation between
the two renders that bracket the goal); the goals are the errors uniform sampling reaches
at 16, 32, 64 and 128 spp. Prints Markdown tables.

The goal is about rendering, so the main time is the **render's CPU time**: each `prism
render` process's CPU time (user + system, which load from other jobs disturbs far less
than wall time) minus that of the same command at 1 x 1 pixel and 1 spp (process start,
scene load, BVH build, writing the image: the same for both methods; the median of three
runs per scene). The whole process's CPU time and Prism's own `render time` (wall, the
rendering alone) are second and third columns. Camera and total rays are exact. The default
resolution, 640 x 360, keeps startup, load and build a small part of every render.
"""
import argparse
import math
import os
import re
import resource
import subprocess
import sys

from benchlib import ROOT, find_prism

ENGINE = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"
SCENES = {
    "spheres": (os.path.join(ROOT, "scenes/spheres.gltf"), "whitted"),
    "engine": (ENGINE, "shadow"),
}
UNIFORM_SPP = [4, 8, 16, 32, 64, 128]
TARGETS = [0.2, 0.1, 0.05, 0.02, 0.01]
ADAPTIVE_MAX_SPP = 1024
GOAL_SPP = [16, 32, 64, 128]  # goals: the errors uniform sampling reaches at these spp


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(cmd):
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), proc.stdout[-2000:]))
    return proc.stdout


def render(prism, scene, integrator, out, args, extra, res=None, startup_cpu=0.0):
    res = res or args.res
    cmd = [prism, "render", scene, "-o", out, "--integrator", integrator,
           "--threads", str(args.threads)] + (["--res", res] if res != "default" else [])
    cmd += args.extra.split() + extra
    before = cpu_seconds()
    text = run(cmd)
    cpu = cpu_seconds() - before
    rays = re.search(r"rays\s+camera ([0-9,]+), .* total ([0-9,]+)", text)
    size = re.search(r", (\d+)x(\d+), ", text)
    return {
        "command": " ".join(cmd),
        "pixels": int(size.group(1)) * int(size.group(2)),
        "seconds": float(re.search(r"render time\s+([0-9.]+) s", text).group(1)),
        "cpu": cpu,
        "render_cpu": cpu - startup_cpu,
        "camera": int(rays.group(1).replace(",", "")),
        "rays": int(rays.group(2).replace(",", "")),
    }


def startup_cpu_seconds(prism, scene, integrator, out, args):
    """Process start, load, BVH build and writing: the CPU time of a 1 x 1, 1-spp render."""
    runs = sorted(render(prism, scene, integrator, out, args, ["--spp", "1"], res="1x1")["cpu"]
                  for _ in range(3))
    return runs[1]


def measure(prism, image, reference):
    text = run([prism, "diff", image, reference, "--metric", "all"])
    row = re.search(r"^RGB\s+(\S+)\s+(\S+)", text, re.M)
    return float(row.group(1)), float(row.group(2))


def cost_to_reach(points, key, metric, goal):
    """Log-log interpolation of `key` (seconds or rays) at which `metric` reaches `goal`."""
    pts = sorted(points, key=lambda p: p[key])
    for a, b in zip(pts, pts[1:]):
        if a[metric] >= goal >= b[metric] and a[metric] > b[metric]:
            t = (math.log(a[metric]) - math.log(goal)) / (math.log(a[metric]) - math.log(b[metric]))
            return math.exp(math.log(a[key]) + t * (math.log(b[key]) - math.log(a[key])))
    for p in pts:
        if p[metric] <= goal:
            return p[key]  # the cheapest render is already below the goal
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default="/tmp/prism-adaptive")
    parser.add_argument("--res", default="640x360",
                        help="WxH, or 'default' for each scene's own (spheres 853x480, engine "
                        "480x480)")
    parser.add_argument("--reference-spp", type=int, default=512)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--scenes", default="spheres,engine")
    parser.add_argument("--extra", default="", help="more `prism render` options for every render")
    parser.add_argument("--keep-reference", action="store_true",
                        help="reuse OUT/<scene>-reference.exr when it exists")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    prism = find_prism("adaptive.py")
    for name in args.scenes.split(","):
        scene, integrator = SCENES[name]
        ref = os.path.join(args.out, "%s-reference.exr" % name)
        print("\n### %s, %s, %s\n" % (os.path.basename(scene), integrator, args.res))
        startup = startup_cpu_seconds(prism, scene, integrator,
                                      os.path.join(args.out, "%s-startup.exr" % name), args)
        print("Startup, load, BVH build and writing (1 x 1, 1 spp): %.3f s CPU\n" % startup)
        if args.keep_reference and os.path.exists(ref):
            print("Reference: %s, kept from an earlier run\n" % ref)
        else:
            r = render(prism, scene, integrator, ref, args, ["--spp", str(args.reference_spp)])
            print("Reference: `%s` (%.1f s)\n" % (r["command"], r["seconds"]))
        points = {"uniform": [], "adaptive": []}
        for spp in UNIFORM_SPP:
            out = os.path.join(args.out, "%s-uniform-%d.exr" % (name, spp))
            p = render(prism, scene, integrator, out, args, ["--spp", str(spp)],
                       startup_cpu=startup)
            p["label"] = "%d spp" % spp
            p["rmse"], p["relmse"] = measure(prism, out, ref)
            points["uniform"].append(p)
        for target in TARGETS:
            out = os.path.join(args.out, "%s-adaptive-%g.exr" % (name, target))
            p = render(prism, scene, integrator, out, args,
                       ["--spp", str(ADAPTIVE_MAX_SPP), "--target-error", str(target)],
                       startup_cpu=startup)
            p["label"] = "target %g" % target
            p["rmse"], p["relmse"] = measure(prism, out, ref)
            points["adaptive"].append(p)
        print("| method | setting | mean spp | render CPU s | process CPU s | render wall s | "
              "camera rays | all rays | RMSE | relMSE |")
        print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for method, pts in points.items():
            for p in pts:
                print("| %s | %s | %.2f | %.3f | %.3f | %.3f | %d | %d | %.5g | %.4g |" % (
                    method, p["label"], p["camera"] / p["pixels"], p["render_cpu"], p["cpu"],
                    p["seconds"], p["camera"], p["rays"], p["rmse"], p["relmse"]))
        print("\nCost to reach the error uniform sampling reaches at %s spp "
              "(adaptive / uniform):\n" % ", ".join(map(str, GOAL_SPP)))
        print("| goal | render CPU s uniform → adaptive | ratio | process CPU s | ratio | "
              "render wall s | ratio | all rays | ratio |")
        print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        fmt = lambda v, f: (f % v) if v is not None else "not reached"
        for metric in ("rmse", "relmse"):
            for spp in GOAL_SPP:
                goal = next(p[metric] for p in points["uniform"] if p["label"] == "%d spp" % spp)
                cells = []
                for key, f in (("render_cpu", "%.3f"), ("cpu", "%.3f"), ("seconds", "%.3f"),
                               ("rays", "%.0f")):
                    u = cost_to_reach(points["uniform"], key, metric, goal)
                    a = cost_to_reach(points["adaptive"], key, metric, goal)
                    cells.append("%s → %s | %s" % (fmt(u, f), fmt(a, f),
                                                   fmt(a / u if a and u else None, "**%.2f**"
                                                       if key == "render_cpu" else "%.2f")))
                print("| %s %.4g (uniform %d spp) | %s |" % (metric, goal, spp, " | ".join(cells)),
                      flush=True)
        with open(os.path.join(args.out, "%s-commands.txt" % name), "w") as f:
            for pts in points.values():
                f.write("\n".join(p["command"] for p in pts) + "\n")


if __name__ == "__main__":
    main()
