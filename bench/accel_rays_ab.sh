#!/usr/bin/env bash
# A change to the kd-tree's traversal, measured on a machine too noisy for one run to tell: this
# checkout's bench/accel_rays.cpp compiled against two revisions of the renderer, the two binaries
# run in alternation (A B, B A, ...), each run `bench_accel_rays --repeats N --meshes LIST`. Per
# mesh, ray set, query and thread count it prints the median over the rounds of the kd-tree's
# rays per second for each revision, B's over A's, and Embree's rays per second over the
# kd-tree's in the same runs (each run interleaves the two accelerators).
#
# Usage: bench/accel_rays_ab.sh [--rounds N] [--repeats N] [--meshes LIST] REV_A REV_B
#   e.g. bench/accel_rays_ab.sh --rounds 2 fb20c5d HEAD
# Worktrees as bench/kdtree_build_ab.sh's (same $AB_DIR). OMP_NUM_THREADS applies to both
# binaries. Run nothing else CPU-heavy meanwhile.
set -euo pipefail

# shellcheck source=bench/ab_common.sh
source "$(dirname "$0")/ab_common.sh"
rounds=2 count=3 meshes=bunny,teapot
start_ab "$0 [--rounds N] [--repeats N] [--meshes LIST] REV_A REV_B" --repeats "$@"
run_ab bench_accel_rays "$runs" "accel_rays.cpp bench_meshes.h bench_common.h" --repeats "$count" --meshes "$meshes"

python3 - "$runs" "$rev_a" "$rev_b" "$rounds" "$count" <<'PY'
import re, statistics, sys
from collections import defaultdict

path, rev_a, rev_b, rounds, repeats = sys.argv[1:]
rows = defaultdict(list)  # (mesh, rays, query, threads, side) -> [(kdtree, embree)] in Mrays/s
keys = []
# The rays-per-second rows of the Markdown output.
row_pattern = re.compile(r"^\| [a-z0-9-]+ \| (primary|random) \| (closest|occluded) \|")
for line in open(path):
    side, row = line.split("\t", 1)
    if not row_pattern.match(row):
        continue
    cells = [c.strip() for c in row.strip().strip("|").split("|")]
    key = tuple(cells[:4])
    if key not in keys:
        keys.append(key)
    rows[key + (side,)].append((float(cells[5]), float(cells[6])))
print(f"A = {rev_a}, B = {rev_b}: {rounds} rounds in alternation of bench_accel_rays "
      f"--repeats {repeats}; medians over the rounds\n")
print("| mesh | rays | query | threads | A kdtree Mrays/s | B kdtree Mrays/s | B / A "
      "| A: Embree / kdtree | B: Embree / kdtree |\n|---|---|---|---:|---:|---:|---:|---:|---:|")
for key in keys:
    a, b = rows[key + ("A",)], rows[key + ("B",)]
    ka = statistics.median(x[0] for x in a)
    kb = statistics.median(x[0] for x in b)
    ra = statistics.median(x[1] / x[0] for x in a)
    rb = statistics.median(x[1] / x[0] for x in b)
    print(f"| {' | '.join(key)} | {ka:.3f} | {kb:.3f} | {kb / ka:.3f} | {ra:.2f}× | {rb:.2f}× |")
PY
