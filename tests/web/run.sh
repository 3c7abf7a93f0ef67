#!/usr/bin/env bash
# Browser tests of the web page (tests/web/web.test.mjs), of the rules against other web sites
# (tests/web/safety.test.mjs) and of the Workers panel (tests/web/workers.test.mjs), one file after
# the other: starts the real `caustic serve` on 127.0.0.1 (a free port, a temporary data folder,
# small limits), runs the tests in Debian's Chromium, headless, through playwright-core, and stops
# the server. The Workers panel is tested again on a scale-out when PostgreSQL's server is installed
# and the binary has the PostgreSQL store: a throwaway cluster (tests/support/postgres.sh), `caustic
# serve --store ... --workers 0` and one `caustic worker`. Bounded in time.
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
pg=""      # the PostgreSQL cluster's folder, under /tmp (its user must get through the parents)
pids=()    # every process started here, stopped in reverse order
stop_process() {
    local pid=$1
    if kill -0 "$pid" 2>/dev/null; then
        kill "$pid" 2>/dev/null || true
        for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
        wait "$pid" 2>/dev/null || true
    fi
}
stop_all() {
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do stop_process "${pids[i]}"; done
    pids=()
    [ -z "$pg" ] || bash "$repo/tests/support/postgres.sh" stop "$pg" || true
}
trap 'stop_all; rm -rf "$work"' EXIT

# Waits until line pattern $2 appears in file $1 (written by process $3); prints the match.
wait_for_line() {
    local match=""
    for _ in $(seq 300); do
        match="$(grep -o "$2" "$1" 2>/dev/null | head -1 || true)"
        [ -n "$match" ] && break
        kill -0 "$3" 2>/dev/null || break
        sleep 0.1
    done
    echo "$match"
}

# Starts `caustic serve` with data in folder $1 and more options; sets server_url (not run in a
# subshell, so that pids keeps the process).
max_spp=4096
start_server() {
    local data=$1
    shift
    "$caustic" serve --host 127.0.0.1 --port 0 --data "$data" --web "$repo/web" \
        --scenes "$repo/scenes" --threads 2 --max-spp "$max_spp" --max-resolution 512 \
        --max-pixels 262144 --max-photons 1000000 --max-time-limit 120 --max-queued 20 "$@" \
        >"$data.out" 2>"$data.log" &
    pids+=($!)
    server_url="$(wait_for_line "$data.out" 'http://127\.0\.0\.1:[0-9]*/' $!)"
    if [ -z "$server_url" ]; then
        echo "web tests: caustic serve did not start:" >&2
        cat "$data.log" >&2
        return 1
    fi
    echo "web tests: caustic serve at $server_url"
}

# Small limits keep every job cheap; the tests read --max-spp back from CAUSTIC_WEB_MAX_SPP.
start_server "$work/data" --workers 1 || exit 1
url=$server_url

status=0
export CAUSTIC_WEB_URL="$url" CAUSTIC_WEB_NODE_MODULES="$modules/node_modules" CHROMIUM="$chromium" \
    CAUSTIC_WEB_SCREENSHOTS="$build_dir/web-screenshots" CAUSTIC_WEB_MAX_SPP="$max_spp"
# One file after the other: they share the server and its one worker.
timeout -k 10 600 node --test --test-reporter=spec "$repo/tests/web/web.test.mjs" || status=$?
timeout -k 10 180 node --test --test-reporter=spec "$repo/tests/web/safety.test.mjs" || status=$?
CAUSTIC_WEB_STORE=sqlite timeout -k 10 120 node --test --test-reporter=spec \
    "$repo/tests/web/workers.test.mjs" || status=$?
if [ "$status" -ne 0 ]; then
    echo "web tests: failed ($status); the server's log:" >&2
    tail -n 40 "$work/data.log" >&2
fi

# The Workers panel on a scale-out.
if [ ! -x "${CAUSTIC_PG_BIN:-/usr/lib/postgresql/15/bin}/initdb" ]; then
    echo "web tests: no PostgreSQL server installed: the scale-out page test is skipped"
elif ! "$caustic" worker --help >/dev/null 2>&1; then
    echo "web tests: this binary has no caustic worker: the scale-out page test is skipped"
else
    pg="$(mktemp -d /tmp/caustic-web-pg.XXXXXX)"
    store="$(bash "$repo/tests/support/postgres.sh" start "$pg" --watch $$ | tail -1)"
    start_server "$work/pgdata" --store "$store" --workers 0 || exit 1
    "$caustic" worker --store "$store" --workers 1 --threads 2 >"$work/worker.out" \
        2>"$work/worker.log" &
    pids+=($!)
    [ -n "$(wait_for_line "$work/worker.out" 'caustic: worker rendering' $!)" ] ||
        { echo "web tests: caustic worker did not start:" >&2; cat "$work/worker.log" >&2; exit 1; }
    CAUSTIC_WEB_URL="$server_url" CAUSTIC_WEB_STORE=postgresql timeout -k 10 240 node --test \
        --test-reporter=spec "$repo/tests/web/workers.test.mjs" || {
        status=$?
        echo "web tests: the scale-out page test failed; the API's and the worker's logs:" >&2
        tail -n 20 "$work/pgdata.log" "$work/worker.log" >&2
    }
fi
exit "$status"
