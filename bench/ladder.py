"""The ladder of a time-to-equal-error comparison (bench/equal_error.py for Mitsuba 3,
bench/cycles_compare.py for Blender Cycles): each renderer renders at every spp of a ladder; a run
is a dict with "spp", "time" (seconds) and "rmse" (against the reference, less its noise).
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


def print_table(caustic, other, name):
    """One row a rung: both renderers' time and RMSE, and Caustic's time to the other's RMSE
    there, interpolated on Caustic's ladder; then the geometric mean of the ratios."""
    print(f"| spp | Caustic s | Caustic RMSE | {name} s | {name} RMSE | Caustic s to {name}'s "
          f"RMSE | {name} / Caustic time to equal RMSE |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    ratios = []
    for c, m in zip(caustic, other):
        t = time_to(m["rmse"], caustic) if m["rmse"] > 0 else float("nan")
        ratio = m["time"] / t if t > 0 else float("nan")
        if math.isfinite(ratio):
            ratios.append(ratio)
        print(f"| {c['spp']} | {c['time']:.3f} | {c['rmse']:.5f} | {m['time']:.3f} | "
              f"{m['rmse']:.5f} | {t:.3f} | {ratio:.2f}x |")
    if ratios:
        mean = math.exp(sum(math.log(r) for r in ratios) / len(ratios))
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
