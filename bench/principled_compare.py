#!/usr/bin/env python3
"""metallic_roughness against Mitsuba 3's principled and Cycles' Principled BSDF (issue 38,
acceptance 2): not the same models, so the channel means are compared (within 3% is the target),
and a side-by-side picture shows where they differ.

Renders the scene (default bench/principled/metallic-roughness.json: a textured floor and three
spheres, plastic, gold and half metal, under assets/meshes/sky.exr) with each renderer's path
tracer at --spp, prints Markdown with the means and their ratios, and writes the three images
side by side to OUT/principled-side-by-side.png. Runs in the
Mitsuba venv (bench/principled_compare.sh); Cycles renders in a process of its own venv's
Python (the same script with --render-cycles), as bpy and Mitsuba live in different venvs.
"""
import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
REPO = Path(__file__).resolve().parent.parent


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"))
    p.add_argument("--cycles-python", help="the cycles venv's python (default: the caustic "
                   "binary's build dir /cycles-venv/bin/python)")
    p.add_argument("--scene", default=str(REPO / "bench/principled/metallic-roughness.json"))
    p.add_argument("--size", type=int, default=192, help="image width and height")
    p.add_argument("--spp", type=int, default=1024)
    p.add_argument("--max-depth", type=int, default=16)
    p.add_argument("--rr-depth", type=int, default=5)
    p.add_argument("--threads", type=int, default=os.cpu_count())
    p.add_argument("--out", help="where the picture goes (default: docs/images; with --smoke, "
                   "the caustic binary's build dir /principled_compare)")
    p.add_argument("--smoke", action="store_true", help="32x32, 16 spp")
    p.add_argument("--furnace", action="store_true",
                   help="each material alone in a white furnace, one bounce: the models' "
                   "reflectance compared without the scene")
    p.add_argument("--render-cycles", metavar="EXR",
                   help="(internal) render the scene with Cycles into EXR and exit")
    args = p.parse_args()
    if args.smoke:
        args.size, args.spp = 32, 16
    if args.out is None:
        args.out = str(Path(args.caustic).resolve().parent.parent / "principled_compare"
                       if args.smoke else REPO / "docs/images")
    if args.cycles_python is None:
        args.cycles_python = str(Path(args.caustic).resolve().parent.parent /
                                 "cycles-venv/bin/python")
    return args


def render_cycles_here(args):
    """Runs in the cycles venv: the scene through cycles_compare's translation, Cycles' EXR
    written to args.render_cycles, its render seconds printed."""
    import caustic_cli
    import cycles_compare
    scene = caustic_cli.load_scene(args.scene, args.size)
    bl = cycles_compare.build_scene(scene, args)
    _, seconds = cycles_compare.render_cycles(bl, args.spp, 0, False, args.render_cycles)
    print(json.dumps({"seconds": seconds}))


def render_all(scene, args):
    """The scene rendered by Caustic, Mitsuba and Cycles at args.spp: ({renderer: image},
    {renderer: seconds})."""
    import mitsuba_compare as mc
    images, seconds = {}, {}
    with tempfile.TemporaryDirectory() as scratch:
        scene_path = Path(scratch) / "scene.json"
        scene_path.write_text(json.dumps(scene))
        image, stats, _ = mc.render_caustic(scene_path, args.spp, 0, args)
        images["caustic"] = image
        seconds["caustic"] = stats["render_seconds"] + stats["setup_seconds"]
        t0 = time.perf_counter()
        images["mitsuba"] = mc.render_mitsuba(scene, args.spp, 0, args, sampler="independent")[0]
        seconds["mitsuba"] = time.perf_counter() - t0
        exr = Path(scratch) / "cycles.exr"
        out = subprocess.run([args.cycles_python, __file__, "--scene", str(scene_path), "--size",
                              str(args.size), "--spp", str(args.spp), "--max-depth",
                              str(args.max_depth), "--threads", str(args.threads),
                              "--render-cycles", str(exr)],
                             check=True, capture_output=True, text=True, cwd=REPO / "bench")
        seconds["cycles"] = json.loads(out.stdout.strip().splitlines()[-1])["seconds"]
        images["cycles"] = mc.read_exr(exr)
    return images, seconds


def furnace(scene, args, command):
    """Each of the scene's materials on a unit sphere in a white furnace (a constant environment
    of 1), one bounce: a pixel on the sphere is the material's directional albedo toward the
    camera, so the disk's mean compares the three models' reflectance alone, with no lighting,
    geometry or texture between them. Base colour textures become white."""
    import numpy as np
    args.max_depth = 1
    print(f"White furnace, one bounce (max_depth 1), {args.size}x{args.size}, {args.spp} spp "
          f"each; means over the sphere's disk (the sphere's edge left out). "
          f"Command: `{command}`\n")
    print("| material | Caustic (R, G, B) | Mitsuba / Caustic - 1 | Cycles / Caustic - 1 |")
    print("|---|---|---|---|")
    # Camera 4 radii away with a 40 degree field: the disk subtends asin(1/4); keep 95% of it.
    half = np.tan(np.radians(20.0))
    x = ((np.arange(args.size) + 0.5) / args.size * 2 - 1) * half
    angle = np.arctan(np.hypot(x[None, :], x[:, None]))
    disk = angle < 0.95 * np.arcsin(0.25)
    for name, material in scene["materials"].items():
        material = {k: v for k, v in material.items() if k != "base_color_texture"}
        one = {"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40,
                          "width": args.size, "height": args.size},
               "materials": {name: material},
               "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                           "material": name}],
               "environment": {"color": [1, 1, 1]}}
        images, _ = render_all(one, args)
        means = {k: image[disk].mean(axis=0) for k, image in images.items()}
        rel = {k: ", ".join(f"{100 * x:+.2f}%" for x in means[k] / means["caustic"] - 1)
               for k in ("mitsuba", "cycles")}
        print(f"| {name} | {', '.join(f'{x:.4f}' for x in means['caustic'])} | "
              f"{rel['mitsuba']} | {rel['cycles']} |")


def to_png(image, path):
    """Linear RGB to an sRGB PNG through OpenImageIO's oiiotool."""
    import mitsuba as mi
    exr = Path(path).with_suffix(".exr")
    mi.Bitmap(image.astype("float32")).write(str(exr))
    subprocess.run(["oiiotool", str(exr), "--ch", "R,G,B", "--colorconvert", "linear", "sRGB",
                    "-d", "uint8", "-o", str(path)], check=True)
    exr.unlink()


def main():
    args = parse_args()
    if args.render_cycles:
        render_cycles_here(args)
        return
    import caustic_cli
    import mitsuba_compare as mc
    import numpy as np
    if not Path(args.cycles_python).exists():
        venv = Path(args.cycles_python).parent.parent
        subprocess.run(["bash", "-c", f'source "{REPO}/scripts/python-venv.sh" && '
                        f'ensure_venv "{venv}" bpy==5.0.1 numpy'], check=True)
    command = os.environ.get("COMPARE_COMMAND") or shlex.join(sys.argv)
    scene = caustic_cli.load_scene(args.scene, args.size)
    if args.furnace:
        furnace(scene, args, command)
        return
    images, seconds = render_all(scene, args)
    print(f"Machine: nproc {os.cpu_count()}, {mc.cpu_model()}, Mitsuba {mc.mi.__version__} "
          f"scalar_rgb. Command: `{command}`\n")
    print(f"{Path(args.scene).name}, {args.size}x{args.size}, {args.spp} spp each, path "
          f"tracing, max_depth {args.max_depth} (Caustic's count).\n")
    print("| renderer | means (R, G, B) | / Caustic's - 1 | seconds |")
    print("|---|---|---|---:|")
    ours = images["caustic"].reshape(-1, 3).mean(axis=0)
    for name, image in images.items():
        means = image.reshape(-1, 3).mean(axis=0)
        rel = ", ".join(f"{100 * x:+.2f}%" for x in means / ours - 1)
        print(f"| {name} | {', '.join(f'{x:.4f}' for x in means)} | {rel} | "
              f"{seconds[name]:.1f} |")
    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    side = np.concatenate([images["caustic"], images["mitsuba"], images["cycles"]], axis=1)
    to_png(side, out_dir / "principled-side-by-side.png")
    print(f"\nPictures (Caustic, Mitsuba, Cycles, left to right): "
          f"{out_dir / 'principled-side-by-side.png'}")


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    main()
