#!/usr/bin/env bash
# tests/mpi/run.sh [WISESKETCH]: the MPI data-parallel fit (`make test-mpi`).
# On a small scene the program makes, with the tiny CLIP fixture
# (tests/fixtures/clip_tiny, converted here) and the edge loss:
# 1. fits on 1, 2 and 3 ranks (--oversubscribe) for each CLIP pass size
#    (--clip-batch 1, 2 and 0 = a whole view), batches of 1 and 3 views, and
#    with the edge loss alone (a view is the unit of work): curves.json,
#    log.csv's losses and the test loss must be the same bytes for every
#    rank count;
# 2. one process of the same build and of the build without MPI give them too;
# 3. a fit on 2 ranks whose rank 1 is killed (SIGKILL) must end at once with
#    a non-zero exit and its line, leave a checkpoint that resumes on 3
#    ranks, and end with the curves of the uninterrupted fit;
# 4. rank 0's write errors (its --out, its checkpoint, the file size limit)
#    are the line printed, on a job of 2 ranks.
# Prints one PASS or FAIL line last; exits non-zero on a mismatch.
set -uo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-build/mpi/wiresketch}
plain=build/wiresketch
mpirun=(mpirun -q --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpirun+=(--allow-run-as-root)
work=$(mktemp -d /tmp/ws_test_mpi_XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "  FAIL: $*"; failures=$((failures + 1)); }

python3 tools/convert_weights.py tests/fixtures/clip_tiny/clip_tiny_state_dict.pt "$work/tiny.bin" --heads 4 \
    >/dev/null || { echo "test-mpi: FAIL (could not convert the CLIP fixture)"; exit 1; }
"$bin" scene cube --out "$work/scene" --size 64 --views-train 6 --views-val 2 --views-test 2 >/dev/null ||
    { echo "test-mpi: FAIL (could not make the scene)"; exit 1; }
common=(--weights "$work/tiny.bin" --size 64 --clip-conv-layer-weights 0 1 --n-curves 6
        --eval-every 1 --threads 1 --quiet --snapshot-every 0)

# What must not depend on the rank count: the curves, the losses, the test loss.
fingerprint() {
    { cat "$1/curves.json"; cut -d, -f1,2,4,5 "$1/log.csv"; grep -o '"test_loss": [^,]*' "$1/metrics.json"; } |
        md5sum | cut -c1-12
}

# "CLIP pass size, views per batch, loss": without CLIP a view is the unit.
for config in "1 1 clip+edges" "1 3 clip+edges" "2 1 clip+edges" "2 3 clip+edges" "0 1 clip+edges" \
              "0 3 clip+edges" "0 3 edges"; do
    read -r g bs loss <<<"$config"
    args=(fit "$work/scene" "${common[@]}" --loss $loss --epochs 1 --inner-steps 2 --batch-size $bs --clip-batch $g)
    what="--loss $loss --clip-batch $g --batch-size $bs"
    line="  $what:"
    ref=""
    for n in 1 2 3; do
        out="$work/g${g}b${bs}$loss$n"
        if ! "${mpirun[@]}" -np $n "$bin" "${args[@]}" --out "$out" >"$out.log" 2>&1; then
            fail "$n ranks, $what: exit $? ($(tail -n 1 "$out.log"))"
            continue
        fi
        f=$(fingerprint "$out")
        line="$line $n ranks $f"
        [ -z "$ref" ] && ref=$f
        [ "$f" = "$ref" ] || fail "$n ranks, $what: other curves or losses than 1 rank"
    done
    for b in "$bin" "$plain"; do
        out="$work/g${g}b${bs}${loss}single"
        rm -rf "$out"
        if "$b" "${args[@]}" --out "$out" >"$out.log" 2>&1; then
            [ "$(fingerprint "$out")" = "$ref" ] || fail "$b alone, $what: other curves than mpirun"
        else
            fail "$b alone, $what: exit $?"
        fi
    done
    echo "$line"
done

# A rank that dies: rank 1 of 2 is killed once checkpoints have been written.
args=(fit "$work/scene" "${common[@]}" --loss clip+edges --epochs 40 --inner-steps 5 --batch-size 2 --clip-batch 2
      --checkpoint-minutes 0.002)
"$plain" "${args[@]}" --out "$work/full" >/dev/null 2>&1 || fail "the uninterrupted fit failed"
"${mpirun[@]}" -np 2 "$bin" "${args[@]}" --out "$work/killed" >"$work/killed.log" 2>&1 &
job=$!
killed=""
for _ in $(seq 100); do
    sleep 0.1
    [ -f "$work/killed/checkpoint.bin" ] || continue
    for pid in $(pgrep -P $job); do
        if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=1; then
            sleep 0.5
            kill -KILL "$pid" && killed=$pid
        fi
    done
    [ -n "$killed" ] && break
done
wait $job
rc=$?
if [ -z "$killed" ]; then
    fail "rank 1 was not found to be killed"
else
    [ $rc -ne 0 ] || fail "the job whose rank 1 was killed exited 0"
    grep -q "the MPI job was ended (a rank died" "$work/killed.log" ||
        fail "no line says the job ended: $(cat "$work/killed.log")"
    [ -f "$work/killed/curves.json" ] && fail "the killed job finished anyway (kill it earlier)"
    if "${mpirun[@]}" -np 3 "$bin" fit --resume "$work/killed" >"$work/resume.log" 2>&1; then
        cmp -s "$work/killed/curves.json" "$work/full/curves.json" ||
            fail "the fit resumed on 3 ranks ends with other curves than the uninterrupted one"
    else
        fail "the checkpoint of the killed job does not resume on 3 ranks: $(tail -n 1 "$work/resume.log")"
    fi
    echo "  rank 1 killed (exit $rc), resumed on 3 ranks: $(grep -c . "$work/killed/log.csv") log rows"
fi

# Rank 0's own I/O error is the line printed, not a collective's mismatch on the others: an
# --out that cannot be made, a first checkpoint that cannot be written, and the file size
# limit (standing in for a full disk) while checkpointing, which stops the job like SIGINT.
# (--overwrite: a folder holding a checkpoint.bin, here a directory, is otherwise refused
# before any rank writes.)
small=(fit "$work/scene" --size 64 --loss edges --threads 1 --quiet --overwrite)
: >"$work/afile"
mkdir -p "$work/ckdir/checkpoint.bin"
for config in "afile/out|1|$work/afile/out: cannot create directory: Not a directory" \
              "ckdir|1|$work/ckdir/checkpoint.bin: is a directory"; do
    IFS='|' read -r dir want_rc want <<<"$config"
    "${mpirun[@]}" -np 2 "$bin" "${small[@]}" --max-steps 5 --out "$work/$dir" >"$work/io.log" 2>&1
    rc=$?
    [ $rc -eq "$want_rc" ] && [ "$(cat "$work/io.log")" = "wiresketch: $want" ] ||
        fail "rank 0 cannot write $dir: exit $rc, said: $(cat "$work/io.log")"
done
"${mpirun[@]}" -np 2 bash -c 'if [ "$OMPI_COMM_WORLD_RANK" = 0 ]; then ulimit -f 60; fi; exec "$@"' - \
    "$bin" "${small[@]}" --epochs 1000 --checkpoint-minutes 0.0001 --max-steps 100000 --out "$work/fsize" \
    >"$work/io.log" 2>&1
rc=$?
want="wiresketch: stopped by SIGXFSZ (the file size limit, ulimit -f); $work/fsize/checkpoint.bin: write failed: File too large; what could be written is in $work/fsize; continue with \`wiresketch fit --resume $work/fsize\`"
[ $rc -eq 153 ] && [ "$(cat "$work/io.log")" = "$want" ] && [ -f "$work/fsize/curves.json" ] ||
    fail "rank 0 past the file size limit: exit $rc, said: $(cat "$work/io.log")"
echo "  rank 0's write errors: their own line (exit 1, 1, 153)"

if [ $failures -eq 0 ]; then
    echo "test-mpi: PASS (curves, losses and test loss the same bytes on 1, 2 and 3 ranks; a killed rank's checkpoint resumes)"
else
    echo "test-mpi: FAIL ($failures mismatches)"
    exit 1
fi
