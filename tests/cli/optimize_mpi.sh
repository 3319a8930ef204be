#!/bin/sh
# gaitlab optimize under mpirun on this machine (loopback), checked against the threaded run.
# Usage: optimize_mpi.sh CASE MPIEXEC GAITLAB SOURCE_DIR WORK_DIR
#   same   3 ranks (rank 0 hands out, 2 evaluate) give the evaluations and best of 2 threads
#   dies   rank 2 kills itself at its first evaluation: rank 1 does its evaluations, same result
#   all    every evaluating rank kills itself: the run ends, saying so
#   broken the spec does not load on rank 2: rank 0 says so, rank 1 evaluates, same result
#   sweep  gaitlab sweep on 3 ranks gives the threaded sweep's table (its --seed reaches the ranks)
#   badopt a bad --rank-timeout is refused before anything runs (no mpirun needed)
set -eu
export GAITLAB_TEST_DYING_RANK="" GAITLAB_TEST_BROKEN_RANK=""
case_=$1 mpiexec=$2 gaitlab=$3 src=$4 work=$5
rm -rf "$work"
mkdir -p "$work"
# OpenMPI refuses to run as root unless told (a container, a CI runner); as a user it needs nothing
if [ "$(id -u)" = 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
fail() {
    echo "FAIL: $*" >&2
    exit 1
}
# evaluations.jsonl without the fields that depend on who ran what, and when
timeless() {
    sed -E 's/,"seconds":[^,]*,"worker":[0-9]+(,"rank":[0-9]+)?//' "$1"
}
same_results() {
    timeless "$1/evaluations.jsonl" > "$work/a.jsonl"
    timeless "$2/evaluations.jsonl" > "$work/b.jsonl"
    [ -s "$work/a.jsonl" ] || fail "$1/evaluations.jsonl is empty"
    cmp -s "$work/a.jsonl" "$work/b.jsonl" || {
        diff "$work/a.jsonl" "$work/b.jsonl" >&2 || true
        fail "the evaluations of $1 and $2 differ"
    }
    grep -v '"command"' "$1/best.json" > "$work/a.json"
    grep -v '"command"' "$2/best.json" > "$work/b.json"
    cmp -s "$work/a.json" "$work/b.json" || {
        diff "$work/a.json" "$work/b.json" >&2 || true
        fail "best.json of $1 and $2 differ"
    }
}
# rank 0 says 2 ranks evaluate, and each did
both_ranks_evaluated() {
    grep -q "2 MPI ranks evaluating, 2 workers in all" "$work/mpi.out" ||
        fail "rank 0 does not report 2 evaluating ranks"
    grep -q '"rank":1' "$work/mpi/evaluations.jsonl" || fail "rank 1 evaluated nothing"
    grep -q '"rank":2' "$work/mpi/evaluations.jsonl" || fail "rank 2 evaluated nothing"
}
mpi() {
    # --enable-recovery: a rank that dies does not end the job (mpirun's default)
    "$mpiexec" --oversubscribe --enable-recovery -x GAITLAB_TEST_DYING_RANK -x GAITLAB_TEST_BROKEN_RANK \
        -n 3 "$gaitlab" "$@"
}

case "$case_" in
same)
    spec=$src/tests/cli/scripts/optimize_small.lua
    "$gaitlab" optimize "$spec" --workers 2 --seed 7 --out "$work/threads" > /dev/null
    GAITLAB_TEST_DYING_RANK="" mpi optimize "$spec" --seed 7 --out "$work/mpi" > "$work/mpi.out"
    cat "$work/mpi.out"
    both_ranks_evaluated
    same_results "$work/threads" "$work/mpi"
    ;;
dies)
    spec=$src/tests/cli/scripts/optimize_rank_dies.lua
    GAITLAB_TEST_DYING_RANK="" "$gaitlab" optimize "$spec" --seed 7 --out "$work/threads" > /dev/null
    GAITLAB_TEST_DYING_RANK=2 mpi optimize "$spec" --seed 7 --rank-timeout 2 --out "$work/mpi" \
        > "$work/mpi.out" 2> "$work/mpi.err" || true
    cat "$work/mpi.out" "$work/mpi.err"
    grep -q "gaitlab: MPI rank 2 is given up (no word for" "$work/mpi.err" ||
        fail "rank 0 does not say that rank 2 is given up"
    grep -q '"rank":2' "$work/mpi/evaluations.jsonl" && fail "rank 2 has results"
    same_results "$work/threads" "$work/mpi"
    ;;
all)
    spec=$src/tests/cli/scripts/optimize_rank_dies.lua
    GAITLAB_TEST_DYING_RANK=all mpi optimize "$spec" --seed 7 --rank-timeout 2 --out "$work/mpi" \
        > "$work/mpi.out" 2> "$work/mpi.err" || true
    cat "$work/mpi.out" "$work/mpi.err"
    grep -q "gaitlab: every evaluating MPI rank is lost (rank 1: no word for .* s; rank 2: no word for .* s): 5 evaluations of this generation cannot be made" "$work/mpi.err" ||
        fail "rank 0 does not say that the run cannot go on"
    [ ! -e "$work/mpi/best.json" ] || fail "a best.json was written"
    ;;
broken)
    spec=$src/tests/cli/scripts/optimize_rank_dies.lua
    "$gaitlab" optimize "$spec" --seed 7 --out "$work/threads" > /dev/null
    GAITLAB_TEST_BROKEN_RANK=2 mpi optimize "$spec" --seed 7 --out "$work/mpi" > "$work/mpi.out" \
        2> "$work/mpi.err" || true
    cat "$work/mpi.out" "$work/mpi.err"
    grep -q "gaitlab: rank 2 does not evaluate: .*optimize_rank_dies.lua:[0-9]*: this rank cannot load the spec" \
        "$work/mpi.err" || fail "rank 0 does not say why rank 2 does not evaluate"
    grep -q "1 MPI rank evaluating, 1 worker in all" "$work/mpi.out" ||
        fail "rank 0 does not report 1 evaluating rank"
    same_results "$work/threads" "$work/mpi"
    ;;
sweep)
    spec=$src/tests/cli/scripts/sweep_random.lua
    grid="amplitude=20:60:20 phase=60:180:60"
    "$gaitlab" sweep "$spec" --grid $grid --workers 2 --seed 7 --out "$work/threads" > /dev/null
    "$gaitlab" sweep "$spec" --grid $grid --workers 2 --seed 8 --out "$work/other" > /dev/null
    mpi sweep "$spec" --grid $grid --seed 7 --out "$work/mpi" > "$work/mpi.out"
    cat "$work/mpi.out"
    both_ranks_evaluated
    same_results "$work/threads" "$work/mpi"
    cmp -s "$work/threads/sweep.csv" "$work/mpi/sweep.csv" || fail "the sweep tables differ"
    # the seed matters to this spec: another seed, another table
    cmp -s "$work/threads/sweep.csv" "$work/other/sweep.csv" && fail "--seed 8 gives --seed 7's table"
    ;;
badopt)
    spec=$src/tests/cli/scripts/optimize_small.lua
    for bad in 0 -1 abc nan ""; do
        status=0
        "$gaitlab" optimize "$spec" --rank-timeout "$bad" --out "$work/bad" > "$work/bad.out" \
            2> "$work/bad.err" || status=$?
        [ "$status" = 2 ] || fail "--rank-timeout '$bad': exit status $status, expected 2"
        grep -q "gaitlab: --rank-timeout: a number of seconds > 0 expected (got '$bad')" \
            "$work/bad.err" || fail "--rank-timeout '$bad': $(cat "$work/bad.err")"
        [ ! -e "$work/bad" ] || fail "--rank-timeout '$bad': a results folder was made"
        status=0
        "$gaitlab" sweep "$spec" --grid phase=60:180:60 --rank-timeout "$bad" --out "$work/bad" \
            > "$work/bad.out" 2> "$work/bad.err" || status=$?
        [ "$status" = 2 ] || fail "sweep --rank-timeout '$bad': exit status $status, expected 2"
        grep -q "gaitlab: --rank-timeout: a number of seconds > 0 expected (got '$bad')" \
            "$work/bad.err" || fail "sweep --rank-timeout '$bad': $(cat "$work/bad.err")"
        [ ! -e "$work/bad" ] || fail "sweep --rank-timeout '$bad': a results folder was made"
    done
    ;;
*)
    fail "unknown case $case_"
    ;;
esac
echo "ok"
