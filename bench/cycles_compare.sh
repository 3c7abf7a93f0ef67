#!/usr/bin/env bash
# Caustic against Blender Cycles, time to equal error (bench/cycles_compare.py; see
# bench/README.md). Not in CI: PyPI's bpy is about 400 MB.
# Usage: bench/cycles_compare.sh [CAUSTIC_BINARY] [cycles_compare.py options, e.g. --smoke]
# Builds nothing: CAUSTIC_BINARY defaults to build/cli/caustic. bpy 5.0.1 (it needs Python 3.11,
# Debian 12's) and numpy go to a venv in that binary's build dir (BUILD/cycles-venv).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/anchor.sh"
run_anchor cycles_compare cycles-venv "bpy==5.0.1 numpy" "$@"
