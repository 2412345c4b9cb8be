"""Builds a textured scene in Blender, exports it to glTF and renders it with Cycles, for
bench/blender_compare.py (docs/blender-comparison.md).

    blender -b --factory-startup --python-exit-code 1 --python bench/peers/blender_asset.py \
        -- OUT_DIR --res 400x300 --spp 512 [--seeds 0,1] [--threads 2] [--lambert]

The scene, built from nothing (no file is read):
- a 8 m x 8 m floor with a checker base-colour texture,
- a cube with a brick base-colour texture and a tangent-space normal map of round bumps,
- a smooth-shaded UV sphere with a striped base-colour texture and a glossy coat,
- a point light (600 W, radius 0: a true point) and a sun (2 W/m^2, angle 0: a true
  directional light), and a perspective camera.
The textures are drawn here with NumPy and saved as 8-bit PNGs into OUT_DIR/textures, then
loaded back, so Cycles and the exported file read exactly the same texels.

Materials are Principled BSDFs with metallic 0. Floor and cube have Specular 0: the glTF
exporter then writes KHR_materials_specular with specularColorFactor 0 (a pure Lambertian
for glTF), and Cycles' Principled BSDF keeps only its diffuse lobe; roughness 0.25 makes
that Disney diffuse lobe closest to Lambert (docs/blender-comparison.md). The sphere keeps
Specular 0.5 (F0 = 0.04, glTF's default) with roughness 0.5, to show the specular models.

Writes into OUT_DIR:
- asset.glb: export_lights=True, convert_lighting_mode='COMPAT' (point: W / 4 pi -> cd,
  sun: W/m^2 -> lx; Prism reads cd as W/sr), tangents exported;
- asset_spec.glb: the same with the exporter's default 'SPEC' mode (x 683 lm/W), only for
  the units table;
- blender_lights.json: each light's Blender type, power/strength, colour and radius;
- cycles_seed<S>.exr (and cycles_lambert_seed<S>.exr with --lambert): multilayer EXRs with
  the linear Combined pass and the object-index pass (floor 1, cube 2, sphere 3), rendered
  with the settings of cycles_render.py (black world, max_bounces 0, box filter, Standard
  view, fixed samples, no denoising).
Prints "CYCLES_RENDER_TIME <seed> <s>".
"""
import argparse
import json
import math
import os
import sys
import time

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_render  # noqa: E402  (sets numpy.bool for the glTF add-on, imports bpy)

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

FLOOR, CUBE, SPHERE = 1, 2, 3  # object pass indices: the masks in blender_compare.py


def save_png(path, rgb):
    """Writes rgb (H x W x 3 floats in [0, 1], row 0 at the bottom as Blender stores it) as an
    8-bit PNG through Blender itself, and returns it loaded back from the file."""
    height, width, _ = rgb.shape
    image = bpy.data.images.new(os.path.basename(path), width, height, alpha=False)
    rgba = numpy.ones((height, width, 4), dtype=numpy.float32)
    rgba[..., :3] = numpy.round(numpy.clip(rgb, 0.0, 1.0) * 255.0) / 255.0
    image.pixels.foreach_set(rgba.ravel())
    image.filepath_raw = path
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)
    return bpy.data.images.load(path)


def checker_texture(size=512, squares=8):
    y, x = numpy.mgrid[0:size, 0:size]
    odd = ((x * squares // size) + (y * squares // size)) % 2 == 1
    rgb = numpy.empty((size, size, 3))
    rgb[odd] = (0.85, 0.82, 0.75)
    rgb[~odd] = (0.25, 0.35, 0.45)
    return rgb


def brick_texture(size=512, rows=8, bricks=4, mortar=0.06):
    y, x = (numpy.mgrid[0:size, 0:size] + 0.5) / size
    row = numpy.floor(y * rows)
    u = x * bricks + 0.5 * (row % 2)
    in_mortar = ((y * rows) % 1.0 < mortar * 2) | ((u % 1.0) < mortar)
    brick_id = numpy.floor(u) + 7 * row
    shade = 0.85 + 0.15 * numpy.sin(brick_id * 12.9898) ** 2
    rgb = numpy.empty((size, size, 3))
    rgb[..., 0] = 0.62 * shade
    rgb[..., 1] = 0.24 * shade
    rgb[..., 2] = 0.16 * shade
    rgb[in_mortar] = (0.7, 0.7, 0.66)
    return rgb


def stripe_texture(size=256, stripes=12):
    y, x = (numpy.mgrid[0:size, 0:size] + 0.5) / size
    band = numpy.floor(x * stripes) % 2 == 0
    rgb = numpy.empty((size, size, 3))
    rgb[band] = (0.8, 0.55, 0.1)
    rgb[~band] = (0.15, 0.45, 0.2)
    return rgb


def bump_normal_map(size=512, bumps=6, height=0.02):
    """Tangent-space normal map (OpenGL convention, as glTF and Blender use: +x along u, +y
    along v) of a grid of round domes, h = height * cos^2(pi/2 * d/R) inside radius R.
    Encoded (n + 1) / 2, linear data."""
    y, x = (numpy.mgrid[0:size, 0:size] + 0.5) / size
    cell = 1.0 / bumps
    dx = (x % cell) / cell - 0.5
    dy = (y % cell) / cell - 0.5
    d = numpy.hypot(dx, dy)
    radius = 0.4
    inside = d < radius
    # dh/dd in texture units (one texture = 1 unit), then the gradient's components.
    slope = numpy.where(inside, -height * math.pi / (2 * radius * cell) *
                        numpy.sin(math.pi * d / radius), 0.0)
    safe = numpy.where(d > 0, d, 1.0)
    gx, gy = slope * dx / safe, slope * dy / safe
    n = numpy.stack([-gx, -gy, numpy.ones_like(gx)], axis=-1)
    n /= numpy.linalg.norm(n, axis=-1, keepdims=True)
    return (n + 1.0) * 0.5


def material(name, base_image, specular, roughness, normal_image=None):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Specular"].default_value = specular
    bsdf.inputs["Roughness"].default_value = roughness
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = base_image
    tex.interpolation = "Linear"
    links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    if normal_image is not None:
        ntex = nodes.new("ShaderNodeTexImage")
        ntex.image = normal_image
        ntex.interpolation = "Linear"
        nmap = nodes.new("ShaderNodeNormalMap")
        nmap.space = "TANGENT"
        nmap.inputs["Strength"].default_value = 1.0
        links.new(ntex.outputs["Color"], nmap.inputs["Color"])
        links.new(nmap.outputs["Normal"], bsdf.inputs["Normal"])
    return mat


def build_scene(out_dir, width, height):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    textures = os.path.join(out_dir, "textures")
    os.makedirs(textures, exist_ok=True)
    checker = save_png(os.path.join(textures, "checker.png"), checker_texture())
    bricks = save_png(os.path.join(textures, "bricks.png"), brick_texture())
    stripes = save_png(os.path.join(textures, "stripes.png"), stripe_texture())
    bumps = save_png(os.path.join(textures, "bumps_normal.png"), bump_normal_map())
    for image in (checker, bricks, stripes):
        image.colorspace_settings.name = "sRGB"
    bumps.colorspace_settings.name = "Non-Color"

    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0))
    floor = bpy.context.object
    floor.name = "Floor"
    floor.data.materials.append(material("FloorChecker", checker, 0.0, 0.25))

    bpy.ops.mesh.primitive_cube_add(size=1.2, location=(-1.3, 0.4, 0.6),
                                    rotation=(0, 0, math.radians(30)))
    cube = bpy.context.object
    cube.name = "BrickCube"
    cube.data.materials.append(material("Bricks", bricks, 0.0, 0.25, normal_image=bumps))

    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.7,
                                         location=(1.2, -0.3, 0.7))
    sphere = bpy.context.object
    sphere.name = "StripedSphere"
    bpy.ops.object.shade_smooth()
    sphere.data.materials.append(material("Stripes", stripes, 0.5, 0.5))
    for obj, index in ((floor, FLOOR), (cube, CUBE), (sphere, SPHERE)):
        obj.pass_index = index

    point = bpy.data.lights.new("PointLight", type="POINT")
    point.energy = 600.0  # W
    point.color = (1.0, 0.9, 0.8)
    point.shadow_soft_size = 0.0  # a true point light: hard shadows, as glTF means it
    point_obj = bpy.data.objects.new("PointLight", point)
    point_obj.location = (2.5, -2.0, 3.5)
    scene.collection.objects.link(point_obj)

    sun = bpy.data.lights.new("Sun", type="SUN")
    sun.energy = 2.0  # W/m^2
    sun.angle = 0.0  # a true directional light
    sun_obj = bpy.data.objects.new("Sun", sun)
    sun_direction = Vector((0.6, 0.5, -0.62)).normalized()  # travel direction
    sun_obj.rotation_euler = sun_direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(sun_obj)

    cam = bpy.data.cameras.new("Camera")
    cam.lens = 35.0
    cam_obj = bpy.data.objects.new("Camera", cam)
    cam_obj.location = (0.4, -7.0, 3.6)
    look_at = Vector((0.0, 0.0, 0.5))
    cam_obj.rotation_euler = (look_at - cam_obj.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(cam_obj)
    scene.camera = cam_obj

    # The exporter writes the camera's aspect ratio (and its yfov from the sensor fit) from
    # the render resolution, so it is set before exporting.
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    bpy.context.view_layer.update()

    lights = {}
    for obj in (point_obj, sun_obj):
        l = obj.data
        lights[obj.name] = {"type": l.type, "energy": l.energy, "color": list(l.color)}
        if l.type == "SUN":
            lights[obj.name]["angle"] = l.angle
        else:
            lights[obj.name]["radius"] = l.shadow_soft_size
    with open(os.path.join(out_dir, "blender_lights.json"), "w") as f:
        json.dump(lights, f, indent=2)
    return scene


def export(path, lighting_mode):
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB", export_lights=True,
                              export_cameras=True, export_tangents=True,
                              export_image_format="AUTO", convert_lighting_mode=lighting_mode)


def render(scene, path, width, height, spp, threads, seed):
    cycles_render.set_up_direct_light_render(scene, path, width, height, spp, threads, seed)
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    bpy.context.view_layer.use_pass_object_index = True
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    print("CYCLES_RENDER_TIME %d %.3f" % (seed, time.perf_counter() - start))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="blender_asset.py")
    parser.add_argument("out_dir")
    parser.add_argument("--res", default="400x300")
    parser.add_argument("--spp", type=int, default=512)
    parser.add_argument("--seeds", default="0,1",
                        help="one Cycles render per seed; two give the noise estimate")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--lambert", action="store_true",
                        help="also render with every material a Diffuse BSDF of its base colour")
    args = parser.parse_args(argv)
    width, height = (int(v) for v in args.res.lower().split("x"))
    out_dir = os.path.abspath(args.out_dir)
    os.makedirs(out_dir, exist_ok=True)

    scene = build_scene(out_dir, width, height)
    export(os.path.join(out_dir, "asset_spec.glb"), "SPEC")
    export(os.path.join(out_dir, "asset.glb"), "COMPAT")
    seeds = [int(s) for s in args.seeds.split(",") if s]
    for seed in seeds:
        render(scene, os.path.join(out_dir, "cycles_seed%d.exr" % seed), width, height,
               args.spp, args.threads, seed)
    if args.lambert:
        cycles_render.make_lambertian()
        render(scene, os.path.join(out_dir, "cycles_lambert_seed%d.exr" % seeds[0]), width,
               height, args.spp, args.threads, seeds[0])


main()
