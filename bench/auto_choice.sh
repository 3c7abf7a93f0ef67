#!/usr/bin/env bash
# What auto chooses per scene and its time to a target against every configuration
# (bench/auto_choice.py; see bench/README.md).
# Usage: bench/auto_choice.sh [CAUSTIC_BINARY] [auto_choice.py options, e.g. --smoke]
# Builds nothing: CAUSTIC_BINARY defaults to build/cli/caustic. Python packages go to a venv in
# that binary's build dir (BUILD/bench-venv), created on first use.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/anchor.sh"
run_anchor auto_choice bench-venv "mitsuba numpy" "$@"
