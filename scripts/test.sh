#!/usr/bin/env bash
# Installs what is needed, builds, and runs the whole test suite. This is the README's test command
# and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh -DCAUSTIC_WERROR=ON
cd "${CAUSTIC_BUILD_DIR:-build}"
# Tests render with every core themselves; run them one at a time.
ctest --output-on-failure --timeout 1200
