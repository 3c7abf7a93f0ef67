#!/usr/bin/env bash
# The HTTP API tests of `caustic serve` (tests/server/test_*.py): integration, hostile input, and
# schemathesis against the OpenAPI document. Each test starts the real server on 127.0.0.1.
# Usage: tests/server/run_pytest.sh [CAUSTIC_BINARY] [pytest options, e.g. -k idempotency -v]
# Builds nothing: CAUSTIC_BINARY defaults to build/cli/caustic. Python packages go to a venv in
# that binary's build dir (BUILD/test-venv), created on first use.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
caustic="$repo/build/cli/caustic"
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
    caustic="$1"
    shift
fi
if [ ! -x "$caustic" ]; then
    echo "run_pytest: no caustic binary at $caustic (build it first, or pass its path)" >&2
    exit 2
fi
caustic="$(cd "$(dirname "$caustic")" && pwd)/$(basename "$caustic")"
build_dir="$(cd "$(dirname "$caustic")/.." && pwd)"
venv="$build_dir/test-venv"

# Versions that work together on Python 3.11 (schemathesis 3.39 reaches into hypothesis, whose
# newest releases break it: hypothesis is pinned too).
requirements=(pytest==8.3.5 pytest-timeout==2.3.1 requests==2.32.3 schemathesis==3.39.16
              hypothesis==6.127.9 openapi-spec-validator==0.7.1)

source "$repo/scripts/python-venv.sh"
ensure_venv "$venv" "${requirements[@]}"

export PYTHONDONTWRITEBYTECODE=1 CAUSTIC_CLI="$caustic"
cd "$repo/tests/server"
exec "$venv/bin/python" -m pytest -c "$repo/tests/server/pytest.ini" \
    --rootdir "$repo/tests/server" "$@" "$repo/tests/server"
