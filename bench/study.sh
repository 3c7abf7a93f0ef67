#!/usr/bin/env bash
# The speed/accuracy study in one command: bench_study renders and measures (CSV), then
# bench/study_report.py draws the plots and writes the summary (docs/study/README.md).
# Usage: bench/study.sh [--out DIR] [bench_study options, e.g. --smoke or --seeds 2]
# Builds nothing: the binary is BUILD/bench/bench_study (BUILD: $CAUSTIC_BUILD_DIR, else build/).
# matplotlib comes from PyPI into a venv in the build dir (BUILD/study-venv), made on first use.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${CAUSTIC_BUILD_DIR:-$repo/build}"
case "$build" in /*) ;; *) build="$repo/$build" ;; esac
out="$repo/docs/study"
args=()
while [ $# -gt 0 ]; do
    case "$1" in
        --out) out="$2"; shift 2 ;;
        *) args+=("$1"); shift ;;
    esac
done
bench="$build/bench/bench_study"
if [ ! -x "$bench" ]; then
    echo "study: no $bench (build first: scripts/build.sh)" >&2
    exit 2
fi
mkdir -p "$out"
source "$repo/scripts/python-venv.sh"
ensure_venv "$build/study-venv" matplotlib
"$bench" "${args[@]}" --csv "$out/study.csv"
"$build/study-venv/bin/python" "$repo/bench/study_report.py" "$out/study.csv" --out "$out" \
    --command "bench/study.sh${args[*]:+ ${args[*]}}"
