#!/usr/bin/env bash
# Caustic against Mitsuba 3 on bench/cross/'s scenes (bench/mitsuba_crosscheck.py; see
# bench/README.md). Usage: bench/mitsuba_crosscheck.sh [CAUSTIC_BINARY] [options, e.g. --smoke]
# Builds nothing; Python packages go to a venv in that binary's build dir (BUILD/bench-venv).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/anchor.sh"
run_anchor mitsuba_crosscheck bench-venv "mitsuba numpy" "$@"
