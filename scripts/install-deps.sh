#!/usr/bin/env bash
# Installs the Debian 12 packages Caustic needs to build, test and benchmark.
# Idempotent: packages already present are skipped by apt. Runs as root (CI, a container build) or
# through sudo.
# usage: install-deps.sh [--build-only|--image-build]
#   --build-only   only what building the `caustic` binary needs: no tests, benchmarks, browser,
#                  sanitizers, containers or PostgreSQL server
#   --image-build  as --build-only, but OpenImageIO comes from docker/oiio-from-wheel.sh (what it
#                  needs to fetch and use it instead of Debian's; docker/Dockerfile's builder stage)
set -euo pipefail

build_only=false image_build=false
case "${1:-}" in
    "") ;;
    --build-only) build_only=true ;;
    --image-build) build_only=true image_build=true ;;
    *) echo "usage: $0 [--build-only|--image-build]" >&2; exit 2 ;;
esac

packages=(
    # Toolchain
    build-essential cmake ninja-build pkg-config
    # Command lines (caustic, the benchmarks)
    libcli11-dev
    # Renderer
    libglm-dev nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev
    libembree-dev libdraco-dev libzip-dev libzstd-dev libmeshoptimizer-dev
    # Render service (libssl-dev: SHA-256 asset ids and TLS; libspdlog-dev: the access log and
    # messages; libpqxx-dev: PostgreSQL's C++ client, for the scale-out store)
    libcpp-httplib-dev libsqlite3-dev libssl-dev libspdlog-dev libpqxx-dev
)
if $image_build; then
    # OpenImageIO's headers use Imath and fmt; its release is fetched over HTTPS with Python.
    packages+=(libimath-dev libfmt-dev zlib1g-dev python3 ca-certificates)
else
    packages+=(libopenimageio-dev)
fi
if ! $build_only; then
    packages+=(
        git openimageio-tools
        # The PostgreSQL server for the tests' throwaway clusters (tests/support/postgres.sh), and
        # libfaketime for workers whose clocks are off (tests/server/test_scale_out_clocks_and_cuts.py),
        # strace for the order of a job's syncs and commit (tests/server/test_power_loss.py)
        postgresql faketime strace
        # Tests and benchmarks (python3-venv: bench/mitsuba_compare.sh pip-installs Mitsuba 3 into a
        # venv; wrk and curl: bench/status_latency.sh; openssl: the TLS tests' certificates; curl
        # and jq: the README's HTTP example, which tests/docs/quickstart_test.py runs)
        libgtest-dev libgmock-dev libbenchmark-dev libnanoflann-dev python3 python3-venv wrk curl
        jq openssl
        # Browser tests of the web page (tests/web/run.sh: playwright-core from npm drives Chromium)
        chromium nodejs npm
        # Sanitizers and fuzzing (cmake/sanitize.cmake): GCC's ASan and UBSan come with
        # build-essential; the fuzz targets need clang with libFuzzer, LLVM's OpenMP, and
        # llvm-symbolizer for the stacks
        clang libclang-rt-14-dev libomp-14-dev llvm
        # The container tests (tests/containers/, ../shared/containers.md): podman with runc, its
        # compose, DNS between a compose project's containers, and debootstrap for the base image
        podman runc podman-compose debootstrap golang-github-containernetworking-plugin-dnsname
    )
fi

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
