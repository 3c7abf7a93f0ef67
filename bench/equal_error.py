"""Time to equal error: Caustic against Mitsuba 3 on one scene (mitsuba_compare.py --ladder).

Each renderer renders the scene once at every spp of the ladder (seed = the rung's index); each
image's RMSE is taken against Caustic's long reference, less that reference's own noise
(caustic_cli.reference). For every
rung of Mitsuba's ladder, the time Caustic needs to reach Mitsuba's RMSE there is interpolated on
Caustic's ladder, linearly in log(time) against log(RMSE) (error falls as a power of time, so
that is a straight line between rungs); beyond Caustic's ladder the line of its last two rungs is
extended. The ratio is Mitsuba's time over Caustic's: above 1, Caustic is faster to that error.
See bench/README.md, "mitsuba_compare".
"""
import math
import os
import shlex
import sys

import caustic_cli
import mitsuba_compare as mc
from ladder import caustic_ladder, print_table, set_errors, settings_at


def measure(args, scene, scene_path, cache):
    command = os.environ.get("COMPARE_COMMAND") or shlex.join(sys.argv)
    print(f"Machine: nproc {os.cpu_count()}, {mc.cpu_model()}, Mitsuba {mc.mi.__version__} "
          f"scalar_rgb. Command: `{command}`\n")
    ref, how, noise2 = caustic_cli.reference(args, scene, scene_path, cache, mc.read_exr,
                                             mc.REFERENCE_SEED)
    load_before = os.getloadavg()[0]
    # Untimed warm-ups at the lowest rung.
    mine = caustic_ladder(args)
    mc.render_caustic(scene_path, mine[0], 0, args, settings_at(args.caustic_set, mine[0]))
    mc.render_mitsuba(scene, 1, 0, args)
    runs = {"caustic": [], "mitsuba": []}
    # Rung by rung, the two renderers alternating, so that a slow spell hits both; each rung's
    # seed is its index in its renderer's ladder.
    for spp in sorted(set(mine) | set(args.ladder)):
        if spp in mine:
            image, stats, _ = mc.render_caustic(scene_path, spp, mine.index(spp), args,
                                                settings_at(args.caustic_set, spp))
            runs["caustic"].append({"spp": spp, "image": image,
                                    "time": stats["render_seconds"] + stats["setup_seconds"]})
        if spp in args.ladder:
            image, seconds = mc.render_mitsuba(scene, spp, sorted(args.ladder).index(spp), args)
            runs["mitsuba"].append({"spp": spp, "image": image, "time": seconds["render"]})
    set_errors(runs, ref, noise2)
    report(args, runs, how, math.sqrt(noise2), (load_before, os.getloadavg()[0]))


def report(args, runs, how, ref_noise, loads):
    settings = ", ".join(args.caustic_set) or "the scene's"
    print(f"{os.path.basename(args.scene)}, {args.size}x{args.size}, every core for both; "
          f"Caustic `path` with settings {settings}; "
          f"Mitsuba `path`, {args.mitsuba_sampler} sampler; "
          f"Caustic max_depth {args.max_depth} = Mitsuba max_depth {args.max_depth + 1}, "
          f"rr_depth {args.rr_depth}. Reference: Caustic, {args.ref_spp} spp, {how}; its own "
          f"noise, {ref_noise:.5f} RMSE, is taken out of every RMSE. Load average (1 min) "
          f"{loads[0]:.2f} before, {loads[1]:.2f} after.\n")
    print_table(runs["caustic"], runs["mitsuba"], "Mitsuba")
