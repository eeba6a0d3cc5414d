#!/usr/bin/env bash
# Runs every test program given on the command line from the repository root,
# adds up their "N passed, N failed" lines, and ends with the total line.
# A program that crashes or prints no summary counts as one failure.
# `--args ARG` first passes ARG to every program (make test-scenes: the
# scenes folder).
set -u
cd "$(dirname "$0")/.."
args=()
if [ "${1:-}" = --args ]; then
    args=("$2")
    shift 2
fi
total_pass=0
total_fail=0
for t in "$@"; do
    name=$(basename "$t")
    start=$EPOCHREALTIME
    out=$("$t" "${args[@]}" 2>&1)
    rc=$?
    secs=$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')
    summary=$(printf '%s\n' "$out" | grep -E '^[0-9]+ passed, [0-9]+ failed$' | tail -n 1)
    if [ -z "$summary" ]; then
        printf '%s\n' "$out" | tail -n 20
        echo "$name: no summary line (exit $rc): counted as 1 failure"
        total_fail=$((total_fail + 1))
        continue
    fi
    p=${summary%% passed*}
    f=${summary#*, }; f=${f%% failed*}
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
    if [ "$f" -ne 0 ]; then printf '%s\n' "$out" | grep -v -E '^[0-9]+ passed' | tail -n 40; fi
    printf '%-28s %4d passed %4d failed  %6ss\n' "$name" "$p" "$f" "$secs"
    total_pass=$((total_pass + p))
    total_fail=$((total_fail + f))
done
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
