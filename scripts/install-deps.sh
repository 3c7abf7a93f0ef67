#!/usr/bin/env bash
# Installs the Debian 12 packages Caustic needs to build, test and benchmark.
# Idempotent: packages already present are skipped by apt. Runs as root (CI) or through sudo.
set -euo pipefail

packages=(
    # Toolchain
    build-essential cmake ninja-build pkg-config git
    # Command lines (caustic, the benchmarks)
    libcli11-dev
    # Renderer
    libglm-dev nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev libopenimageio-dev
    openimageio-tools libembree-dev
    # Render service (libssl-dev: SHA-256 asset ids; libspdlog-dev: the access log and messages)
    libcpp-httplib-dev libsqlite3-dev libssl-dev libspdlog-dev
    # The scale-out store: libpqxx (PostgreSQL's C++ client); the server itself for the tests'
    # throwaway clusters (tests/support/postgres.sh)
    libpqxx-dev postgresql
    # Tests and benchmarks (python3-venv: bench/mitsuba_compare.sh pip-installs Mitsuba 3 into a venv;
    # wrk and curl: bench/status_latency.sh)
    libgtest-dev libgmock-dev libbenchmark-dev libnanoflann-dev python3 python3-venv wrk curl
    # Browser tests of the web page (tests/web/run.sh: playwright-core from npm drives Chromium)
    chromium nodejs npm
    # Sanitizers and fuzzing (cmake/sanitize.cmake): GCC's ASan and UBSan come with build-essential;
    # the fuzz targets need clang with libFuzzer, LLVM's OpenMP, and llvm-symbolizer for the stacks
    clang libclang-rt-14-dev libomp-14-dev llvm
)

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi

missing=()
for p in "${packages[@]}"; do
    # A Node.js from NodeSource bundles npm and conflicts with Debian's npm package.
    if [ "$p" = npm ] && command -v npm >/dev/null; then continue; fi
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "caustic: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    "${sudo_cmd[@]}" apt-get update -qq
    "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
