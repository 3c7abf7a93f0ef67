"""The ladder of a time-to-equal-error comparison (bench/equal_error.py for Mitsuba 3,
bench/cycles_compare.py for Blender Cycles): each renderer renders at every spp of a ladder; a run
is a dict with "spp", "time" (seconds) and "rmse" (against the reference, less its noise).
Caustic may render more rungs than the other renderer (--caustic-rungs), so that the other's
errors fall inside its ladder and its time to them is interpolated rather than extrapolated.
"""
import math

import numpy as np


def time_to(rmse, runs):
    """Seconds the ladder `runs` (sorted by spp) needs to reach `rmse`, interpolated in log-log."""
    pts = [(math.log(r["rmse"]), math.log(r["time"])) for r in runs if r["rmse"] > 0]
    target = math.log(rmse)
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e1 <= target <= e0 and e0 != e1:
            return math.exp(t0 + (t1 - t0) * (target - e0) / (e1 - e0))
    (e0, t0), (e1, t1) = (pts[0], pts[1]) if target > pts[0][0] else (pts[-2], pts[-1])
    if e0 == e1:
        return float("nan")
    return math.exp(t0 + (t1 - t0) * (target - e0) / (e1 - e0))


def caustic_ladder(args):
    """Caustic's rungs: the shared ladder and args.caustic_rungs, in order."""
    return sorted(set(args.ladder) | set(args.caustic_rungs or ()))


def settings_at(settings, spp):
    """--caustic-set's KEY=VALUE settings for a rung of `spp` samples: spp_per_pass, which may not
    exceed spp, is capped at it (with sobol_sequence the image is the same sequence's prefix)."""
    capped = []
    for s in settings:
        key, _, value = s.partition("=")
        capped.append(f"{key}={min(int(value), spp)}" if key == "spp_per_pass" else s)
    return capped


def geometric_mean(values):
    return math.exp(sum(math.log(v) for v in values) / len(values))


def print_table(caustic, other, name):
    """One row a rung of the other renderer: its time and RMSE, Caustic's at the same spp (if it
    rendered that rung), and Caustic's time to the other's RMSE, interpolated on Caustic's ladder
    (bold: inside it) or extrapolated beyond it; then the geometric means of the ratios."""
    print(f"| spp | Caustic s | Caustic RMSE | {name} s | {name} RMSE | Caustic s to {name}'s "
          f"RMSE | {name} / Caustic time to equal RMSE |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    by_spp = {c["spp"]: c for c in caustic}
    errors = [c["rmse"] for c in caustic if c["rmse"] > 0]
    ratios, inside = [], []
    for m in other:
        t = time_to(m["rmse"], caustic) if m["rmse"] > 0 else float("nan")
        ratio = m["time"] / t if t > 0 else float("nan")
        within = bool(errors) and min(errors) <= m["rmse"] <= max(errors)
        if math.isfinite(ratio):
            ratios.append(ratio)
            if within:
                inside.append(ratio)
        c = by_spp.get(m["spp"])
        mine = f"{c['time']:.3f} | {c['rmse']:.5f}" if c else "— | —"
        cell = f"**{ratio:.2f}x**" if within else f"{ratio:.2f}x"
        print(f"| {m['spp']} | {mine} | {m['time']:.3f} | {m['rmse']:.5f} | {t:.3f} | {cell} |")
    if inside:
        print(f"\nOn the rungs inside Caustic's ladder (bold; interpolated, not extrapolated): "
              f"{geometric_mean(inside):.2f}x.")
    if ratios:
        mean = geometric_mean(ratios)
        goal = "met" if mean >= 5 else "NOT met"
        print(f"\n**{name} / Caustic time to equal RMSE: {mean:.2f}x** (geometric mean over the "
              f"rungs; goal at least 5x: {goal}).")


def set_errors(runs, ref, noise2):
    """Sets each run's "rmse" (runs maps a renderer's name to its ladder) against `ref`, less the
    reference's noise, `noise2` (its squared RMSE; caustic_cli.reference)."""
    for rs in runs.values():
        for r in rs:
            raw2 = float(np.mean((r["image"] - ref) ** 2))
            r["rmse"] = math.sqrt(max(raw2 - noise2, 0.0))
