#!/usr/bin/env python3
"""Where a textured scene's render time goes (issue 38, acceptance 5): a scene of 20 textured
metallic-roughness materials (base colour, metallic-roughness and normal maps, each with its own
texture transform) on 20 objects under the sky environment, rendered by `caustic render` with path
tracing, under `perf record` (the cpu-clock timer event, user space, the whole process: virtual
machines often have no hardware counters). The share of samples in
OpenImageIO's texture system (libOpenImageIO) is the texture lookups' share; the share in the
light-sampling code (the light choice per point, the environment's and the lights' sampling and
densities, the 2D distributions) is light sampling's. Then the same scene with every texture
removed (factors kept) and the same settings, rendered in alternation with the textured one: the
ratio of their render times is what the textures cost end to end.

Samples land in the function that was running: what the compiler inlined (a light's pdf into the
integrator, a texture frame into the shading) counts for its caller, so the light-sampling share
is a lower bound. perf needs kernel.perf_event_paranoid <= 2 (Debian's default) and linux-perf.

Usage: bench/texture_share.py [--caustic build/cli/caustic] [--spp 16] [--rounds 3]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TEXTURES = ["tiles.png", "spot-pattern.png"]

# Symbols (demangled, substrings) that make up light sampling.
LIGHT_SAMPLING = ["LocalLightSampler", "LightSampler::", "EnvironmentLight::", "SpotLight::",
                  "PointLight::", "DirectionalLight::", "AreaLight::", "Distribution1D",
                  "Distribution2D", "sampleDirectLight"]


def scene(textured):
    materials, shapes = {}, []
    for i in range(20):
        row, col = divmod(i, 5)
        m = {"type": "metallic_roughness", "base_color": [1, 1, 1],
             "metallic": 1.0 if i % 3 == 0 else 0.0, "roughness": 1.0}
        if textured:
            scale = 1 + i % 4
            transform = {"scale": [scale, scale], "rotation": 9 * i, "offset": [0.05 * i, 0]}
            m["base_color_texture"] = {"file": TEXTURES[i % 2], "transform": transform}
            m["metallic_roughness_texture"] = {"file": "tiles-mr.png", "transform": transform}
            m["normal_texture"] = {"file": "tiles-normal.png", "transform": transform}
        materials[f"m{i}"] = m
        center = [-2.0 + col, 0.4 + 0.0 * row, -row * 1.1]
        shapes.append({"type": "sphere", "center": center, "radius": 0.4, "material": f"m{i}"})
    materials["floor"] = {"type": "metallic_roughness", "metallic": 0, "roughness": 0.6,
                          "base_color": [0.8, 0.8, 0.8]}
    if textured:
        materials["floor"]["base_color_texture"] = {"file": "tiles.png",
                                                     "transform": {"scale": [4, 4]}}
    shapes.append({"type": "quad", "origin": [-6, 0, 4], "u": [12, 0, 0], "v": [0, 0, -12],
                   "material": "floor"})
    return {"camera": {"position": [0, 2.2, 4.2], "look_at": [0, 0.3, -1.6], "fov": 45,
                       "width": 320, "height": 200},
            "materials": materials, "shapes": shapes,
            "environment": {"file": "sky.exr", "strength": 1}}


def render(caustic, scene_file, spp, out_dir, name, perf=None):
    stats = os.path.join(out_dir, name + ".stats.json")
    cmd = [caustic, "render", scene_file, "-o", os.path.join(out_dir, name + ".exr"),
           "--spp", str(spp), "--seed", "1", "--stats", stats, "--integrator", "path"]
    if perf:
        cmd = ["perf", "record", "-e", "cpu-clock:u", "-F", "999", "-o", perf, "--"] + cmd
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(stats) as f:
        return json.load(f)["stats"]


def shares(perf_data):
    """Self-time shares by shared object and by symbol, from `perf report`."""
    report = subprocess.run(["perf", "report", "-i", perf_data, "--no-children", "--stdio",
                             "--sort", "dso,sym", "--percent-limit", "0"],
                            check=True, capture_output=True, text=True).stdout
    texture = light = 0.0
    for line in report.splitlines():
        line = line.strip()
        if not line or line.startswith("#") or "%" not in line.split()[0]:
            continue
        percent = float(line.split()[0].rstrip("%"))
        if "libOpenImageIO" in line:
            texture += percent
        elif any(s in line for s in LIGHT_SAMPLING):
            light += percent
    return texture, light


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--caustic", default=os.path.join(ROOT, "build", "cli", "caustic"))
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="caustic-texture-share-") as tmp:
        files = {}
        for name, textured in [("textured", True), ("plain", False)]:
            files[name] = os.path.join(tmp, name + ".json")
            doc = scene(textured)
            with open(files[name], "w") as f:
                json.dump(doc, f)
        # Scene files name assets relative to the assets folder, found by default.
        perf_data = os.path.join(tmp, "perf.data")
        render(args.caustic, files["textured"], args.spp, tmp, "warm")  # prepares the textures
        stats = render(args.caustic, files["textured"], args.spp, tmp, "profiled", perf_data)
        texture, light = shares(perf_data)
        print(f"textured scene, {args.spp} spp, {stats['render_seconds']:.2f} s rendering under "
              f"perf: texture lookups (libOpenImageIO) {texture:.1f}% of the process's "
              f"user-space cycles, light sampling {light:.1f}%")
        times = {"textured": [], "plain": []}
        for _ in range(args.rounds):
            for name in ("textured", "plain"):
                times[name].append(render(args.caustic, files[name], args.spp, tmp, name)
                                   ["render_seconds"])
        t, p = sorted(times["textured"]), sorted(times["plain"])
        print(f"render seconds over {args.rounds} alternating rounds: textured {t}, "
              f"without textures {p}; median ratio {t[len(t) // 2] / p[len(p) // 2]:.2f}x")


if __name__ == "__main__":
    sys.exit(main())
