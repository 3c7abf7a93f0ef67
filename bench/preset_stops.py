"""Where each preset stops, and how true its reported error is there, with each sampler.

For every scene, preset and sampler: the render's stopping spp and passes, its render seconds, the
relative error it reports (Film::relativeError) and the true one against a long reference (RMS of
image - reference over RMS of the reference, less the reference's own noise), averaged over seeds.
The reference takes the scene's settings with `--ref-spp` spp, independent passes of 16 Sobol'
points (sampler sobol), and no target; its noise is its own squared standard error. Images are read
as bench/mitsuba_compare.py reads them."""
import argparse
import json
import math
import os
import sys
import tempfile
from pathlib import Path

# numpy's OpenBLAS threads spin after start-up and would take CPU from the timed renders.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import caustic_cli  # noqa: E402
import numpy as np  # noqa: E402
from mitsuba_compare import read_exr  # noqa: E402

REPO = Path(__file__).resolve().parent.parent


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"), help="caustic binary")
    p.add_argument("--scenes", default="bunny,cornell-box,cornell-spheres",
                   help="comma-separated names under scenes/")
    p.add_argument("--presets", default="draft,preview,final")
    p.add_argument("--samplers", default="sobol,sobol_sequence")
    p.add_argument("--per-pass", default="preset",
                   help="comma-separated spp_per_pass values to try; `preset`: the preset's own")
    p.add_argument("--size", type=int, default=128, help="image width and height")
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--seeds", type=int, default=2)
    p.add_argument("--smoke", action="store_true",
                   help="cornell-box, 16x16, draft, 64-spp reference")
    args = p.parse_args()
    if args.smoke:
        args.scenes, args.presets, args.size, args.ref_spp, args.seeds = (
            "cornell-box", "draft", 16, 64, 1)
    return args


def render(args, scene_path, cli_args):
    return caustic_cli.run(args.caustic, scene_path, cli_args, read_exr)[:2]


def main():
    args = parse_args()
    print(f"Command: `{' '.join(sys.argv)}`; {args.size}x{args.size}, {args.seeds} seeds, "
          f"{args.ref_spp}-spp references (independent passes of 16 Sobol' points).\n")
    print("| scene | preset | sampler | spp a pass | spp at the stop | passes | render s | "
          "reported error | true error | reported / true |")
    print("|---|---|---|---|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as scratch:
        scene_path = Path(scratch) / "scene.json"
        for name in args.scenes.split(","):
            scene_path.write_text(json.dumps(
                caustic_cli.load_scene(REPO / "scenes" / f"{name}.json", args.size)))
            ref, st = render(args, scene_path, [
                "--set", f"spp={args.ref_spp}", "--set", "spp_per_pass=16", "--set",
                "sampler=sobol", "--set", "adaptive=false", "--set", "target_error=0",
                "--set", f"seed={caustic_cli.REFERENCE_SEED}"])
            ref2 = float(np.mean(ref ** 2))
            noise2 = st["relative_error"] ** 2 * ref2
            for preset in args.presets.split(","):
                for sampler in args.samplers.split(","):
                    for per_pass in args.per_pass.split(","):
                        own = [] if per_pass == "preset" else ["--set", f"spp_per_pass={per_pass}"]
                        rows = []
                        for seed in range(args.seeds):
                            image, st = render(args, scene_path, [
                                "--preset", preset, "--set", f"sampler={sampler}", *own,
                                "--set", f"seed={seed}"])
                            mse = max(float(np.mean((image - ref) ** 2)) - noise2, 0.0)
                            rows.append([st["spp"], st["passes"], st["render_seconds"],
                                         st["relative_error"], math.sqrt(mse / ref2)])
                        spp, passes, secs, reported, true = np.mean(rows, axis=0)
                        print(f"| {name} | {preset} | {sampler} | {per_pass} | {spp:.0f} | "
                              f"{passes:.1f} | {secs:.2f} | {reported:.4f} | {true:.4f} | "
                              f"{reported / true if true > 0 else float('nan'):.2f} |",
                              flush=True)

if __name__ == "__main__":
    main()
