#!/usr/bin/env python3
"""Caustic's path integrator against Mitsuba 3 (scalar_rgb) on one scene at equal spp.

Renders the scene with both, interleaved, --repeats times; prints Markdown with the time ratio
(Mitsuba / Caustic) and each image's RMSE against a long high-spp reference that is cached under
--cache-dir. The Mitsuba scene is translated from the Caustic scene JSON, so both see the same
geometry, materials, camera and box pixel filter. See bench/README.md, "mitsuba_compare".
"""
import argparse
import json
import os
import resource
import shlex
import statistics
import sys
import tempfile
import time
from pathlib import Path

# numpy's OpenBLAS threads spin after start-up and would take CPU from Mitsuba's render; this
# script needs no BLAS.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import caustic_cli  # noqa: E402
import mitsuba as mi  # noqa: E402
import numpy as np  # noqa: E402

mi.set_variant("scalar_rgb")
REPO = Path(__file__).resolve().parent.parent
REFERENCE_SEED = caustic_cli.REFERENCE_SEED


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"), help="caustic binary")
    p.add_argument("--scene", default=str(REPO / "scenes/cornell-spheres.json"))
    p.add_argument("--size", type=int, default=256, help="image width and height")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--reference", choices=["caustic", "mitsuba", "both"], default="both",
                   help="which renderers render a reference")
    p.add_argument("--max-depth", type=int, default=16, help="Caustic's: most scattering events")
    p.add_argument("--rr-depth", type=int, default=5, help="bounces before Russian roulette")
    p.add_argument("--cache-dir", help="where references are kept "
                   "(default: the caustic binary's build dir /mitsuba_compare)")
    p.add_argument("--smoke", action="store_true",
                   help="32x32, 4 spp, 16 spp references, 1 repeat (what CTest runs)")
    p.add_argument("--ladder", type=lambda v: [int(x) for x in v.split(",")],
                   help="comma-separated spp: measure the time each renderer needs to reach the "
                   "same RMSE instead (bench/equal_error.py), e.g. 8,16,32,64,128,256")
    p.add_argument("--caustic-set", action="append", default=[], metavar="KEY=VALUE",
                   help="a setting for Caustic's timed renders (not its reference), repeatable: "
                   "sampler=sobol, spp_per_pass=16")
    p.add_argument("--mitsuba-sampler", default="independent",
                   choices=["independent", "stratified", "multijitter", "orthogonal", "ldsampler"],
                   help="Mitsuba's sampler for its timed renders (its reference keeps "
                   "independent). All but independent round the spp up (ldsampler to a power of "
                   "4, stratified and multijitter to about a square, orthogonal to a prime's "
                   "square): use a ladder such as 16,64,256, or read a rung's spp as a label, "
                   "since its time and error are the rounded render's")
    p.add_argument("--caustic-rungs", type=lambda v: [int(x) for x in v.split(",")], default=[],
                   help="with --ladder: comma-separated spp Caustic renders besides the ladder "
                   "(e.g. 4,8: its time to Mitsuba's low-spp errors is then interpolated, not "
                   "extrapolated); spp_per_pass is capped at a rung's spp")
    args = p.parse_args()
    if args.smoke:
        args.size, args.spp, args.ref_spp, args.repeats = 32, 4, 16, 1
        if args.ladder:
            args.ladder = [1, 2, 4]
    if args.cache_dir is None:
        args.cache_dir = str(Path(args.caustic).resolve().parent.parent / "mitsuba_compare")
    return args


def rgb(value):
    return {"type": "rgb", "value": [float(c) for c in value]}


def quad_to_world(q):
    """Maps Mitsuba's rectangle ([-1,1]^2 in z=0, normal +z) onto origin + [0,1]u + [0,1]v.
    The third column is the unit normal cross(u, v): the inverse transpose then sends +z to
    cross(u, v), so Mitsuba's emitting front side is Caustic's."""
    o, u, v = (np.asarray(q[k], dtype=float) for k in ("origin", "u", "v"))
    n = np.cross(u, v)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = u / 2, v / 2, n / np.linalg.norm(n)
    m[:3, 3] = o + u / 2 + v / 2
    return mi.ScalarTransform4f(m.tolist())


def bsdf(material):
    """Caustic's diffuse and mirror scatter from both sides; Mitsuba's only from the front, so
    they are wrapped in 'twosided'. A dielectric is two-sided in both."""
    kind = material["type"]
    if kind == "diffuse":
        return {"type": "twosided", "bsdf": {"type": "diffuse",
                                             "reflectance": rgb(material.get("albedo", [0.5] * 3))}}
    if kind == "mirror":
        return {"type": "twosided", "bsdf": {"type": "conductor", "material": "none",
                "specular_reflectance": rgb(material.get("reflectance", [1, 1, 1]))}}
    alpha = float(material.get("roughness", 0.0)) ** 2  # Caustic's roughness is perceptual
    if kind == "dielectric":
        if material.get("fresnel", "exact") != "exact":
            sys.exit("mitsuba_compare: Mitsuba has no Schlick dielectric")
        tint = rgb(material.get("tint", [1, 1, 1]))
        out = {"type": "dielectric", "int_ior": float(material.get("ior", 1.5)), "ext_ior": 1.0,
               "specular_reflectance": tint, "specular_transmittance": tint}
        if material.get("roughness", 0.0) >= 0.03:
            out.update({"type": "roughdielectric", "distribution": "ggx", "alpha": alpha,
                        "sample_visible": True})
        return out
    if kind == "conductor":
        # Mitsuba's conductors have the exact Fresnel term of a complex index and no
        # multiple-scattering lobe: the Caustic scene must say eta, k and multiple_scattering false.
        if "eta" not in material or material.get("multiple_scattering", True) and alpha > 0:
            sys.exit("mitsuba_compare: a conductor needs eta, k and multiple_scattering false")
        out = {"type": "conductor", "eta": rgb(material["eta"]),
               "k": rgb(material.get("k", [0, 0, 0]))}
        if material.get("roughness", 0.0) >= 0.03:
            out.update({"type": "roughconductor", "distribution": "ggx", "alpha": alpha,
                        "sample_visible": True})
        return {"type": "twosided", "bsdf": out}
    if kind == "metallic_roughness":
        return principled(material)
    sys.exit(f"mitsuba_compare: material type {kind!r} has no translation")


def texture_transform(slot):
    """glTF's KHR_texture_transform (scale, then rotation, then offset) as a Mitsuba to_uv."""
    t = slot.get("transform", {}) if isinstance(slot, dict) else {}
    offset, scale = t.get("offset", [0, 0]), t.get("scale", [1, 1])
    return (mi.ScalarTransform4f().translate([float(offset[0]), float(offset[1]), 0])
            .rotate([0, 0, 1], float(t.get("rotation", 0.0)))
            .scale([float(scale[0]), float(scale[1]), 1]))


def principled(material):
    """metallic_roughness (glTF's model) as Mitsuba's `principled` (the Disney BSDF): not the same
    model (Disney's retro-reflective diffuse, its own metallic mix; no multiple-scattering
    compensation), so the comparison is of means, within 3%. specular 0.5 is an F0 of 0.04 (ior
    1.5); roughness is perceptual in both. Only the base colour may be a texture (Mitsuba reads
    no channel of an image as a scalar). One-sided in Mitsuba: shapes are seen from the front."""
    for key in ("metallic_roughness_texture", "normal_texture", "transmission", "alpha_mode"):
        if key in material:
            sys.exit(f"mitsuba_compare: principled has no translation of {key!r}")
    out = {"type": "principled", "metallic": float(material.get("metallic", 1.0)),
           "roughness": float(material.get("roughness", 1.0)), "specular": 0.5,
           "base_color": rgb(material.get("base_color", [1, 1, 1]))}
    slot = material.get("base_color_texture")
    if slot is not None:
        if "base_color" in material:
            sys.exit("mitsuba_compare: a base colour texture times a factor has no translation")
        out["base_color"] = quad_bitmap(slot)
    return out


def quad_bitmap(slot):
    """A texture slot on a quad as a Mitsuba bitmap (sRGB-decoded, bilinear). A Caustic quad's
    texture coordinates are (s, 1 - t) for its point origin + s u + t v
    (geometry/texture_frame.cpp), a Mitsuba rectangle's (s, t); both read row 0 at 0."""
    name = slot["file"] if isinstance(slot, dict) else slot
    flip = mi.ScalarTransform4f().translate([0, 1, 0]).scale([1, -1, 1])
    return {"type": "bitmap", "filename": str(REPO / "assets/meshes" / name),
            "to_uv": texture_transform(slot) @ flip}


def emitters(scene):
    """Caustic's point, spot and directional lights and its environment, as Mitsuba emitters. A
    spot light's falloff is glTF's (squared, linear in cos) and Mitsuba's linear in the angle:
    only a hard-edged cone (inner_angle == outer_angle) is the same light in both."""
    out = {}
    for i, light in enumerate(scene.get("lights", [])):
        if "intensity" not in light and "irradiance" not in light:
            sys.exit("mitsuba_compare: lights need intensity or irradiance (not candela or lux)")
        kind = light["type"]
        if kind == "point":
            out[f"light{i}"] = {"type": "point", "position": [float(c) for c in light["position"]],
                                "intensity": rgb(light["intensity"])}
        elif kind == "spot":
            inner, outer = float(light.get("inner_angle", 0)), float(light.get("outer_angle", 45))
            if inner != outer:
                sys.exit("mitsuba_compare: only a hard-edged spot (inner == outer) translates")
            position = np.asarray(light["position"], dtype=float)
            target = position + np.asarray(light["direction"], dtype=float)
            up = [0, 1, 0] if abs(light["direction"][1]) < 0.9 * np.linalg.norm(
                light["direction"]) else [1, 0, 0]
            out[f"light{i}"] = {"type": "spot", "intensity": rgb(light["intensity"]),
                                "cutoff_angle": outer, "beam_width": inner,
                                "to_world": mi.ScalarTransform4f().look_at(
                                    origin=position.tolist(), target=target.tolist(), up=up)}
        else:
            out[f"light{i}"] = {"type": "directional",
                                "direction": [float(c) for c in light["direction"]],
                                "irradiance": rgb(light["irradiance"])}
    env = scene.get("environment")
    if env:
        strength = float(env.get("strength", 1.0))
        if "color" in env:
            out["environment"] = {"type": "constant",
                                  "radiance": rgb([strength * c for c in env["color"]])}
        else:
            out["environment"] = {"type": "envmap", "scale": strength,
                                  "filename": str(REPO / "assets/meshes" / env["file"]),
                                  "to_world": mi.ScalarTransform4f().rotate(
                                      [0, 1, 0], float(env.get("rotation", 0.0)))}
    return out


def mesh_to_world(t):
    """Caustic's mesh transform (scene/mesh_loader.cpp): scale, then rotate about x, y and z in
    degrees, then translate. Caustic shades meshes flat: face normals in Mitsuba too."""
    scale = t.get("scale", 1.0)
    scale = [float(scale)] * 3 if isinstance(scale, (int, float)) else [float(c) for c in scale]
    rx, ry, rz = (float(c) for c in t.get("rotate", [0, 0, 0]))
    return (mi.ScalarTransform4f().translate([float(c) for c in t.get("translate", [0, 0, 0])])
            .rotate([0, 0, 1], rz).rotate([0, 1, 0], ry).rotate([1, 0, 0], rx).scale(scale))


def shape(s, materials):
    material = materials[s["material"]]
    if s["type"] == "quad":
        out = {"type": "rectangle", "to_world": quad_to_world(s)}
    elif s["type"] == "sphere":
        out = {"type": "sphere", "center": [float(c) for c in s["center"]],
               "radius": float(s["radius"]), "flip_normals": bool(s.get("flip_normals", False))}
    elif s["type"] == "mesh":
        out = {"type": "obj", "filename": str(REPO / "assets/meshes" / s["file"]),
               "face_normals": True, "to_world": mesh_to_world(s.get("transform", {}))}
    else:
        sys.exit(f"mitsuba_compare: shape type {s['type']!r} has no translation")
    out["bsdf"] = bsdf(material)
    if "emissive_texture" in material:
        # Mitsuba's area emitter takes a texture as its radiance, with no factor: 1 here.
        if s["type"] != "quad" or material.get("emission") != [1, 1, 1]:
            sys.exit("mitsuba_compare: an emissive texture translates on a quad with emission "
                     "[1, 1, 1] only")
        out["emitter"] = {"type": "area", "radiance": quad_bitmap(material["emissive_texture"])}
    elif any(c > 0 for c in material.get("emission", [0, 0, 0])):
        out["emitter"] = {"type": "area", "radiance": rgb(material["emission"])}
    return out


def mitsuba_dict(scene, spp, max_depth, rr_depth, sampler):
    """The Mitsuba scene. Mitsuba's max_depth counts path segments (1: emitters seen directly),
    Caustic's counts scattering events (1: direct light), hence the + 1. rr_depth means the same
    in both: roulette starts after that many scattering events."""
    if any(scene.get("background", [0, 0, 0])):
        sys.exit("mitsuba_compare: a background (not a light) has no translation")
    cam = scene["camera"]
    d = {"type": "scene",
         "integrator": {"type": "path", "max_depth": max_depth + 1, "rr_depth": rr_depth},
         "sensor": {"type": "perspective", "fov": float(cam.get("fov", 40)), "fov_axis": "y",
                    "to_world": mi.ScalarTransform4f().look_at(
                        origin=cam["position"], target=cam["look_at"], up=cam.get("up", [0, 1, 0])),
                    "film": {"type": "hdrfilm", "width": cam["width"], "height": cam["height"],
                             "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                    "sampler": {"type": sampler, "sample_count": spp}}}
    for i, s in enumerate(scene["shapes"]):
        d[f"shape{i}"] = shape(s, scene["materials"])
    d.update(emitters(scene))
    return d


def render_mitsuba(scene, spp, seed, args, sampler=None):
    """Returns (image, {load, render, cpu} seconds); cpu covers the load and the render. The
    sampler is --mitsuba-sampler's unless given."""
    cpu0, t0 = caustic_cli.cpu_seconds(resource.RUSAGE_SELF), time.perf_counter()
    loaded = mi.load_dict(mitsuba_dict(scene, spp, args.max_depth, args.rr_depth,
                                       sampler or args.mitsuba_sampler))
    t1 = time.perf_counter()
    image = np.array(mi.render(loaded, spp=spp, seed=seed), dtype=np.float64)
    t2 = time.perf_counter()
    return image, {"load": t1 - t0, "render": t2 - t1,
                   "cpu": caustic_cli.cpu_seconds(resource.RUSAGE_SELF) - cpu0}


def read_exr(path):
    bitmap = mi.Bitmap(str(path)).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                           srgb_gamma=False)
    return np.array(bitmap, dtype=np.float64)


def render_caustic(scene_path, spp, seed, args, settings=()):
    """Returns (image, stats dict, {wall, cpu} seconds of the whole process)."""
    return caustic_cli.render(args, scene_path, spp, seed, settings, read_exr)


def reference(renderer, scene, scene_path, cache, args):
    """The high-spp reference of one renderer, cached by everything that determines it."""
    if renderer == "caustic":
        return caustic_cli.reference(args, scene, scene_path, cache, read_exr, REFERENCE_SEED)[:2]
    path = cache / caustic_cli.reference_key(renderer, mi.__version__, scene, args,
                                             REFERENCE_SEED)
    if path.exists():
        return np.load(path), "cached"
    t0 = time.perf_counter()
    image = render_mitsuba(scene, args.ref_spp, REFERENCE_SEED, args, sampler="independent")[0]
    np.save(path, image)
    return image, f"rendered in {time.perf_counter() - t0:.0f} s"


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def cpu_model():
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return "unknown CPU"


def main():
    args = parse_args()
    cache = Path(args.cache_dir)
    cache.mkdir(parents=True, exist_ok=True)
    scene = caustic_cli.load_scene(args.scene, args.size)
    # Caustic's scene copy and outputs live in a private folder: runs may overlap.
    with tempfile.TemporaryDirectory() as scratch:
        scene_path = Path(scratch) / "scene.json"
        scene_path.write_text(json.dumps(scene))
        if args.ladder:
            import equal_error
            equal_error.measure(args, scene, scene_path, cache)
        else:
            measure(args, scene, scene_path, cache)


def measure(args, scene, scene_path, cache):
    # mitsuba_compare.sh passes the command it was run with; the venv's python is a detail.
    command = os.environ.get("COMPARE_COMMAND") or shlex.join(sys.argv)
    print(f"Machine: nproc {os.cpu_count()}, {cpu_model()}, Mitsuba {mi.__version__} "
          f"scalar_rgb. Command: `{command}`\n")
    refs = {r: reference(r, scene, scene_path, cache, args)
            for r in (["caustic", "mitsuba"] if args.reference == "both" else [args.reference])}
    load_before = os.getloadavg()[0]

    # One untimed warm-up each (page cache, Mitsuba's plugin loading), then interleaved pairs so
    # that a slow spell on the shared machine hits both renderers.
    render_caustic(scene_path, 1, 0, args)
    render_mitsuba(scene, 1, 0, args)
    runs = {"caustic": [], "mitsuba": []}
    for seed in range(args.repeats):
        image, stats, process = render_caustic(scene_path, args.spp, seed, args)
        runs["caustic"].append({"image": image, "time": stats["render_seconds"] +
                                stats["setup_seconds"], "stats": stats, **process})
        image, seconds = render_mitsuba(scene, args.spp, seed, args)
        runs["mitsuba"].append({"image": image, "time": seconds["render"],
                                "wall": seconds["load"] + seconds["render"], **seconds})
    report(args, refs, runs, (load_before, os.getloadavg()[0]))


def median(runs, key):
    return statistics.median(r[key] for r in runs)


def ratio(runs, key, of=median):
    """Mitsuba's over Caustic's: above 1, Caustic is faster."""
    return of(runs["mitsuba"], key) / of(runs["caustic"], key)


def smallest(runs, key):
    return min(r[key] for r in runs)


def report(args, refs, runs, loads):
    c, m = runs["caustic"], runs["mitsuba"]
    print(f"{Path(args.scene).stem}, {args.size}x{args.size}, {args.spp} spp, {args.repeats} "
          f"repeats (seeds 0..{args.repeats - 1}), every core for both; Caustic max_depth "
          f"{args.max_depth} = Mitsuba max_depth {args.max_depth + 1}, rr_depth {args.rr_depth} in "
          f"both. Load average (1 min) {loads[0]:.2f} before, {loads[1]:.2f} after: above "
          f"{os.cpu_count()}, other work shared the CPU and wall times stretch.\n")
    print("| renderer | time s (median) | time s (min) | CPU s (median) | wall s (median) "
          "| cores used | Mrays/s |")
    print("|---|---|---|---|---|---|---|")
    rays = statistics.median(r["stats"]["rays"] / r["stats"]["render_seconds"] for r in c)
    for name, rs, mrays in (("Caustic", c, f"{rays / 1e6:.2f}"), ("Mitsuba 3", m, "–")):
        print(f"| {name} | {median(rs, 'time'):.3f} | {smallest(rs, 'time'):.3f} | "
              f"{median(rs, 'cpu'):.3f} | {median(rs, 'wall'):.3f} | "
              f"{median(rs, 'cpu') / median(rs, 'wall'):.2f} of {os.cpu_count()} | {mrays} |")
    print(f"\ntime: Caustic's render + setup (`--stats`), Mitsuba's `mi.render` (its scene load, "
          f"median {median(m, 'load'):.3f} s, apart). CPU (user + system) and wall: Caustic's "
          f"whole process (start-up, scene, EXR out), Mitsuba's load + render.\n")
    speedup = ratio(runs, "time")
    print(f"**Mitsuba / Caustic time: {speedup:.2f}x** (ratio of medians; of mins "
          f"{ratio(runs, 'time', smallest):.2f}x; CPU {ratio(runs, 'cpu'):.2f}x; "
          f"wall {ratio(runs, 'wall'):.2f}x).\n")

    print(f"| RMSE, linear RGB, median of {args.repeats} | "
          + " | ".join(f"vs {r} reference" for r in refs) + " |")
    print("|---|" + "---|" * len(refs))
    errors = {}
    for name, rs in (("Caustic", c), ("Mitsuba 3", m)):
        errors[name] = [statistics.median(rmse(r["image"], ref[0]) for r in rs)
                        for ref in refs.values()]
        print(f"| {name}, {args.spp} spp | " + " | ".join(f"{e:.5f}" for e in errors[name]) + " |")
    print()
    for r, (image, how) in refs.items():
        unlike = ", unlike the timed runs" if r == "caustic" else ""
        print(f"- {r} reference: {args.ref_spp} spp, seed {REFERENCE_SEED}{unlike}, {how}; "
              f"mean {image.mean():.5f}.")
    if len(refs) == 2:
        # Noise falls as 1/sqrt(spp): without bias, two references differ by about this.
        noise = np.hypot(errors["Caustic"][0], errors["Mitsuba 3"][0]) * np.sqrt(
            args.spp / args.ref_spp)
        print(f"- RMSE between the two references: "
              f"{rmse(refs['caustic'][0], refs['mitsuba'][0]):.5f}; their noise alone would "
              f"make it about {noise:.5f}.")
    error_ratio = errors["Caustic"][0] / errors["Mitsuba 3"][0]
    goal = "met" if speedup >= 5 and error_ratio <= 1 else "NOT met"
    print(f"- Goal (at least 5x faster, RMSE no worse): **{goal}**: {speedup:.2f}x faster "
          f"({speedup / 5:.0%} of the goal), Caustic RMSE / Mitsuba RMSE {error_ratio:.3f} "
          f"(against the {next(iter(refs))} reference).")
    stats = c[0]["stats"]
    print(f"""
Differences that remain (both estimators are unbiased, so both converge to the same image):
- Russian roulette: both continue with probability max(throughput) * eta^2 (the throughput without
  refraction's radiance scaling), Mitsuba capped at 0.95, Caustic at 1.
- Emitter choice: Caustic by power, Mitsuba uniformly (one emitter in cornell-spheres: the same).
- Caustic renders in passes ({stats['passes']} of {stats['spp'] // stats['passes']} spp here) to \
estimate its own error; Mitsuba in one.
- Random numbers: Caustic's `sampler` setting vs Mitsuba's {args.mitsuba_sampler} sampler.""")


if __name__ == "__main__":
    main()
