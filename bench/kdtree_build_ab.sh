#!/usr/bin/env bash
# A change to the kd-tree's build, measured on a machine too noisy for one run to tell: this
# checkout's bench/kdtree_build.cpp compiled against two revisions of the renderer, the two
# binaries run in alternation (A B, B A, A B, ...), each run --builds builds of each mesh. Per mesh
# and revision it prints the best round's fastest build, the median of the rounds' fastest builds,
# Embree's median build in the same runs, and B's times over A's.
#
# Usage: bench/kdtree_build_ab.sh [--rounds N] [--builds N] [--meshes LIST] REV_A REV_B
#   e.g. bench/kdtree_build_ab.sh 8f2300c HEAD
# Each revision is built once in a git worktree under $AB_DIR (default /tmp/caustic-kdtree-ab), its
# folder named by the commit, and reused by later runs (remove them with `git worktree remove`).
# OMP_NUM_THREADS applies to both binaries. Run nothing else CPU-heavy meanwhile.
set -euo pipefail

# shellcheck source=bench/ab_common.sh
source "$(dirname "$0")/ab_common.sh"
rounds=10 count=8 meshes=bunny,teapot
start_ab "$0 [--rounds N] [--builds N] [--meshes LIST] REV_A REV_B" --builds "$@"
run_ab bench_kdtree_build "$runs" "kdtree_build.cpp bench_meshes.h bench_common.h" --repeats "$count" --meshes "$meshes" --tsv

python3 - "$runs" "$rev_a" "$rev_b" "$rounds" "$count" <<'EOF'
import statistics, sys
from collections import defaultdict

path, rev_a, rev_b, rounds, builds = sys.argv[1:]
rows = defaultdict(list)  # (mesh, side) -> [(kd min, embree median, interior, references, sah)]
for line in open(path):
    side, mesh, kd_min, kd_median, em_min, em_median, interior, refs, sah = line.split("\t")
    rows[(mesh, side)].append((float(kd_min), float(em_median), interior, refs, float(sah)))
print(f"A = {rev_a}, B = {rev_b}: {rounds} rounds in alternation, {builds} builds of each mesh a "
      "run; times in ms\n")
print("| mesh | rev | best round | median round | Embree median | interior nodes | references "
      "| SAH cost |\n|---|---|---:|---:|---:|---:|---:|---:|")
meshes = list(dict.fromkeys(mesh for mesh, _ in rows))  # in the order measured
summary = []
for mesh in meshes:
    stats = {}
    for side, rev in (("A", rev_a), ("B", rev_b)):
        r = rows[(mesh, side)]
        fastest = [x[0] for x in r]
        stats[side] = (min(fastest), statistics.median(fastest))
        print(f"| {mesh} | {side} {rev} | {stats[side][0]:.2f} | {stats[side][1]:.2f} | "
              f"{statistics.median(x[1] for x in r):.2f} | {r[-1][2]} | {r[-1][3]} | "
              f"{r[-1][4]:.2f} |")
    summary.append(f"{mesh}: B/A {stats['B'][0] / stats['A'][0]:.3f} (best round), "
                   f"{stats['B'][1] / stats['A'][1]:.3f} (median round)")
print()
print("\n".join(summary))
EOF
