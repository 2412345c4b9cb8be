#!/usr/bin/env python3
"""Renders analytic scenes with a prism binary and prints their error against closed forms.

  gltf_brdf_check.py PRISM OUT_DIR

1. A plane under a point light, seen by an orthographic camera, for a metal at roughness
   0.3 / 0.5 / 0.7 and a dielectric at 0.5, with `shadow --ambient 0`: the worst relative
   difference from glTF's BRDF (specification Appendix B, evaluated here in double) and the
   ratio of the rendered highlight peak to Appendix B's.
2. A white furnace (`--background 1`, a uniform environment that every integrator takes as
   its ambient term; no lights): one sphere per material, each
   integrator; the largest value rendered (never above 1 for an energy-conserving model).

Pixels are read back with `oiiotool --dumpdata`, so the script needs no Python image module.
"""
import json
import math
import os
import subprocess
import sys

RES = 96
TILT = math.radians(50.0)
LIGHT = (0.4, 1.5, -0.3)
INTENSITY = 20.0
HALF = 2.5
BASE = (0.9, 0.6, 0.3)


def camera_matrix():
    a = -(math.pi / 2 - TILT)
    forward = (0.0, -math.cos(TILT), -math.sin(TILT))
    eye = tuple(-10.0 * f for f in forward)
    # glTF node matrix, column-major: rotation about X by a, then the translation.
    return [1, 0, 0, 0,
            0, math.cos(a), math.sin(a), 0,
            0, -math.sin(a), math.cos(a), 0,
            eye[0], eye[1], eye[2], 1], eye, forward


def write_gltf(path, materials, meshes_json, buffers, extra_nodes, lights):
    matrix, _, _ = camera_matrix()
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(extra_nodes)))}],
        "nodes": extra_nodes,
        "cameras": [{"type": "orthographic",
                     "orthographic": {"xmag": HALF, "ymag": HALF, "znear": 0.01, "zfar": 100}}],
        "materials": materials,
        "meshes": meshes_json,
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
    }
    doc.update(buffers)
    with open(path, "w") as f:
        json.dump(doc, f)


def plane_buffers():
    import base64
    import struct
    h = 4.0
    pos = [(-h, 0, h), (h, 0, h), (h, 0, -h), (-h, 0, -h)]
    nrm = [(0, 1, 0)] * 4
    idx = [0, 1, 2, 0, 2, 3]
    data = b"".join(struct.pack("<3f", *p) for p in pos)
    data += b"".join(struct.pack("<3f", *n) for n in nrm)
    data += b"".join(struct.pack("<H", i) for i in idx)
    uri = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    return {
        "buffers": [{"byteLength": len(data), "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-h, 0, -h], "max": [h, 0, h]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }


def appendix_b(rho, m, alpha, v, l):
    nl, nv = l[1], v[1]
    if nl <= 0 or nv <= 0:
        return 0.0
    h = [v[i] + l[i] for i in range(3)]
    hl = math.sqrt(sum(c * c for c in h))
    h = [c / hl for c in h]
    vh = sum(v[i] * h[i] for i in range(3))
    nh = h[1]
    a2 = alpha * alpha
    d = a2 / (math.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    vis = 0.5 / (nl * math.sqrt(nv * nv * (1 - a2) + a2) + nv * math.sqrt(nl * nl * (1 - a2) + a2))
    s = (1 - vh) ** 5
    metal = (rho + (1 - rho) * s) * vis * d
    fr = 0.04 + 0.96 * s
    dielectric = (1 - fr) * rho / math.pi + fr * vis * d
    return (1 - m) * dielectric + m * metal


def read_pixels(path):
    out = subprocess.run(["oiiotool", "--dumpdata", path], capture_output=True, text=True,
                         check=True).stdout
    pixels = {}
    for line in out.splitlines():
        line = line.strip()
        if not line.startswith("Pixel ("):
            continue
        coords, values = line[len("Pixel ("):].split("):")
        x, y = (int(c) for c in coords.split(","))
        pixels[(x, y)] = [float(c) for c in values.split()]
    return pixels


def run(prism, args):
    subprocess.run([prism, "render"] + args, check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)


def plane_check(prism, out_dir):
    _, eye, forward = camera_matrix()
    # The camera's axes: local +X stays +X, local +Y is the rotated up, right x forward.
    right = (1.0, 0.0, 0.0)
    up = (0.0, math.sin(TILT), -math.cos(TILT))
    for metallic, roughness in [(1.0, 0.3), (1.0, 0.5), (1.0, 0.7), (0.0, 0.5)]:
        path = os.path.join(out_dir, f"plane_m{metallic:g}_r{roughness:g}.gltf")
        nodes = [{"camera": 0, "matrix": camera_matrix()[0]},
                 {"mesh": 0},
                 {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": list(LIGHT)}]
        write_gltf(path, [{"pbrMetallicRoughness": {"baseColorFactor": list(BASE) + [1],
                                                    "metallicFactor": metallic,
                                                    "roughnessFactor": roughness}}],
                   [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                     "material": 0}]}],
                   plane_buffers(), nodes,
                   [{"type": "point", "intensity": INTENSITY, "color": [1, 1, 1]}])
        exr = path.replace(".gltf", ".exr")
        run(prism, [path, "-o", exr, "--integrator", "shadow", "--ambient", "0", "--spp", "1",
                    "--res", f"{RES}x{RES}"])
        pixels = read_pixels(exr)
        worst, peak_got, peak_ref = 0.0, 0.0, 0.0
        for (x, y), value in pixels.items():
            sx = (2 * (x + 0.5) / RES - 1) * HALF
            sy = (1 - 2 * (y + 0.5) / RES) * HALF
            o = [eye[i] + right[i] * sx + up[i] * sy for i in range(3)]
            t = -o[1] / forward[1]
            p = [o[i] + forward[i] * t for i in range(3)]
            if abs(p[0]) > 3.9 or abs(p[2]) > 3.9:
                continue
            tl = [LIGHT[i] - p[i] for i in range(3)]
            d2 = sum(c * c for c in tl)
            l = [c / math.sqrt(d2) for c in tl]
            v = [-c for c in forward]
            for ch in range(3):
                ref = appendix_b(BASE[ch], metallic, roughness * roughness, v, l) * INTENSITY / d2 * l[1]
                worst = max(worst, abs(value[ch] - ref) / ref)
                if ch == 0:
                    peak_got = max(peak_got, value[ch])
                    peak_ref = max(peak_ref, ref)
        print(f"plane metallic {metallic:g} roughness {roughness:g}: worst relative error "
              f"{worst:.3g}, highlight peak {peak_got / peak_ref:.3f} x Appendix B's")


def furnace_check(prism, out_dir):
    cases = [("lambert", 1.0, 0.0, 1.0, 0.0, 0.0), ("rough dielectric", 1.0, 0.0, 0.5, 0.0, 1.0),
             ("smooth dielectric", 1.0, 0.0, 0.0, 0.0, 1.0), ("rough metal", 1.0, 1.0, 0.5, 0.0, 1.0),
             ("smooth metal", 1.0, 1.0, 0.0, 0.0, 1.0), ("glass", 1.0, 0.0, 0.0, 1.0, 1.0),
             ("tinted glass", 0.6, 0.0, 0.0, 1.0, 1.0)]
    for name, rho, metallic, roughness, transmission, specular in cases:
        path = os.path.join(out_dir, "furnace_" + name.replace(" ", "_") + ".gltf")
        material = {"pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1],
                                             "metallicFactor": metallic,
                                             "roughnessFactor": roughness},
                    "extensions": {"KHR_materials_transmission": {"transmissionFactor": transmission},
                                   "KHR_materials_specular": {"specularFactor": specular}}}
        # A UV-sphere mesh, rendered as the analytic sphere Prism detects in it; and a light of
        # intensity 0, so that no default light is added: the furnace's only light is the
        # uniform environment.
        nodes = [{"camera": 0, "translation": [0, 0, 5]}, {"mesh": 0},
                 {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 5, 0]}]
        write_gltf(path, [material], [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1},
                                                       "indices": 2, "material": 0}]}],
                   sphere_buffers(), nodes, [{"type": "point", "intensity": 0.0}])
        doc = json.load(open(path))
        doc["extensionsUsed"].append("KHR_materials_specular")
        doc["cameras"][0]["orthographic"].update({"xmag": 1.05, "ymag": 1.05})
        json.dump(doc, open(path, "w"))
        line = f"furnace {name:17s}"
        for integrator in ("phong", "shadow", "whitted"):
            exr = path.replace(".gltf", f"_{integrator}.exr")
            run(prism, [path, "-o", exr, "--integrator", integrator,
                        "--background", "1", "--spp", "1", "--res", "64x64", "--detect-spheres"])
            highest = max(max(v[:3]) for v in read_pixels(exr).values())
            line += f"  {integrator} max {highest:.5f}"
        print(line)


def sphere_buffers():
    import base64
    import struct
    rings, segments = 48, 96
    pos, nrm, idx = [], [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segments + 1):
            ph = 2 * math.pi * j / segments
            p = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            pos.append(p)
            nrm.append(p)
    for i in range(rings):
        for j in range(segments):
            a = i * (segments + 1) + j
            b = a + segments + 1
            idx += [a, a + 1, b, a + 1, b + 1, b]
    data = b"".join(struct.pack("<3f", *p) for p in pos)
    n_off = len(data)
    data += b"".join(struct.pack("<3f", *n) for n in nrm)
    i_off = len(data)
    data += b"".join(struct.pack("<I", k) for k in idx)
    uri = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    return {
        "buffers": [{"byteLength": len(data), "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": n_off},
                        {"buffer": 0, "byteOffset": n_off, "byteLength": i_off - n_off},
                        {"buffer": 0, "byteOffset": i_off, "byteLength": len(data) - i_off}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": len(pos), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
    }


def main():
    prism, out_dir = sys.argv[1], sys.argv[2]
    os.makedirs(out_dir, exist_ok=True)
    plane_check(prism, out_dir)
    furnace_check(prism, out_dir)


if __name__ == "__main__":
    main()
