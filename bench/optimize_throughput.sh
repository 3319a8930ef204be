#!/usr/bin/env bash
# gaitlab optimize's throughput and memory (docs/performance.md, section 10):
#   - evaluations per second with 1 and 2 worker threads, and under mpirun with 2 evaluating
#     ranks of 1 thread (mpirun -n 3: rank 0 only hands out), median of REPEATS interleaved runs;
#   - the runner's own cost with 1 worker: wall time less the sum of the evaluations' own times,
#     (a) per generation, from the difference between a run of G generations and one of 1 (the
#     method's ask/tell, handing out, evaluations.jsonl), over the evaluations' time; (b) once
#     per run (process start, the spec loaded, the best saved as a simulation file);
#   - the machine's own ceiling: two independent `--workers 1` runs at the same time, whose
#     evaluations per second over one run's say what any parallel run can reach here;
#   - the peak resident memory of runs of about 1 000 and 10 000 short evaluations.
#
#   bench/optimize_throughput.sh [--quick] [--long] [--generations N] [--no-mpi]
#                                [--only throughput|memory]
#
# --long: evaluations of 4 simulated s instead of 1 (the fixed cost of a run weighs less).
# --generations N: generations of 16 evaluations per run (default 4); a longer run weighs the
#   once-per-run cost (start, the best run recorded) as a real optimization of hundreds of
#   evaluations does.
#
# GAITLAB (default build/gaitlab) is the binary; bench/lua/optimize_short.lua the spec. Prints
# markdown tables; the machine's load average before and after, so that a loaded machine shows.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
gaitlab=${GAITLAB:-$root/build/gaitlab}
spec=$root/bench/lua/optimize_short.lua
repeats=5 generations=4 memory_gens=209 mpi=1 only="" duration=1
while [ $# -gt 0 ]; do
    case "$1" in
        --quick) repeats=3 generations=2 memory_gens=105 ;;
        --long) duration=4 ;;
        --generations)
            [[ "${2:-}" =~ ^[1-9][0-9]*$ ]] || { echo "bench: --generations: a whole number >= 1 expected, got '${2:-}'" >&2; exit 2; }
            generations=$2; shift ;;
        --no-mpi) mpi=0 ;;
        --only) only=$2; shift ;;
        *) echo "usage: bench/optimize_throughput.sh [--quick] [--long] [--generations N] [--no-mpi] [--only throughput|memory]" >&2; exit 2 ;;
    esac
    shift
done
[ -x "$gaitlab" ] || { echo "bench: $gaitlab: not built (cmake --build build)" >&2; exit 1; }
command -v mpirun >/dev/null || mpi=0
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
work=$(mktemp -d /tmp/gaitlab-optbench.XXXXXX)
trap 'rm -rf "$work"' EXIT

now() { date +%s.%N; }
median() { sort -g | awk '{v[NR]=$1} END {print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}'; }
# sum of the evaluations' own seconds in a results folder
eval_seconds() { awk -F'"seconds":' '{split($2,a,","); s+=a[1]} END {printf "%.6f", s}' "$1/evaluations.jsonl"; }
evaluations() { wc -l < "$1/evaluations.jsonl"; }

echo "machine: $(nproc) cores, load average before: $(cut -d' ' -f1-3 /proc/loadavg)"

if [ -z "$only" ] || [ "$only" = throughput ]; then
    # each run: "evaluations/s wall evaluation-seconds"
    run() {  # NAME GENERATIONS COMMAND...
        local name=$1 gens=$2 out=$work/$1-$r; shift 2
        local t0 t1 n s
        t0=$(now)
        "$@" --generations "$gens" --seed 1 --out "$out" > /dev/null
        t1=$(now)
        n=$(evaluations "$out")
        s=$(eval_seconds "$out")
        awk -v n="$n" -v t0="$t0" -v t1="$t1" -v s="$s" \
            'BEGIN {w = t1 - t0; printf "%.4f %.6f %.6f\n", n / w, w, s}' >> "$work/$name.txt"
    }
    # two independent runs at once: "evaluations/s of both" into pair.txt
    pair() {
        local t0 t1 n
        t0=$(now)
        "$gaitlab" optimize "$spec" --workers 1 --generations "$generations" --seed 1 \
            --out "$work/pa-$r" > /dev/null &
        "$gaitlab" optimize "$spec" --workers 1 --generations "$generations" --seed 1 \
            --out "$work/pb-$r" > /dev/null
        wait
        t1=$(now)
        n=$(( $(evaluations "$work/pa-$r") + $(evaluations "$work/pb-$r") ))
        awk -v n="$n" -v t0="$t0" -v t1="$t1" 'BEGIN {printf "%.4f\n", n / (t1 - t0)}' >> "$work/pair.txt"
    }
    export GAITLAB_BENCH_DURATION=$duration
    for r in $(seq 1 "$repeats"); do
        run one 1 "$gaitlab" optimize "$spec" --workers 1
        run w1 "$generations" "$gaitlab" optimize "$spec" --workers 1
        run w2 "$generations" "$gaitlab" optimize "$spec" --workers 2
        if [ "$mpi" = 1 ]; then
            run mpi2 "$generations" mpirun --oversubscribe -n 3 "$gaitlab" optimize "$spec" \
                --workers 1
        fi
        pair
    done
    per=$((generations * 16))
    echo
    echo "### Evaluations per second ($per evaluations of $duration simulated s of the 8-module snake per run, median of $repeats interleaved runs)"
    echo
    echo "| run | evaluations / s (median) | runs | vs 1 worker |"
    echo "|---|---|---|---|"
    m1=$(cut -d' ' -f1 "$work/w1.txt" | median)
    for name in w1 w2 mpi2 pair; do
        [ -f "$work/$name.txt" ] || continue
        m=$(cut -d' ' -f1 "$work/$name.txt" | median)
        all=$(cut -d' ' -f1 "$work/$name.txt" | tr '\n' ' ')
        case $name in
            w1) label="--workers 1" ;;
            w2) label="--workers 2" ;;
            mpi2) label="mpirun -n 3 (2 evaluating ranks x 1 worker)" ;;
            pair) label="the ceiling: two --workers 1 runs at once, both counted" ;;
        esac
        echo "| $label | $m | $all| $(awk -v a="$m" -v b="$m1" 'BEGIN {printf "%.2fx", a / b}') |"
    done
    echo
    # per repeat: (a) ((wG - w1) - (sG - s1)) / (sG - s1); (b) w1 - s1
    paste -d' ' "$work/w1.txt" "$work/one.txt" |
        awk '{dw = $2 - $5; ds = $3 - $6; print (dw - ds) / ds, $5 - $6}' > "$work/overhead.txt"
    a=$(cut -d' ' -f1 "$work/overhead.txt" | median)
    b=$(cut -d' ' -f2 "$work/overhead.txt" | median)
    echo "the runner's own cost, 1 worker, median of $repeats:"
    echo "- per generation, over the evaluations' time: $(awk -v a="$a" 'BEGIN {printf "%.3f %%", 100 * a}') (runs: $(cut -d' ' -f1 "$work/overhead.txt" | awk '{printf "%.3f%% ", 100 * $1}'))"
    echo "- once per run (start, spec, best saved): $(awk -v b="$b" 'BEGIN {printf "%.3f s", b}') (runs: $(cut -d' ' -f2 "$work/overhead.txt" | awk '{printf "%.3f ", $1}'))"
fi

if [ -z "$only" ] || [ "$only" = memory ]; then
    echo
    echo "### Peak resident memory (0.02 simulated s per evaluation, 2 workers, population 50)"
    echo
    echo "| evaluations | peak RSS | wall |"
    echo "|---|---|---|"
    for gens in $((memory_gens / 10)) "$memory_gens"; do
        out=$work/mem-$gens
        GAITLAB_BENCH_DURATION=0.02 /usr/bin/time -f "%M %e" -o "$work/time-$gens" \
            "$gaitlab" optimize "$spec" --workers 2 --population 50 --generations "$gens" \
            --method ga --out "$out" > /dev/null
        read -r kb secs < "$work/time-$gens"
        echo "| $(evaluations "$out") | $((kb / 1024)) MB ($kb kB) | ${secs} s |"
    done
fi
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
