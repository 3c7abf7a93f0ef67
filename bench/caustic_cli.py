"""Caustic's side of the comparisons with other renderers (bench/mitsuba_compare.py,
bench/cycles_compare.py): a render through the CLI, timed by its own stats and by the process's
CPU, and the cache key of a reference."""
import hashlib
import json
import resource
import shlex
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

# The references' seed; the timed runs use 0, 1, ..., never this one.
REFERENCE_SEED = 1_000_003


def cpu_seconds(who):
    """User + system CPU seconds of every thread of this process, or of its waited-for children:
    less sensitive than wall time to other work on a shared machine."""
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def run(caustic, scene_path, cli_args, read_exr):
    """Runs `caustic render` on scene_path with the given arguments (settings, presets); returns
    (image read by read_exr, stats dict, {wall, cpu} seconds of the whole process)."""
    out, stats = scene_path.with_name("render.exr"), scene_path.with_name("stats.json")
    cmd = [caustic, "render", str(scene_path), "-o", str(out), "--stats", str(stats),
           "--no-progress", *cli_args]
    cpu0, t0 = cpu_seconds(resource.RUSAGE_CHILDREN), time.perf_counter()
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"caustic_cli: {shlex.join(cmd)} failed:\n{done.stderr}")
    process = {"wall": time.perf_counter() - t0,
               "cpu": cpu_seconds(resource.RUSAGE_CHILDREN) - cpu0}
    return read_exr(out), json.loads(stats.read_text())["stats"], process


def render(args, scene_path, spp, seed, settings, read_exr):
    """Renders with path tracing, args.max_depth and args.rr_depth, and the settings KEY=VALUE
    given; returns what run() does."""
    cli_args = ["--set", "integrator=path", "--set", f"spp={spp}", "--set", f"seed={seed}",
                "--set", f"max_depth={args.max_depth}", "--set", f"rr_depth={args.rr_depth}"]
    for setting in settings:
        cli_args += ["--set", setting]
    return run(args.caustic, scene_path, cli_args, read_exr)


def reference_key(renderer, version, scene, args, seed):
    """A file name for a reference, from everything that determines it. Caustic's `version` is its
    binary's hash: a rebuilt renderer renders its reference anew."""
    key = json.dumps([renderer, version, scene, args.ref_spp, args.max_depth, args.rr_depth, seed],
                     sort_keys=True)
    return f"reference-{renderer}-{hashlib.sha256(key.encode()).hexdigest()[:16]}.npy"


def binary_hash(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def reference(args, scene, scene_path, cache, read_exr, seed):
    """Caustic's long reference (args.ref_spp, the scene's settings), cached by everything that
    determines it; returns (image, how it was had, its noise's squared RMSE). The noise: Caustic's
    squared error at s spp is about c / s, so one more render at ref_spp / 16 (seed + 1), whose
    squared RMSE against the reference is c / s + c / ref_spp, gives c and the reference's
    c / ref_spp. It is measured with the reference's settings, whatever the timed renders use."""
    path = cache / reference_key("caustic", binary_hash(args.caustic), scene, args, seed)
    noise_path = path.with_suffix(".noise2.json")
    how = "cached"
    if path.exists():
        image = np.load(path)
    else:
        t0 = time.perf_counter()
        image = render(args, scene_path, args.ref_spp, seed, (), read_exr)[0]
        np.save(path, image)
        how = f"rendered in {time.perf_counter() - t0:.0f} s"
    if not noise_path.exists():
        spp = max(1, args.ref_spp // 16)
        probe = render(args, scene_path, spp, seed + 1, (), read_exr)[0]
        c = float(np.mean((probe - image) ** 2)) / (1.0 / spp + 1.0 / args.ref_spp)
        noise_path.write_text(json.dumps({"noise2": c / args.ref_spp, "probe_spp": spp}))
    return image, how, json.loads(noise_path.read_text())["noise2"]


def load_scene(path, size):
    """The Caustic scene with its camera resized (the resolution lives only in the JSON)."""
    scene = json.loads(Path(path).read_text())
    scene["camera"]["width"] = scene["camera"]["height"] = size
    return scene
