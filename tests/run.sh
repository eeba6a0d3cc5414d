#!/usr/bin/env bash
# Runs every test program given on the command line from the repository root,
# TEST_JOBS at a time (default: the number of CPUs), adds up their
# "N passed, N failed" lines, and ends with the total line. Programs whose
# source (tests/NAME.c) holds the line "/* slow test */" start first, so
# that the longest ones do not start last. A test asserts nothing about
# time (timings belong to benchmarks). A program's result line (and,
# when it failed, its failures) is printed as it ends.
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
jobs=${TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
# OpenMP's idle threads sleep instead of spinning, as in `wiresketch`
# (base/runtime.h): spinning ones take the cores that the programs running
# beside them need.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
results=$(mktemp -d /tmp/ws_test_run_XXXXXX)
trap 'rm -rf "$results"' EXIT

slow=()
rest=()
for t in "$@"; do
    src="tests/$(basename "$t").c"
    if grep -qxF '/* slow test */' "$src" 2>/dev/null; then
        slow+=("$t")
    else
        rest+=("$t")
    fi
done

# Runs test $1 and writes its report and its counts ("PASS FAIL") to
# $results/NAME.report and $results/NAME.counts.
run_one() {
    local t=$1 name out rc secs summary p f start=$EPOCHREALTIME
    name=$(basename "$t")
    out=$("$t" "${args[@]}" 2>&1)
    rc=$?
    secs=$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')
    summary=$(printf '%s\n' "$out" | grep -E '^[0-9]+ passed, [0-9]+ failed$' | tail -n 1)
    {
        if [ -z "$summary" ]; then
            printf '%s\n' "$out" | tail -n 20
            echo "$name: no summary line (exit $rc): counted as 1 failure"
            p=0 f=1
        else
            p=${summary%% passed*}
            f=${summary#*, }; f=${f%% failed*}
            if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1; fi
            if [ "$f" -ne 0 ]; then printf '%s\n' "$out" | grep -v -E '^[0-9]+ passed' | tail -n 40; fi
            printf '%-28s %4d passed %4d failed  %6ss\n' "$name" "$p" "$f" "$secs"
        fi
    } >"$results/$name.report"
    echo "$p $f" >"$results/$name.counts"
}

running=0
for t in "${slow[@]}" "${rest[@]}"; do
    if [ "$running" -ge "$jobs" ]; then
        wait -n
        running=$((running - 1))
    fi
    (run_one "$t"; cat "$results/$(basename "$t").report") &
    running=$((running + 1))
done
wait

total_pass=0
total_fail=0
for t in "$@"; do
    p=0 f=1 # a program whose runner died counts as one failure
    [ -f "$results/$(basename "$t").counts" ] && read -r p f <"$results/$(basename "$t").counts"
    total_pass=$((total_pass + p))
    total_fail=$((total_fail + f))
done
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
