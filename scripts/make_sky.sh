#!/usr/bin/env bash
# Regenerates assets/meshes/sky.exr, the example scenes' environment (scripts/make_sky.py), as a
# half-float, zip-compressed EXR through OpenImageIO's oiiotool (scripts/install-deps.sh installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp --suffix=.hdr)
trap 'rm -f "$tmp"' EXIT
python3 scripts/make_sky.py "$tmp" "${1:-1024}"
oiiotool "$tmp" -d half --compression zip -o assets/meshes/sky.exr
ls -l assets/meshes/sky.exr
