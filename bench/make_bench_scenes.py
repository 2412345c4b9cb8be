#!/usr/bin/env python3
"""Writes the two generated scenes of the macro benchmark (bench/macro.py) to paths given on
the command line; they are too big to ship, so they are made where the run needs them:

    python3 bench/make_bench_scenes.py --spheres OUT.gltf [--sphere-count 4096]
                                       --mesh OUT.glb [--mesh-side 710]

  --spheres  a field of PRISM_sphere nodes (a square grid with jittered radii and a few
             materials, some mirrors and glass) on a floor, two lights, one camera. Every
             sphere node shares one small fallback mesh, so the file stays small.
  --mesh     a displaced grid (a smooth height field) of 2 * (side - 1)^2 triangles with
             vertex normals, written as binary glTF: side 710 gives 1,005,362 triangles.

Only Python's standard library; deterministic (fixed seed), so every run traces the same
scene. The glTF helpers come from scenes/make_scenes.py.
"""
import argparse
import array
import json
import math
import os
import random
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "scenes"))
from make_scenes import Builder, direction_to_quaternion, icosphere, normalised  # noqa: E402


def sphere_field(path, count):
    b = Builder()
    floor = b.material("floor", (0.7, 0.7, 0.7), 0.0, 0.9)
    palette = [b.material("red plastic", (0.8, 0.1, 0.08), 0.0, 0.35),
               b.material("blue matte", (0.15, 0.25, 0.7), 0.0, 1.0, specular=0.0),
               b.material("green plastic", (0.2, 0.7, 0.25), 0.0, 0.3),
               b.material("white matte", (0.8, 0.8, 0.8), 0.0, 1.0, specular=0.0),
               b.material("gold", (1.0, 0.77, 0.34), 1.0, 0.08),
               b.material("mirror", (0.9, 0.9, 0.9), 1.0, 0.0),
               b.material("glass", (1.0, 1.0, 1.0), 0.0, 0.0, transmission=1.0, ior=1.5)]
    # Mostly diffuse and plastic, one in ten mirrors or glass: enough secondary rays for the
    # whitted integrator to matter without every pixel being a deep reflection chain.
    weights = [0.3, 0.25, 0.2, 0.15, 0.04, 0.03, 0.03]
    side = int(math.ceil(math.sqrt(count)))
    extent = 1.0 * side
    b.quad("floor", [-extent, 0, extent], [2 * extent, 0, 0], [0, 0, -2 * extent], floor)
    verts, faces = icosphere(1)
    fallback = b.mesh("sphere fallback", verts, verts, faces, palette[0])
    b.use_extension("PRISM_sphere")
    rng = random.Random(4)
    placed = 0
    for i in range(side):
        for j in range(side):
            if placed == count:
                break
            r = 0.25 + 0.2 * rng.random()
            x = (i - 0.5 * (side - 1)) * 2.0 * extent / side + rng.uniform(-0.2, 0.2)
            z = (j - 0.5 * (side - 1)) * 2.0 * extent / side + rng.uniform(-0.2, 0.2)
            m = rng.choices(palette, weights)[0]
            b.node({"name": "sphere %d" % placed, "translation": [x, r, z], "scale": [r] * 3,
                    "mesh": fallback,
                    "extensions": {"PRISM_sphere": {"radius": 1.0, "material": m}}})
            placed += 1
    b.light("key", {"type": "point", "color": [1.0, 0.95, 0.88], "intensity": 40.0 * side},
            translation=[0.3 * extent, 0.8 * extent, 0.5 * extent])
    b.light("sky", {"type": "directional", "color": [0.75, 0.85, 1.0], "intensity": 0.8},
            rotation=direction_to_quaternion(normalised((-0.3, -1.0, -0.4))))
    b.camera("main", (0.0, 0.45 * extent, 1.25 * extent), (0.0, 0.0, 0.1 * extent), 0.9,
             16.0 / 9.0)
    b.write(os.path.abspath(path))


def height(x, z):
    """A smooth, non-periodic-looking terrain: a few sines of different wavelengths."""
    return (0.35 * math.sin(1.3 * x) * math.cos(1.1 * z) + 0.12 * math.sin(3.7 * x + 1.0) +
            0.1 * math.cos(4.3 * z - 0.5) + 0.04 * math.sin(9.1 * x + 7.3 * z))


def height_gradient(x, z):
    dx = (0.35 * 1.3 * math.cos(1.3 * x) * math.cos(1.1 * z) + 0.12 * 3.7 * math.cos(3.7 * x + 1.0)
          + 0.04 * 9.1 * math.cos(9.1 * x + 7.3 * z))
    dz = (-0.35 * 1.1 * math.sin(1.3 * x) * math.sin(1.1 * z) - 0.1 * 4.3 * math.sin(4.3 * z - 0.5)
          + 0.04 * 7.3 * math.cos(9.1 * x + 7.3 * z))
    return dx, dz


def dense_mesh(path, side):
    """side x side vertices over [-4, 4]^2, two triangles per cell, counter-clockwise seen
    from above (+Y)."""
    half = 4.0
    positions = array.array("f")
    normals = array.array("f")
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for j in range(side):
        z = -half + 2.0 * half * j / (side - 1)
        for i in range(side):
            x = -half + 2.0 * half * i / (side - 1)
            y = height(x, z)
            positions.extend((x, y, z))
            dx, dz = height_gradient(x, z)
            n = math.sqrt(dx * dx + 1.0 + dz * dz)
            normals.extend((-dx / n, 1.0 / n, -dz / n))
            for k, c in enumerate((x, y, z)):
                lo[k] = min(lo[k], c)
                hi[k] = max(hi[k], c)
    indices = array.array("I")
    for j in range(side - 1):
        row, nxt = j * side, (j + 1) * side
        for i in range(side - 1):
            a, b, c, d = row + i, row + i + 1, nxt + i + 1, nxt + i
            # z grows with j, so (a, d, c) and (a, c, b) wind counter-clockwise seen from +Y.
            indices.extend((a, d, c, a, c, b))
    if sys.byteorder != "little":
        for arr in (positions, normals, indices):
            arr.byteswap()
    blobs = [positions.tobytes(), normals.tobytes(), indices.tobytes()]
    views, offset = [], 0
    for blob, target in zip(blobs, (34962, 34962, 34963)):
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob),
                      "target": target})
        offset += len(blob)
    vertices = side * side
    gltf = {
        "asset": {"version": "2.0", "generator": "prism bench/make_bench_scenes.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"name": "terrain", "mesh": 0},
                  {"name": "key", "translation": [3.0, 5.0, 4.0],
                   "extensions": {"KHR_lights_punctual": {"light": 0}}},
                  {"name": "camera", "camera": 0,
                   "matrix": camera_matrix((0.0, 3.2, 6.5), (0.0, -0.2, 0.0))}],
        "meshes": [{"name": "terrain", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"name": "terrain", "pbrMetallicRoughness": {
            "baseColorFactor": [0.6, 0.55, 0.45, 1.0], "metallicFactor": 0.0,
            "roughnessFactor": 0.6}}],
        "cameras": [{"name": "main", "type": "perspective",
                     "perspective": {"yfov": 0.8, "aspectRatio": 16.0 / 9.0, "znear": 0.01}}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "key", "type": "point", "color": [1.0, 0.95, 0.9], "intensity": 80.0}]}},
        "buffers": [{"byteLength": offset}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": vertices, "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": vertices, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(indices), "type": "SCALAR"}],
    }
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)  # chunks are 4-byte aligned; JSON pads with spaces
    binary = b"".join(blobs)
    binary += b"\0" * (-len(binary) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(binary), 0x004E4942) + binary)
    print("wrote %s (%d triangles)" % (path, len(indices) // 3))


def camera_matrix(eye, target):
    """glTF column-major camera-to-world matrix looking from eye at target, +Y up."""
    back = normalised([eye[i] - target[i] for i in range(3)])
    right = normalised([back[2], 0.0, -back[0]])  # up x back with up = +Y
    up = [back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
          back[0] * right[1] - back[1] * right[0]]
    return list(right) + [0.0] + up + [0.0] + list(back) + [0.0] + list(eye) + [1.0]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--spheres", help="write the sphere field here (.gltf)")
    parser.add_argument("--sphere-count", type=int, default=4096)
    parser.add_argument("--mesh", help="write the dense mesh here (.glb)")
    parser.add_argument("--mesh-side", type=int, default=710,
                        help="vertices per side; triangles = 2 (side - 1)^2")
    args = parser.parse_args()
    if not args.spheres and not args.mesh:
        parser.error("nothing to write: give --spheres and/or --mesh")
    if args.spheres:
        sphere_field(args.spheres, args.sphere_count)
    if args.mesh:
        dense_mesh(args.mesh, args.mesh_side)


if __name__ == "__main__":
    main()
