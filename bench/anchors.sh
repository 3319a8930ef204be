#!/usr/bin/env bash
# gaitlab against ODE and MuJoCo on the same snake, at equal accuracy (docs/performance.md,
# section 12): for each engine a sweep of its settings (dt, solver iterations, control period),
# the per-cycle speed of each against the engine's own converged reference (dt / 4, 4x the
# default iterations), and the CPU time per step of every setting, all engines interleaved.
#
#   bench/anchors.sh [--anchors DIR] [--gaitlab BIN] [--reps R] [--seconds S] [--jobs J]
#                    [--n N] [--only accuracy|timing] [--quick]
#   bench/anchors.sh --prepare SRC DIR
#   bench/anchors.sh --from RAW        (the tables again from the raw lines of a run)
#
# The peer engines are the performance anchors (a separate project: one program per engine,
# ode_snake and mujoco_snake, stepping the workload of their src/common.h). This script needs a
# build of them with bench/anchors/trace.patch applied (a start phase for the gait, the control
# period, the head's position every gait cycle and the loop's CPU time). `--prepare SRC DIR`
# makes one: it copies the anchors' sources SRC to DIR, applies the patch and builds DIR/build.
# ANCHORS_BUILD (or --anchors) names that build directory. gaitlab runs the same robot through
# its Lua API: bench/lua/anchor_snake.lua under BIN (default build/gaitlab, or $GAITLAB).
#
# ANCHORS_SETTINGS=FILE replaces the built-in settings, one row a line: ENGINE DT_MS ITERS
# PERIOD_MS [ref] [solver=pgs|block_nncg] (blank lines and lines from '#' on are skipped). A
# gaitlab row with solver=block_nncg runs gaitlab.simulation{ solver = "block_nncg" } and is an
# engine of its own in the tables, "gaitlab block_nncg", with its own reference row if the file
# has one (else gaitlab's, the pgs reference, which the table then says); plain gaitlab rows
# and solver=pgs run pgs, named to the script (the engine's default is block_nncg). Every
# gaitlab row runs on the engine's default floor, compliant since 2026-11-28 (3e3 N/m and 60
# N s/m per contact point since 2026-11-30, 1e5 N/m before); the tables of docs/performance.md
# from before 2026-11-28 ran on a rigid one.
#
# Accuracy: each run simulates 22 s and samples the head every 2 s (a gait cycle); the per-cycle
# speed is the mean of |head displacement| over the 10 cycles after the first. Pitch-yaw
# averages it over 5 start phases (0, 72, 144, 216, 288 deg). The runs are deterministic, so
# --jobs of them run at once (default 2). Timing: R rounds (default 5), each running every
# setting once for S simulated s (--seconds, default 10; longer for settings of large dt, whose
# 10 s are few steps), one program at a time, the order reversed every other round; the table
# shows the median CPU time per step of the stepping loop (thread CPU time for ODE and MuJoCo,
# process CPU time for gaitlab, which steps on one thread).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
anchors=${ANCHORS_BUILD:-}
gaitlab=${GAITLAB:-$root/build/gaitlab}
reps=5
seconds=10
jobs=2
n=8
only=
quick=0
from=

prepare() {  # SRC DIR
    local src=$1 dir=$2
    if [ ! -f "$src/src/common.h" ] || [ ! -f "$src/CMakeLists.txt" ]; then
        echo "anchors.sh: '$src' is not the anchors' source folder (no src/common.h and" \
            "CMakeLists.txt there)" >&2
        exit 2
    fi
    if [ -e "$dir" ]; then
        echo "anchors.sh: '$dir' exists; --prepare makes a fresh copy, give a new folder" >&2
        exit 2
    fi
    mkdir -p "$dir"
    cp -r "$src/src" "$src/CMakeLists.txt" "$dir/"
    patch -s -d "$dir" -p1 < "$root/bench/anchors/trace.patch"
    cmake -S "$dir" -B "$dir/build" -DCMAKE_BUILD_TYPE=Release > /dev/null
    cmake --build "$dir/build" -j2 --target ode_snake mujoco_snake > /dev/null
    echo "anchors built in $dir/build: bench/anchors.sh --anchors $dir/build"
}

usage() {
    sed -n '7,10p' "$0" | sed 's/^# *//' >&2
    exit 2
}
while [ $# -gt 0 ]; do
    case "$1" in
        --prepare)
            [ $# -eq 3 ] || usage
            prepare "$2" "$3"
            exit 0
            ;;
        --anchors) anchors=${2:?}; shift ;;
        --gaitlab) gaitlab=${2:?}; shift ;;
        --reps) reps=${2:?}; shift ;;
        --seconds) seconds=${2:?}; shift ;;
        --jobs) jobs=${2:?}; shift ;;
        --n) n=${2:?}; shift ;;
        --only) only=${2:?}; shift ;;
        --quick) quick=1 ;;
        --from) from=${2:?}; shift ;;
        *) usage ;;
    esac
    shift
done
for v in "$reps" "$seconds" "$jobs" "$n"; do
    [[ $v =~ ^[1-9][0-9]*$ ]] || { echo "anchors.sh: --reps, --seconds, --jobs and --n take a positive integer (got '$v')" >&2; exit 2; }
done
case "$only" in "" | accuracy | timing | none) ;; *) echo "anchors.sh: --only takes accuracy or timing (got '$only')" >&2; exit 2 ;; esac

script=$root/bench/lua/anchor_snake.lua

# settings: ENGINE DT_MS ITERS CONTROL_PERIOD_MS [ref] [solver=NAME]; one per line. The
# control period (the gait's update) is 10 ms but where a row says otherwise.
# ANCHORS_SETTINGS=FILE: the rows of FILE instead.
raw_settings() {
    if [ -n "${ANCHORS_SETTINGS:-}" ]; then
        cat "$ANCHORS_SETTINGS"
        return
    fi
    cat << 'EOF'
gaitlab 0.25 80 10 ref
gaitlab 0.5 7 10
gaitlab 0.5 10 10
gaitlab 0.5 14 10
gaitlab 0.5 20 10
gaitlab 1 5 10
gaitlab 1 7 10
gaitlab 1 10 10
gaitlab 1 14 10
gaitlab 1 20 10
gaitlab 1 10 30
gaitlab 1 20 30
gaitlab 2 10 10
gaitlab 2 20 10
gaitlab 2.5 10 10
gaitlab 2.5 14 10
gaitlab 2.5 20 10
gaitlab 5 20 10
gaitlab 5 40 10
ode 0.25 80 10 ref
ode 0.5 7 10
ode 0.5 10 10
ode 0.5 20 10
ode 1 5 10
ode 1 7 10
ode 1 10 10
ode 1 14 10
ode 1 20 10
ode 2 10 10
ode 2 20 10
ode 2.5 10 10
ode 2.5 20 10
ode 5 10 10
ode 5 14 10
ode 5 20 10
mujoco 0.25 400 10 ref
mujoco 0.5 2 10
mujoco 0.5 3 10
mujoco 0.5 100 10
mujoco 1 2 10
mujoco 1 3 10
mujoco 1 5 10
mujoco 1 100 10
mujoco 2 3 10
mujoco 2 100 10
EOF
}

# the rows checked and made uniform: ENGINE DT_MS ITERS PERIOD_MS [ref], ENGINE gaitlab,
# gaitlab/block_nncg, ode or mujoco; a bad row stops the script with its file and line
settings() {
    raw_settings | awk -v file="${ANCHORS_SETTINGS:-the built-in settings}" '
        function bad(what) {
            printf "anchors.sh: %s, line %d: %s; a row is ENGINE DT_MS ITERS PERIOD_MS [ref] " \
                "[solver=pgs|block_nncg], ENGINE gaitlab, ode or mujoco (got \"%s\")\n", file, NR, what, line > "/dev/stderr"
            failed = 1
            exit 2
        }
        { line = $0; sub(/#.*/, "") }
        NF == 0 { next }
        {
            e = $1
            if (e != "gaitlab" && e != "ode" && e != "mujoco") bad("unknown engine \"" e "\"")
            if (NF < 4) bad("too few fields")
            if ($2 !~ /^([0-9]+\.?[0-9]*|\.[0-9]+)$/ || $2 + 0 <= 0) bad("DT_MS must be a positive number")
            if ($3 !~ /^[1-9][0-9]*$/) bad("ITERS must be a positive integer")
            if ($4 !~ /^([0-9]+\.?[0-9]*|\.[0-9]+)$/ || $4 + 0 <= 0) bad("PERIOD_MS must be a positive number")
            ref = ""; solver = ""
            for (i = 5; i <= NF; ++i) {
                if ($i == "ref" && ref == "") ref = " ref"
                else if ($i ~ /^solver=/ && solver == "") {
                    solver = substr($i, 8)
                    if (e != "gaitlab") bad("solver= is a setting of gaitlab rows only")
                    if (solver != "pgs" && solver != "block_nncg") bad("solver must be pgs or block_nncg")
                }
                else bad("unexpected \"" $i "\"")
            }
            if (solver == "block_nncg") e = e "/" solver
            print e, $2, $3, $4 ref
        }
        END { if (failed) exit 2 }'
}

if [ -z "$from" ]; then
    if [ -n "${ANCHORS_SETTINGS:-}" ] && [ ! -f "$ANCHORS_SETTINGS" ]; then
        echo "anchors.sh: ANCHORS_SETTINGS names no file ('$ANCHORS_SETTINGS')" >&2
        exit 2
    fi
    rows_checked=$(settings)  # stops here on a bad row
    [ -n "$rows_checked" ] || { echo "anchors.sh: ${ANCHORS_SETTINGS:-the settings} has no rows" >&2; exit 2; }
fi

if [ -n "$from" ]; then
    [ -f "$from" ] || { echo "anchors.sh: --from: no file '$from'" >&2; exit 2; }
    only=none
elif [ -z "$anchors" ] || [ ! -x "$anchors/ode_snake" ] || [ ! -x "$anchors/mujoco_snake" ]; then
    cat >&2 << EOF
anchors.sh: no build of the performance anchors${anchors:+ in '$anchors'} (it needs ode_snake and
mujoco_snake there). Make one from the anchors' sources (their folder has src/common.h):
    apt-get install -y cmake g++ pkg-config libbullet-dev libbullet-extras-dev libmujoco-dev \\
        libode-dev liblua5.4-dev
    bench/anchors.sh --prepare ANCHORS_SOURCE_DIR /tmp/anchors
then run   bench/anchors.sh --anchors /tmp/anchors/build   (or set ANCHORS_BUILD).
EOF
    exit 2
elif ! "$anchors/ode_snake" --n 2 --time 0.01 --trace-every 0.01 > /dev/null 2>&1; then
    echo "anchors.sh: $anchors/ode_snake does not take --trace-every: build it with" \
        "bench/anchors/trace.patch (bench/anchors.sh --prepare SRC DIR)" >&2
    exit 2
fi
if [ ! -x "$gaitlab" ]; then
    echo "anchors.sh: no gaitlab program at '$gaitlab': build the project (tools/build.sh) or" \
        "give --gaitlab BIN" >&2
    exit 2
fi

# command ENGINE CONN DT_MS ITERS PERIOD_MS SECONDS PHASE0 TRACE -> the command line
command_for() {
    local e=$1 conn=$2 dtms=$3 it=$4 pms=$5 secs=$6 ph=$7 tr=$8 dt ce
    dt=$(awk -v d="$dtms" 'BEGIN {printf "%.10g", d / 1000}')
    ce=$(awk -v p="$pms" -v d="$dtms" 'BEGIN {printf "%d", p / d + 0.5}')
    case "$e" in
        gaitlab | gaitlab/*)
            # a row without solver= is pgs, named: the engine's default is block_nncg
            local solver=" solver=pgs"
            [ "$e" = gaitlab ] || solver=" solver=${e#gaitlab/}"
            echo "$gaitlab run $script n=$n conn=$conn dt=$dt iters=$it ce=$ce time=$secs" \
                "phase0=$ph trace=$tr$solver --no-record"
            ;;
        ode | mujoco)
            local prog=ode_snake
            [ "$e" = mujoco ] && prog=mujoco_snake
            echo "$anchors/$prog --n $n --conn $conn --dt $dt --iters $it --ctrl-every $ce" \
                "--time $secs --phase0 $ph --trace-every $tr"
            ;;
    esac
}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
phases_py="0 72 144 216 288"
conns="pp py"
if [ $quick -eq 1 ]; then
    phases_py="0 144"
    reps=3
fi

if [ -z "$from" ]; then
    echo "## gaitlab vs ODE and MuJoCo at equal accuracy ($(date -u '+%Y-%m-%d %H:%M UTC'), n = $n)"
    echo
    echo "- machine: $(nproc) vCPU, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
    echo "- load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
    echo "- accuracy: 22 simulated s, head sampled every 2 s, mean |displacement| per cycle over" \
        "cycles 2-11; pitch-yaw averaged over start phases $phases_py"
    echo "- timing: $reps interleaved rounds of $seconds simulated s, median CPU time per step"
fi

# ---------------------------------------------------------------------------- accuracy ----
acc=$work/accuracy.txt
: > "$acc"
if [ -n "$from" ]; then
    grep -v ' round=' "$from" > "$acc" || true
fi
if [ "$only" != timing ] && [ "$only" != none ]; then
    list=$work/acc_cmds.txt
    : > "$list"
    for conn in $conns; do
        phases=0
        [ "$conn" = py ] && phases=$phases_py
        while read -r e dtms it pms ref; do
            for ph in $phases; do
                echo "$e $conn $dtms $it $pms ${ref:--} $ph|$(command_for "$e" "$conn" "$dtms" "$it" "$pms" 22 "$ph" 2)" >> "$list"
            done
        done <<< "$rows_checked"
    done
    # the costliest runs (the references) first, so that the jobs finish together
    sort -t'|' -k1,1 -s < "$list" | awk '/ ref /' > "$work/ordered"
    awk '!/ ref /' "$list" >> "$work/ordered"
    run_one() {  # "TAGS|COMMAND" -> "TAGS RESULT LINE"
        local tags=${1%%|*} cmd=${1#*|} out
        # shellcheck disable=SC2086
        if ! out=$($cmd 2>&1 | tail -1); then out="status=FAILED"; fi
        echo "tags=${tags// /:} $out"
    }
    export -f run_one
    tr '\n' '\0' < "$work/ordered" | xargs -0 -P "$jobs" -I{} bash -c 'run_one "$1"' _ {} >> "$acc"
fi

# ------------------------------------------------------------------------------ timing ----
tim=$work/timing.txt
: > "$tim"
if [ -n "$from" ]; then
    grep ' round=' "$from" > "$tim" || true
fi
if [ "$only" != accuracy ] && [ "$only" != none ]; then
    mapfile -t rows < <(for conn in $conns; do awk -v c="$conn" '$5 != "ref" {print $1, c, $2, $3, $4}' <<< "$rows_checked"; done)
    for ((r = 0; r < reps; ++r)); do
        order=("${rows[@]}")
        if ((r % 2)); then
            mapfile -t order < <(printf '%s\n' "${rows[@]}" | tac)
        fi
        for row in "${order[@]}"; do
            read -r e conn dtms it pms <<< "$row"
            # shellcheck disable=SC2091  # runs the command it prints
            out=$($(command_for "$e" "$conn" "$dtms" "$it" "$pms" "$seconds" 0 0) 2>&1 | tail -1) || out="status=FAILED"
            echo "tags=$e:$conn:$dtms:$it:$pms round=$r $out" >> "$tim"
        done
    done
fi
[ -z "$from" ] && echo "- load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
echo

# ------------------------------------------------------------------------------- table ----
awk -v phases_py="$phases_py" '
    function field(line, name,   m) {
        if (match(line, "(^| )" name "=[^ ]*")) {
            m = substr(line, RSTART, RLENGTH); sub(/^ /, "", m); return substr(m, length(name) + 2)
        }
        return ""
    }
    # mean |head displacement| per cycle over cycles 2..11, mm (NaN if the trace is short or bad)
    function speed(trace,   pts, k, n, xy, x, y, s) {
        n = split(trace, pts, ";")
        if (n < 12) return "nan"
        for (k = 1; k <= n; ++k) { split(pts[k], xy, ","); x[k] = xy[1]; y[k] = xy[2] }
        s = 0
        for (k = 2; k <= 11; ++k) s += sqrt((x[k + 1] - x[k]) ^ 2 + (y[k + 1] - y[k]) ^ 2)
        return s / 10 * 1000
    }
    FILENAME ~ /accuracy/ {
        split(field($0, "tags"), t, ":")   # engine conn dt it period [ref] phase
        ref = (t[6] == "ref"); ph = t[7]
        key = t[1] SUBSEP t[2] SUBSEP t[3] SUBSEP t[4] SUBSEP t[5]
        st = field($0, "status")
        v = speed(field($0, "trace"))
        if ((st != "" && st != "ok") || v == "nan" || v != v + 0) bad[key] = 1
        else { sp[key, ph] = v; sum[key] += v; cnt[key]++ }
        if (ref) refkey[t[1], t[2]] = key
        keys[key] = 1
        next
    }
    FILENAME ~ /timing/ {
        split(field($0, "tags"), t, ":")
        key = t[1] SUBSEP t[2] SUBSEP t[3] SUBSEP t[4] SUBSEP t[5]
        c = field($0, "cpu_us_per_step")
        if (c == "" || field($0, "status") == "FAILED") next
        ts[key] = ts[key] " " c
        keys[key] = 1
        next
    }
    function median(list,   a, n, i, j, tmp) {
        n = split(list, a, " ")
        if (n == 0) return ""
        for (i = 2; i <= n; ++i) for (j = i; j > 1 && a[j - 1] + 0 > a[j] + 0; --j) { tmp = a[j]; a[j] = a[j - 1]; a[j - 1] = tmp }
        return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
    }
    function range(list,   a, n, i, lo, hi) {
        n = split(list, a, " ")
        lo = hi = a[1]
        for (i = 2; i <= n; ++i) { if (a[i] + 0 < lo + 0) lo = a[i]; if (a[i] + 0 > hi + 0) hi = a[i] }
        return sprintf("%.1f–%.1f", lo, hi)
    }
    END {
        nph = split(phases_py, P, " ")
        print "| engine | conn | dt (ms) | iterations | control period (ms) | speed (mm/cycle) | error vs own reference | worst start phase | CPU µs/step (median) | range | CPU µs per simulated ms |"
        print "|---|---|---|---|---|---|---|---|---|---|---|"
        # the engines: gaitlab, its solver variants (gaitlab/NAME, shown "gaitlab NAME"), ode,
        # mujoco; gaitlab and ode and mujoco always (as before the variants), a variant if it ran
        nv = 0
        for (key in keys) { split(key, t, SUBSEP); if (t[1] ~ /^gaitlab\// && !(t[1] in isvar)) { isvar[t[1]] = 1; V[++nv] = t[1] } }
        for (i = 2; i <= nv; ++i) for (j = i; j > 1 && V[j - 1] > V[j]; --j) { tmp = V[j]; V[j] = V[j - 1]; V[j - 1] = tmp }
        ne = 0; E[++ne] = "gaitlab"
        for (i = 1; i <= nv; ++i) E[++ne] = V[i]
        E[++ne] = "ode"; E[++ne] = "mujoco"
        ng = nv + 1
        for (ei = 1; ei <= ne; ++ei) { name[E[ei]] = E[ei]; sub("/", " ", name[E[ei]]) }
        nc = split("pp py", C, " ")
        for (ci = 1; ci <= nc; ++ci) for (ei = 1; ei <= ne; ++ei) {
            e = E[ei]; c = C[ci]
            rk = refkey[e, c]
            # a solver variant without a reference row of its own: gaitlab'"'"'s (pgs)
            if (rk == "" && e ~ /^gaitlab\// && refkey["gaitlab", c] != "") { rk = refkey["gaitlab", c]; borrowed[e, c] = 1 }
            # rows of this engine and connection: sort by dt, then iterations, then period
            m = 0
            for (key in keys) {
                split(key, t, SUBSEP)
                if (t[1] != e || t[2] != c) continue
                row[++m] = key
            }
            for (i = 2; i <= m; ++i) for (j = i; j > 1; --j) {
                split(row[j - 1], a, SUBSEP); split(row[j], b, SUBSEP)
                if (a[3] + 0 < b[3] + 0 || (a[3] == b[3] && (a[4] + 0 < b[4] + 0 || (a[4] == b[4] && a[5] + 0 <= b[5] + 0)))) break
                tmp = row[j]; row[j] = row[j - 1]; row[j - 1] = tmp
            }
            best = ""; bestcost = 1e30
            for (i = 1; i <= m; ++i) {
                key = row[i]; split(key, t, SUBSEP)
                isref = (key == rk)
                np = (c == "py") ? nph : 1
                if (key in bad || cnt[key] < np) { acc = "failed"; err = "—"; worst = "—"; errv = 1e30 }
                else {
                    acc = sprintf("%.1f", sum[key] / cnt[key])
                    if (isref) { err = "(reference)"; worst = "—"; errv = 0 }
                    else if (rk == "" || (rk in bad) || cnt[rk] < np) { err = "no reference"; worst = "—"; errv = 1e30 }
                    else {
                        errv = 100 * (sum[key] / cnt[key] - sum[rk] / cnt[rk]) / (sum[rk] / cnt[rk])
                        err = sprintf("%+.2f %%", errv)
                        w = 0
                        for (p = 1; p <= np; ++p) {
                            ph = (c == "py") ? P[p] : 0
                            d = 100 * (sp[key, ph] - sp[rk, ph]) / sp[rk, ph]
                            if (d < 0) d = -d
                            if (d > w) w = d
                        }
                        worst = (c == "py") ? sprintf("%.2f %%", w) : "—"
                        if (errv < 0) errv = -errv
                        if (errv > 2) err = "**" err "**"
                    }
                }
                med = median(ts[key])
                cost = med == "" ? "" : sprintf("%.1f", med / t[3])
                print "| " name[e] " | " c " | " t[3] " | " t[4] " | " t[5] " | " acc " | " err " | " worst " | " (med == "" ? "—" : sprintf("%.2f", med)) " | " (med == "" ? "—" : range(ts[key])) " | " (cost == "" ? "—" : cost) " |"
                errv_of[key] = errv; med_of[key] = (med == "" ? "" : med / t[3])
                if (!isref && errv <= 2 && med != "" && med / t[3] < bestcost) { bestcost = med / t[3]; best = key }
            }
            if (best != "") { cheapest[e, c] = best; cheapcost[e, c] = bestcost }
            if ((e, c) in borrowed) notes = notes "\n" name[e] " " c ": no reference row of its own; errors against gaitlab'"'"'s (pgs) reference."
            for (i = 1; i <= m; ++i) {
                key = row[i]; split(key, t, SUBSEP)
                s3 = t[1] SUBSEP t[3] SUBSEP t[4] SUBSEP t[5]
                okc[s3, c] = (key != rk && errv_of[key] != "" && errv_of[key] <= 2)
                costc[s3, c] = med_of[key]
                settingkeys[s3] = 1
            }
        }
        if (notes != "") print substr(notes, 2)
        print ""
        print "Cheapest setting within 2 % of the engine'"'"'s own reference (by CPU time per simulated ms, so that settings of different dt compare):"
        print ""
        print "| conn | engine | setting (dt ms, iterations, period ms) | CPU µs per simulated ms | gaitlab faster by |"
        print "|---|---|---|---|---|"
        for (ci = 1; ci <= nc; ++ci) for (ei = 1; ei <= ne; ++ei) {
            e = E[ei]; c = C[ci]
            if (!((e, c) in cheapest)) { print "| " c " | " name[e] " | none within 2 % | — | — |"; continue }
            split(cheapest[e, c], t, SUBSEP)
            # against each gaitlab solver that has a setting within 2 % (named if there are several)
            ratio = ""
            if (ei > ng) for (gi = 1; gi <= ng; ++gi) {
                g = E[gi]
                if (!((g, c) in cheapest)) continue
                ratio = ratio (ratio == "" ? "" : ", ") sprintf("**%.2f×**", cheapcost[e, c] / cheapcost[g, c]) (ng > 1 ? " (" name[g] ")" : "")
            }
            if (ratio == "") ratio = "—"
            print "| " c " | " name[e] " | " t[3] ", " t[4] ", " t[5] " | " sprintf("%.1f", cheapcost[e, c]) " | " ratio " |"
        }
        # one setting for both gaits: a user picks settings once, for every gait
        for (ei = 1; ei <= ne; ++ei) {
            e = E[ei]; bothcost[e] = 1e30
            for (s3 in settingkeys) {
                split(s3, t, SUBSEP)
                if (t[1] != e || !okc[s3, "pp"] || !okc[s3, "py"]) continue
                if (costc[s3, "pp"] == "" || costc[s3, "py"] == "") continue
                if (costc[s3, "pp"] + costc[s3, "py"] < bothcost[e]) { bothcost[e] = costc[s3, "pp"] + costc[s3, "py"]; both[e] = s3 }
            }
        }
        print ""
        print "Cheapest single setting within 2 % on both pp and py:"
        print ""
        print "| engine | setting (dt ms, iterations, period ms) | pp: CPU µs per simulated ms | py | gaitlab faster by (pp, py) |"
        print "|---|---|---|---|---|"
        for (ei = 1; ei <= ne; ++ei) {
            e = E[ei]
            if (!(e in both)) { print "| " name[e] " | none | — | — | — |"; continue }
            split(both[e], t, SUBSEP)
            ratio = ""
            if (ei > ng) for (gi = 1; gi <= ng; ++gi) {
                g = both[E[gi]]
                if (g == "") continue
                ratio = ratio (ratio == "" ? "" : "; ") sprintf("**%.2f×, %.2f×**", costc[both[e], "pp"] / costc[g, "pp"], costc[both[e], "py"] / costc[g, "py"]) (ng > 1 ? " (" name[E[gi]] ")" : "")
            }
            if (ratio == "") ratio = "—"
            print "| " name[e] " | " t[2] ", " t[3] ", " t[4] " | " sprintf("%.1f", costc[both[e], "pp"]) " | " sprintf("%.1f", costc[both[e], "py"]) " | " ratio " |"
        }
    }' "$acc" "$tim"

if [ -n "${ANCHORS_RAW:-}" ]; then
    cat "$acc" "$tim" > "$ANCHORS_RAW"
    echo
    echo "(raw result lines in $ANCHORS_RAW)"
fi
