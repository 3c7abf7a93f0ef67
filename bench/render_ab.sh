#!/usr/bin/env bash
# A change to the renderer's speed, measured on a machine too noisy for one run to tell: the
# `caustic` binary built at two revisions, the same render run by each in alternation (A B, B A,
# A B, ...). Prints each revision's render seconds (the stats' render_seconds: set-up and start-up
# apart) per round, their medians, B's median over A's, and whether the two revisions' images are
# the same to the bit (idiff, OpenImageIO's tools: scripts/install-deps.sh installs them).
#
# Usage: bench/render_ab.sh [--rounds N] REV_A REV_B SCENE [caustic render options...]
#   e.g. bench/render_ab.sh --rounds 6 HEAD~1 HEAD scenes/bunny.json --set spp=64
# Worktrees as bench/kdtree_build_ab.sh's (same $AB_DIR). Run nothing else CPU-heavy meanwhile.
set -euo pipefail

# shellcheck source=bench/ab_common.sh
source "$(dirname "$0")/ab_common.sh"
rounds=6
if [[ ${1:-} == --rounds ]]; then
    rounds=$2
    shift 2
fi
if [[ $# -lt 3 ]]; then
    sed -n '2,/^set -/p' "$0" | sed '$d' | cut -c3-
    exit 2
fi
rev_a=$1 rev_b=$2 scene=$(realpath "$3")
shift 3

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
declare -A binary
for side in A B; do
    rev=$rev_a
    [[ $side == B ]] && rev=$rev_b
    worktree=$(worktree_of "$rev")
    ninja -C "$worktree/build" caustic >&2
    binary[$side]=$worktree/build/cli/caustic
done

for ((round = 0; round < rounds; round++)); do
    order=(A B)
    ((round % 2)) && order=(B A)
    for side in "${order[@]}"; do
        "${binary[$side]}" render "$scene" -o "$out/$side.exr" --stats "$out/$side.json" \
            --no-progress "$@" >/dev/null
        python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["stats"]["render_seconds"])' \
            "$out/$side.json" >>"$out/$side.seconds"
    done
    echo "round $((round + 1)) of $rounds done" >&2
done

same="differ"
idiff -q -fail 0 -warn 0 "$out/A.exr" "$out/B.exr" >/dev/null 2>&1 && same="are the same to the bit"
python3 - "$out" "$rev_a" "$rev_b" "$same" "$*" <<'EOF'
import statistics, sys
out, rev_a, rev_b, same, options = sys.argv[1:]
a, b = ([float(x) for x in open(f"{out}/{side}.seconds")] for side in "AB")
print(f"A = {rev_a}, B = {rev_b}: {len(a)} renders each in alternation, options: {options}")
print("render seconds, A: " + " ".join(f"{x:.3f}" for x in a))
print("render seconds, B: " + " ".join(f"{x:.3f}" for x in b))
ma, mb = statistics.median(a), statistics.median(b)
print(f"medians: A {ma:.3f} s, B {mb:.3f} s; B / A = {mb / ma:.3f} (A / B = {ma / mb:.3f})")
print(f"the last renders' images {same}")
EOF
