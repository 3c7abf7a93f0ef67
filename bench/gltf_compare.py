#!/usr/bin/env python3
"""glTF files written by a real exporter, rendered by Caustic from the file and by Blender Cycles
from the same file through Blender's importer (issue 39, acceptance 1): channel means within 3%,
and the pictures side by side.

Builds four scenes in Blender (bpy from PyPI) and exports each with Blender's glTF exporter:
  textured  a floor with a base colour image, Spot (a textured cow), a gold sphere and a rough
            red plastic teapot, under a sun and a point light, seen through the file's camera;
  glass     a smooth glass monkey and a frosted glass sphere on the tiled floor, a spot light, a
            point light and an emissive panel (KHR_materials_emissive_strength);
  lights    three coloured spot lights, a point light and a sun on a grey floor and white shapes;
  draco     the textured scene again, its meshes Draco-compressed (KHR_draco_mesh_compression).
Then, per scene: Cycles renders it after importing the .glb into an empty Blender scene (its
world black, as the file has none), Caustic with `caustic render FILE.glb`; both path trace at
--spp with the same bounce limit and write linear EXR. Caustic adds its caustic photon map
(`caustics=photon_map`, biased but consistent: its radius shrinks pass by pass): a path tracer
cannot reach a point light through smooth glass, and Cycles, whose roughness-0 glass is a
microfacet surface of a tiny roughness, reaches it by light sampling at the price of rare,
enormous samples. Prints a Markdown table of the channel
means and writes docs/images/gltf-side-by-side.png (Caustic above, Cycles below, one column per
scene).

Runs in the Cycles venv (bench/gltf_compare.sh). Not in CTest: bpy is about 400 MB.
"""
import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cycles_compare import configure_cycles, read_exr, render_cycles  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
MESHES = REPO / "assets/meshes"
SCENES = ("textured", "glass", "lights", "draco")


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"))
    p.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--spp", type=int, default=512)
    p.add_argument("--max-depth", type=int, default=8)
    p.add_argument("--threads", type=int, default=os.cpu_count())
    p.add_argument("--out", default=str(REPO / "docs/images"))
    p.add_argument("--keep", help="a folder to keep the .glb files and EXR images in")
    p.add_argument("--smoke", action="store_true", help="80 pixels wide, 8 spp")
    p.add_argument("--export", metavar="DIR",
                   help="only write the scenes' .glb files into DIR (the repository's example "
                   "assets/models/still-life.glb is the draco scene)")
    args = p.parse_args()
    if args.smoke:
        args.width, args.spp = 80, 8
    return args


# Scene building (Blender's own coordinates: z up; the exporter turns them y up).

def material(name, color=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.5, image=None,
             transmission=0.0, emission=None, strength=1.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Transmission Weight"].default_value = transmission
    if emission:
        bsdf.inputs["Emission Color"].default_value = (*emission, 1)
        bsdf.inputs["Emission Strength"].default_value = strength
    if image:
        tex = m.node_tree.nodes.new("ShaderNodeTexImage")
        tex.image = bpy.data.images.load(str(MESHES / image))
        m.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return m


def assign(obj, mat):
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    return obj


def floor(mat, size=8):
    bpy.ops.mesh.primitive_plane_add(size=size)
    return assign(bpy.context.object, mat)


def obj_file(name, location, scale, rotation, mat, smooth=True):
    bpy.ops.wm.obj_import(filepath=str(MESHES / name), forward_axis="NEGATIVE_Y", up_axis="Z")
    o = bpy.context.selected_objects[0]
    o.location, o.scale, o.rotation_euler = location, (scale,) * 3, rotation
    if smooth:
        bpy.ops.object.shade_smooth()
    return assign(o, mat)


def sphere(location, radius, mat):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=radius,
                                         location=location)
    bpy.ops.object.shade_smooth()
    return assign(bpy.context.object, mat)


def light(kind, location, energy, color=(1, 1, 1), aim=None, size=0.0, blend=0.15):
    bpy.ops.object.light_add(type=kind, location=location)
    o = bpy.context.object
    o.data.energy, o.data.color = energy, color
    if kind != "SUN":
        o.data.shadow_soft_size = 0.0  # punctual, as glTF's are
    else:
        o.data.angle = 0.0
    if kind == "SPOT":
        o.data.spot_size, o.data.spot_blend = size, blend
    if aim is not None:
        direction = Vector(aim) - Vector(location)
        o.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    return o


def camera(location, aim, lens=40):
    bpy.ops.object.camera_add(location=location)
    o = bpy.context.object
    o.rotation_euler = (Vector(aim) - Vector(location)).to_track_quat("-Z", "Y").to_euler()
    o.data.lens = lens
    bpy.context.scene.camera = o
    bpy.context.scene.render.resolution_x, bpy.context.scene.render.resolution_y = 16, 9


def build_textured():
    floor(material("Tiles", roughness=0.6, image="tiles.png"))
    obj_file("spot.obj", (-0.9, 0.2, 0.73), 1.0, (math.radians(90), 0, math.radians(-30)),
             material("Spot", roughness=0.45, image="spot-pattern.png"))
    sphere((0.9, -0.2, 0.55), 0.55, material("Gold", (1.0, 0.77, 0.34), metallic=1.0,
                                              roughness=0.25))
    obj_file("teapot.obj", (0.3, 1.5, 0.0), 0.35, (math.radians(90), 0, 0),
             material("RedPlastic", (0.8, 0.1, 0.08), roughness=0.35))
    light("SUN", (3, -4, 6), 2.5, (1.0, 0.95, 0.9), aim=(0, 0, 0))
    light("POINT", (-2.5, -2.0, 3.0), 600, (0.9, 0.95, 1.0))
    camera((0.0, -5.5, 2.6), (0.0, 0.3, 0.55))


def build_glass():
    floor(material("Tiles", roughness=0.5, image="tiles.png"))
    bpy.ops.mesh.primitive_monkey_add(location=(-0.7, 0, 0.75), rotation=(math.radians(-20), 0, 0))
    monkey = bpy.context.object
    monkey.modifiers.new("smooth", "SUBSURF").levels = 2
    bpy.ops.object.shade_smooth()
    assign(monkey, material("Glass", (1, 1, 1), roughness=0.0, transmission=1.0))
    sphere((0.9, 0.3, 0.5), 0.5, material("Frosted", (0.9, 0.95, 1.0), roughness=0.3,
                                          transmission=1.0))
    bpy.ops.mesh.primitive_plane_add(size=1.5, location=(0, 2.5, 1.5),
                                     rotation=(math.radians(90), 0, 0))
    assign(bpy.context.object, material("Panel", (0, 0, 0), roughness=1.0,
                                        emission=(1.0, 0.9, 0.8), strength=6.0))
    light("SPOT", (2.5, -2.5, 4.0), 1500, aim=(0, 0, 0), size=math.radians(50))
    light("POINT", (-2.5, -1.5, 2.5), 400)
    camera((0.0, -5.0, 2.2), (0.0, 0.3, 0.6))


def build_lights():
    floor(material("Grey", (0.5, 0.5, 0.5), roughness=0.8), size=10)
    obj_file("stanford-bunny.obj", (0.0, 0.3, -0.33), 10.0, (math.radians(90), 0, 0),
             material("White", (0.85, 0.85, 0.85), roughness=0.5))
    sphere((-1.6, 0.0, 0.5), 0.5, material("Copper", (0.95, 0.64, 0.54), metallic=1.0,
                                           roughness=0.35))
    sphere((1.6, 0.2, 0.5), 0.5, material("Plastic", (0.2, 0.4, 0.8), roughness=0.3))
    for color, x in (((1.0, 0.2, 0.2), -2.0), ((0.2, 1.0, 0.2), 0.0), ((0.3, 0.4, 1.0), 2.0)):
        light("SPOT", (x, -2.5, 4.0), 1200, color, aim=(x * 0.5, 0.3, 0.0),
              size=math.radians(35), blend=0.0)
    light("POINT", (0.0, 2.0, 1.5), 200, (1.0, 0.9, 0.7))
    light("SUN", (1, 3, 5), 0.4, (0.8, 0.85, 1.0), aim=(0, 0, 0))
    camera((0.0, -6.5, 3.0), (0.0, 0.3, 0.5), lens=35)


BUILDERS = {"textured": build_textured, "glass": build_glass, "lights": build_lights,
            "draco": build_textured}


def export(name, path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    BUILDERS[name]()
    bpy.ops.export_scene.gltf(filepath=str(path), export_format="GLB", export_lights=True,
                              export_cameras=True, export_apply=True,
                              export_draco_mesh_compression_enable=(name == "draco"))


# Rendering.

def render_with_cycles(glb, width, height, args, out):
    """The file through Blender's importer into an empty scene (its world black, as the file has
    none), rendered by Cycles as cycles_compare renders; (image, seconds)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(glb))
    bl = bpy.context.scene
    bl.camera = next(o for o in bl.objects if o.type == "CAMERA")
    configure_cycles(bl, width, height, args)
    return render_cycles(bl, args.spp, 0, False, out)


def render_caustic(glb, args, out):
    stats = out.with_suffix(".json")
    cmd = [args.caustic, "render", str(glb), "-o", str(out), "--stats", str(stats),
           "--no-progress", "--set", "integrator=path", "--set", f"spp={args.spp}",
           "--set", f"max_depth={args.max_depth}", "--set", "rr_depth=5",
           "--set", f"width={args.width}", "--set", "caustics=photon_map"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"gltf_compare: {shlex.join(cmd)} failed:\n{done.stderr}")
    warnings = [line for line in done.stderr.splitlines() if "warning" in line]
    s = json.loads(stats.read_text())["stats"]
    return read_exr(out), s["render_seconds"] + s["setup_seconds"], warnings


def to_png(image, path):
    """Linear RGB to an sRGB PNG through Blender's image writer."""
    h, w, _ = image.shape
    img = bpy.data.images.new("side", w, h, float_buffer=True)
    rgba = np.concatenate([image, np.ones((h, w, 1))], axis=2)[::-1].astype(np.float32)
    img.pixels[:] = rgba.ravel()
    img.filepath_raw, img.file_format = str(path), "PNG"
    scene = bpy.context.scene
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_depth = "8"
    img.save_render(str(path), scene=scene)
    bpy.data.images.remove(img)


def main():
    args = parse_args()
    if args.export:
        Path(args.export).mkdir(parents=True, exist_ok=True)
        for name in args.scenes:
            export(name, Path(args.export) / f"{name}.glb")
        return
    command = os.environ.get("COMPARE_COMMAND") or shlex.join(sys.argv)
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.keep or scratch)
        folder.mkdir(parents=True, exist_ok=True)
        rows, columns = [], []
        for name in args.scenes:
            glb = folder / f"{name}.glb"
            export(name, glb)
            ours, our_seconds, warnings = render_caustic(glb, args, folder / f"{name}-caustic.exr")
            h, w, _ = ours.shape
            theirs, their_seconds = render_with_cycles(glb, w, h, args,
                                                       folder / f"{name}-cycles.exr")
            a, b = ours.reshape(-1, 3).mean(axis=0), theirs.reshape(-1, 3).mean(axis=0)
            rows.append((name, glb.stat().st_size, a, b, our_seconds, their_seconds, warnings))
            columns.append(np.concatenate([ours, theirs], axis=0))
    print(f"Blender {bpy.app.version_string}, {args.width} px wide, {args.spp} spp each, path "
          f"tracing, max_depth {args.max_depth}. Command: `{command}`\n")
    print("| scene | .glb bytes | Caustic means (R, G, B) | Cycles / Caustic − 1 | seconds "
          "(Caustic, Cycles) |")
    print("|---|---:|---|---|---|")
    for name, size, a, b, s1, s2, _ in rows:
        rel = ", ".join(f"{100 * x:+.2f}%" for x in b / a - 1)
        print(f"| {name} | {size} | {', '.join(f'{x:.4f}' for x in a)} | {rel} | "
              f"{s1:.1f}, {s2:.1f} |")
    for name, *_, warnings in rows:
        for w in warnings:
            print(f"\n{name}: {w}")
    height = max(c.shape[0] for c in columns)
    side = np.concatenate([np.pad(c, ((0, height - c.shape[0]), (0, 4), (0, 0)))
                           for c in columns], axis=1)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    to_png(side, out / "gltf-side-by-side.png")
    print(f"\nPictures (Caustic above, Cycles below; {', '.join(args.scenes)}): "
          f"{out / 'gltf-side-by-side.png'}")


if __name__ == "__main__":
    main()
