#!/usr/bin/env python3
"""Writes a many-lights test scene: a floor with a grid of boxes under N point or spot
lights, for measuring what each light costs (docs/benchmarks.md, "Many lights").

    python3 bench/make_light_scene.py --lights N -o OUT.gltf [--kind point|spot] [--range R]

  --lights N  lights on a jittered grid 3 m above the 12 m x 12 m floor. Their intensities
              add up to the same total whatever N, so images of any N look alike. N = 0
              writes one light of intensity 0 (the scene still has a light, so no default
              light is added): the cost of the camera rays and shading without any light.
  --kind      point (default): unlimited range, every light reaches every hit the normal
              faces; the cost per light then measures the shadow rays themselves.
              spot: each points straight down with a 0.6 rad outer cone, so it lights a
              disc about 4 m across and most hits are outside most cones.
  --range R   glTF's range (m) on every light; 0 (default) is unlimited.

Only Python's standard library; deterministic (fixed seed). The glTF helpers come from
scenes/make_scenes.py.
"""
import argparse
import math
import os
import random
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "scenes"))
from make_scenes import Builder, direction_to_quaternion  # noqa: E402

HALF = 6.0  # the floor spans [-HALF, HALF] in x and z
TOTAL_INTENSITY = 120.0  # candela, shared by the lights


def box(b, name, centre, size, material):
    """An axis-aligned box of six quads, each facing outwards (counter-clockwise seen from
    outside)."""
    cx, cy, cz = centre
    h = size / 2.0
    s = size
    faces = [([cx - h, cy - h, cz + h], [s, 0, 0], [0, s, 0]),    # +z
             ([cx + h, cy - h, cz - h], [-s, 0, 0], [0, s, 0]),   # -z
             ([cx + h, cy - h, cz + h], [0, 0, -s], [0, s, 0]),   # +x
             ([cx - h, cy - h, cz - h], [0, 0, s], [0, s, 0]),    # -x
             ([cx - h, cy + h, cz + h], [s, 0, 0], [0, 0, -s])]   # +y (the bottom is unseen)
    for i, (corner, u, v) in enumerate(faces):
        b.quad("%s face %d" % (name, i), corner, u, v, material)


def light_scene(path, count, kind, light_range):
    b = Builder()
    floor = b.material("floor", (0.7, 0.7, 0.7), 0.0, 0.8)
    boxes = b.material("boxes", (0.6, 0.3, 0.2), 0.0, 0.5)
    b.quad("floor", [-HALF, 0, HALF], [2 * HALF, 0, 0], [0, 0, -2 * HALF], floor)
    for i in range(3):
        for j in range(3):
            box(b, "box %d" % (3 * i + j), ((i - 1) * 3.5, 0.6, (j - 1) * 3.5), 1.2, boxes)
    rng = random.Random(14)
    lights = max(count, 1)
    side = int(math.ceil(math.sqrt(lights)))
    down = direction_to_quaternion((0.0, -1.0, 0.0))
    for k in range(lights):
        i, j = k % side, k // side
        x = (i + 0.5) / side * 2 * HALF - HALF + rng.uniform(-0.3, 0.3)
        z = (j + 0.5) / side * 2 * HALF - HALF + rng.uniform(-0.3, 0.3)
        light = {"type": kind, "color": [1.0, 0.95, 0.9],
                 "intensity": TOTAL_INTENSITY / lights if count > 0 else 0.0}
        if light_range > 0:
            light["range"] = light_range
        if kind == "spot":
            light["spot"] = {"innerConeAngle": 0.4, "outerConeAngle": 0.6}
        b.light("light %d" % k, light, translation=[x, 3.0, z],
                rotation=down if kind == "spot" else None)
    b.camera("main", (0.0, 7.0, 9.0), (0.0, 0.0, 0.5), 0.9, 4.0 / 3.0)
    b.write(os.path.abspath(path))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--lights", type=int, required=True, help="number of lights (0: one dark light)")
    parser.add_argument("-o", "--output", required=True, help="the .gltf to write")
    parser.add_argument("--kind", choices=["point", "spot"], default="point")
    parser.add_argument("--range", type=float, default=0.0, help="glTF light range in m; 0 = unlimited")
    args = parser.parse_args()
    if args.lights < 0:
        parser.error("--lights must be 0 or more")
    if args.range < 0:
        parser.error("--range must be 0 or more")
    light_scene(args.output, args.lights, args.kind, args.range)


if __name__ == "__main__":
    main()
