#!/usr/bin/env python3
"""Time to equal error: Caustic's path tracer against Blender Cycles (CPU) on one scene.

The scene is translated from Caustic's JSON into Blender through `bpy` (PyPI's Blender as a
Python module). Each renderer renders at every spp of a ladder; each RMSE is against Caustic's
long reference less that reference's noise, and Caustic's time to Cycles' RMSE is interpolated on
its own ladder (bench/ladder.py). Cycles runs twice: with the settings that make it estimate what
Caustic estimates (no adaptive sampling), and with its adaptive sampling on. See bench/README.md,
"cycles_compare".
"""
import argparse
import json
import math
import os
import shlex
import sys
import tempfile
import time
from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix, Vector

import caustic_cli
from ladder import caustic_ladder, print_table, set_errors, settings_at

REPO = Path(__file__).resolve().parent.parent
REFERENCE_SEED = caustic_cli.REFERENCE_SEED


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"), help="caustic binary")
    p.add_argument("--scene", default=str(REPO / "scenes/cornell-spheres.json"))
    p.add_argument("--size", type=int, default=256, help="image width and height")
    p.add_argument("--ladder", type=lambda v: [int(x) for x in v.split(",")],
                   default=[16, 32, 64, 128, 256], help="comma-separated spp")
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--max-depth", type=int, default=16, help="Caustic's: most scattering events")
    p.add_argument("--rr-depth", type=int, default=5, help="Caustic's bounces before roulette")
    p.add_argument("--threads", type=int, default=os.cpu_count())
    p.add_argument("--caustic-set", action="append", default=[], metavar="KEY=VALUE",
                   help="a setting for Caustic's timed renders (not its reference), repeatable")
    p.add_argument("--caustic-rungs", type=lambda v: [int(x) for x in v.split(",")], default=[],
                   help="comma-separated spp Caustic renders besides the ladder (e.g. 4,8: its "
                   "time to Cycles' low-spp errors is then interpolated, not extrapolated)")
    p.add_argument("--cache-dir", help="where references are kept (default: the caustic "
                   "binary's build dir /mitsuba_compare, shared with mitsuba_compare.sh)")
    p.add_argument("--smoke", action="store_true", help="32x32, ladder 1,2,4, 16-spp reference")
    args = p.parse_args()
    if args.smoke:
        args.size, args.ladder, args.ref_spp = 32, [1, 2, 4], 16
    if args.cache_dir is None:
        args.cache_dir = str(Path(args.caustic).resolve().parent.parent / "mitsuba_compare")
    return args


# ---- The scene in Blender. Caustic's coordinates are kept as they are (y up): only the camera
# needs an orientation, and it gets Caustic's.

def material(name, m):
    """Caustic's materials scatter from both sides, as Cycles' do. An emitter emits from its front
    only (Caustic's quads emit on the side of cross(u, v)): Cycles emits from both sides, so the
    emission is mixed with black on back faces (Geometry > Backfacing)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    kind = m["type"]
    if kind == "diffuse":
        surface = nodes.new("ShaderNodeBsdfDiffuse")
        surface.inputs["Color"].default_value = (*m.get("albedo", [0.5] * 3), 1)
        surface.inputs["Roughness"].default_value = 0.0  # Lambert
    elif kind == "mirror":
        surface = nodes.new("ShaderNodeBsdfGlossy")
        surface.inputs["Color"].default_value = (*m.get("reflectance", [1, 1, 1]), 1)
        surface.inputs["Roughness"].default_value = 0.0
    elif kind == "dielectric":
        if m.get("fresnel", "exact") != "exact":
            sys.exit("cycles_compare: Cycles has no Schlick dielectric")
        surface = nodes.new("ShaderNodeBsdfGlass")
        surface.inputs["Color"].default_value = (*m.get("tint", [1, 1, 1]), 1)
        surface.inputs["Roughness"].default_value = 0.0
        surface.inputs["IOR"].default_value = float(m.get("ior", 1.5))
    elif kind == "metallic_roughness":
        surface = principled(nodes, links, m)
    else:
        sys.exit(f"cycles_compare: material type {kind!r} has no translation")
    shader = surface.outputs[0]
    emission = m.get("emission", [0, 0, 0])
    if any(c > 0 for c in emission):
        # An Emission shader of strength 1 gives radiance equal to its color.
        emit = nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (*emission, 1)
        emit.inputs["Strength"].default_value = 1.0
        geometry = nodes.new("ShaderNodeNewGeometry")
        front = nodes.new("ShaderNodeMixShader")
        links.new(geometry.outputs["Backfacing"], front.inputs["Fac"])
        links.new(emit.outputs[0], front.inputs[1])  # Fac 0 (front face): the emission
        add = nodes.new("ShaderNodeAddShader")
        links.new(shader, add.inputs[0])
        links.new(front.outputs[0], add.inputs[1])
        shader = add.outputs[0]
    links.new(shader, out.inputs["Surface"])
    return mat


def principled(nodes, links, m):
    """metallic_roughness (glTF's model) as the Principled BSDF: not the same model (Cycles
    layers its specular over the diffuse by the specular's albedo, where glTF mixes them by a
    Fresnel term), so the comparison is of means, within 3%. IOR 1.5 is glTF's F0 of 0.04;
    roughness is perceptual in both; multiple-scattering GGX, as Caustic's compensation. Only the
    base colour may be a texture, sRGB, through its KHR_texture_transform."""
    for key in ("metallic_roughness_texture", "normal_texture", "emissive_texture",
                "transmission", "alpha_mode"):
        if key in m:
            sys.exit(f"cycles_compare: the Principled BSDF has no translation of {key!r}")
    surface = nodes.new("ShaderNodeBsdfPrincipled")
    surface.distribution = "MULTI_GGX"
    surface.inputs["Base Color"].default_value = (*m.get("base_color", [1, 1, 1]), 1)
    surface.inputs["Metallic"].default_value = float(m.get("metallic", 1.0))
    surface.inputs["Roughness"].default_value = float(m.get("roughness", 1.0))
    surface.inputs["IOR"].default_value = 1.5
    surface.inputs["Specular IOR Level"].default_value = 0.5
    slot = m.get("base_color_texture")
    if slot is not None:
        if "base_color" in m:
            sys.exit("cycles_compare: a base colour texture times a factor has no translation")
        name = slot["file"] if isinstance(slot, dict) else slot
        t = slot.get("transform", {}) if isinstance(slot, dict) else {}
        image = nodes.new("ShaderNodeTexImage")
        image.image = bpy.data.images.load(str(REPO / "assets/meshes" / name))
        image.image.colorspace_settings.name = "sRGB"
        image.interpolation = "Linear"
        # glTF's texture coordinates have t down the image, Blender's v up it: the mesh's UVs are
        # glTF's (quad_uvs), flipped here after the transform (scale, rotation, offset).
        coords = nodes.new("ShaderNodeTexCoord")
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Scale"].default_value = (*t.get("scale", [1, 1]), 1)
        mapping.inputs["Rotation"].default_value = (0, 0, math.radians(t.get("rotation", 0.0)))
        mapping.inputs["Location"].default_value = (*t.get("offset", [0, 0]), 0)
        flip = nodes.new("ShaderNodeMapping")
        flip.inputs["Scale"].default_value = (1, -1, 1)
        flip.inputs["Location"].default_value = (0, 1, 0)
        links.new(coords.outputs["UV"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], flip.inputs["Vector"])
        links.new(flip.outputs["Vector"], image.inputs["Vector"])
        links.new(image.outputs["Color"], surface.inputs["Base Color"])
    return surface


def environment_world(env):
    """Caustic's environment as a Blender world. Coordinates are Caustic's (y up); Blender's
    equirectangular lookup assumes z up and u = 0.5 - atan2(y, x) / 2 pi, Caustic's
    u = atan2(x, -z) / 2 pi of the direction turned back by the rotation about y, v from +y
    (lights/environment_light.cpp): the direction d becomes (d.z, d.x, d.y) for Blender."""
    world = bpy.data.worlds.new("environment")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes["Background"]
    background.inputs["Strength"].default_value = float(env.get("strength", 1.0))
    if "color" in env:
        background.inputs["Color"].default_value = (*env["color"], 1)
        return world
    coords = nodes.new("ShaderNodeTexCoord")
    turn = nodes.new("ShaderNodeVectorRotate")
    turn.rotation_type = "Y_AXIS"
    turn.invert = True
    turn.inputs["Angle"].default_value = math.radians(float(env.get("rotation", 0.0)))
    split = nodes.new("ShaderNodeSeparateXYZ")
    join = nodes.new("ShaderNodeCombineXYZ")
    texture = nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(str(REPO / "assets/meshes" / env["file"]))
    texture.image.colorspace_settings.name = "Linear Rec.709"
    texture.interpolation = "Linear"
    links.new(coords.outputs["Generated"], turn.inputs["Vector"])
    links.new(turn.outputs["Vector"], split.inputs["Vector"])
    links.new(split.outputs["Z"], join.inputs["X"])
    links.new(split.outputs["X"], join.inputs["Y"])
    links.new(split.outputs["Y"], join.inputs["Z"])
    links.new(join.outputs["Vector"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], background.inputs["Color"])
    return world


def mesh_object(name, verts, faces, mat, smooth=False, uvs=None):
    """uvs: one (u, v) per face corner, in the order of the faces' vertices."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(v) for v in verts], [], faces)
    if uvs is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        for loop, uv in zip(layer.data, uvs):
            loop.uv = uv
    mesh.update()
    for poly in mesh.polygons:
        poly.use_smooth = smooth
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def sphere(name, center, radius, mat, flip):
    """A UV sphere of 256 x 128 quads, smooth-shaded: Cycles has no analytic sphere for
    surfaces (its point clouds are for particles)."""
    segments, rings = 256, 128
    verts = [(0, 0, radius)]
    for i in range(1, rings):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            verts.append((radius * math.sin(theta) * math.cos(phi),
                          radius * math.sin(theta) * math.sin(phi), radius * math.cos(theta)))
    verts.append((0, 0, -radius))
    verts = [Vector(v) + Vector(center) for v in verts]
    faces, last = [], len(verts) - 1
    ring = lambda i, j: 1 + (i - 1) * segments + j % segments  # noqa: E731
    for j in range(segments):
        faces.append((0, ring(1, j), ring(1, j + 1)))
        faces.append((last, ring(rings - 1, j + 1), ring(rings - 1, j)))
    for i in range(1, rings - 1):
        for j in range(segments):
            faces.append((ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)))
    if flip:
        faces = [tuple(reversed(f)) for f in faces]
    return mesh_object(name, verts, faces, mat, smooth=True)


def obj_mesh(name, path, transform, mat):
    """An OBJ as Caustic reads it: positions and faces only, shaded flat, under its transform
    (scene/mesh_loader.cpp: scale, then rotations about x, y, z in degrees, then translation)."""
    verts, faces = [], []
    for line in Path(path).read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            verts.append(Vector(float(c) for c in parts[1:4]))
        elif parts[0] == "f":
            idx = [int(p.split("/")[0]) for p in parts[1:]]
            faces.append(tuple(i - 1 if i > 0 else len(verts) + i for i in idx))
    scale = transform.get("scale", 1.0)
    scale = [float(scale)] * 3 if isinstance(scale, (int, float)) else scale
    rx, ry, rz = (math.radians(float(c)) for c in transform.get("rotate", [0, 0, 0]))
    m = (Matrix.Translation(Vector(transform.get("translate", [0, 0, 0])))
         @ Matrix.Rotation(rz, 4, "Z") @ Matrix.Rotation(ry, 4, "Y") @ Matrix.Rotation(rx, 4, "X")
         @ Matrix.Diagonal((*scale, 1)))
    return mesh_object(name, [m @ v for v in verts], faces, mat)


def camera(cam):
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(float(cam.get("fov", 40)))
    obj = bpy.data.objects.new("camera", data)
    bpy.context.scene.collection.objects.link(obj)
    position, target = Vector(cam["position"]), Vector(cam["look_at"])
    forward = (target - position).normalized()
    right = forward.cross(Vector(cam.get("up", [0, 1, 0]))).normalized()
    up = right.cross(forward)
    # A Blender camera looks down its -z with +y up.
    obj.matrix_world = Matrix((
        (right.x, up.x, -forward.x, position.x), (right.y, up.y, -forward.y, position.y),
        (right.z, up.z, -forward.z, position.z), (0, 0, 0, 1)))
    return obj


def build_scene(scene, args):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if scene.get("lights") or any(scene.get("background", [0, 0, 0])):
        sys.exit("cycles_compare: point lights and backgrounds have no translation")
    mats = {name: material(name, m) for name, m in scene["materials"].items()}
    for i, s in enumerate(scene["shapes"]):
        mat = mats[s["material"]]
        if s["type"] == "quad":
            o, u, v = (Vector(s[k]) for k in ("origin", "u", "v"))
            # Caustic's texture coordinates of a quad: (s, 1 - t) at origin + s u + t v.
            mesh_object(f"shape{i}", [o, o + u, o + u + v, o + v], [(0, 1, 2, 3)], mat,
                        uvs=[(0, 1), (1, 1), (1, 0), (0, 0)])
        elif s["type"] == "sphere":
            sphere(f"shape{i}", s["center"], float(s["radius"]), mat,
                   bool(s.get("flip_normals", False)))
        elif s["type"] == "mesh":
            obj_mesh(f"shape{i}", REPO / "assets/meshes" / s["file"], s.get("transform", {}),
                     mat)
        else:
            sys.exit(f"cycles_compare: shape type {s['type']!r} has no translation")
    bl = bpy.context.scene
    bl.camera = camera(scene["camera"])
    if "environment" in scene:
        bl.world = environment_world(scene["environment"])
    configure_cycles(bl, args.size, args.size, args)
    return bl


def configure_cycles(bl, width, height, args):
    """Cycles as the comparisons render: CPU, args.threads, a width x height 32-bit EXR, the
    Standard view, a box filter of one pixel, no clamping, caustics on, no glossy blur, the bounce
    limits of args.max_depth; a black world unless the scene has one."""
    if bl.world is None:
        world = bpy.data.worlds.new("black")
        world.use_nodes = True
        world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
        bl.world = world
    r = bl.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = width, height
    r.resolution_percentage = 100
    r.threads_mode, r.threads = "FIXED", args.threads
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    bl.view_settings.view_transform = "Standard"
    c = bl.cycles
    c.device = "CPU"
    c.pixel_filter_type, c.filter_width = "BOX", 1.0
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.use_denoising = False
    # Caustic's max_depth counts scattering events (1: direct light), Cycles' bounces after the
    # first hit (0: direct light).
    bounces = args.max_depth - 1
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = bounces
    c.transmission_bounces = c.transparent_max_bounces = bounces


def render_cycles(bl, spp, seed, adaptive, out):
    c = bl.cycles
    c.samples, c.seed = spp, seed
    c.use_adaptive_sampling = adaptive
    bl.render.filepath = str(out)
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - t0
    return read_exr(out), seconds


def read_exr(path):
    """Linear RGB, top row first (Blender's pixel buffer starts at the bottom; its EXR is RGBA)."""
    image = bpy.data.images.load(str(path))
    image.colorspace_settings.name = "Non-Color"
    w, h = image.size
    pixels = np.array(image.pixels[:], dtype=np.float64).reshape(h, w, 4)[::-1, :, :3]
    bpy.data.images.remove(image)
    return pixels


def main():
    args = parse_args()
    cache = Path(args.cache_dir)
    cache.mkdir(parents=True, exist_ok=True)
    scene = caustic_cli.load_scene(args.scene, args.size)
    command = os.environ.get("COMPARE_COMMAND") or shlex.join(sys.argv)
    print(f"Machine: nproc {os.cpu_count()}, Blender {bpy.app.version_string} Cycles CPU, "
          f"{args.threads} threads. Command: `{command}`\n")
    with tempfile.TemporaryDirectory() as scratch:
        scene_path = Path(scratch) / "scene.json"
        scene_path.write_text(json.dumps(scene))
        ref, how, noise2 = caustic_cli.reference(args, scene, scene_path, cache, read_exr,
                                                 REFERENCE_SEED)
        bl = build_scene(scene, args)
        out = Path(scratch) / "cycles.exr"
        # Untimed warm-ups: Cycles compiles its kernels and builds its BVH on the first render.
        render_cycles(bl, 1, 0, False, out)
        mine = caustic_ladder(args)
        caustic_cli.render(args, scene_path, mine[0], 0, settings_at(args.caustic_set, mine[0]),
                           read_exr)
        runs = {"caustic": [], "cycles": [], "cycles adaptive": []}
        # Rung by rung, alternating; each rung's seed is its index in its renderer's ladder.
        for spp in sorted(set(mine) | set(args.ladder)):
            if spp in mine:
                image, stats, _ = caustic_cli.render(args, scene_path, spp, mine.index(spp),
                                                     settings_at(args.caustic_set, spp), read_exr)
                runs["caustic"].append({"spp": spp, "image": image,
                                        "time": stats["render_seconds"] + stats["setup_seconds"]})
            if spp not in args.ladder:
                continue
            for name, adaptive in (("cycles", False), ("cycles adaptive", True)):
                image, seconds = render_cycles(bl, spp, sorted(args.ladder).index(spp), adaptive,
                                               out)
                runs[name].append({"spp": spp, "image": image, "time": seconds})
    set_errors(runs, ref, noise2)
    settings = ", ".join(args.caustic_set) or "the scene's"
    print(f"{Path(args.scene).name}, {args.size}x{args.size}; Caustic `path` with settings "
          f"{settings}; Cycles' time is the whole `render.render` call (its scene sync and BVH "
          f"included, as Caustic's setup is). Reference: Caustic, {args.ref_spp} spp, {how}; its "
          f"noise, {math.sqrt(noise2):.5f} RMSE, is taken out of every RMSE. Reference mean "
          f"{ref.mean():.5f}; Cycles' highest rung's mean {runs['cycles'][-1]['image'].mean():.5f}."
          f"\n")
    print("Cycles as Caustic estimates (adaptive sampling off):\n")
    print_table(runs["caustic"], runs["cycles"], "Cycles")
    print("\nCycles with its adaptive sampling (threshold 0.01, its default):\n")
    print_table(runs["caustic"], runs["cycles adaptive"], "Cycles adaptive")


if __name__ == "__main__":
    main()
