#!/usr/bin/env bash
# Where each preset stops and how true its reported error is there, per sampler
# (bench/preset_stops.py; see bench/README.md).
# Usage: bench/preset_stops.sh [CAUSTIC_BINARY] [preset_stops.py options, e.g. --smoke]
# Builds nothing: CAUSTIC_BINARY defaults to build/cli/caustic. Python packages go to a venv in
# that binary's build dir (BUILD/bench-venv), created on first use.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/anchor.sh"
run_anchor preset_stops bench-venv "mitsuba numpy" "$@"
