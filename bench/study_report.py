"""The speed/accuracy study's report: plots and summary from bench_study's CSV (bench/study.sh).

Every figure in the summary is computed here from the CSV, so the text cannot disagree with it.
Writes, into --out: one log-log plot of error against time per scene (<scene>.png), the
error-trust plot (error-trust.png) and README.md.
"""

import argparse
import csv
import json
import math
import os
import statistics
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

UNBIASED = ("path",)  # integrators whose pass variance is their whole error


def load(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            for k in ("spp_per_pass", "seed", "spp", "passes"):
                r[k] = int(r[k])
            for k in ("seconds", "rmse", "rel_mse", "rmse_edges", "reported_rel_error",
                      "true_rel_error", "noise_rel_error", "bias_rms", "coverage95"):
                r[k] = float(r[k])
            r["rmse_caustic"] = float(r["rmse_caustic"]) if r["rmse_caustic"] else None
            rows.append(r)
    return rows


def curves(rows):
    """{scene: {config: [(spp, seconds, rmse, row...)]}}: per rung, the median time over seeds and
    the RMS of the error over seeds (the error's expectation, not one seed's luck)."""
    by = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    for r in rows:
        by[r["scene"]][r["config"]][r["spp"]].append(r)
    out = defaultdict(dict)
    for scene, configs in by.items():
        for config, rungs in configs.items():
            points = []
            for spp in sorted(rungs):
                rs = rungs[spp]
                rms = lambda key: math.sqrt(statistics.fmean(x[key] ** 2 for x in rs))  # noqa: E731
                caustic = [x["rmse_caustic"] for x in rs if x["rmse_caustic"] is not None]
                points.append({
                    "spp": spp,
                    "passes": rs[0]["passes"],
                    "seconds": statistics.median(x["seconds"] for x in rs),
                    "rmse": rms("rmse"),
                    "rel_mse": statistics.fmean(x["rel_mse"] for x in rs),
                    "rmse_edges": rms("rmse_edges"),
                    "rmse_caustic": math.sqrt(statistics.fmean(c * c for c in caustic))
                    if caustic else None,
                    "rows": rs,
                })
            out[scene][config] = points
    return out


def integrator_of(rows, config):
    return next(r["integrator"] for r in rows if r["config"] == config)


def sampler_of(rows, config):
    return next(r["sampler"] for r in rows if r["config"] == config)


def time_to_reach(points, target):
    """Seconds at which the curve's RMSE first falls to `target`, interpolated log-log between
    rungs; None when it never does within the ladder."""
    prev = None
    for p in points:
        if p["rmse"] <= target:
            if prev is None or p["rmse"] <= 0:
                return p["seconds"]
            # log-log interpolation between the rung above the target and this one
            f = (math.log(prev["rmse"]) - math.log(target)) / (
                math.log(prev["rmse"]) - math.log(p["rmse"]))
            return math.exp(math.log(prev["seconds"]) +
                            f * (math.log(p["seconds"]) - math.log(prev["seconds"])))
        prev = p
    return None


def fit_slope(points, key_x, key_y="rmse", min_passes=2):
    """Least-squares slope of log(MSE) against log(x) over the rungs with at least min_passes."""
    pts = [(math.log(p[key_x]), 2 * math.log(p[key_y])) for p in points
           if p["passes"] >= min_passes and p[key_y] and p[key_y] > 0]
    if len(pts) < 3:
        return None
    mx = statistics.fmean(x for x, _ in pts)
    my = statistics.fmean(y for _, y in pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sxx if sxx > 0 else None


def equal_time_ratio(a_points, b_points):
    """a's RMSE over b's at the latest time both curves reach (interpolated log-log): > 1 when b
    has less error at equal time. None when the curves share no time."""
    t = min(a_points[-1]["seconds"], b_points[-1]["seconds"])
    a, b = interpolate_rmse(a_points, t), interpolate_rmse(b_points, t)
    return a / b if a and b else None


def interpolate_rmse(points, seconds):
    """The curve's RMSE at `seconds` (log-log between rungs); None outside its time range."""
    if points and abs(points[-1]["seconds"] - seconds) < 1e-12:
        return points[-1]["rmse"]
    for a, b in zip(points, points[1:]):
        if a["seconds"] <= seconds <= b["seconds"] and a["rmse"] > 0 and b["rmse"] > 0:
            f = (math.log(seconds) - math.log(a["seconds"])) / (
                math.log(b["seconds"]) - math.log(a["seconds"]))
            return math.exp(math.log(a["rmse"]) + f * (math.log(b["rmse"]) - math.log(a["rmse"])))
    return None


def fmt_s(v):
    return "—" if v is None else (f"{v:.3g} s" if v < 100 else f"{v:.0f} s")


def plot_scene(scene, configs, out_dir):
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    # tab20: a colour of its own for each of up to 20 configurations.
    for i, (config, points) in enumerate(configs.items()):
        style = "-" if config.startswith("path") else "--"
        ax.loglog([p["seconds"] for p in points], [p["rmse"] for p in points], style,
                  marker="o", markersize=3, label=config, color=plt.cm.tab20(i % 20))
    ax.set_xlabel("seconds (2 threads)")
    ax.set_ylabel("RMSE against the reference")
    ax.set_title(scene)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, f"{scene}.png"), dpi=100)
    plt.close(fig)


def plot_trust(rows, out_dir):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    by = defaultdict(list)
    for r in rows:
        if r["integrator"] in UNBIASED and r["passes"] >= 2 and r["true_rel_error"] > 0:
            by[(r["scene"], r["config"])].append(r)
    for (scene, config), rs in sorted(by.items()):
        if config != "path":
            continue
        rs.sort(key=lambda r: (r["seed"], r["spp"]))
        for seed in sorted({r["seed"] for r in rs}):
            s = [r for r in rs if r["seed"] == seed]
            a1.semilogx([r["spp"] for r in s],
                        [r["reported_rel_error"] / r["true_rel_error"] for r in s], marker="o",
                        markersize=3, label=scene if seed == 1 else None)
            a2.semilogx([r["spp"] for r in s], [r["coverage95"] for r in s], marker="o",
                        markersize=3, label=scene if seed == 1 else None)
    for a in (a1, a2):
        a.set_xlabel("spp (path, 4 per pass)")
        a.grid(True, which="both", alpha=0.3)
    a1.axhspan(0.8, 1.25, color="green", alpha=0.1)
    a1.set_ylabel("reported / true relative error")
    a2.axhline(0.95, color="black", lw=0.8)
    a2.set_ylabel("share of pixel values inside their 95% interval")
    a1.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "error-trust.png"), dpi=100)
    plt.close(fig)


def report(rows, meta, command, out_dir):
    cv = curves(rows)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    configs = list(dict.fromkeys(r["config"] for r in rows))
    for scene in scenes:
        plot_scene(scene, cv[scene], out_dir)
    plot_trust(rows, out_dir)
    lines = []
    w = lines.append
    w("# Speed versus accuracy: the study\n")
    w("Generated by `bench/study_report.py` from `study.csv`; every figure below is computed from "
      "that file. Reproduce it with one command (about 30 minutes on 2 cores; the references are "
      "cached beside the binary):\n")
    w("```\n" + command + "\n```\n")
    w(f"Run: {meta['machine']} {meta['size']}×{meta['size']} pixels, reference {meta['ref_spp']} "
      f"spp, rungs {', '.join(map(str, meta['ladder']))} spp, {meta['seeds']} seed(s); "
      f"{len(rows)} rows. References took: " +
      ", ".join(f"{s} {t:.0f} s" for s, t in meta["reference_seconds"].items()) + ".\n")
    w("**Method.** Each example scene at the CSV's resolution, rendered by each configuration once "
      "per seed to the top of a ladder of samples per pixel; at every rung (a pass boundary: the "
      "image after N passes is bit for bit the render of N passes) the time so far and the error "
      "against a long `path` reference (independent sampler, seed 1000003). RMSE is over every "
      "pixel and channel, less the reference's own noise (√(MSE − Σ reference se² / n)); relative "
      "MSE is the mean of (v − r)² / (r² + 0.01). Regions: *caustic*, the floor disk the glass "
      "sphere focuses the light on (scenes with a glass sphere); *edges*, pixels within 0.1 of two "
      "walls. Curves are the RMS over seeds of each rung's error, at the median time. Times are "
      "wall seconds on this machine's 2 threads, setup included.\n")
    w("Configurations: " + "; ".join(
        f"`{c}` ({integrator_of(rows, c)}, {next(r['sampler'] for r in rows if r['config'] == c)}"
        f" sampler, {next(r['spp_per_pass'] for r in rows if r['config'] == c)} spp per pass)"
        for c in configs) + ". Photon configurations trace 50,000 photon paths and 200,000 "
      "caustic photon paths per pass; `photon` uses the k nearest photons, `ppm` shrinks its "
      "radius with `alpha` (2/3 unless named). `path+photon_map` is `path` with "
      "`caustics=photon_map`: caustics from a caustic photon map of 15,000 (4 spp a pass) or "
      "50,000 (16 spp a pass) caustic photon paths per pass, its radius shrinking as `ppm`'s. "
      "`path+indirect_map` is `path` with `indirect=photon_map`: the light leaving the second "
      "diffuse vertex from an indirect photon map of 10,000 (4 spp a pass) or 30,000 (16 spp a "
      "pass, the default) photon paths per pass, its radius shrinking likewise; "
      "`path+photon_maps` has both maps. Every `path` configuration estimates the emission a "
      "camera ray sees first with `emission_samples` (default 8) more rays a sample. "
      "`sobol-sequence` runs one Sobol' sequence through a pixel's passes (`sampler=sobol_sequence`) "
      "instead of scrambling each pass anew. Whitted and ray casting are left out: they do not "
      "converge to the same image.\n")

    # 1. Time to a given error.
    w("## Which configuration reaches a given error fastest\n")
    w("Target: the RMSE `path` reaches at its 64-spp rung (its last, if the ladder is shorter) on "
      "that scene. Time to reach it, "
      "interpolated log-log between rungs (— : not within the ladder); the fastest in bold.\n")
    w("| scene | target RMSE | " + " | ".join(configs) + " | fastest | × path |")
    w("|---|---:|" + "---:|" * len(configs) + "---|---:|")
    fastest = {}
    for scene in scenes:
        path = cv[scene].get("path")
        target = next((p["rmse"] for p in path if p["spp"] == 64), path[-1]["rmse"]) if path else None
        if not target or target <= 0:
            continue
        times = {c: time_to_reach(cv[scene][c], target) for c in configs if c in cv[scene]}
        reached = {c: t for c, t in times.items() if t is not None}
        if not reached:
            continue
        best = min(reached, key=reached.get)
        fastest[scene] = (best, reached[best], times.get("path"))
        cells = [("**" + fmt_s(times.get(c)) + "**") if c == best else fmt_s(times.get(c))
                 for c in configs]
        ratio = times["path"] / reached[best] if times.get("path") else None
        w(f"| {scene} | {target:.4g} | " + " | ".join(cells) + f" | {best} | " +
          (f"{ratio:.2f} |" if ratio else "— |"))
    w("")
    for scene, (best, t, tp) in fastest.items():
        w(f"- **{scene}**: `{best}` reaches the target in {fmt_s(t)}"
          + (f", {tp / t:.2f}× faster than `path` ({fmt_s(tp)})." if tp and best != "path"
             else "; nothing beats `path` there."))
    w("")

    # 2. Convergence rates.
    w("## Convergence rates\n")
    w("Least-squares slope of log MSE against log spp over the rungs with at least 2 passes. "
      "Monte Carlo gives −1; progressive photon mapping tends to −alpha (−2/3) once its shrinking "
      "radius' noise dominates, and a fixed photon map flattens towards 0 as its bias takes over; "
      "over a short ladder the camera paths' own noise (−1) still weighs in. Adaptive sampling "
      "looks steeper than −1 because its samples move after the pilot (32 spp at 4 per pass): a "
      "one-time gain, not a faster rate. Against time the slopes are alike: time grows in "
      "proportion to spp.\n")
    w("| scene | " + " | ".join(configs) + " |")
    w("|---|" + "---:|" * len(configs))
    for scene in scenes:
        cells = []
        for c in configs:
            s = fit_slope(cv[scene][c], "spp") if c in cv[scene] else None
            cells.append("—" if s is None else f"{s:.2f}")
        w(f"| {scene} | " + " | ".join(cells) + " |")
    w("")
    ranges = []
    for c in configs:
        slopes = [fit_slope(cv[sc][c], "spp") for sc in scenes if c in cv[sc]]
        slopes = [x for x in slopes if x is not None]
        if slopes:
            ranges.append(f"`{c}` {min(slopes):.2f} to {max(slopes):.2f}")
    w("Measured ranges over the scenes: " + "; ".join(ranges) + ".\n")

    # 3. Samplers at equal time.
    w("## The sobol sampler against independent numbers, at equal time\n")
    w("RMSE of `path` over the sobol configuration's, both interpolated at the latest time both "
      "reached (> 1: sobol wins). MSE ratios are the square.\n")
    sobols = [c for c in configs if c.startswith("path-sobol") and not c.endswith("adaptive")]
    w("| scene | " + " | ".join(f"path ÷ {c}" for c in sobols) + " |")
    w("|---|" + "---:|" * len(sobols))
    for scene in scenes:
        cells = []
        for c in sobols:
            r = equal_time_ratio(cv[scene]["path"], cv[scene][c])
            cells.append("—" if r is None else f"{r:.2f}")
        w(f"| {scene} | " + " | ".join(cells) + " |")
    w("")

    # 3b. Adaptive sampling at equal time.
    adaptive = [(c, c.replace("-adaptive", "")) for c in configs
                if c.endswith("-adaptive") and c.replace("-adaptive", "") in configs]
    if adaptive:
        w("## Adaptive sampling against uniform sampling, at equal time\n")
        w("RMSE of the uniform configuration over the adaptive one's, both interpolated at the "
          "latest time both reached (> 1: adaptive wins); and their relative MSE at the top rung "
          "(equal spp), which weighs dark pixels more.\n")
        w("| scene | " + " | ".join(f"{u} ÷ {a}" for a, u in adaptive) + " | " +
          " | ".join(f"relMSE {u} ÷ {a}" for a, u in adaptive) + " |")
        w("|---|" + "---:|" * (2 * len(adaptive)))
        for scene in scenes:
            cells, rel = [], []
            for a, u in adaptive:
                r = equal_time_ratio(cv[scene][u], cv[scene][a])
                cells.append("—" if r is None else f"{r:.2f}")
                rel.append(f"{cv[scene][u][-1]['rel_mse'] / cv[scene][a][-1]['rel_mse']:.2f}")
            w(f"| {scene} | " + " | ".join(cells) + " | " + " | ".join(rel) + " |")
        w("")

    # 4. Error estimates.
    w("## Can users trust the reported error?\n")
    w("For the unbiased path tracer, the relative error the render reports (from its pass "
      "variance) over the true relative error (against the reference, less its noise), over the "
      "rungs with at least 8 passes and every seed; and the share of pixel values whose 95% "
      "Student-t interval from the passes (widened by the reference's own standard error) holds "
      "the reference, at the top rung (mean over seeds). Goal: ratio within 0.8 – 1.25, coverage "
      "about 95%; except for `sobol_sequence`, whose passes are negatively correlated (one "
      "sequence runs through them), so that its reported error is an overestimate by design: "
      "its goal is a ratio of at least 0.8.\n")
    w("| scene | config | ratio min | ratio median | ratio max | coverage at top rung |")
    w("|---|---|---:|---:|---:|---:|")
    for scene in scenes:
        for c in configs:
            if integrator_of(rows, c) not in UNBIASED or c not in cv[scene]:
                continue
            rs = [r for p in cv[scene][c] for r in p["rows"]
                  if r["passes"] >= 8 and r["true_rel_error"] > 0]
            if not rs:
                continue
            ratios = [r["reported_rel_error"] / r["true_rel_error"] for r in rs]
            top = cv[scene][c][-1]["rows"]
            cov = statistics.fmean(r["coverage95"] for r in top)
            w(f"| {scene} | {c} | {min(ratios):.2f} | {statistics.median(ratios):.2f} | "
              f"{max(ratios):.2f} | {100 * cov:.1f}% |")
    w("")
    w("Photon mapping's reported error excludes its bias: the passes of `photon` share one bias "
      "and `ppm`'s (and `path+photon_map`'s) shrinks pass by pass, so the pass variance sees neither. Its share of the "
      "error at the top rung, √(MSE − noise² − reference noise²) over the RMSE. `path`, which "
      "has no bias, is the control: what it shows is the measure's own floor (the pass "
      "variance's error as a noise estimate, and the reference's). Left out: the "
      "`sobol_sequence` configurations, whose pass variance overestimates their noise, so that "
      "this measure finds no bias whatever there is.\n")
    photon_configs = [c for c in configs if integrator_of(rows, c) not in UNBIASED
                      and sampler_of(rows, c) != "sobol_sequence"]
    if "path" in configs:
        photon_configs.insert(0, "path")
    w("| scene | " + " | ".join(c + (" (control)" if c == "path" else "")
                               for c in photon_configs) + " |")
    w("|---|" + "---:|" * len(photon_configs))
    for scene in scenes:
        cells = []
        for c in photon_configs:
            top = cv[scene][c][-1]["rows"]
            rmse = math.sqrt(statistics.fmean(r["rmse"] ** 2 for r in top))
            bias = math.sqrt(statistics.fmean(r["bias_rms"] ** 2 for r in top))
            cells.append(f"{100 * bias / rmse:.0f}%" if rmse > 0 else "—")
        w(f"| {scene} | " + " | ".join(cells) + " |")
    w("")

    # 4b. Forecasts.
    fpath = meta.get("forecast_csv")
    if fpath and os.path.exists(fpath):
        with open(fpath, newline="") as f:
            frows = list(csv.DictReader(f))
        w("## How long until the target error? The forecast against the real time\n")
        w(f"`path`, 4 spp per pass, `target_error` {meta['forecast_target']}, seed 1: the "
          "forecast the render reports (`eta_seconds` in the API, the CLI's ETA) after 8, 16 and "
          "32 passes, as a predicted total time, against the time the render took to reach the "
          "target (render seconds, setup excluded).\n")
        w("| scene | real passes | real s | after 8: predicted s (÷ real) | after 16 | after 32 |")
        w("|---|---:|---:|---:|---:|---:|")
        for scene in scenes:
            rs = [r for r in frows if r["scene"] == scene]
            if not rs:
                continue
            real = float(rs[0]["real_seconds"])
            by = {int(r["after_passes"]): float(r["predicted_seconds"]) for r in rs}
            cells = [f"{by[n]:.2f} ({by[n] / real:.2f})" if n in by else "—" for n in (8, 16, 32)]
            w(f"| {scene} | {rs[0]['real_passes']} | {real:.2f} | " + " | ".join(cells) + " |")
        w("")

    # 5. Regions.
    w("## Regions at the top rung\n")
    w("RMSE over the caustic and over the room's edges and corners (RMS over seeds).\n")
    w("| scene | config | spp | seconds | RMSE | caustic | edges |")
    w("|---|---|---:|---:|---:|---:|---:|")
    for scene in scenes:
        for c in configs:
            top = cv[scene][c][-1]
            caustic = "—" if top["rmse_caustic"] is None else f"{top['rmse_caustic']:.4f}"
            w(f"| {scene} | {c} | {top['spp']} | {top['seconds']:.2f} | {top['rmse']:.4f} | "
              f"{caustic} | {top['rmse_edges']:.4f} |")
    w("")
    w("## Plots\n")
    for scene in scenes:
        w(f"![{scene}]({scene}.png)")
    w("\n![error trust](error-trust.png)\n")
    with open(os.path.join(out_dir, "README.md"), "w") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("csv")
    ap.add_argument("--out", required=True)
    ap.add_argument("--command", default="bench/study.sh")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    with open(a.csv + ".json") as f:
        meta = json.load(f)
    meta["forecast_csv"] = a.csv[:a.csv.rfind(".")] + "-forecast.csv"
    report(load(a.csv), meta, a.command, a.out)
    print(f"wrote {a.out}/README.md and its plots")


if __name__ == "__main__":
    main()
