#!/usr/bin/env bash
# Regenerates the example scenes' textures in assets/meshes (scripts/make_textures.py) as PNG
# through OpenImageIO's oiiotool (scripts/install-deps.sh installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 scripts/make_textures.py "$tmp"
for name in tiles tiles-mr tiles-normal spot-pattern; do
    oiiotool "$tmp/$name.ppm" -o "assets/meshes/$name.png"
done
ls -l assets/meshes/*.png
