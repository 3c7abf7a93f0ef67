#!/usr/bin/env bash
# metallic_roughness against Mitsuba 3's principled and Cycles' Principled BSDF: channel means and
# side-by-side pictures (bench/principled_compare.py; see bench/README.md).
# Usage: bench/principled_compare.sh [CAUSTIC_BINARY] [principled_compare.py options]
# Builds nothing. Mitsuba and numpy go to BUILD/bench-venv, bpy==5.0.1 and numpy to
# BUILD/cycles-venv (about 400 MB), each made on first use.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/anchor.sh"
run_anchor principled_compare bench-venv "mitsuba numpy" "$@"
