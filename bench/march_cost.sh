#!/usr/bin/env bash
# What a portable instruction set costs: the same renders by two `caustic` binaries built from the
# same sources with different -march (the image's x86-64 baseline against this machine's native),
# interleaved so that a slow spell of the machine hits both. Prints a Markdown table of the render
# phase's median seconds (the renders' own stats) and the ratio, and whether the images are equal.
# usage: bench/march_cost.sh BASELINE_BINARY NATIVE_BINARY [REPEATS]
# The image's binary: podman create --name c caustic && podman cp c:/usr/local/bin/caustic /tmp/
set -euo pipefail
baseline=$1 native=$2 repeats=${3:-5}
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# scene | settings: path tracing through a mesh (kd-tree or Embree, triangle tests, BSDFs), and
# photon mapping (photon tracing, the photon kd-tree's k-nearest look-ups).
cases=(
    "bunny|--integrator path --spp 16 --accelerator kdtree"
    "bunny|--integrator path --spp 16 --accelerator embree"
    "cornell-spheres|--integrator photon --photons 400000 --spp 4"
)

echo "Machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -n 1)"
echo "Command: bench/march_cost.sh $* ($repeats repeats)"
echo
echo "| scene | settings | baseline s (median) | native s (median) | baseline / native | same image |"
echo "|---|---|---|---|---|---|"
for c in "${cases[@]}"; do
    scene=${c%%|*} settings=${c#*|}
    for i in $(seq "$repeats"); do
        for which in baseline native; do
            bin=$baseline
            [ "$which" = native ] && bin=$native
            # shellcheck disable=SC2086
            CAUSTIC_ASSETS="$repo/assets/meshes" "$bin" render "$repo/scenes/$scene.json" \
                $settings --seed 1 -q -o "$tmp/$which.exr" --stats "$tmp/$which.json"
            python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['stats']['render_seconds'])" \
                "$tmp/$which.json" >>"$tmp/$which.times"
        done
    done
    same=$(cmp -s "$tmp/baseline.exr" "$tmp/native.exr" && echo yes || echo no)
    python3 - "$scene" "$settings" "$tmp/baseline.times" "$tmp/native.times" "$same" <<'PY'
import statistics, sys
scene, settings, b, n, same = sys.argv[1:]
mb = statistics.median(float(x) for x in open(b))
mn = statistics.median(float(x) for x in open(n))
print(f"| {scene} | `{settings}` | {mb:.3f} | {mn:.3f} | {mb / mn:.2f} | {same} |")
PY
    rm -f "$tmp"/*.times
done
