#!/usr/bin/env bash
# Installs what is needed, builds, and starts the render service with its embedded defaults
# (127.0.0.1:8080, data in ./data); it prints the URL to open. Ctrl-C stops it. Extra arguments go
# to `caustic serve` (see `build/cli/caustic serve --help`); the build goes to
# ${CAUSTIC_BUILD_DIR:-build}.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
exec "${CAUSTIC_BUILD_DIR:-build}/cli/caustic" serve "$@"
