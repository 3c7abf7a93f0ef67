#!/usr/bin/env bash
# Status latency of `caustic serve` while a render uses every core (bench/README.md,
# "status_latency"). Starts the server on loopback (a temporary data folder, a free port), measures
# GET /healthz and GET /api/jobs/{id} with wrk while the server is idle and while a long render
# runs, prints p50/p90/p99/max latency and requests per second as a Markdown table, then cancels the
# render and stops the server. Stops by itself; changes nothing outside its temporary folder.
#
# usage: bench/status_latency.sh [options]
#   --binary LABEL=PATH  a caustic binary to measure, repeatable: each gets its own server and
#                        render, one after the other, in one table (default: build=build/cli/caustic)
#   --duration S         seconds per endpoint while rendering (default 20); idle: a quarter of it
#   --connections N      concurrent connections (default 4)
#   --size N             the render's width and height (default 256)
#   --smoke              2 s per measure and a 64² render: checks that it all runs (CTest)
# Needs wrk (Debian: wrk, in scripts/install-deps.sh) and python3. The target is p99 < 50 ms while
# rendering; this script reports, it does not judge.
set -euo pipefail

command_line="$(printf '%q ' "$0" "$@")"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
binaries=()
duration=20
connections=4
size=256
smoke=0
while [ $# -gt 0 ]; do
    case "$1" in
        --binary) binaries+=("$2"); shift 2 ;;
        --duration) duration="$2"; shift 2 ;;
        --connections) connections="$2"; shift 2 ;;
        --size) size="$2"; shift 2 ;;
        --smoke) smoke=1; shift ;;
        -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        *) echo "status_latency: unknown option $1 (--help lists them)" >&2; exit 2 ;;
    esac
done
if [ ${#binaries[@]} -eq 0 ]; then binaries=("build=$repo/build/cli/caustic"); fi
if [ "$smoke" = 1 ]; then duration=2; size=64; fi
idle_duration=$(( duration >= 8 ? duration / 4 : 1 ))
if ! command -v wrk >/dev/null; then
    echo "status_latency: wrk is not installed (apt-get install wrk; scripts/install-deps.sh)" >&2
    exit 77
fi
for b in "${binaries[@]}"; do
    if [ ! -x "${b#*=}" ]; then
        echo "status_latency: no caustic binary at ${b#*=} (build it, or give --binary LABEL=PATH)" >&2
        exit 2
    fi
done

tmp="$(mktemp -d "${TMPDIR:-/tmp}/caustic-latency.XXXXXX")"
server_pid=""
base=""
job=""
stop_server() {
    if [ -n "$job" ] && [ -n "$base" ]; then
        curl -s -m 5 -o /dev/null -X POST "$base/api/jobs/$job/cancel" || true
    fi
    job=""
    if [ -n "$server_pid" ]; then
        kill -TERM "$server_pid" 2>/dev/null || true
        for _ in $(seq 50); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
        kill -KILL "$server_pid" 2>/dev/null || true
        wait "$server_pid" 2>/dev/null || true
    fi
    server_pid=""
}
trap 'stop_server; rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

cat > "$tmp/report.lua" <<'EOF'
done = function(summary, latency, requests)
    local e = summary.errors
    io.write(string.format("RESULT %d %d %d %.3f %.3f %.3f %.3f\n", summary.requests,
        summary.duration, e.connect + e.read + e.write + e.status + e.timeout,
        latency:percentile(50) / 1000, latency:percentile(90) / 1000,
        latency:percentile(99) / 1000, latency.max / 1000))
end
EOF

# json FILE EXPR: a value from a JSON file (python3; no jq needed).
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print($2)" "$1"; }

start_server() {  # LABEL PATH
    "$2" serve --port 0 --data "$tmp/data-$1" >"$tmp/server-$1.log" 2>&1 &
    server_pid=$!
    for _ in $(seq 150); do
        base="$(sed -n 's|^caustic: serving on \(http://[^/]*\)/.*|\1|p' "$tmp/server-$1.log")"
        [ -n "$base" ] && return 0
        kill -0 "$server_pid" 2>/dev/null || break
        sleep 0.1
    done
    echo "status_latency: the server did not start:" >&2
    cat "$tmp/server-$1.log" >&2
    exit 1
}

submit() {  # BODY_FILE -> job id
    curl -sf -m 30 -X POST "$base/api/jobs" -H 'Content-Type: application/json' \
        --data-binary @"$1" -o "$tmp/submitted.json"
    json "$tmp/submitted.json" 'd["id"]'
}

wait_state() {  # ID STATE... : waits up to 120 s for one of the states (and, running, a pass)
    local id="$1" state
    shift
    for _ in $(seq 600); do
        curl -sf -m 5 "$base/api/jobs/$id" -o "$tmp/job.json" || true
        state="$(json "$tmp/job.json" 'd["state"] + ("+" if d["passes_done"] > 0 else "")' \
            2>/dev/null || true)"
        for s in "$@"; do [ "$state" = "$s" ] && return 0; done
        case "$state" in failed*|cancelled*) break ;; esac
        sleep 0.2
    done
    echo "status_latency: job $id did not reach $* (last: $state)" >&2
    exit 1
}

rows=()
measure() {  # LABEL CONDITION ENDPOINT SECONDS
    local out
    out="$(wrk -t 1 -c "$connections" -d "${4}s" --timeout 5s -s "$tmp/report.lua" "$base$3")"
    read -r _ requests micros errors p50 p90 p99 max <<<"$(grep '^RESULT' <<<"$out")"
    local rps
    rps="$(awk -v n="$requests" -v us="$micros" 'BEGIN { printf "%.0f", n / (us / 1e6) }')"
    rows+=("| $1 | $2 | \`GET $3\` | $rps | $p50 | $p90 | $p99 | $max | $errors |")
    echo "status_latency: $1, $2, $3: p99 $p99 ms, $rps requests/s" >&2
}

# The render: cornell-spheres at size², as many spp as allowed in 4-spp passes (a checkpoint and a
# store write about every second), with a time limit well past the measurements; cancelled after.
python3 - "$repo/scenes/cornell-spheres.json" "$size" "$((duration * 4 + 120))" >"$tmp/render.json" <<'EOF'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["camera"]["width"] = scene["camera"]["height"] = int(sys.argv[2])
print(json.dumps({"scene": scene, "settings": {"spp": 65536, "spp_per_pass": 4,
                                               "time_limit": int(sys.argv[3])}}))
EOF
echo '{"scene": "cornell-spheres", "settings": {"spp": 1}}' >"$tmp/small.json"

load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
for b in "${binaries[@]}"; do
    label="${b%%=*}"
    start_server "$label" "${b#*=}"
    # Idle: a finished job's status, and /healthz, with nothing rendering.
    done_job="$(submit "$tmp/small.json")"
    wait_state "$done_job" succeeded+
    measure "$label" idle /healthz "$idle_duration"
    measure "$label" idle "/api/jobs/$done_job" "$idle_duration"
    # Rendering on every core, from its first finished pass on.
    job="$(submit "$tmp/render.json")"
    wait_state "$job" running+
    measure "$label" rendering /healthz "$duration"
    measure "$label" rendering "/api/jobs/$job" "$duration"
    curl -sf -m 5 "$base/api/jobs/$job" -o "$tmp/job.json"
    state="$(json "$tmp/job.json" 'd["state"] + ", pass " + str(d["passes_done"])')"
    [ "${state%%,*}" = running ] || rows+=("| $label | (the render was $state by the end) |")
    stop_server
done
load_after="$(cut -d' ' -f1-3 /proc/loadavg)"

cpu="$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)"
echo "machine: nproc $(nproc), $cpu; load average $load_before before, $load_after after"
echo "command: $command_line"
echo "render: cornell-spheres ${size}x${size}, path, 4 spp per pass, every core; wrk: 1 thread," \
    "$connections connections, ${duration} s per endpoint while rendering, ${idle_duration} s idle"
echo
echo "| server | while | request | requests/s | p50 ms | p90 ms | p99 ms | max ms | errors |"
echo "|---|---|---|---:|---:|---:|---:|---:|---:|"
printf '%s\n' "${rows[@]}"
