#!/usr/bin/env bash
# Caustic against Mitsuba 3 at equal spp, or to equal error with --ladder
# (bench/mitsuba_compare.py; see bench/README.md).
# Usage: bench/mitsuba_compare.sh [CAUSTIC_BINARY] [mitsuba_compare.py options, e.g. --smoke]
# Builds nothing: CAUSTIC_BINARY defaults to build/cli/caustic. Python packages go to a venv in
# that binary's build dir (BUILD/bench-venv), created on first use.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/anchor.sh"
run_anchor mitsuba_compare bench-venv "mitsuba numpy" "$@"
