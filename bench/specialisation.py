#!/usr/bin/python3
"""What the integrators' specialisation on the scene's features saves (issue 5,
docs/info.md "What each feature flag skips"), timed in one run:

    /usr/bin/python3 bench/specialisation.py [--runs 5] [--res 640x480] [--spp 1]
                                            [--threads N] [--out DIR]

  - a diffuse-only scene with occluders (Debian's 2CylinderEngine.glb): `whitted` against
    `shadow`; whitted has no mirror or glass to trace, so it should cost the same (target
    <= 1.05x);
  - a scene where nothing can block a shadow ray (a flat 80,000-triangle floor under the
    sun, written to DIR/flat_floor.gltf, and the shipped scenes/furnace.gltf, one sphere
    lit from inside): `shadow` against `phong` (target <= 1.05x).

Each scene also runs with `--general-path` (the unspecialised code, same image) to show
what was saved. Every configuration of a scene runs once per round, the rounds interleaved
(so a load change on this shared machine hits all alike), and the median render time of
--runs rounds is kept. The ray counts come from the last round. Prism is $PRISM, else
build-bench/apps/prism, else build/apps/prism.
"""
import argparse
import base64
import json
import os
import re
import statistics
import struct
import subprocess
import sys

from benchlib import ROOT, find_prism

ENGINE = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"


def write_flat_floor(path, side=201):
    """A side x side vertex grid in the plane y = 0, one normal for every vertex, lit by a
    directional light from above and seen by a camera above it."""
    positions, normals, indices = bytearray(), bytearray(), bytearray()
    for j in range(side):
        for i in range(side):
            positions += struct.pack("<3f", -10.0 + 20.0 * i / (side - 1), 0.0,
                                     -10.0 + 20.0 * j / (side - 1))
            normals += struct.pack("<3f", 0.0, 1.0, 0.0)
    for j in range(side - 1):
        for i in range(side - 1):
            a = j * side + i
            indices += struct.pack("<6I", a, a + side, a + 1, a + 1, a + side, a + side + 1)
    blob = bytes(positions + normals + indices)
    n = side * side
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "intensity": 3.0}]}},
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * n},
                        {"buffer": 0, "byteOffset": 12 * n, "byteLength": 12 * n},
                        {"buffer": 0, "byteOffset": 24 * n, "byteLength": len(indices)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
                       "min": [-10.0, 0.0, -10.0], "max": [10.0, 0.0, 10.0]},
                      {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125, "count": len(indices) // 4,
                       "type": "SCALAR"}],
        "materials": [{"name": "grey", "pbrMetallicRoughness": {
            "baseColorFactor": [0.6, 0.6, 0.6, 1.0], "metallicFactor": 0.0,
            "roughnessFactor": 0.8}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": 0}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}],
        "nodes": [{"mesh": 0, "name": "floor"},
                  # 6 m up, 8 m back, looking down at 36.87 degrees.
                  {"camera": 0, "translation": [0.0, 6.0, 8.0],
                   "rotation": [-0.3162278, 0.0, 0.0, 0.9486833]},
                  # The sun, tilted from straight down.
                  {"extensions": {"KHR_lights_punctual": {"light": 0}},
                   "rotation": [-0.6532815, 0.2705981, 0.2705981, 0.6532815]}],
        "scenes": [{"nodes": [0, 1, 2]}],
        "scene": 0,
    }
    with open(path, "w") as f:
        json.dump(doc, f)


def render(prism, scene, integrator, general, args, image):
    cmd = [prism, "render", scene, "-o", image, "--integrator", integrator, "--res", args.res,
           "--spp", str(args.spp), "--threads", str(args.threads)]
    if general:
        cmd.append("--general-path")
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (proc.returncode, " ".join(cmd), proc.stderr[-2000:]))
    seconds = float(re.search(r"render time\s+([0-9.]+) s", proc.stdout).group(1))
    rays = re.search(r"rays\s+camera ([0-9,]+), shadow ([0-9,]+), reflection ([0-9,]+), "
                     r"refraction ([0-9,]+)", proc.stdout)
    counts = tuple(int(rays.group(k).replace(",", "")) for k in range(1, 5))
    return seconds, counts, " ".join(cmd)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--res", default="640x480")
    parser.add_argument("--spp", type=int, default=1)
    parser.add_argument("--threads", type=int, default=os.cpu_count())
    parser.add_argument("--out", default="/tmp/prism-specialisation")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    prism = find_prism("specialisation.py")
    floor = os.path.join(args.out, "flat_floor.gltf")
    write_flat_floor(floor)
    furnace = os.path.join(ROOT, "scenes", "furnace.gltf")
    # (scene, the integrator that should cost no more, the one it is measured against)
    pairs = [(ENGINE, "whitted", "shadow"), (floor, "shadow", "phong"),
             (furnace, "shadow", "phong")]
    configs = []
    for scene, slow, fast in pairs:
        if not os.path.exists(scene):
            sys.exit("specialisation.py: missing scene " + scene)
        configs += [(scene, slow, False), (scene, fast, False), (scene, slow, True)]
    times = {c: [] for c in configs}
    counts, commands = {}, {}
    for r in range(args.runs):
        for c in configs:
            scene, integrator, general = c
            image = os.path.join(args.out, "%s_%s%s.exr" % (
                os.path.splitext(os.path.basename(scene))[0], integrator,
                "_general" if general else ""))
            seconds, counts[c], commands[c] = render(prism, scene, integrator, general, args,
                                                     image)
            times[c].append(seconds)
        print("round %d/%d done" % (r + 1, args.runs), file=sys.stderr, flush=True)

    median = {c: statistics.median(t) for c, t in times.items()}
    print("%s, %d spp, %d threads, median of %d interleaved rounds." % (
        args.res, args.spp, args.threads, args.runs))
    print()
    print("| scene | integrator | code | render s (median) | camera | shadow | reflection | "
          "refraction |")
    print("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |")
    for c in configs:
        scene, integrator, general = c
        print("| %s | %s | %s | %.4f | %d | %d | %d | %d |" % (
            (os.path.basename(scene), integrator, "general" if general else "specialised",
             median[c]) + counts[c]))
    print()
    for scene, slow, fast in pairs:
        name = os.path.basename(scene)
        print("%s: %s / %s = %.3f (target <= 1.05); %s general / specialised = %.3f" % (
            name, slow, fast, median[(scene, slow, False)] / median[(scene, fast, False)], slow,
            median[(scene, slow, True)] / median[(scene, slow, False)]))
    with open(os.path.join(args.out, "commands.txt"), "w") as f:
        f.write("\n".join(commands[c] for c in configs) + "\n")


if __name__ == "__main__":
    main()
