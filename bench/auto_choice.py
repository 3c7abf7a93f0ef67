"""What `auto` chooses on each scene, and its time to a target error against every configuration's.

For every scene and configuration: the seconds to the target (the render's own setup and render
seconds, `total_seconds`; median of --seeds runs, with the range), spp and passes at the stop, the
reported error and the true one there (RMS of image - reference over RMS of the reference, less
the reference's own noise). A configuration counts as reaching the target only where its median
true error is at most --tolerance times the target: one that stops on an error it underreports
does not win on time. The best is the fastest of those; the last column is each configuration's
time over the best's, and `auto`'s is the figure the preset is judged by (at most 1.25).

The references: the scene at --ref-spp, independent passes of 16 Sobol' points, no target, the
path tracer; stage-lights' with both photon maps, the one estimator here that sees its spot and
point lights' caustics through glass (a camera path never reaches a delta light). Images are read
as bench/mitsuba_compare.py reads them. The references are Caustic's own: this compares Caustic's
configurations with each other, not with another renderer. "(biased)" marks the consistent
estimators (photon maps), whose bias is in the error they report and in the true error here."""
import argparse
import hashlib
import json
import math
import os
import statistics
import sys
import tempfile
from pathlib import Path

# numpy's OpenBLAS threads spin after start-up and would take CPU from the timed renders.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import caustic_cli  # noqa: E402
import numpy as np  # noqa: E402
from mitsuba_compare import read_exr  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
STUDY = "cornell-box,cornell-spheres,bunny,caustic-glass,meshes,indirect"
HELD_OUT = "outdoor-metals,product-shot,stage-lights"



def sequence(per_pass):
    return ["--preset", "none", "--set", "sampler=sobol_sequence",
            "--set", f"spp_per_pass={per_pass}"]


CAUSTIC_MAP = ["--set", "caustics=photon_map"]
INDIRECT_MAP = ["--set", "indirect=photon_map"]
# Name, CLI arguments. `auto` is the default preset; the others name none, so that only what is
# listed differs from the built-in defaults. The path tracer and each choice of maps at auto's two
# pass sizes (16 a pass, and 4 under a target).
CONFIGS = [
    ("auto (biased where it takes a map)", []),
    ("defaults (none)", ["--preset", "none"]),
    *[(f"{label}, sobol_sequence {n}{' (biased)' if maps else ''}", sequence(n) + maps)
      for n in (16, 4)
      for label, maps in (("path", []), ("+ caustic map", CAUSTIC_MAP),
                          ("+ indirect map", INDIRECT_MAP),
                          ("+ both maps", CAUSTIC_MAP + INDIRECT_MAP))],
    ("ppm (biased)", ["--preset", "none", "--set", "integrator=ppm", "--set", "spp_per_pass=4"]),
    ("photon k50 (biased)",
     ["--preset", "none", "--set", "integrator=photon", "--set", "spp_per_pass=4"]),
]


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"), help="caustic binary")
    p.add_argument("--scenes", default=f"{STUDY},{HELD_OUT}",
                   help="comma-separated names under scenes/")
    p.add_argument("--size", type=int, default=128, help="image width and height")
    p.add_argument("--target", type=float, default=0.02, help="target_error")
    p.add_argument("--max-spp", type=int, default=8192, help="the budget a render stops at")
    p.add_argument("--time-limit", type=float, default=60,
                   help="seconds a render stops at (it then has not reached the target)")
    p.add_argument("--ref-spp", type=int, default=8192)
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--configs", default="",
                   help="comma-separated words: only the configurations whose name has one "
                        "(auto always runs); e.g. `path,map` leaves out ppm and photon")
    p.add_argument("--tolerance", type=float, default=1.25,
                   help="most true error over the target that counts as reaching it")
    p.add_argument("--cache-dir", default=str(REPO / "build/bench-cache"))
    p.add_argument("--smoke", action="store_true", help="cornell-box, 16x16, 1 seed, 64-spp ref")
    args = p.parse_args()
    if args.smoke:
        args.scenes, args.size, args.ref_spp, args.seeds, args.target = (
            "cornell-box", 16, 64, 1, 0.2)
    return args


def reference(args, name, scene_path):
    """The scene's long render and its noise (squared, absolute), cached by what determines it."""
    extra = CAUSTIC_MAP + INDIRECT_MAP if name == "stage-lights" else []
    cli = ["--preset", "none", "--set", f"spp={args.ref_spp}", "--set", "spp_per_pass=16",
           "--set", "sampler=sobol", "--set", f"seed={caustic_cli.REFERENCE_SEED}", *extra]
    key = json.dumps([caustic_cli.binary_hash(args.caustic), scene_path.read_text(), cli])
    cache = Path(args.cache_dir)
    cache.mkdir(parents=True, exist_ok=True)
    path = cache / f"auto-choice-{hashlib.sha256(key.encode()).hexdigest()[:16]}"
    if not path.with_suffix(".npy").exists():
        image, stats, _ = caustic_cli.run(args.caustic, scene_path, cli, read_exr)
        np.save(path.with_suffix(".npy"), image)
        path.with_suffix(".json").write_text(json.dumps(stats))
    image = np.load(path.with_suffix(".npy"))
    stats = json.loads(path.with_suffix(".json").read_text())
    # The reference's reported error (noise, plus the maps' bias for stage-lights) is relative
    # RMS: its square times the image's mean square is its squared error.
    return image, stats["relative_error"] ** 2 * float(np.mean(image ** 2))


def measure(args, scene_path, cli, ref, noise2):
    rows = []
    for seed in range(args.seeds):
        image, st, _ = caustic_cli.run(args.caustic, scene_path, [
            *cli, "--set", f"target_error={args.target}", "--set", f"spp={args.max_spp}",
            "--set", f"time_limit={args.time_limit}", "--set", f"seed={seed}"], read_exr)
        ref2 = float(np.mean(ref ** 2))
        true = math.sqrt(max(float(np.mean((image - ref) ** 2)) - noise2, 0.0) / ref2)
        rows.append({"seconds": st["total_seconds"], "spp": st["spp"], "passes": st["passes"],
                     "reported": st["relative_error"], "bias": st.get("relative_bias") or 0.0,
                     "true": true, "stop": st["stop_reason"]})
    med = {k: statistics.median(r[k] for r in rows)
           for k in ("seconds", "spp", "passes", "reported", "bias", "true")}
    med["range"] = (min(r["seconds"] for r in rows), max(r["seconds"] for r in rows))
    med["reached"] = (all(r["stop"] == "target_error" for r in rows)
                      and med["true"] <= args.tolerance * args.target)
    return med


def chosen(args):
    words = [w for w in args.configs.split(",") if w]
    return [(label, cli) for i, (label, cli) in enumerate(CONFIGS)
            if i == 0 or not words or any(w in label for w in words)]


def main():
    args = parse_args()
    command = os.environ.get("COMPARE_COMMAND", " ".join(sys.argv))
    print(f"Command: `{command}`; {args.size}x{args.size}, target_error {args.target}, "
          f"at most {args.max_spp} spp and {args.time_limit:g} s, {args.seeds} seeds (median, "
          f"range), {args.ref_spp}-spp references.\n")
    print("| scene | configuration | seconds (range) | spp | passes | reported (bias) | true | "
          "reached | / best |")
    print("|---|---|---:|---:|---:|---:|---:|---|---:|")
    summary = []
    with tempfile.TemporaryDirectory() as scratch:
        scene_path = Path(scratch) / "scene.json"
        for name in args.scenes.split(","):
            scene_path.write_text(json.dumps(
                caustic_cli.load_scene(REPO / "scenes" / f"{name}.json", args.size)))
            ref, noise2 = reference(args, name, scene_path)
            results = [(label, measure(args, scene_path, cli, ref, noise2))
                       for label, cli in chosen(args)]
            reached = [m["seconds"] for _, m in results if m["reached"]]
            best = min(reached) if reached else float("nan")
            for label, m in results:
                print(f"| {name} | {label} | {m['seconds']:.2f} ({m['range'][0]:.2f}-"
                      f"{m['range'][1]:.2f}) | {m['spp']:.0f} | {m['passes']:.0f} | "
                      f"{m['reported']:.4f} ({m['bias']:.4f}) | {m['true']:.4f} | "
                      f"{'yes' if m['reached'] else 'no'} | {m['seconds'] / best:.2f} |",
                      flush=True)
            auto = results[0][1]
            summary.append((name, auto["seconds"] / best, auto["reached"],
                            min((m["seconds"], label) for label, m in results if m["reached"])[1]
                            if reached else "none"))
    print("\n| scene | auto / best | auto reached | best |")
    print("|---|---:|---|---|")
    for name, ratio, ok, best_label in summary:
        print(f"| {name} | {ratio:.2f} | {'yes' if ok else 'no'} | {best_label} |")


if __name__ == "__main__":
    main()
