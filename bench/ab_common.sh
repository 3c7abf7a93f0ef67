#!/usr/bin/env bash
# Sourced by the A/B scripts (kdtree_build_ab.sh, accel_rays_ab.sh): their options, the builds of
# one of this checkout's benchmarks against two revisions of the renderer, in git worktrees, and
# the runs of the two binaries in alternation.
#
# worktree_of REV: the worktree $root/<commit> of REV (created once, reused by later runs; remove
# them with `git worktree remove`), configured for a Release build without tests. Prints its path.
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)  # this checkout
root=${AB_DIR:-/tmp/caustic-kdtree-ab}
worktree_of() {
    local sha worktree
    sha=$(git -C "$src" rev-parse --verify "$1^{commit}")
    worktree=$root/$sha
    [[ -d $worktree ]] || git -C "$src" worktree add --detach -q "$worktree" "$sha"
    local launcher=()
    command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    cmake -S "$worktree" -B "$worktree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCAUSTIC_BUILD_TESTS=OFF "${launcher[@]}" >/dev/null
    echo "$worktree"
}

# build_revision REV TARGET SOURCE...: REV's worktree (worktree_of), this checkout's SOURCE files
# copied into its bench/ (they use only the accelerators' public interface, so they compile
# against older renderers too), TARGET added to its bench/CMakeLists.txt if missing (from the
# first SOURCE) and built. Prints the binary's path.
build_revision() {
    local rev=$1 target=$2 worktree
    shift 2
    worktree=$(worktree_of "$rev")
    local file
    for file in "$@"; do cp "$src/bench/$file" "$worktree/bench/"; done
    if ! grep -q "add_executable($target " "$worktree/bench/CMakeLists.txt"; then
        printf '%s\n' "add_executable($target $1)" \
            "target_link_libraries($target PRIVATE caustic_renderer caustic_command_line)" \
            >>"$worktree/bench/CMakeLists.txt"
        cmake "$worktree/build" >/dev/null
    fi
    ninja -C "$worktree/build" "$target" >&2
    echo "$worktree/build/bench/$target"
}

# start_ab USAGE COUNT_OPTION "$@": the A/B scripts' options. Sets rounds, meshes and count
# (COUNT_OPTION's value; the caller sets their defaults), rev_a and rev_b, and `runs`, a temporary
# file for the runs' output, removed on exit. -h prints the calling script's header comment.
start_ab() {
    local usage=$1 count_option=$2
    shift 2
    while [[ $# -gt 0 ]]; do
        case $1 in
            --rounds) rounds=$2; shift 2 ;;
            --meshes) meshes=$2; shift 2 ;;
            "$count_option") count=$2; shift 2 ;;
            -h | --help) sed -n '2,/^set -/p' "$0" | sed '$d' | cut -c3-; exit 0 ;;
            *) break ;;
        esac
    done
    if [[ $# -ne 2 ]]; then
        echo "usage: $usage" >&2
        exit 2
    fi
    rev_a=$1 rev_b=$2
    runs=$(mktemp)
    trap 'rm -f "$runs"' EXIT
}

# alternate BINARY_A BINARY_B OUT ARGS...: runs the two binaries with ARGS, $rounds times each, in
# alternation (A B, B A, A B, ...), appending their output lines to OUT, each prefixed with its
# side, A or B, and a tab.
alternate() {
    local binary_a=$1 binary_b=$2 out=$3 round side
    shift 3
    for ((round = 0; round < rounds; round++)); do
        local order=(A B)
        ((round % 2)) && order=(B A)
        for side in "${order[@]}"; do
            local binary=$binary_a
            [[ $side == B ]] && binary=$binary_b
            "$binary" "$@" | sed "s/^/$side\t/" >>"$out"
        done
        echo "round $((round + 1)) of $rounds done" >&2
    done
}

# run_ab TARGET OUT "SOURCE..." ARGS...: TARGET built from the SOURCE files (space-separated) for
# $rev_a and $rev_b, then the two run in alternation with ARGS, their output appended to OUT.
run_ab() {
    local target=$1 out=$2 sources binary_a binary_b
    read -ra sources <<<"$3"
    shift 3
    binary_a=$(build_revision "$rev_a" "$target" "${sources[@]}")
    binary_b=$(build_revision "$rev_b" "$target" "${sources[@]}")
    alternate "$binary_a" "$binary_b" "$out" "$@"
}
