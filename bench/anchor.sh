# Sourced by bench/mitsuba_compare.sh and bench/cycles_compare.sh, which compare Caustic with
# another renderer (an anchor) from Python packages kept in a venv beside the caustic binary.
# run_anchor NAME VENV "PACKAGES" [CAUSTIC_BINARY] [NAME.py options]: builds nothing;
# CAUSTIC_BINARY defaults to build/cli/caustic, the venv is BUILD/VENV, made on first use.
run_anchor() {
    local name="$1" venv_name="$2" packages="$3"
    shift 3
    # The report names the command as it was typed.
    local command
    command="$(printf '%q ' "$0" "$@")"
    export COMPARE_COMMAND="${command% }"
    local repo caustic build_dir
    repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
    caustic="$repo/build/cli/caustic"
    if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
        caustic="$1"
        shift
    fi
    if [ ! -x "$caustic" ]; then
        echo "$name: no caustic binary at $caustic (build it first, or pass its path)" >&2
        exit 2
    fi
    build_dir="$(cd "$(dirname "$caustic")/.." && pwd)"
    source "$repo/scripts/python-venv.sh"
    # shellcheck disable=SC2086 # the package list is split into words on purpose
    ensure_venv "$build_dir/$venv_name" $packages
    exec "$build_dir/$venv_name/bin/python" "$repo/bench/$name.py" --caustic "$caustic" "$@"
}
