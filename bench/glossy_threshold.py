#!/usr/bin/env python3
"""Where the photon mappers should follow glossy surfaces as mirrors (the setting
follow_roughness): cornell-spheres with its mirror sphere made a rough metal (conductor, F0
[0.95, 0.93, 0.88]) of each --roughness, 128x128. For each, the relative RMSE (RMSE over the
reference's mean) against path tracing at --ref-spp of: photon at 64 spp and ppm at 256 spp,
with the sphere estimated from the photon maps (follow_roughness=0) and followed
(follow_roughness=1); and path at 64 spp for scale. Prints Markdown. Needs only numpy and
OpenImageIO's Python module or Mitsuba's bitmap reader: run it in bench/mitsuba_compare.sh's venv:

  build/bench-venv/bin/python bench/glossy_threshold.py
"""
import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import caustic_cli  # noqa: E402
import mitsuba_compare as mc  # noqa: E402

REPO = Path(__file__).resolve().parent.parent


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--caustic", default=str(REPO / "build/cli/caustic"))
    p.add_argument("--roughness", type=lambda v: [float(x) for x in v.split(",")],
                   default=[0.05, 0.1, 0.2, 0.3, 0.4, 0.5])
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--size", type=int, default=128)
    args = p.parse_args()
    base = json.loads((REPO / "scenes/cornell-spheres.json").read_text())
    base["camera"]["width"] = base["camera"]["height"] = args.size
    base.pop("settings", None)
    runs = [("photon, maps", ["integrator=photon", "spp=64", "follow_roughness=0"]),
            ("photon, followed", ["integrator=photon", "spp=64", "follow_roughness=1"]),
            ("ppm, maps", ["integrator=ppm", "spp=256", "follow_roughness=0"]),
            ("ppm, followed", ["integrator=ppm", "spp=256", "follow_roughness=1"]),
            ("path", ["integrator=path", "spp=64"])]
    print(f"`{' '.join(sys.argv)}`: cornell-spheres, {args.size}², the metal sphere's roughness "
          f"per row; relative RMSE against path at {args.ref_spp} spp (photon 64 spp, ppm 256, "
          f"path 64).\n")
    print("| roughness | " + " | ".join(name for name, _ in runs) + " |")
    print("|---:|" + "---:|" * len(runs))
    with tempfile.TemporaryDirectory() as scratch:
        for r in args.roughness:
            scene = json.loads(json.dumps(base))
            scene["materials"]["mirror"] = {"type": "conductor", "roughness": r,
                                            "f0": [0.95, 0.93, 0.88]}
            path = Path(scratch) / "scene.json"
            path.write_text(json.dumps(scene))
            settings = lambda s: sum((["--set", x] for x in s), [])  # noqa: E731
            ref = caustic_cli.run(args.caustic, path, settings(
                ["integrator=path", f"spp={args.ref_spp}", "seed=7"]), mc.read_exr)[0]
            errors = []
            for _, s in runs:
                image = caustic_cli.run(args.caustic, path, settings(s), mc.read_exr)[0]
                errors.append(mc.rmse(image, ref) / ref.mean())
            print(f"| {r} | " + " | ".join(f"{e:.4f}" for e in errors) + " |", flush=True)


if __name__ == "__main__":
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    main()
