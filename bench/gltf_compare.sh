#!/usr/bin/env bash
# glTF files exported by Blender, rendered by Caustic and by Cycles from the same file: channel
# means and a side-by-side picture (bench/gltf_compare.py; see bench/README.md).
# Usage: bench/gltf_compare.sh [CAUSTIC_BINARY] [gltf_compare.py options]
# Builds nothing. bpy==5.0.1 and numpy go to BUILD/cycles-venv (about 400 MB), made on first use.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/anchor.sh"
run_anchor gltf_compare cycles-venv "bpy==5.0.1 numpy" "$@"
