"""The ladder of a time-to-equal-error comparison (bench/equal_error.py for Mitsuba 3,
bench/cycles_compare.py for Blender Cycles): each renderer renders at every spp of a ladder; a run
is a dict with "spp", "time" (seconds) and "rmse" (against the reference, less its noise).
"""
import math


def reference_noise2(runs, ref_spp):
    """The squared RMSE the reference's own noise adds to every measured one: Caustic's squared
    error is about c / spp, and its reference's noise is c / ref_spp; c is estimated from the
    ladder's highest rung, whose error the reference's noise inflates the least."""
    top = max(runs, key=lambda r: r["spp"])
    # measured^2 = c / spp + c / ref_spp: solve for c.
    c = top["raw2"] / (1.0 / top["spp"] + 1.0 / ref_spp)
    return c / ref_spp


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
