#!/usr/bin/env bash
# Caustic against Mitsuba 3 at equal spp (bench/mitsuba_compare.py; see bench/README.md).
# Usage: bench/mitsuba_compare.sh [CAUSTIC_BINARY] [mitsuba_compare.py options, e.g. --smoke]
# Builds nothing: CAUSTIC_BINARY defaults to build/cli/caustic. Python packages go to a venv in
# that binary's build dir (BUILD/bench-venv), created on first use.
set -euo pipefail

# The report names the command as it was typed.
MITSUBA_COMPARE_COMMAND="$(printf '%q ' "$0" "$@")"
export MITSUBA_COMPARE_COMMAND="${MITSUBA_COMPARE_COMMAND% }"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
caustic="$repo/build/cli/caustic"
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
    caustic="$1"
    shift
fi
if [ ! -x "$caustic" ]; then
    echo "mitsuba_compare: no caustic binary at $caustic (build it first, or pass its path)" >&2
    exit 2
fi
build_dir="$(cd "$(dirname "$caustic")/.." && pwd)"
venv="$build_dir/bench-venv"

source "$repo/scripts/python-venv.sh"
ensure_venv "$venv" mitsuba numpy

exec "$venv/bin/python" "$repo/bench/mitsuba_compare.py" --caustic "$caustic" "$@"
