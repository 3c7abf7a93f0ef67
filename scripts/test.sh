#!/usr/bin/env bash
# Installs what is needed, builds, and runs the whole test suite. This is the README's test command
# and what CI runs. Three build folders: the normal build and its tests; the C++ unit tests again,
# built by clang under AddressSanitizer and UndefinedBehaviorSanitizer; the fuzz targets, built by
# clang too, each run for a minute (cmake/sanitize.cmake, tests/fuzz/README.md). Every stage runs;
# any failure fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
build=${CAUSTIC_BUILD_DIR:-build}
status=0

bash scripts/build.sh -DCAUSTIC_WERROR=ON
# Tests render with every core themselves; run them one at a time.
(cd "$build" && ctest --output-on-failure --timeout 1200) || status=1

# Label "sanitize": renderer_tests (less its statistical trust suites, tests/CMakeLists.txt says
# why), server_tests and cli_tests (the CLI they run is instrumented too), about 17 minutes on 2
# cores after a 16-minute build. Built by clang: GCC takes 25 minutes to build the same
# instrumented code. Benchmarks are not built.
if CAUSTIC_BUILD_DIR=$build-sanitize bash scripts/build.sh -DCAUSTIC_WERROR=ON -DCAUSTIC_SANITIZE=ON \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCAUSTIC_BUILD_BENCH=OFF; then
    (cd "$build-sanitize" && ctest --output-on-failure -L sanitize) || status=1
else
    echo "caustic: the sanitizer build failed" >&2
    status=1
fi

# Label "fuzz": six targets of one thread each, two at a time, a minute each.
if CAUSTIC_BUILD_DIR=$build-fuzz bash scripts/build.sh -DCAUSTIC_WERROR=ON \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCAUSTIC_FUZZ=ON; then
    (cd "$build-fuzz" && ctest --output-on-failure -L fuzz -j 2) || status=1
else
    echo "caustic: the fuzz build failed" >&2
    status=1
fi
exit $status
