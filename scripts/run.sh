#!/usr/bin/env bash
# Installs what is needed, builds, and renders the default scene. (Once the render service exists,
# this starts it instead and prints its URL.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
./build/cli/caustic render scenes/cornell-spheres.json -o out/cornell-spheres.png -o out/cornell-spheres.exr
echo "caustic: open $(pwd)/out/cornell-spheres.png (linear HDR: out/cornell-spheres.exr)"
