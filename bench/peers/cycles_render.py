"""Renders a glTF scene with Blender Cycles, direct light only, for bench/peers/, or path
traced for bench/cycles_path_compare.py.

    blender -b --factory-startup --python-exit-code 1 --python bench/peers/cycles_render.py \
        -- SCENE.glb|gltf OUT.exr --res WxH --spp N [--threads 2] [--seed 0] [--lambert]
        [--max-bounces B [--environment MAP.exr] [--environment-strength K] [--no-key-light]]
        [--adaptive-threshold T [--adaptive-min-samples N]]

--max-bounces B renders with path tracing instead (set_up_path_render): B bounces after
the first hit, i.e. Prism's `path --max-depth B+1` (Cycles' max_bounces 0 is direct light
only, Prism's max-depth 1). Its world is MAP.exr (equirectangular, closest-texel lookup as
Prism's, linear) times K, or black; every Principled BSDF is set to single-scattering 'GGX'.

What it sets up, so that Cycles sees what Prism's `shadow` integrator sees:
- an empty scene (the factory startup cube, camera and lamp are removed) and a black world;
- glTF import with convert_lighting_mode='COMPAT': point/spot lights get P = 4 pi I watts
  (I in candela read as W/sr; Cycles' point lamp of P watts has intensity P / (4 pi) W/sr),
  suns get I W/m^2. The importer's default, 'SPEC', also divides by 683 lm/W, which makes
  the lights 683 times weaker than Prism's, which reads candela as W/sr.
- punctual lights made point-like: the importer leaves Blender's default radius
  (shadow_soft_size 0.25 m), which would make them sphere lights with soft shadows;
- without lights, the same default directional key light Prism adds (pi W/m^2 along the
  camera's forward - 0.6 up + 0.4 right, scene_passes/scene_defaults.cpp);
- the glTF scene's first camera, the given resolution, a 1-pixel box filter (Prism's
  samples are uniform in the pixel square), fixed samples (no adaptive sampling, no
  denoising), max_bounces = 0 (camera ray + light samples only: direct light);
- CPU, a fixed thread count, and a scene-linear 32-bit float EXR (view transform Standard,
  which EXR output ignores anyway).
Prints "PEER_RENDER_TIME <s>" (bpy.ops.render.render: sync, BVH build and sampling) and
"PEER_IMPORT_TIME <s>".
"""
import argparse
import math
import sys
import time

import numpy

numpy.bool = bool  # Blender 3.4's glTF importer uses numpy.bool, gone in NumPy 1.24

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402


def make_lambertian():
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        nodes = material.node_tree.nodes
        principled = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
        output = next((n for n in nodes if n.type == "OUTPUT_MATERIAL"), None)
        if principled is None or output is None:
            continue
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Roughness"].default_value = 0.0  # Oren-Nayar at 0 is Lambert
        base = principled.inputs["Base Color"]
        if base.is_linked:
            material.node_tree.links.new(base.links[0].from_socket, diffuse.inputs["Color"])
        else:
            diffuse.inputs["Color"].default_value = base.default_value
        surface = diffuse.outputs["BSDF"]
        # Keep an emissive material's light (the Cornell box's ceiling panel).
        emission_colour = principled.inputs["Emission"]
        strength = principled.inputs["Emission Strength"].default_value
        if emission_colour.is_linked or (strength > 0 and
                                         any(emission_colour.default_value[:3])):
            emission = nodes.new("ShaderNodeEmission")
            if emission_colour.is_linked:
                material.node_tree.links.new(emission_colour.links[0].from_socket,
                                             emission.inputs["Color"])
            else:
                emission.inputs["Color"].default_value = emission_colour.default_value
            emission.inputs["Strength"].default_value = strength
            add = nodes.new("ShaderNodeAddShader")
            material.node_tree.links.new(surface, add.inputs[0])
            material.node_tree.links.new(emission.outputs["Emission"], add.inputs[1])
            surface = add.outputs["Shader"]
        material.node_tree.links.new(surface, output.inputs["Surface"])


def set_up_direct_light_render(scene, output, width, height, spp, threads, seed):
    """Black world, Cycles direct light only (max_bounces 0), fixed samples, 1-pixel box
    filter, fixed threads, Standard view, 32-bit float EXR at `output`. Shared with
    bench/peers/blender_asset.py."""
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = spp
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = seed
    cycles.max_bounces = 0
    cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = 0
    cycles.volume_bounces = cycles.transparent_max_bounces = 0
    cycles.caustics_reflective = cycles.caustics_refractive = False
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    cycles.filter_type = "BOX"
    cycles.filter_width = 1.0
    cycles.use_auto_tile = False
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.color_mode = "RGBA"
    settings.exr_codec = "ZIP"
    scene.render.filepath = output
    scene.render.use_file_extension = False


def set_up_path_render(scene, max_bounces, environment, strength):
    """Path tracing with `max_bounces` bounces of every kind, nothing biased away: no glossy
    filter, no clamping, caustics on, no light threshold, no light tree; single-scattering
    GGX on every Principled BSDF (Multiscatter GGX adds energy glTF's BRDF does not have);
    the world is `environment` (or black). Call after set_up_direct_light_render."""
    cycles = scene.cycles
    cycles.max_bounces = max_bounces
    cycles.diffuse_bounces = cycles.glossy_bounces = max_bounces
    cycles.transmission_bounces = cycles.transparent_max_bounces = max_bounces
    cycles.volume_bounces = 0
    cycles.min_light_bounces = cycles.min_transparent_bounces = 0
    cycles.caustics_reflective = cycles.caustics_refractive = True
    cycles.blur_glossy = 0.0  # "Filter Glossy" in the UI
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    if hasattr(cycles, "use_light_tree"):  # Blender 3.5 on; 3.4 has none
        cycles.use_light_tree = False
    for material in bpy.data.materials:
        if material.use_nodes:
            for node in material.node_tree.nodes:
                if node.type == "BSDF_PRINCIPLED":
                    node.distribution = "GGX"
    if environment:
        world = scene.world
        nodes, links = world.node_tree.nodes, world.node_tree.links
        texture = nodes.new("ShaderNodeTexEnvironment")
        texture.image = bpy.data.images.load(environment)
        texture.image.colorspace_settings.name = "Linear"
        texture.interpolation = "Closest"
        texture.projection = "EQUIRECTANGULAR"
        background = nodes["Background"]
        links.new(texture.outputs["Color"], background.inputs["Color"])
        background.inputs["Strength"].default_value = strength
        world.cycles.sampling_method = "MANUAL"
        # Importance-sample the map at its own resolution (Prism samples texels exactly).
        world.cycles.sample_map_resolution = max(texture.image.size[0], 64)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="cycles_render.py")
    parser.add_argument("scene")
    parser.add_argument("output")
    parser.add_argument("--res", required=True)
    parser.add_argument("--spp", type=int, required=True)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--lambert", action="store_true",
                        help="replace every material by a Diffuse BSDF (Lambert) of its base "
                             "colour: isolates the light units from the Principled BSDF")
    parser.add_argument("--max-bounces", type=int, default=None,
                        help="path trace with this many bounces (Prism's max-depth - 1)")
    parser.add_argument("--environment", default="",
                        help="with --max-bounces: an equirectangular map as the world")
    parser.add_argument("--environment-strength", type=float, default=1.0)
    parser.add_argument("--adaptive-threshold", type=float, default=0.0,
                        help="Cycles' adaptive sampling with this noise threshold, --spp the "
                             "most a pixel takes (0: fixed samples)")
    parser.add_argument("--adaptive-min-samples", type=int, default=0,
                        help="with --adaptive-threshold: the samples every pixel takes first "
                             "(0: Cycles' automatic choice)")
    parser.add_argument("--no-key-light", action="store_true",
                        help="do not add Prism's default key light to a scene without lights")
    args = parser.parse_args(argv)
    width, height = (int(v) for v in args.res.lower().split("x"))

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    start = time.perf_counter()
    bpy.ops.import_scene.gltf(filepath=args.scene, convert_lighting_mode="COMPAT")
    print("PEER_IMPORT_TIME %.4f" % (time.perf_counter() - start))

    cameras = [o for o in scene.objects if o.type == "CAMERA"]
    if not cameras:
        raise SystemExit("the scene has no camera")
    # The importer names objects after glTF nodes; take the first camera in name order as a
    # stand-in for "the first glTF camera" (the scenes used here have one).
    scene.camera = sorted(cameras, key=lambda o: o.name)[0]
    bpy.context.view_layer.update()

    lights = [o for o in scene.objects if o.type == "LIGHT"]
    for light in lights:
        if light.data.type in ("POINT", "SPOT"):
            light.data.shadow_soft_size = 0.0
    if not lights and not args.no_key_light:
        m = scene.camera.matrix_world
        right = m.col[0].xyz.normalized()
        up = m.col[1].xyz.normalized()
        forward = -m.col[2].xyz.normalized()
        direction = (forward - 0.6 * up + 0.4 * right).normalized()
        sun = bpy.data.lights.new("default key light", type="SUN")
        sun.energy = math.pi
        sun.angle = 0.0
        obj = bpy.data.objects.new("default key light", sun)
        scene.collection.objects.link(obj)
        obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
        print("no lights: added a pi W/m^2 sun along", tuple(round(c, 4) for c in direction))

    if args.lambert:
        make_lambertian()

    set_up_direct_light_render(scene, args.output, width, height, args.spp, args.threads,
                               args.seed)
    if args.max_bounces is not None:
        set_up_path_render(scene, args.max_bounces, args.environment,
                           args.environment_strength)
    if args.adaptive_threshold > 0:
        scene.cycles.use_adaptive_sampling = True
        scene.cycles.adaptive_threshold = args.adaptive_threshold
        scene.cycles.adaptive_min_samples = args.adaptive_min_samples

    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    print("PEER_RENDER_TIME %.4f" % (time.perf_counter() - start))


if __name__ == "__main__":  # also imported by blender_asset.py for its pieces
    main()
