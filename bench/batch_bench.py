#!/usr/bin/python3
"""Batch benchmark: `prism batch` (one process, each scene loaded once) against the same
renders as one `prism render` process each, timed as whole processes, interleaved
(batch, serial, batch, serial, ...) after warm-up rounds, medians quoted.

    /usr/bin/python3 bench/batch_bench.py PRISM OUT_DIR [--reps 3] [--large-reps 3]
        [--warmup 1] [--old-prism OLD_PRISM] [--skip-small] [--skip-large]

    e.g. /usr/bin/python3 bench/batch_bench.py build/apps/prism /tmp/prism-batch-bench

PRISM is the binary measured; OUT_DIR receives the job files, the images, every run's
report and log, commands.txt (every command measured, exactly) and results.md (the
tables this prints). Needs Debian's assimp-testmodels (the small jobs' assets) and the
repository's scenes/ (the large jobs). On a 2-core machine at load average 9 to 11 it took
14 minutes with --warmup 0 (docs/batch-benchmarks.md); the default --warmup 1 adds a round
to each part (about 19 minutes there).

1. Small jobs: 24 glTF assets of assimp-testmodels that `prism render` renders without
   error (each candidate is checked with a 32x24 render first; the first 24 that pass, in
   a fixed order, are used), every camera of each ("camera": "all"; a file without one has
   the default camera), integrators shadow and whitted, --brdf gltf and lecture, 320x240,
   4 spp: 100 renders. (a) `PRISM batch small.json --force --quiet`, (b) the same 100
   renders as 100 `PRISM render` processes one after the other (a Python loop; no
   --quiet, to read each one's `render time` line). With --old-prism, (c) the same 100
   processes of another binary (e.g. an older commit's), interleaved with (a) and (b),
   without the options it does not have (9e464b0: --brdf, so it renders its one model).
   Printed: median wall of each, throughput ratio (b)/(a), the per-job overhead of the
   batch = (batch wall - sum over jobs of the report's load + build + render + write) /
   jobs, and whether scenes_loaded equals the number of distinct scene files.
2. Large jobs: scenes/whitted.gltf and scenes/spheres.gltf, whitted, 640x480, 48 to 96 spp
   (10 renders of 2 s or more each). Printed: batch wall / sum of the render processes'
   walls, batch wall / sum of their `render time` lines, and the batch's summed
   render_seconds / the processes' summed render times.
3. Where the time goes: per job in the batch (the report's load, build, render, write and
   the rest of the wall), per `prism render` process (its own `render time`, `load +
   build` and `total` lines, and the rest of the process's wall: start-up and exit), plus
   `ldd PRISM | wc -l` and the median wall of `PRISM --help`.

Walls are measured here with time.perf_counter around each process (the serial loop: around
the whole loop); CPU seconds come from os.wait4's rusage.
"""
import argparse
import functools
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

from benchlib import ROOT

ASSIMP = "/usr/share/assimp/models/glTF2"
# Candidates in the order tried; the first N that render are used.
CANDIDATES = [
    "2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
    "BoxBadNormals-glTF-Binary/BoxBadNormals.glb",
    "BoxTexcoords-glTF/boxTexcoords.gltf",
    "BoxTextured-glTF/BoxTextured.gltf",
    "BoxTextured-glTF-Binary/BoxTextured.glb",
    "BoxTextured-glTF-Embedded/BoxTextured.gltf",
    "BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf",
    "ClearCoat-glTF/ClearCoatTest.gltf",
    "cameras/Cameras.gltf",
    "draco/2CylinderEngine.gltf",
    "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
    "issue_3269/texcoord_crash.gltf",
    "simple_skin/simple_skin.gltf",
    "textureTransform/TextureTransformTest.gltf",
] + ["glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_%02d.gltf" % i
     for i in range(16)]
INTEGRATORS = ["shadow", "whitted"]
BRDFS = ["gltf", "lecture"]
LARGE_SCENES = ["scenes/whitted.gltf", "scenes/spheres.gltf"]
# Every large job is to render for at least 2 s: 32 to 64 spp did at first, and fell to 1.6 s
# as the renderer got faster.
LARGE_SPP = [48, 56, 64, 80, 96]


def timed(cmd, log=None):
    """Runs cmd; returns (wall s, user + sys s, output). Exits on failure."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    if log:
        with open(log, "a") as f:
            f.write("$ " + " ".join(cmd) + "\n" + out)
    if proc.returncode != 0:
        sys.exit("batch_bench.py: failed (%d): %s\n%s" % (proc.returncode, " ".join(cmd),
                                                          out[-3000:]))
    return wall, usage.ru_utime + usage.ru_stime, out


def number(pattern, text):
    m = re.search(pattern, text)
    if not m:
        sys.exit("batch_bench.py: no match for %r in:\n%s" % (pattern, text[-2000:]))
    return float(m.group(1).replace(",", ""))


def camera_count(prism, scene):
    out = subprocess.run([prism, "info", scene], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True).stdout
    m = re.search(r"^cameras: ([0-9]+)", out, re.M)
    return int(m.group(1)) if m else 0


def pick_assets(prism, out_dir, count):
    picked = []
    for rel in CANDIDATES:
        path = os.path.join(ASSIMP, rel)
        if not os.path.exists(path):
            continue
        proc = subprocess.run([prism, "render", path, "-o", os.path.join(out_dir, "probe.exr"),
                               "--res", "32x24", "--quiet"], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True)
        if proc.returncode == 0:
            picked.append(path)
        else:
            print("skipped %s: %s" % (rel, proc.stdout.strip().splitlines()[-1]),
                  file=sys.stderr)
        if len(picked) == count:
            break
    return picked


def tag_of(path):
    parts = path.split(os.sep)
    return (parts[-2] + "-" + os.path.splitext(parts[-1])[0]).replace(" ", "_")


def small_jobs(prism, out_dir, assets):
    """The job file and the equivalent `prism render` commands (same order as the batch)."""
    jobs, serial = [], []
    for scene in assets:
        cams = camera_count(prism, scene)
        for brdf in BRDFS:
            name = "%s-%s" % (tag_of(scene), brdf)
            jobs.append({"name": name, "scene": scene, "camera": "all",
                         "integrator": INTEGRATORS, "brdf": brdf,
                         "output": "batch/{job}_{camera}_{integrator}.exr"})
            for cam in (range(cams) if cams else [None]):
                for integ in INTEGRATORS:
                    out = os.path.join(out_dir, "serial", "%s_%s_%s.exr" % (
                        name, "default" if cam is None else cam, integ))
                    cmd = [prism, "render", scene, "-o", out, "--res", "320x240", "--spp", "4",
                           "--integrator", integ, "--brdf", brdf]
                    if cam is not None:
                        cmd += ["--camera", str(cam)]
                    serial.append(cmd)
    doc = {"version": 1, "defaults": {"resolution": "320x240", "spp": 4}, "jobs": jobs}
    return doc, serial


def large_jobs(prism, out_dir):
    jobs, serial = [], []
    for rel in LARGE_SCENES:
        scene = os.path.join(ROOT, rel)
        for spp in LARGE_SPP:
            name = "%s-%dspp" % (os.path.splitext(os.path.basename(rel))[0], spp)
            jobs.append({"name": name, "scene": scene, "spp": spp,
                         "output": "batch/%s.exr" % name})
            serial.append([prism, "render", scene, "-o",
                           os.path.join(out_dir, "serial", name + ".exr"), "--res", "640x480",
                           "--spp", str(spp), "--integrator", "whitted"])
    doc = {"version": 1, "defaults": {"resolution": "640x480", "integrator": "whitted"},
           "jobs": jobs}
    return doc, serial


def run_serial(cmds, log):
    """The loop of processes: (loop wall, per-process walls, render times, prism totals,
    load + build, cpu)."""
    walls, renders, totals, loads, cpu = [], [], [], [], 0.0
    start = time.perf_counter()
    for cmd in cmds:
        wall, c, out = timed(cmd, log)
        walls.append(wall)
        cpu += c
        renders.append(number(r"render time\s+([0-9.]+) s", out))
        loads.append(number(r"load \+ build ([0-9.]+) s", out))
        totals.append(number(r"total ([0-9.]+) s\)", out))
    return dict(wall=time.perf_counter() - start, walls=walls, renders=renders, totals=totals,
                loads=loads, cpu=cpu)


def run_batch(prism, job_file, report_path, keep, log):
    wall, cpu, _ = timed([prism, "batch", job_file, "--force", "--quiet"], log)
    with open(report_path) as f:
        report = json.load(f)
    shutil.copy(report_path, keep)
    jobs = report["jobs"]
    sums = {k: sum(j[k] for j in jobs) for k in
            ("load_seconds", "build_seconds", "render_seconds", "write_seconds")}
    statuses = {j["status"] for j in jobs}
    if statuses != {"rendered"}:
        sys.exit("batch_bench.py: not every job rendered: %s" % report["counts"])
    return dict(wall=wall, cpu=cpu, report_wall=report["wall_seconds"], jobs=len(jobs),
                scenes_loaded=report["scenes_loaded"], sums=sums,
                renders=[j["render_seconds"] for j in jobs])


def med(xs):
    return statistics.median(xs)


def runs(xs):
    return ", ".join("%.3f" % x for x in xs)


@functools.lru_cache(maxsize=None)
def render_help(prism):
    return subprocess.run([prism, "render", "--help"], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True).stdout


def without_unknown_options(prism, command):
    """`command` without the options (and their values) that `prism render --help` of an
    older binary does not list (9e464b0 has no --brdf: it renders its one model)."""
    help_text = render_help(prism)
    out, i = [], 0
    while i < len(command):
        arg = command[i]
        if arg.startswith("--") and not re.search(r"(^|[\s,])%s\b" % re.escape(arg), help_text):
            i += 2  # every option the small jobs pass takes one value
            continue
        out.append(arg)
        i += 1
    return out


def measure(label, prism, doc, serial, out_dir, reps, warmup, old_prism, emit, commands):
    os.makedirs(os.path.join(out_dir, "serial"), exist_ok=True)
    os.makedirs(os.path.join(out_dir, "batch"), exist_ok=True)
    job_file = os.path.join(out_dir, label + ".json")
    with open(job_file, "w") as f:
        json.dump(doc, f, indent=2)
    report_path = os.path.join(out_dir, "batch", "batch-report.json")
    log = os.path.join(out_dir, label + ".log")
    commands.append("%s batch %s --force --quiet" % (prism, job_file))
    commands += [" ".join(c) for c in serial]
    old = [without_unknown_options(old_prism, [old_prism] + c[1:]) for c in serial] \
        if old_prism else None
    if old:
        commands += [" ".join(c) for c in old]
    distinct = len({j["scene"] for j in doc["jobs"]})
    dry = subprocess.run([prism, "batch", job_file, "--dry-run"], stdout=subprocess.PIPE,
                         text=True).stdout
    planned = int(number(r"([0-9]+) renders", dry))
    if planned != len(serial):
        sys.exit("batch_bench.py: the batch plans %d renders, the loop has %d" % (
            planned, len(serial)))
    b, s, o = [], [], []
    for rep in range(warmup + reps):
        counted = rep >= warmup
        with open(os.path.join(out_dir, "load.txt"), "a") as f:
            f.write("%s %s rep %d: %s" % (time.strftime("%H:%M:%S"), label, rep,
                                          open("/proc/loadavg").read()))
        r = run_batch(prism, job_file, report_path,
                      os.path.join(out_dir, "report-%s-%d.json" % (label, rep)), log)
        if counted:
            b.append(r)
        r = run_serial(serial, log)
        if counted:
            s.append(r)
        if old:
            r = run_serial(old, log)
            if counted:
                o.append(r)
        print("%s rep %d%s: batch %.3f s, serial %.3f s%s" % (
            label, rep, "" if counted else " (warm-up)", b[-1]["wall"] if counted else 0,
            s[-1]["wall"] if counted else 0, (", old %.3f s" % o[-1]["wall"]) if o and counted
            else ""), file=sys.stderr, flush=True)
    jobs = b[0]["jobs"]
    bw = med([x["wall"] for x in b])
    sw = med([x["wall"] for x in s])
    pair = [y["wall"] / x["wall"] for x, y in zip(b, s)]
    own = [sum(x["sums"].values()) for x in b]
    overhead = [(x["wall"] - sum(x["sums"].values())) / jobs for x in b]
    emit("### %s: %d renders, %d distinct scene files, %d counted rounds after %d warm-up"
         % (label, jobs, distinct, reps, warmup))
    emit("")
    emit("| figure | median | runs |")
    emit("| --- | ---: | --- |")
    emit("| (a) `prism batch` wall s | %.3f | %s |" % (bw, runs([x["wall"] for x in b])))
    emit("| (a) its report's wall_seconds | %.3f | %s |" % (
        med([x["report_wall"] for x in b]), runs([x["report_wall"] for x in b])))
    emit("| (a) CPU s (user + sys) | %.3f | %s |" % (
        med([x["cpu"] for x in b]), runs([x["cpu"] for x in b])))
    emit("| (b) %d `prism render` processes, loop wall s | %.3f | %s |" % (
        len(serial), sw, runs([x["wall"] for x in s])))
    emit("| (b) CPU s (user + sys) | %.3f | %s |" % (
        med([x["cpu"] for x in s]), runs([x["cpu"] for x in s])))
    emit("| **throughput (b)/(a)**, pair by pair | **%.2f** | %s |" % (med(pair), runs(pair)))
    if o:
        ow = med([x["wall"] for x in o])
        opair = [y["wall"] / x["wall"] for x, y in zip(b, o)]
        emit("| (c) old binary's %d processes, loop wall s | %.3f | %s |" % (
            len(serial), ow, runs([x["wall"] for x in o])))
        emit("| **throughput (c)/(a)**, pair by pair | **%.2f** | %s |" % (med(opair),
                                                                        runs(opair)))
    emit("| (a) sum of jobs' load + build + render + write s | %.3f | %s |" % (
        med(own), runs(own)))
    emit("| **(a) per-job overhead ms** = (wall - that sum) / jobs | **%.1f** | %s |" % (
        1000 * med(overhead), ", ".join("%.1f" % (1000 * x) for x in overhead)))
    inproc = [(x["report_wall"] - sum(x["sums"].values())) / jobs for x in b]
    emit("| (a) the same from the report's wall_seconds (in-process, no start-up) ms | %.1f "
         "| %s |" % (1000 * med(inproc), ", ".join("%.1f" % (1000 * x) for x in inproc)))
    emit("| (a) process wall - report's wall_seconds (start-up, exit) s | %.3f | %s |" % (
        med([x["wall"] - x["report_wall"] for x in b]),
        runs([x["wall"] - x["report_wall"] for x in b])))
    # A job's files are written while the next job renders, so the sum above counts the
    # writes twice over; leaving them out gives what the batch spends beside the renders.
    lbr = [(x["wall"] - x["sums"]["load_seconds"] - x["sums"]["build_seconds"] -
            x["sums"]["render_seconds"]) / jobs for x in b]
    emit("| (a) (wall - load - build - render) / jobs, writes counted as overlapped, ms | %.1f "
         "| %s |" % (1000 * med(lbr), ", ".join("%.1f" % (1000 * x) for x in lbr)))
    lbr = [(x["report_wall"] - x["sums"]["load_seconds"] - x["sums"]["build_seconds"] -
            x["sums"]["render_seconds"]) / jobs for x in b]
    emit("| (a) the same from the report's wall_seconds, ms | %.1f | %s |" % (
        1000 * med(lbr), ", ".join("%.1f" % (1000 * x) for x in lbr)))
    loaded = [x["scenes_loaded"] for x in b]
    emit("| (a) scenes_loaded (distinct scene files: %d) | %d | %s — %s |" % (
        distinct, med(loaded), ", ".join(map(str, loaded)),
        "each loaded once" if all(n == distinct for n in loaded) else "NOT once each"))
    emit("")
    # Where the time goes, per job: medians over the rounds of the per-job means.
    emit("Per job, mean over the %d jobs (median over rounds), ms:" % jobs)
    emit("")
    emit("| where | `prism batch` | one `prism render` process |")
    emit("| --- | ---: | ---: |")
    per = lambda k: 1000 * med([x["sums"][k] / jobs for x in b])
    sload = 1000 * med([sum(x["loads"]) / len(serial) for x in s])
    srender = 1000 * med([sum(x["renders"]) / len(serial) for x in s])
    stotal = 1000 * med([sum(x["totals"]) / len(serial) for x in s])
    swall = 1000 * med([sum(x["walls"]) / len(serial) for x in s])
    emit("| load | %.1f | %.1f (load + build) |" % (per("load_seconds"), sload))
    emit("| build | %.1f | (above) |" % per("build_seconds"))
    emit("| render | %.1f | %.1f |" % (per("render_seconds"), srender))
    emit("| write | %.1f | %.1f (rest of its own `total`: write, set-up) |" % (
        per("write_seconds"), stotal - sload - srender))
    emit("| rest of the wall | %.1f | %.1f (process wall - its `total`: start-up, exit) |" % (
        1000 * med(overhead), swall - stotal))
    emit("| whole | %.1f | %.1f (process wall) |" % (1000 * bw / jobs, swall))
    emit("")
    return b, s


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("prism", help="the prism binary measured")
    parser.add_argument("out_dir", help="where job files, images, reports and logs go")
    parser.add_argument("--reps", type=int, default=3, help="counted rounds, small jobs")
    parser.add_argument("--large-reps", type=int, default=3, help="counted rounds, large jobs")
    parser.add_argument("--warmup", type=int, default=1, help="uncounted rounds first, each part")
    parser.add_argument("--assets", type=int, default=24, help="small jobs' asset count")
    parser.add_argument("--old-prism", help="another binary whose processes (c) are timed too")
    parser.add_argument("--skip-small", action="store_true")
    parser.add_argument("--skip-large", action="store_true")
    args = parser.parse_args()
    prism = os.path.abspath(args.prism)
    out = os.path.abspath(args.out_dir)
    os.makedirs(out, exist_ok=True)
    lines, commands = [], []

    def emit(line):
        print(line, flush=True)
        lines.append(line)

    emit("Machine: %d cores; load average at start %s" % (
        os.cpu_count(), open("/proc/loadavg").read().split(" ", 3)[:3]))
    emit("")
    if not args.skip_small:
        d = os.path.join(out, "small")
        os.makedirs(d, exist_ok=True)
        assets = pick_assets(prism, d, args.assets)
        doc, serial = small_jobs(prism, d, assets)
        emit("Small jobs: %d assets: %s" % (len(assets), ", ".join(
            os.path.relpath(a, ASSIMP) for a in assets)))
        emit("")
        measure("small", prism, doc, serial, d, args.reps, args.warmup, args.old_prism, emit,
                commands)
    if not args.skip_large:
        d = os.path.join(out, "large")
        doc, serial = large_jobs(prism, d)
        b, s = measure("large", prism, doc, serial, d, args.large_reps, args.warmup, None,
                       emit, commands)
        bw = [x["wall"] for x in b]
        ratios = {
            "batch wall / sum of the render processes' walls":
                [x["wall"] / sum(y["walls"]) for x, y in zip(b, s)],
            "batch wall / sum of the processes' `render time` lines":
                [x["wall"] / sum(y["renders"]) for x, y in zip(b, s)],
            "batch's summed render_seconds / the processes' summed `render time`":
                [x["sums"]["render_seconds"] / sum(y["renders"]) for x, y in zip(b, s)],
        }
        emit("Large jobs, round by round (goal: batch wall within 2 %% of the summed render "
             "times); shortest job's render_seconds in the batch: %.3f s" % min(
                 min(x["renders"]) for x in b))
        emit("")
        emit("| ratio | median | runs |")
        emit("| --- | ---: | --- |")
        for k, v in ratios.items():
            emit("| %s | **%.4f** | %s |" % (k, med(v), ", ".join("%.4f" % r for r in v)))
        emit("")
    # Start-up of one process.
    ldd = subprocess.run(["ldd", prism], stdout=subprocess.PIPE, text=True).stdout
    helps = [timed([prism, "--help"])[0] for _ in range(11)]
    commands += ["ldd %s | wc -l" % prism, "%s --help  (11 times)" % prism]
    emit("Start-up: `ldd prism | wc -l` = %d; `prism --help` wall, median of 11: %.1f ms "
         "(min %.1f, max %.1f)" % (len(ldd.strip().splitlines()), 1000 * med(helps),
                                   1000 * min(helps), 1000 * max(helps)))
    emit("Load average at the end: %s" % open("/proc/loadavg").read().split(" ", 3)[:3])
    with open(os.path.join(out, "commands.txt"), "w") as f:
        f.write("\n".join(commands) + "\n")
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
