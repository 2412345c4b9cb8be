#!/usr/bin/env python3
"""Writes the glTF scenes Prism ships (scenes/*.gltf), using only Python's standard library.

Spheres are nodes with the PRISM_sphere extension (docs/spheres.md); each also carries a
unit icosphere mesh scaled to its radius, so viewers without the extension (Blender, web
viewers) still show the scene. Run it again after changing it: python3 scenes/make_scenes.py
"""
import base64
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def icosphere(level):
    t = (1.0 + 5.0 ** 0.5) / 2.0
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        cache = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(verts[a][i] + verts[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                verts.append(tuple(x / n for x in m))
                cache[key] = len(verts) - 1
            return cache[key]

        new_faces = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    return verts, faces


def checker_png(size, cells, dark, light):
    rows = []
    for y in range(size):
        row = bytearray([0])  # filter: none
        for x in range(size):
            on = ((x * cells // size) + (y * cells // size)) % 2 == 0
            row += bytes(light if on else dark)
        rows.append(bytes(row))
    raw = b"".join(rows)

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) +
            chunk(b"IEND", b""))


class Builder:
    def __init__(self):
        self.gltf = {"asset": {"version": "2.0", "generator": "prism scenes/make_scenes.py"},
                     "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
                     "materials": [], "buffers": [], "bufferViews": [], "accessors": [],
                     "extensionsUsed": []}

    def use_extension(self, name):
        if name not in self.gltf["extensionsUsed"]:
            self.gltf["extensionsUsed"].append(name)

    def _accessor(self, data, fmt, count, comp, kind, target, minmax=None):
        blob = struct.pack("<" + fmt * count, *data) if count else b""
        self.gltf["buffers"].append({"byteLength": len(blob), "uri":
                                     "data:application/octet-stream;base64," +
                                     base64.b64encode(blob).decode()})
        self.gltf["bufferViews"].append({"buffer": len(self.gltf["buffers"]) - 1,
                                         "byteLength": len(blob), "target": target})
        acc = {"bufferView": len(self.gltf["bufferViews"]) - 1, "componentType": comp,
               "count": count // {"VEC3": 3, "VEC2": 2, "SCALAR": 1}[kind], "type": kind}
        if minmax:
            acc["min"], acc["max"] = minmax
        self.gltf["accessors"].append(acc)
        return len(self.gltf["accessors"]) - 1

    def mesh(self, name, positions, normals, indices, material, uvs=None):
        flat_p = [c for p in positions for c in p]
        mins = [min(p[i] for p in positions) for i in range(3)]
        maxs = [max(p[i] for p in positions) for i in range(3)]
        attrs = {"POSITION": self._accessor(flat_p, "f", len(flat_p), 5126, "VEC3", 34962,
                                            (mins, maxs)),
                 "NORMAL": self._accessor([c for n in normals for c in n], "f",
                                          3 * len(normals), 5126, "VEC3", 34962)}
        if uvs:
            attrs["TEXCOORD_0"] = self._accessor([c for t in uvs for c in t], "f", 2 * len(uvs),
                                                 5126, "VEC2", 34962)
        flat_i = [i for tri in indices for i in tri]
        prim = {"attributes": attrs,
                "indices": self._accessor(flat_i, "H", len(flat_i), 5123, "SCALAR", 34963),
                "material": material}
        self.gltf["meshes"].append({"name": name, "primitives": [prim]})
        return len(self.gltf["meshes"]) - 1

    def material(self, name, base, metallic, roughness, transmission=0.0, ior=None, texture=None,
                 specular=None, emissive=None, emissive_strength=None):
        m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(base) + [1.0],
                                                    "metallicFactor": metallic,
                                                    "roughnessFactor": roughness}}
        if emissive is not None:
            m["emissiveFactor"] = list(emissive)
        if emissive_strength is not None:
            m.setdefault("extensions", {})["KHR_materials_emissive_strength"] = {
                "emissiveStrength": emissive_strength}
            self.use_extension("KHR_materials_emissive_strength")
        if texture is not None:
            m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": texture}
        if transmission:
            m.setdefault("extensions", {})["KHR_materials_transmission"] = {
                "transmissionFactor": transmission}
            self.use_extension("KHR_materials_transmission")
        if ior is not None:
            m.setdefault("extensions", {})["KHR_materials_ior"] = {"ior": ior}
            self.use_extension("KHR_materials_ior")
        if specular is not None:
            m.setdefault("extensions", {})["KHR_materials_specular"] = {"specularFactor": specular}
            self.use_extension("KHR_materials_specular")
        self.gltf["materials"].append(m)
        return len(self.gltf["materials"]) - 1

    def texture_png(self, name, png):
        g = self.gltf
        g.setdefault("images", []).append(
            {"name": name, "uri": "data:image/png;base64," + base64.b64encode(png).decode()})
        g.setdefault("samplers", []).append({"wrapS": 10497, "wrapT": 10497})
        g.setdefault("textures", []).append({"source": len(g["images"]) - 1,
                                             "sampler": len(g["samplers"]) - 1})
        return len(g["textures"]) - 1

    def node(self, node):
        self.gltf["nodes"].append(node)
        self.gltf["scenes"][0]["nodes"].append(len(self.gltf["nodes"]) - 1)
        return len(self.gltf["nodes"]) - 1

    def sphere(self, name, centre, radius, material, level=2):
        verts, faces = icosphere(level)
        mesh = self.mesh(name + " fallback", verts, verts, faces, material)
        self.use_extension("PRISM_sphere")
        return self.node({"name": name, "translation": list(centre), "scale": [radius] * 3,
                          "mesh": mesh,
                          "extensions": {"PRISM_sphere": {"radius": 1.0, "material": material}}})

    def quad(self, name, corner, edge_u, edge_v, material, uv_scale=1.0):
        p = [corner, [corner[i] + edge_u[i] for i in range(3)],
             [corner[i] + edge_u[i] + edge_v[i] for i in range(3)],
             [corner[i] + edge_v[i] for i in range(3)]]
        n = [edge_u[1] * edge_v[2] - edge_u[2] * edge_v[1],
             edge_u[2] * edge_v[0] - edge_u[0] * edge_v[2],
             edge_u[0] * edge_v[1] - edge_u[1] * edge_v[0]]
        length = math.sqrt(sum(c * c for c in n))
        n = [c / length for c in n]
        uvs = [(0, uv_scale), (uv_scale, uv_scale), (uv_scale, 0), (0, 0)]
        mesh = self.mesh(name, p, [n] * 4, [(0, 1, 2), (0, 2, 3)], material, uvs)
        return self.node({"name": name, "mesh": mesh})

    def light(self, name, light, translation=None, rotation=None):
        self.use_extension("KHR_lights_punctual")
        lights = self.gltf.setdefault("extensions", {}).setdefault(
            "KHR_lights_punctual", {"lights": []})["lights"]
        lights.append(dict(light, name=name))
        node = {"name": name, "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}}
        if translation:
            node["translation"] = translation
        if rotation:
            node["rotation"] = rotation
        return self.node(node)

    def camera(self, name, eye, target, yfov, aspect):
        f = [target[i] - eye[i] for i in range(3)]
        fl = math.sqrt(sum(c * c for c in f))
        back = [-c / fl for c in f]
        up = [0.0, 1.0, 0.0]
        right = [up[1] * back[2] - up[2] * back[1], up[2] * back[0] - up[0] * back[2],
                 up[0] * back[1] - up[1] * back[0]]
        rl = math.sqrt(sum(c * c for c in right))
        right = [c / rl for c in right]
        up = [back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
              back[0] * right[1] - back[1] * right[0]]
        self.gltf.setdefault("cameras", []).append(
            {"name": name, "type": "perspective",
             "perspective": {"yfov": yfov, "aspectRatio": aspect, "znear": 0.01}})
        matrix = right + [0.0] + up + [0.0] + back + [0.0] + list(eye) + [1.0]
        return self.node({"name": name, "camera": len(self.gltf["cameras"]) - 1,
                          "matrix": matrix})

    def write(self, filename):
        if not self.gltf["extensionsUsed"]:
            del self.gltf["extensionsUsed"]
        path = os.path.join(HERE, filename)
        with open(path, "w") as f:
            json.dump(self.gltf, f, indent=1)
            f.write("\n")
        print("wrote", path)


def direction_to_quaternion(d):
    """Rotation taking the light's -Z to the unit direction d."""
    fx, fy, fz = 0.0, 0.0, -1.0
    cx, cy, cz = fy * d[2] - fz * d[1], fz * d[0] - fx * d[2], fx * d[1] - fy * d[0]
    w = 1.0 + fx * d[0] + fy * d[1] + fz * d[2]
    n = math.sqrt(cx * cx + cy * cy + cz * cz + w * w)
    return [cx / n, cy / n, cz / n, w / n]


def spheres_scene():
    """The default scene: the lecture's Whitted spheres on a checker floor."""
    b = Builder()
    checker = b.texture_png("checker", checker_png(256, 8, (40, 40, 48), (215, 215, 205)))
    floor = b.material("floor", (1.0, 1.0, 1.0), 0.0, 0.7, texture=checker)
    wall = b.material("wall", (0.55, 0.6, 0.7), 0.0, 0.9)
    mirror = b.material("mirror", (0.95, 0.95, 0.95), 1.0, 0.0)
    glass = b.material("glass", (1.0, 1.0, 1.0), 0.0, 0.0, transmission=1.0, ior=1.5)
    red = b.material("red plastic", (0.8, 0.08, 0.06), 0.0, 0.35)
    gold = b.material("gold", (1.0, 0.77, 0.34), 1.0, 0.08)
    b.quad("floor", [-6, 0, 5], [12, 0, 0], [0, 0, -11], floor, uv_scale=3.0)
    b.quad("back wall", [-6, 0, -6], [12, 0, 0], [0, 6, 0], wall)
    b.sphere("mirror sphere", (-1.25, 1.0, -0.6), 1.0, mirror)
    b.sphere("glass sphere", (1.15, 0.8, 0.9), 0.8, glass)
    b.sphere("red sphere", (1.6, 0.55, -1.8), 0.55, red)
    b.sphere("gold sphere", (-0.2, 0.35, 1.6), 0.35, gold)
    b.light("key", {"type": "point", "color": [1.0, 0.95, 0.88], "intensity": 60.0},
            translation=[3.0, 5.0, 4.0])
    b.light("sky", {"type": "directional", "color": [0.75, 0.85, 1.0], "intensity": 0.8},
            rotation=direction_to_quaternion(normalised((-0.3, -1.0, -0.4))))
    b.camera("main", (0.0, 2.0, 7.0), (0.0, 0.8, 0.0), 0.65, 16.0 / 9.0)
    b.write("spheres.gltf")


def furnace_scene():
    """pbrt-v4's RadianceMatches furnace: the camera inside a closed Lambertian sphere of
    radius 1 and albedo 0.5, an isotropic point light of pi candela at its centre. Every
    pixel's direct radiance is exactly 0.5 (E = pi / 1^2, L = 0.5 / pi * E)."""
    b = Builder()
    lambert = b.material("lambert 0.5", (0.5, 0.5, 0.5), 0.0, 1.0, specular=0.0)
    b.sphere("furnace", (0.0, 0.0, 0.0), 1.0, lambert, level=3)
    b.light("bulb", {"type": "point", "color": [1.0, 1.0, 1.0], "intensity": math.pi},
            translation=[0.0, 0.0, 0.0])
    b.camera("inside", (0.0, 0.0, 0.0), (0.0, 0.0, -1.0), 1.2, 1.0)
    b.write("furnace.gltf")


def normalised(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def whitted_scene():
    """Whitted's test scene, kept simple for cross-renderer checks (bench/peers/): solid
    colours, analytic spheres (mirror, glass, plastic, Lambertian), a Lambertian floor and two
    point lights. bench/peers/whitted.pov is the same scene for POV-Ray."""
    b = Builder()
    floor = b.material("floor", (0.8, 0.8, 0.8), 0.0, 1.0, specular=0.0)
    matte = b.material("white matte", (0.8, 0.8, 0.8), 0.0, 1.0, specular=0.0)
    mirror = b.material("mirror", (0.9, 0.9, 0.9), 1.0, 0.0)
    glass = b.material("glass", (1.0, 1.0, 1.0), 0.0, 0.0, transmission=1.0, ior=1.5)
    red = b.material("red plastic", (0.8, 0.1, 0.08), 0.0, 0.35)
    b.quad("floor", [-10, 0, 8], [20, 0, 0], [0, 0, -24], floor)
    b.sphere("mirror sphere", (-1.3, 1.0, -0.8), 1.0, mirror, level=4)
    b.sphere("glass sphere", (1.0, 0.7, 0.8), 0.7, glass, level=4)
    b.sphere("red sphere", (1.9, 0.5, -1.5), 0.5, red, level=4)
    b.sphere("matte sphere", (-0.4, 0.4, 1.9), 0.4, matte, level=4)
    b.light("key", {"type": "point", "color": [1.0, 1.0, 1.0], "intensity": 40.0},
            translation=[3.0, 5.0, 4.0])
    b.light("fill", {"type": "point", "color": [1.0, 0.9, 0.8], "intensity": 12.0},
            translation=[-4.0, 3.0, 2.0])
    b.camera("main", (0.0, 1.6, 6.0), (0.0, 0.8, 0.0), 0.7, 4.0 / 3.0)
    b.write("whitted.gltf")


def cornell_scene():
    """A Cornell box 2 m on a side lit only by an emissive ceiling panel (0.5 m x 0.5 m,
    emissiveFactor times KHR_materials_emissive_strength): no punctual light, so every light in
    the image comes from emissive geometry. Lambertian walls (no specular layer), a tall and a
    short block."""
    b = Builder()
    white = b.material("white", (0.73, 0.73, 0.73), 0.0, 1.0, specular=0.0)
    red = b.material("red", (0.63, 0.065, 0.05), 0.0, 1.0, specular=0.0)
    green = b.material("green", (0.14, 0.45, 0.091), 0.0, 1.0, specular=0.0)
    panel = b.material("ceiling panel", (0.0, 0.0, 0.0), 0.0, 1.0, specular=0.0,
                       emissive=(1.0, 0.85, 0.6), emissive_strength=17.0)
    # Each quad's front (edge_u x edge_v) faces into the box.
    b.quad("floor", [-1, 0, 1], [2, 0, 0], [0, 0, -2], white)
    b.quad("ceiling", [-1, 2, -1], [2, 0, 0], [0, 0, 2], white)
    b.quad("back wall", [-1, 0, -1], [2, 0, 0], [0, 2, 0], white)
    b.quad("left wall", [-1, 0, 1], [0, 0, -2], [0, 2, 0], red)
    b.quad("right wall", [1, 0, -1], [0, 0, 2], [0, 2, 0], green)
    b.quad("ceiling panel", [-0.25, 1.99, -0.25], [0.5, 0, 0], [0, 0, 0.5], panel)

    def block(name, centre, half, height, angle):
        c, s = math.cos(angle), math.sin(angle)
        u = [half * c, 0.0, -half * s]  # the block's local x and z half edges, turned
        w = [half * s, 0.0, half * c]
        base = [centre[0] - u[0] - w[0], 0.0, centre[2] - u[2] - w[2]]
        up = [0.0, height, 0.0]
        e_u = [2 * x for x in u]
        e_w = [2 * x for x in w]
        top = [base[0], height, base[2]]
        b.quad(name + " top", top, e_w, e_u, white)
        b.quad(name + " front", [base[0] + e_w[0], 0.0, base[2] + e_w[2]], e_u, up, white)
        b.quad(name + " back", [base[0] + e_u[0], 0.0, base[2] + e_u[2]], [-x for x in e_u], up,
               white)
        b.quad(name + " left", base, e_w, up, white)
        b.quad(name + " right", [base[0] + e_u[0] + e_w[0], 0.0, base[2] + e_u[2] + e_w[2]],
               [-x for x in e_w], up, white)

    block("tall block", (-0.33, 0.0, -0.3), 0.3, 1.2, 0.3)
    block("short block", (0.35, 0.0, 0.35), 0.3, 0.6, -0.3)
    b.camera("front", (0.0, 1.0, 3.9), (0.0, 1.0, 0.0), 0.69, 1.0)
    b.write("cornell.gltf")


if __name__ == "__main__":
    spheres_scene()
    furnace_scene()
    whitted_scene()
    cornell_scene()
