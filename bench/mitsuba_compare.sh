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

# Debian ships venv (with ensurepip) apart from python3: install it when a venv cannot be made.
if [ ! -x "$venv/bin/python" ] && ! python3 -m venv "$venv" 2>/dev/null; then
    rm -rf "$venv"
    sudo_cmd=()
    if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
    echo "mitsuba_compare: installing python3-venv" >&2
    export DEBIAN_FRONTEND=noninteractive
    "${sudo_cmd[@]}" apt-get update -qq
    "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
    python3 -m venv "$venv"
fi
# pip only reaches the network when a package is missing.
if ! "$venv/bin/python" -c "import mitsuba, numpy" 2>/dev/null; then
    "$venv/bin/python" -m pip install --quiet mitsuba numpy >&2
fi

exec "$venv/bin/python" "$repo/bench/mitsuba_compare.py" --caustic "$caustic" "$@"
