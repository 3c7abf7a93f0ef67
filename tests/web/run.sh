#!/usr/bin/env bash
# Browser tests of the web page (tests/web/web.test.mjs) and of the rules against other web sites
# (tests/web/safety.test.mjs, one file after the other): starts the real `caustic serve` on
# 127.0.0.1 (a free port, a temporary data folder, small limits), runs the tests in Debian's
# Chromium, headless, through playwright-core, and stops the server. Bounded in time.
# Usage: tests/web/run.sh [CAUSTIC_BINARY]   (default build/cli/caustic)
# Needs node, npm and chromium (scripts/install-deps.sh). playwright-core is installed once, with
# `npm ci` from tests/web/package-lock.json, into BUILD/web-tests; screenshots go to
# BUILD/web-screenshots.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
caustic="${1:-$repo/build/cli/caustic}"
if [ ! -x "$caustic" ]; then
    echo "web tests: no caustic binary at $caustic (build it first, or pass its path)" >&2
    exit 2
fi
caustic="$(cd "$(dirname "$caustic")" && pwd)/$(basename "$caustic")"
build_dir="$(cd "$(dirname "$caustic")/.." && pwd)"
chromium="${CHROMIUM:-/usr/bin/chromium}"
for tool in node npm "$chromium"; do
    command -v "$tool" >/dev/null || { echo "web tests: $tool not found (scripts/install-deps.sh)" >&2; exit 2; }
done

# playwright-core, once per lock file.
modules="$build_dir/web-tests"
if [ ! -f "$modules/node_modules/playwright-core/package.json" ] ||
    ! cmp -s "$repo/tests/web/package-lock.json" "$modules/package-lock.json"; then
    mkdir -p "$modules"
    cp "$repo/tests/web/package.json" "$repo/tests/web/package-lock.json" "$modules/"
    (cd "$modules" && timeout 300 npm ci --no-audit --no-fund --loglevel=error)
fi

work="$(mktemp -d "${TMPDIR:-/tmp}/caustic-web.XXXXXX")"
server_pid=""
stop_server() {
    if [ -n "$server_pid" ] && kill -0 "$server_pid" 2>/dev/null; then
        kill "$server_pid" 2>/dev/null || true
        for _ in $(seq 100); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$server_pid" 2>/dev/null || true
        wait "$server_pid" 2>/dev/null || true
    fi
    server_pid=""
}
trap 'stop_server; rm -rf "$work"' EXIT

# Small limits keep every job cheap; the tests read --max-spp back from CAUSTIC_WEB_MAX_SPP.
max_spp=4096
"$caustic" serve --host 127.0.0.1 --port 0 --data "$work/data" --web "$repo/web" \
    --scenes "$repo/scenes" --workers 1 --threads 2 --max-spp "$max_spp" --max-resolution 512 \
    --max-pixels 262144 --max-photons 1000000 --max-time-limit 120 --max-queued 20 \
    >"$work/server.out" 2>"$work/server.log" &
server_pid=$!
url=""
for _ in $(seq 300); do
    url="$(grep -o 'http://127\.0\.0\.1:[0-9]*/' "$work/server.out" 2>/dev/null | head -1 || true)"
    [ -n "$url" ] && break
    kill -0 "$server_pid" 2>/dev/null || break
    sleep 0.1
done
if [ -z "$url" ]; then
    echo "web tests: caustic serve did not start:" >&2
    cat "$work/server.log" >&2
    exit 1
fi
echo "web tests: caustic serve at $url"

status=0
export CAUSTIC_WEB_URL="$url" CAUSTIC_WEB_NODE_MODULES="$modules/node_modules" CHROMIUM="$chromium" \
    CAUSTIC_WEB_SCREENSHOTS="$build_dir/web-screenshots" CAUSTIC_WEB_MAX_SPP="$max_spp"
# One file after the other: they share the server and its one worker.
timeout -k 10 600 node --test --test-reporter=spec "$repo/tests/web/web.test.mjs" || status=$?
timeout -k 10 180 node --test --test-reporter=spec "$repo/tests/web/safety.test.mjs" || status=$?
if [ "$status" -ne 0 ]; then
    echo "web tests: failed ($status); the server's log:" >&2
    tail -n 40 "$work/server.log" >&2
fi
exit "$status"
