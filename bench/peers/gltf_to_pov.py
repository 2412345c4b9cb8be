#!/usr/bin/env python3
"""Writes a POV-Ray 3.7 scene from one of Prism's simple glTF scenes (bench/peers/README.md).

    python3 bench/peers/gltf_to_pov.py scenes/whitted.gltf bench/peers/whitted.pov

Handles what scenes/make_scenes.py's whitted_scene() uses, and fails loudly on anything
else: PRISM_sphere nodes (analytic spheres), triangle meshes without node transforms,
solid-colour metallic-roughness materials (+ KHR_materials_transmission, _ior, _specular
factor), KHR_lights_punctual point lights, one perspective camera given by a node matrix.

Coordinates: glTF is right-handed (camera looks down -Z), POV-Ray is left-handed. Mirroring
z (x, y, z) -> (x, y, -z) maps one onto the other and keeps the picture the same way round.

Lights: Prism's point light gives a white Lambertian surface facing it, at distance d,
radiance L = (rho / pi) * I / d^2 (I in candela, read as W/sr). POV-Ray gives
L = C * diffuse * rho * cos * attenuation, attenuation = 2 / (1 + (d / D)^2) for
fade_power 2 and fade_distance D. For D << d, attenuation = 2 D^2 / d^2 (relative error
(D/d)^2), so with diffuse = 1 the colour C = I * colour / (2 pi D^2) reproduces Prism.

Materials follow docs/materials.md: F0 = s ((ior-1)/(ior+1))^2, rho_d = rho (1-m)(1-T)(1-F0),
k_s = F0 (1-m) + rho m, Phong exponent n = min(2/alpha^2 - 2, 10000), alpha = r^2.
  diffuse term   -> pigment rho_d, diffuse 1 (POV's diffuse is albedo x cos, Prism's rho_d/pi x E)
  Phong lobe     -> phong k_s (n+2)/2, phong_size n (Prism's normalised lobe k_s (n+2)/(2 pi)
                    times E = pi x POV's light colour; POV's phong has no N.L factor, Prism's has)
  mirror (r<=0.1)-> reflection { k_s, 1 falloff 5 }: POV's variable reflection with falloff 5
                    is exactly Schlick's Fresnel that Prism uses for mirrors
  transmission   -> pigment filter 1, reflection { 0, 1 fresnel on }, conserve_energy,
                    interior { ior }: exact dielectric Fresnel, as in Prism
Prism's transmissive objects cast full shadows (Whitted's model); POV-Ray lets light
through filtering objects, so each transmissive sphere gets an opaque twin just inside it
(no_image no_reflection) that only casts the shadow.
"""
import base64
import json
import math
import struct
import sys

FADE_DISTANCE = 0.01  # D in the mapping above; far below every light-to-surface distance


def mirror(v):
    return (v[0], v[1], -v[2])


def vec(v):
    return "<%.9g, %.9g, %.9g>" % tuple(v)


def read_accessor(gltf, index):
    acc = gltf["accessors"][index]
    view = gltf["bufferViews"][acc["bufferView"]]
    uri = gltf["buffers"][view["buffer"]]["uri"]
    if not uri.startswith("data:"):
        sys.exit("only embedded buffers are supported")
    blob = base64.b64decode(uri.split(",", 1)[1])
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[acc["type"]]
    fmt = {5126: "f", 5123: "H", 5125: "I"}[acc["componentType"]]
    values = struct.unpack_from("<" + fmt * (width * acc["count"]), blob, start)
    return [values[i:i + width] for i in range(0, len(values), width)] if width > 1 else values


def material_pov(gltf, index):
    m = gltf["materials"][index]
    pbr = m.get("pbrMetallicRoughness", {})
    if "baseColorTexture" in pbr:
        sys.exit("textures are not supported")
    rho = pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]
    metal = pbr.get("metallicFactor", 1.0)
    rough = pbr.get("roughnessFactor", 1.0)
    ext = m.get("extensions", {})
    trans = ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0)
    ior = ext.get("KHR_materials_ior", {}).get("ior", 1.5)
    spec = ext.get("KHR_materials_specular", {}).get("specularFactor", 1.0)
    f0 = min(spec * ((ior - 1) / (ior + 1)) ** 2, 1.0)
    rho_d = [c * (1 - metal) * (1 - trans) * (1 - f0) for c in rho]
    k_s = [f0 * (1 - metal) + c * metal for c in rho]
    alpha = rough * rough
    n = 10000.0 if alpha == 0 else min(2 / alpha ** 2 - 2, 10000.0)
    if n <= 0:  # Prism's lobe is then k_s / pi, a second Lambertian term
        rho_d = [d + s for d, s in zip(rho_d, k_s)]
        k_s = [0.0, 0.0, 0.0]
        n = 0
    if len(set(round(c, 6) for c in k_s)) > 1:
        sys.exit("coloured specular is not supported (POV phong is grey unless metallic)")
    t = trans * (1 - metal)
    if 0 < t < 1:
        sys.exit("partial transmission is not supported")
    lines = ["// %s" % m.get("name", "material %d" % index)]
    if t == 1:
        lines.append("pigment { rgbf <%.6g, %.6g, %.6g, 1> }" % tuple(rho))
    else:
        lines.append("pigment { rgb %s }" % vec(rho_d))
    fin = ["ambient 0", "emission 0", "diffuse %s" % ("0" if t == 1 else "1")]
    if k_s[0] > 0 and n > 0:
        fin.append("phong %.9g phong_size %.9g" % (k_s[0] * (n + 2) / 2, n))
    if t == 1:
        fin.append("reflection { 0, 1 fresnel on } conserve_energy")
    elif rough <= 0.1:
        fin.append("reflection { rgb %s, rgb 1 falloff 5 }" % vec(k_s))
    lines.append("finish { %s }" % " ".join(fin))
    if t == 1:
        lines.append("interior { ior %.9g }" % ior)
    return "\n  ".join(lines), t == 1


def main(src, dst):
    gltf = json.load(open(src))
    out = ["// Generated by bench/peers/gltf_to_pov.py from %s: do not edit." % src,
           "// glTF z is negated (POV-Ray is left-handed); see that script for the unit mapping.",
           "#version 3.7;",
           "global_settings { assumed_gamma 1.0 ambient_light 0 max_trace_level 6 "
           "adc_bailout 0 }",
           "background { rgb 0 }", ""]
    lights = gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    cameras = 0
    for node in gltf["nodes"]:
        name = node.get("name", "")
        ext = node.get("extensions", {})
        if "camera" in node:
            cameras += 1
            if cameras > 1:
                continue
            cam = gltf["cameras"][node["camera"]]["perspective"]
            m = node["matrix"]
            up, back, eye = m[4:7], m[8:11], m[12:15]
            aspect = cam["aspectRatio"]
            hfov = 2 * math.atan(math.tan(cam["yfov"] / 2) * aspect)
            out += ["// camera %s: glTF yfov %.6g rad, aspect %.6g -> horizontal angle" % (
                        name, cam["yfov"], aspect),
                    "camera {", "  perspective",
                    "  location %s" % vec(mirror(eye)),
                    "  right x * %.9g" % aspect, "  up y",
                    "  sky %s" % vec(mirror(up)),
                    "  angle %.9g" % math.degrees(hfov),
                    "  look_at %s" % vec(mirror([e - b for e, b in zip(eye, back)])),
                    "}", ""]
        elif "KHR_lights_punctual" in ext:
            light = lights[ext["KHR_lights_punctual"]["light"]]
            if light["type"] != "point" or "range" in light:
                sys.exit("only point lights without range are supported")
            scale = light.get("intensity", 1.0) / (2 * math.pi * FADE_DISTANCE ** 2)
            colour = [c * scale for c in light.get("color", [1, 1, 1])]
            out += ["// light %s: %.6g cd -> colour = I * colour / (2 pi D^2), D = %g" % (
                        name, light.get("intensity", 1.0), FADE_DISTANCE),
                    "light_source { %s color rgb %s fade_distance %g fade_power 2 }" % (
                        vec(mirror(node["translation"])), vec(colour), FADE_DISTANCE), ""]
        elif "PRISM_sphere" in ext:
            sph = ext["PRISM_sphere"]
            centre = node.get("translation", [0, 0, 0])
            scale = node.get("scale", [1, 1, 1])
            if len(set(scale)) != 1 or "rotation" in node or "matrix" in node:
                sys.exit("sphere %s: only translation and uniform scale are supported" % name)
            radius = sph.get("radius", 1.0) * scale[0]
            mat, clear = material_pov(gltf, sph["material"])
            out += ["// sphere %s" % name,
                    "sphere { %s, %.9g\n  %s\n}" % (vec(mirror(centre)), radius, mat)]
            if clear:
                out.append("sphere { %s, %.9g pigment { rgb 0 } finish { ambient 0 diffuse 0 }"
                           " no_image no_reflection }  // casts the full shadow Prism casts"
                           % (vec(mirror(centre)), radius * 0.999))
            out.append("")
        elif "mesh" in node:
            if any(k in node for k in ("translation", "rotation", "scale", "matrix")):
                sys.exit("mesh node %s: transforms are not supported" % name)
            for prim in gltf["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    sys.exit("only triangles are supported")
                pos = read_accessor(gltf, prim["attributes"]["POSITION"])
                idx = read_accessor(gltf, prim["indices"])
                mat, _ = material_pov(gltf, prim["material"])
                tris = ["  triangle { %s, %s, %s }" % tuple(vec(mirror(pos[i]))
                                                           for i in idx[k:k + 3])
                        for k in range(0, len(idx), 3)]
                out += ["// mesh %s" % name, "mesh {"] + tris + ["  " + mat, "}", ""]
    with open(dst, "w") as f:
        f.write("\n".join(out))
    print("wrote", dst)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
