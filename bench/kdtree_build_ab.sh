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

rounds=10 builds=8 meshes=bunny,teapot
while [[ $# -gt 0 ]]; do
    case $1 in
        --rounds) rounds=$2; shift 2 ;;
        --builds) builds=$2; shift 2 ;;
        --meshes) meshes=$2; shift 2 ;;
        -h | --help) sed -n '2,12p' "$0" | cut -c3-; exit 0 ;;
        *) break ;;
    esac
done
if [[ $# -ne 2 ]]; then
    echo "usage: $0 [--rounds N] [--builds N] [--meshes LIST] REV_A REV_B" >&2
    exit 2
fi
src=$(cd "$(dirname "$0")/.." && pwd)
root=${AB_DIR:-/tmp/caustic-kdtree-ab}

# Builds bench_kdtree_build for revision $1; prints the binary's path.
build_revision() {
    local sha worktree
    sha=$(git -C "$src" rev-parse --verify "$1^{commit}")
    worktree=$root/$sha
    [[ -d $worktree ]] || git -C "$src" worktree add --detach -q "$worktree" "$sha"
    # This checkout's benchmark, whatever the revision holds: it uses only the accelerators'
    # public interface, so it compiles against older renderers too.
    cp "$src"/bench/{kdtree_build.cpp,bench_meshes.h,bench_common.h} "$worktree/bench/"
    grep -q bench_kdtree_build "$worktree/bench/CMakeLists.txt" ||
        printf '%s\n' 'add_executable(bench_kdtree_build kdtree_build.cpp)' \
            'target_link_libraries(bench_kdtree_build PRIVATE caustic_renderer caustic_command_line)' \
            >>"$worktree/bench/CMakeLists.txt"
    local launcher=()
    command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    cmake -S "$worktree" -B "$worktree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCAUSTIC_BUILD_TESTS=OFF "${launcher[@]}" >/dev/null
    ninja -C "$worktree/build" bench_kdtree_build >&2
    echo "$worktree/build/bench/bench_kdtree_build"
}

binary_a=$(build_revision "$1")
binary_b=$(build_revision "$2")
runs=$(mktemp)
trap 'rm -f "$runs"' EXIT
for ((round = 0; round < rounds; round++)); do
    order=(A B)
    ((round % 2)) && order=(B A)
    for side in "${order[@]}"; do
        binary=$binary_a
        [[ $side == B ]] && binary=$binary_b
        "$binary" --repeats "$builds" --meshes "$meshes" --tsv | sed "s/^/$side\t/" >>"$runs"
    done
    echo "round $((round + 1)) of $rounds done" >&2
done

python3 - "$runs" "$1" "$2" "$rounds" "$builds" <<'EOF'
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
