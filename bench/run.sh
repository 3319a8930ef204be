#!/usr/bin/env bash
# Builds the benchmarks and runs them all; prints markdown tables (docs/performance.md).
#
#   bench/run.sh [--quick] [--no-build] [--only SECTION]...
#
# SECTION: overhead | lua | callgrind (incl. the built-in controllers) | sensors | process |
# accuracy | record (recording cost, time and callgrind) | memory (a one-hour recorded run) |
# micro (Google Benchmark: one controller step, one recorder row, XML parsing)
# viewer (what serving the viewer costs)
# (default: all of them).
# --quick: shorter runs, fewer repetitions and scenarios (about 3 minutes instead of about 10).
# BUILD_DIR (default build-bench) selects the build directory.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
quick=0
do_build=1
sections=()
while [ $# -gt 0 ]; do
    case "$1" in
        --quick) quick=1 ;;
        --no-build) do_build=0 ;;
        --only) sections+=("$2"); shift ;;
        *) echo "usage: bench/run.sh [--quick] [--no-build] [--only SECTION]..." >&2; exit 2 ;;
    esac
    shift
done
[ ${#sections[@]} -eq 0 ] && sections=(overhead lua callgrind sensors process accuracy record memory micro viewer)
want() { local s; for s in "${sections[@]}"; do [ "$s" = "$1" ] && return 0; done; return 1; }

if [ $do_build -eq 1 ]; then
    generator=()
    command -v ninja >/dev/null && generator=(-G Ninja)
    if [ ! -f "$build/CMakeCache.txt" ]; then
        cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
    fi
    cmake --build "$build" --target gaitlab_bench raw_bullet_loop gaitlab gaitlab_microbench viewer_bench >/dev/null
fi
bench=$build/bench/gaitlab_bench
raw=$build/bench/raw_bullet_loop
micro=$build/bench/gaitlab_microbench
gaitlab=$build/gaitlab
my_sine=$root/examples/controllers/my_sine.lua
q=()
[ $quick -eq 1 ] && q=(--quick)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "## gaitlab benchmarks ($(date -u '+%Y-%m-%d %H:%M UTC'))"
echo
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')
ram=$(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo)
echo "- machine: $(nproc) vCPU, $cpu, $ram RAM"
echo "- compiler: $(c++ --version | head -1); Bullet $(pkg-config --modversion bullet)"
echo "- load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "- mode: $([ $quick -eq 1 ] && echo quick || echo full)"

want overhead && "$bench" overhead "${q[@]}"
want lua && "$bench" lua "${q[@]}"

# instruction counts of the stepping loop only (callgrind, --instr-atstart=no; the program
# switches instrumentation on around the loop). Two valgrind processes run at a time.
cg_ir() {  # impl conn modules ce seconds [controller] -> instructions
    local out="$work/cg.$1.$2.$3.$4.${6:-sine}"
    valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file="$out" \
        "$bench" one --impl "$1" --conn "$2" --modules "$3" --ce "$4" --seconds "$5" \
        --controller "${6:-sine}" >/dev/null 2>&1
    awk '/^totals:/ {print $2}' "$out"
}
cg_table() {  # title impl_a impl_b seconds ce...
    local title=$1 a=$2 b=$3 secs=$4
    shift 4
    local steps
    steps=$(awk -v s="$secs" 'BEGIN {printf "%d", s * 1000 + 0.5}')
    echo
    echo "### $title: instructions per step (callgrind, $secs simulated s = $steps steps)"
    echo
    echo "| scenario | $a Ir/step | $b Ir/step | ratio |"
    echo "|---|---|---|---|"
    local ce conn n ia ib
    for ce in "$@"; do
        for conn in pp py; do
            for n in 8 16 32; do
                [ $quick -eq 1 ] && [ "$n" = 16 ] && continue
                cg_ir "$a" "$conn" "$n" "$ce" "$secs" > "$work/ia" &
                cg_ir "$b" "$conn" "$n" "$ce" "$secs" > "$work/ib" &
                wait
                ia=$(cat "$work/ia"); ib=$(cat "$work/ib")
                awk -v l="$conn$n ce$ce" -v a="$ia" -v b="$ib" -v s="$steps" 'BEGIN {
                    printf "| %s | %.0f | %.0f | **%.4f** |\n", l, a / s, b / s, b / a }'
            done
        done
    done
}
# what each built-in controller costs on pp8 ce10: the instructions inside its step function
# (inclusive, callgrind: the step function's own line, not those of lambdas inside it, which it
# includes) as a share of the whole stepping loop. Comparing whole runs would
# compare different physics (a gait lifts the body off the floor, an offset holds it down).
controllers_table() {
    local secs=$1 names name out total own steps
    steps=$(awk -v s="$secs" 'BEGIN {printf "%d", s * 1000 + 0.5}')
    printf 'local t = {}\nfor k in pairs(gaitlab.controllers) do t[#t + 1] = k end\n%s\n' \
        'table.sort(t) print(table.concat(t, " "))' > "$work/names.lua"
    names=$("$gaitlab" run "$work/names.lua")
    echo
    echo "### Built-in controllers on pp8, control_every = 10: their own cost (callgrind)"
    echo
    echo "| controller | step() Ir per physics step | whole loop Ir/step | share of the loop |"
    echo "|---|---|---|---|"
    for name in $names; do
        out="$work/cgc.$name"
        valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file="$out" \
            "$bench" one --impl gaitlab --conn pp --modules 8 --ce 10 --seconds "$secs" \
            --controller "$name" >/dev/null 2>&1
        total=$(awk '/^totals:/ {print $2}' "$out")
        own=$(callgrind_annotate --inclusive=yes --threshold=100 "$out" 2>/dev/null |
            grep -E 'gaitlab::controllers::[A-Za-z]+::step\(gaitlab::ControlIO&\) \[' |
            awk '{gsub(",", "", $1); s += $1} END {print s + 0}')
        awk -v n="$name" -v t="$total" -v o="$own" -v s="$steps" \
            'BEGIN { printf "| %s | %.0f | %.0f | **%.3f %%** |\n", n, o / s, t / s, 100 * o / t }'
    done
}

if want callgrind; then
    if command -v valgrind >/dev/null; then
        secs=1
        [ $quick -eq 1 ] && secs=0.5
        ces=(10 30)
        [ $quick -eq 1 ] && ces=(10)
        cg_table "gaitlab vs raw Bullet loop" raw gaitlab "$secs" "${ces[@]}"
        cg_table "Lua controller vs C++ sine" gaitlab lua-controller "$secs" 10
        controllers_table "$secs"
    else
        echo; echo "(valgrind not found: callgrind section skipped)"
    fi
fi

# what sensors cost: the same gait with no sensors, with 4 per module + 1 all switched off, and
# with them all on (callgrind, instructions of the stepping loop); the share of the loop spent
# reading them is Sensing::update's inclusive count
sensors_table() {
    local secs=$1 steps n s out none total own
    steps=$(awk -v s="$secs" 'BEGIN {printf "%d", s * 1000 + 0.5}')
    echo
    echo "### Sensors on pp, control_every = 10: none, all switched off, all on (callgrind, $secs simulated s)"
    echo
    echo "| robot | sensors | state | Ir/step | vs none | reading them, Ir/step |"
    echo "|---|---|---|---|---|---|"
    for n in 8 32; do
        for s in none off on; do
            out="$work/cgs.$n.$s"
            valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file="$out" \
                "$bench" one --impl gaitlab --conn pp --modules "$n" --ce 10 --seconds "$secs" \
                --sensors "$s" >/dev/null 2>&1 &
        done
        wait
        none=$(awk '/^totals:/ {print $2}' "$work/cgs.$n.none")
        for s in none off on; do
            out="$work/cgs.$n.$s"
            total=$(awk '/^totals:/ {print $2}' "$out")
            own=$(callgrind_annotate --inclusive=yes --threshold=100 "$out" 2>/dev/null |
                grep -E 'gaitlab::Sensing::update\(' | awk '{gsub(",", "", $1); s += $1} END {print s + 0}')
            awk -v n="$n" -v st="$s" -v t="$total" -v z="$none" -v o="$own" -v k="$steps" 'BEGIN {
                count = st == "none" ? 0 : 4 * n + 1
                printf "| pp%d | %d | %s | %.0f | **%+.4f %%** | %.0f |\n", n, count, st, t / k,
                    100 * (t - z) / z, o / k }'
        done
    done
}
if want sensors; then
    if command -v valgrind >/dev/null; then
        secs=1
        [ $quick -eq 1 ] && secs=0.5
        sensors_table "$secs"
    else
        echo; echo "(valgrind not found: sensors section skipped)"
    fi
fi

# whole processes (start-up, scene build, 20 simulated s, exit) with hyperfine
if want process; then
    if command -v hyperfine >/dev/null; then
        runs=5
        [ $quick -eq 1 ] && runs=3
        echo
        echo "### Whole process, pp32, control_every = 10, 20 simulated s (hyperfine, $runs runs)"
        echo
        hyperfine --style none --warmup 1 --runs "$runs" --export-markdown "$work/hf.md" \
            -n "raw_bullet_loop" "$raw --modules 32 --conn pp --ce 10" \
            -n "gaitlab run, C++ sine" "$gaitlab run $root/bench/lua/snake.lua 32 pp 10 sine" \
            -n "gaitlab run, Lua my_sine" \
            "$gaitlab run $root/bench/lua/snake.lua 32 pp 10 $my_sine" >/dev/null
        cat "$work/hf.md"
        echo
        echo "### Start-up: \`gaitlab run\` of an empty script (hyperfine, 20 runs)"
        echo
        : > "$work/empty.lua"
        hyperfine -N --style none --warmup 3 --runs 20 --export-markdown "$work/hf0.md" \
            -n "gaitlab run empty.lua" "$gaitlab run $work/empty.lua" >/dev/null
        cat "$work/hf0.md"
    else
        echo; echo "(hyperfine not found: whole-process section skipped)"
    fi
fi

want accuracy && "$bench" accuracy "${q[@]}"

# recording every series at every control tick of a 16-module robot: time, then instructions
if want record; then
    "$bench" record "${q[@]}"
    if command -v valgrind >/dev/null; then
        secs=1
        [ $quick -eq 1 ] && secs=0.5
        echo
        echo "### Recording: instructions per step (callgrind, $secs simulated s), every series at every control tick"
        echo
        echo "| scenario | gaitlab Ir/step | recorded Ir/step | ratio |"
        echo "|---|---|---|---|"
        steps=$(awk -v s="$secs" 'BEGIN {printf "%d", s * 1000 + 0.5}')
        for ce in 30 10; do
            for conn in pp py; do
                cg_ir gaitlab "$conn" 16 "$ce" "$secs" > "$work/ia" &
                valgrind --tool=callgrind --instr-atstart=no \
                    --callgrind-out-file="$work/cg.rec.$conn.$ce" "$bench" one --impl gaitlab \
                    --conn "$conn" --modules 16 --ce "$ce" --seconds "$secs" \
                    --record "$work/run.$conn.$ce" >/dev/null 2>&1 &
                wait
                ia=$(cat "$work/ia")
                ib=$(awk '/^totals:/ {print $2}' "$work/cg.rec.$conn.$ce")
                awk -v l="$conn""16 ce$ce" -v a="$ia" -v b="$ib" -v s="$steps" 'BEGIN {
                    printf "| %s | %.0f | %.0f | **%.4f** |\n", l, a / s, b / s, b / a }'
            done
        done
    fi
fi

# memory over one simulated hour of recording (4 modules to keep it to a few minutes)
if want memory; then
    hours=1
    [ $quick -eq 1 ] && hours=0.25
    "$bench" memory --hours "$hours" --modules 4 --ce 30
fi
# the micro-benchmarks: R repetitions of each, CPU time per call (median and range over the
# repetitions) and throughput; Google Benchmark picks the iterations of each repetition
if want micro; then
    reps=5
    min_time=0.5
    [ $quick -eq 1 ] && reps=3 && min_time=0.1
    "$micro" --benchmark_repetitions="$reps" --benchmark_min_time="$min_time" \
        --benchmark_format=csv 2>/dev/null > "$work/micro.csv"
    echo
    echo "### Micro-benchmarks (Google Benchmark, $reps repetitions of at least $min_time s each)"
    echo
    echo "| benchmark | CPU time per call, median | range over the repetitions | throughput (median) | note |"
    echo "|---|---|---|---|---|"
    awk -F, '
        function fmt(ns) {
            if (ns >= 1e6) return sprintf("%.2f ms", ns / 1e6)
            if (ns >= 1e3) return sprintf("%.2f µs", ns / 1e3)
            return sprintf("%.1f ns", ns)
        }
        function rate(v, unit) {
            if (v >= 1e9) return sprintf("%.2f G%s/s", v / 1e9, unit)
            if (v >= 1e6) return sprintf("%.1f M%s/s", v / 1e6, unit)
            return sprintf("%.0f k%s/s", v / 1e3, unit)
        }
        NR == 1 { next }
        {
            for (i = 1; i <= NF; ++i) gsub(/"/, "", $i)
            name = $1; cpu = $4 + 0
            if (name ~ /_(mean|stddev|cv)$/) next
            if (name ~ /_median$/) {
                sub(/_median$/, "", name)
                tp = $6 != "" ? rate($6, "B") : $7 != "" ? rate($7, "") : ""
                if (name ~ /controller_step/ && $7 != "") tp = rate($7, " joint steps")
                if (name ~ /series_sample/ && $7 != "") tp = rate($7, " series")
                med[name] = cpu; thr[name] = tp; note[name] = $8
                order[++n] = name
                next
            }
            if (!(name in lo) || cpu < lo[name]) lo[name] = cpu
            if (!(name in hi) || cpu > hi[name]) hi[name] = cpu
        }
        END {
            for (k = 1; k <= n; ++k) {
                m = order[k]
                printf "| %s | **%s** | %s – %s | %s | %s |\n", m, fmt(med[m]), fmt(lo[m]), fmt(hi[m]), thr[m], note[m]
            }
        }' "$work/micro.csv"
fi

want viewer && "$build/bench/viewer_bench" "${q[@]}"
exit 0
