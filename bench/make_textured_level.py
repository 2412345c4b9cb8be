#!/usr/bin/env python3
"""Writes a textured "game level" for the texture-loading benchmark: a floor and walls of
textured quads whose materials each have a base colour (sRGB), a normal map and a
metallic-roughness map, as separate PNG files beside the .gltf, the way exported levels ship:

    python3 bench/make_textured_level.py OUT_DIR [--large 2] [--small 6]

  --large  materials with 2048 x 2048 maps
  --small  materials with 1024 x 1024 maps

Each material has three maps, so the defaults (2 and 6) make 24 PNGs (44 Mi texels). Base colours
alternate RGB and RGBA. The texels are a gradient under 5 bits of noise, which zlib packs to
about 2:1 as real textures pack, so decoding costs what it costs on real assets. Only
Python's standard library (zlib, struct); deterministic (fixed seed). Writes
OUT_DIR/level.gltf and prints its path.
"""
import argparse
import json
import math
import os
import random
import struct
import sys
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "scenes"))
from make_scenes import Builder  # noqa: E402


def png_bytes(side, channels, rng):
    """side x side 8-bit PNG of `channels` channels: each row is a slice of one noise buffer
    mapped through that row's table (a gradient), at C speed."""
    row_bytes = side * channels
    noise = rng.randbytes(row_bytes * 2)
    rows = []
    for y in range(side):
        # A table of its own for every row in zlib's 32 KiB window, so no row repeats another.
        base = (y * 160) // side + (y % 16)
        table = bytes(((v >> 3) + base) & 0xFF for v in range(256))
        start = (y * 7919) % row_bytes
        rows.append(b"\x00" + noise[start:start + row_bytes].translate(table))
    colour_type = {1: 0, 2: 4, 3: 2, 4: 6}[channels]

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", side, side, 8, colour_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
            chunk(b"IDAT", zlib.compress(b"".join(rows), 6)) + chunk(b"IEND", b""))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir")
    parser.add_argument("--large", type=int, default=2)
    parser.add_argument("--small", type=int, default=6)
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    rng = random.Random(14)
    b = Builder()
    g = b.gltf
    g["images"], g["samplers"], g["textures"] = [], [{"wrapS": 10497, "wrapT": 10497}], []

    def texture(name, side, channels):
        path = os.path.join(args.out_dir, name + ".png")
        with open(path, "wb") as f:
            f.write(png_bytes(side, channels, rng))
        g["images"].append({"name": name, "uri": name + ".png"})
        g["textures"].append({"source": len(g["images"]) - 1, "sampler": 0})
        return len(g["textures"]) - 1

    sides = [2048] * args.large + [1024] * args.small
    count = len(sides)
    columns = max(1, math.ceil(math.sqrt(count)))
    for k, side in enumerate(sides):
        base = texture("m%02d_base" % k, side, 4 if k % 2 else 3)
        normal = texture("m%02d_normal" % k, side, 3)
        mr = texture("m%02d_mr" % k, side, 3)
        material = b.material("material %d" % k, (1.0, 1.0, 1.0), 1.0, 1.0)
        m = g["materials"][material]
        m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": base}
        m["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {"index": mr}
        m["normalTexture"] = {"index": normal}
        x, z = (k % columns) * 2.2 - columns * 1.1, -(k // columns) * 2.2
        b.quad("floor %d" % k, [x, 0.0, z], [2.0, 0.0, 0.0], [0.0, 0.0, -2.0], material, 2.0)
        b.quad("wall %d" % k, [x, 0.0, z - 2.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], material)
    b.light("sun", {"type": "directional", "intensity": 3.0},
            rotation=[-0.3826834, 0.0, 0.0, 0.9238795])
    depth = (count + columns - 1) // columns * 2.2
    b.camera("overview", [0.0, 3.0 + depth * 0.4, 4.0], [0.0, 0.0, -depth / 2.0], 0.9, 4 / 3)
    path = os.path.join(args.out_dir, "level.gltf")
    with open(path, "w") as f:
        json.dump(g, f, indent=1)
        f.write("\n")
    print(path)


if __name__ == "__main__":
    main()
