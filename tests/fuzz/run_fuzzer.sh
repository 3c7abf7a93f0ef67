#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time on a copy of its seed corpus, so that what it
# learns stays in the build folder. Fails on any finding: a crash or sanitizer report, an input
# that takes over -timeout seconds (a hang), or one that takes over -rss_limit_mb (a blow-up).
# usage: run_fuzzer.sh FUZZER SEEDS DICT WORK_DIR SECONDS
set -euo pipefail
fuzzer=$1 seeds=$2 dict=$3 work=$4 seconds=$5

rm -rf "$work"
mkdir -p "$work/corpus" "$work/findings"
cp "$seeds"/* "$work/corpus/"
# One thread per target (see fuzz_support.h); findings are written to $work/findings/, each report
# with its stack. Leaks inside libraries we do not build are suppressed as in the sanitizer build
# (tests/sanitize/lsan.supp, each with its reason).
export OMP_NUM_THREADS=1 UBSAN_OPTIONS=print_stacktrace=1
export LSAN_OPTIONS="suppressions=$(cd "$(dirname "$0")/../sanitize" && pwd)/lsan.supp"
"$fuzzer" "$work/corpus" -dict="$dict" -max_total_time="$seconds" -timeout=5 \
    -rss_limit_mb=2048 -max_len=8192 -artifact_prefix="$work/findings/" -print_final_stats=1
