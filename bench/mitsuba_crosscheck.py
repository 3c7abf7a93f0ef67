#!/usr/bin/env python3
"""Caustic against Mitsuba 3 on the scenes of bench/cross/ (issue 38, acceptance 2): rough
conductors, rough dielectrics, an HDR environment, point, spot and directional lights, an
emissive texture, each built from models both renderers share (exact conductor Fresnel from eta
and k, no multiple-scattering lobe, a hard-edged spot, an area emitter with a bitmap radiance;
bench/mitsuba_compare.py translates the scenes).

Per scene: the channel means of each renderer's long render (--ref-spp) and their ratio; then
the RMSE of Caustic's and of Mitsuba's --spp render against Mitsuba's long render, over
--repeats seeds each, and their ratio (Caustic's over Mitsuba's: at most 1.1 is the target).
Prints Markdown. Run through bench/mitsuba_crosscheck.sh (a venv with Mitsuba and numpy).
"""
import argparse
import json
import os
import shlex
import sys
import tempfile
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import mitsuba_compare as mc  # noqa: E402  (sets the scalar_rgb variant)
import numpy as np  # noqa: E402

REPO = Path(__file__).resolve().parent.parent


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"))
    p.add_argument("--scenes", nargs="*", default=sorted(str(s) for s in (REPO / "bench/cross")
                                                         .glob("*.json")))
    p.add_argument("--size", type=int, default=128)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--repeats", type=int, default=4)
    p.add_argument("--max-depth", type=int, default=16)
    p.add_argument("--rr-depth", type=int, default=5)
    p.add_argument("--smoke", action="store_true", help="32x32, 4 spp, 16 spp references")
    args = p.parse_args()
    if args.smoke:
        args.size, args.spp, args.ref_spp, args.repeats = 32, 4, 16, 1
    args.mitsuba_sampler = "independent"
    return args


def main():
    args = parse_args()
    command = os.environ.get("COMPARE_COMMAND") or shlex.join(sys.argv)
    print(f"Machine: nproc {os.cpu_count()}, {mc.cpu_model()}, Mitsuba {mc.mi.__version__} "
          f"scalar_rgb. Command: `{command}`\n")
    print(f"{args.size}x{args.size}, long renders {args.ref_spp} spp, timed {args.spp} spp x "
          f"{args.repeats} seeds; path tracing, max_depth {args.max_depth}, rr_depth "
          f"{args.rr_depth}.\n")
    print("| scene | Caustic means (R, G, B) | Mitsuba means | Caustic / Mitsuba - 1 | "
          f"RMSE at {args.spp} spp: Caustic | Mitsuba | ratio |")
    print("|---|---|---|---|---:|---:|---:|")
    for path in args.scenes:
        scene = mc.caustic_cli.load_scene(path, args.size)
        with tempfile.TemporaryDirectory() as scratch:
            scene_path = Path(scratch) / "scene.json"
            scene_path.write_text(json.dumps(scene))
            ours = mc.render_caustic(scene_path, args.ref_spp, mc.REFERENCE_SEED, args)[0]
            theirs = mc.render_mitsuba(scene, args.ref_spp, mc.REFERENCE_SEED, args)[0]
            errors = {"caustic": [], "mitsuba": []}
            for seed in range(args.repeats):
                errors["caustic"].append(
                    mc.rmse(mc.render_caustic(scene_path, args.spp, seed, args)[0], theirs))
                errors["mitsuba"].append(
                    mc.rmse(mc.render_mitsuba(scene, args.spp, seed, args)[0], theirs))
        m_ours = ours.reshape(-1, 3).mean(axis=0)
        m_theirs = theirs.reshape(-1, 3).mean(axis=0)
        rel = m_ours / m_theirs - 1
        e_ours, e_theirs = np.mean(errors["caustic"]), np.mean(errors["mitsuba"])
        fmt = lambda v: ", ".join(f"{x:.4f}" for x in v)  # noqa: E731
        print(f"| {Path(path).stem} | {fmt(m_ours)} | {fmt(m_theirs)} | "
              f"{', '.join(f'{100 * x:+.2f}%' for x in rel)} | {e_ours:.4f} | {e_theirs:.4f} | "
              f"{e_ours / e_theirs:.2f} |", flush=True)


if __name__ == "__main__":
    main()
