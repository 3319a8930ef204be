#!/usr/bin/env bash
# Where a step's instructions go, gaitlab against ODE, on the anchors' snake (docs/performance.md,
# section 13): callgrind over a short run of each setting, the instructions per step of each part
# of the step (inclusive counts of the functions that do it, over the steps run).
#
#   bench/anchors_profile.sh [--anchors DIR] [--gaitlab BIN] [--n N] [--time S] SETTING...
#
# SETTING is ENGINE:CONN:DT_MS:ITERS[:SOLVER], e.g. gaitlab:pp:1:7 ode:py:1:14
# gaitlab:py:2.5:10:block_nncg (ENGINE gaitlab or ode; SOLVER, gaitlab's only, pgs or block_nncg:
# gaitlab.simulation's solver, the engine's default block_nncg if left out; the floor is the
# engine's default, compliant). The run simulates S seconds (default 2) with the control period 10 ms, the gait from phase 0; ODE
# needs the anchors' build with bench/anchors/trace.patch (bench/anchors.sh --prepare SRC DIR).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
anchors=${ANCHORS_BUILD:-}
gaitlab=${GAITLAB:-$root/build/gaitlab}
n=8
secs=2
settings=()
usage() {
    sed -n '5,5p' "$0" | sed 's/^# *//' >&2
    exit 2
}
while [ $# -gt 0 ]; do
    case "$1" in
        --anchors) anchors=${2:?}; shift ;;
        --gaitlab) gaitlab=${2:?}; shift ;;
        --n) n=${2:?}; shift ;;
        --time) secs=${2:?}; shift ;;
        -*) usage ;;
        *) settings+=("$1") ;;
    esac
    shift
done
[ ${#settings[@]} -gt 0 ] || usage
command -v valgrind > /dev/null || { echo "anchors_profile.sh: needs valgrind (apt-get install valgrind)" >&2; exit 2; }
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT

# the parts of a step: LABEL|REGEX of the function (callgrind_annotate's names, arguments
# included) whose inclusive count is the part's
gaitlab_parts='whole step (Simulation::step)|^gaitlab::Simulation::step\(long\)
Bullet step|^btDiscreteDynamicsWorld::stepSimulation\(
collision|^btCollisionWorld::performDiscreteCollisionDetection\(\)
  box-plane pairs|^(btConvexPlaneCollisionAlgorithm|gaitlab::BoxPlaneAlgorithm)::processCollision\(
  bounding boxes|^btCollisionWorld::updateAabbs\(\)
  broadphase|^btDbvtBroadphase::calculateOverlappingPairs\(
solver|^gaitlab::CoulombSolver::solveGroup\(
  setup|^btSequentialImpulseConstraintSolver::solveGroupCacheFriendlySetup\(
    contacts|^gaitlab::CoulombSolver::convertContacts\(
    joints|^btSequentialImpulseConstraintSolver::convertJoints\(
  iterations|^btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyIterations\(
    joint and friction rows|^btSequentialImpulseConstraintSolver::resolveSingleConstraintRowGeneric(SIMD)?\(
    contact rows|^btSequentialImpulseConstraintSolver::resolveSingleConstraintRowLowerLimit(SIMD)?\(
    split impulse|^btSequentialImpulseConstraintSolver::resolveSplitPenetration(SIMD|Impulse)\(
  finish|^gaitlab::CoulombSolver::solveGroupCacheFriendlyFinish\(
integration|^btDiscreteDynamicsWorld::(predictUnconstraintMotion|integrateTransforms)\(
islands|^btDiscreteDynamicsWorld::calculateSimulationIslands\(\)'
# with solver = block_nncg, the iterations' own parts too (in "iterations" above)
block_parts='    of them: a sweep and the nncg step|^gaitlab::CoulombSolver::own_iteration\(
      the joints'"'"' block factored (first iteration)|^gaitlab::CoulombSolver::factor_block\(\)
      the joints'"'"' block solved (substitutions)|^gaitlab::CoulombSolver::solve_block\(\)
      friction disks|^gaitlab::CoulombSolver::solve_friction\(
      motor rows (outside the block; unnamed in Debian'"'"'s libbullet 3.24, the rows the sweep calls)|^0x000000000004aa00$
      contact rows (the same)|^0x000000000004a790$'
ode_parts='whole loop (main: gait, servo, collide, step; set-up included)|^main$
collision|^dSpaceCollide$
  box-plane pairs|^dCollideBoxPlane\(
  contact joints|^dJointCreateContact$
QuickStep|^dWorldQuickStep$
  islands|^dxProcessIslands\(
  solver (setup and SOR iterations)|^dxQuickStepIsland\(
    SOR row updates (unnamed in Debian'"'"'s libode 0.16.2: called once per row and iteration)|^0x0000000000071010$
  integration|^dxStepBody\(
contact joints freed|^dJointGroupEmpty$'

printf '| setting | part | instructions per step | share of the whole step | calls per step |\n|---|---|---|---|---|\n'
for s in "${settings[@]}"; do
    IFS=: read -r e conn dtms it solver extra <<< "$s"
    if [ -z "${it:-}" ] || [ -n "${extra:-}" ]; then
        echo "anchors_profile.sh: '$s' is not ENGINE:CONN:DT_MS:ITERS[:SOLVER]" >&2
        exit 2
    fi
    case "${solver:-}" in
        "" | pgs | block_nncg) ;;
        *) echo "anchors_profile.sh: '$s': the solver is pgs or block_nncg (got '$solver')" >&2; exit 2 ;;
    esac
    [ -z "${solver:-}" ] || [ "$e" = gaitlab ] || { echo "anchors_profile.sh: '$s': a solver is a setting of gaitlab only" >&2; exit 2; }
    dt=$(awk -v d="$dtms" 'BEGIN {printf "%.10g", d / 1000}')
    ce=$(awk -v d="$dtms" 'BEGIN {printf "%d", 10 / d + 0.5}')
    steps=$(awk -v t="$secs" -v d="$dtms" 'BEGIN {printf "%d", t * 1000 / d + 0.5}')
    out=$work/cg.$e.$conn.$dtms.$it${solver:+.$solver}
    case "$e" in
        gaitlab)
            cmd=("$gaitlab" run "$root/bench/lua/anchor_snake.lua" "n=$n" "conn=$conn" "dt=$dt"
                "iters=$it" "ce=$ce" "time=$secs" ${solver:+"solver=$solver"} --no-record)
            parts=$gaitlab_parts
            if [ "${solver:-}" = block_nncg ]; then
                # after the iterations' rows
                parts=$(EXTRA=$block_parts awk '{ print } /^    split impulse\|/ { print ENVIRON["EXTRA"] }' <<< "$gaitlab_parts")
            fi
            ;;
        ode)
            [ -x "$anchors/ode_snake" ] || { echo "anchors_profile.sh: no ode_snake in '$anchors' (--anchors DIR)" >&2; exit 2; }
            cmd=("$anchors/ode_snake" --n "$n" --conn "$conn" --dt "$dt" --iters "$it"
                --ctrl-every "$ce" --time "$secs")
            parts=$ode_parts
            ;;
        *) echo "anchors_profile.sh: unknown engine '$e' (gaitlab or ode)" >&2; exit 2 ;;
    esac
    valgrind --tool=callgrind --callgrind-out-file="$out" "${cmd[@]}" > /dev/null 2> "$out.log" ||
        { echo "anchors_profile.sh: $s failed under callgrind:" >&2; tail -5 "$out.log" >&2; exit 1; }
    callgrind_annotate --inclusive=yes --threshold=100 "$out" 2> /dev/null > "$out.txt"
    # calls of each function from its callers ("(123x)"), for the rows the solver solves
    callgrind_annotate --tree=caller --threshold=100 "$out" 2> /dev/null |
        awk '/^ *[0-9,]+ .* < / && match($0, /\([0-9,]+x\)/) { c = substr($0, RSTART + 1, RLENGTH - 3); gsub(",", "", c); calls += c; next }
             /^ *[0-9,]+ .* \* / { line = $0; sub(/^.*\* +[^:]*:/, "", line); sub(/ \[[^]]*\]$/, "", line); print calls "\t" line; calls = 0; next }
             { calls = 0 }' > "$out.calls"
    PARTS=$parts awk -v steps="$steps" -v setting="$e${solver:+ $solver} $conn, dt $dtms ms, $it it" -F '\t' '
        FILENAME ~ /calls$/ { ncalls[$2] = $1; next }
        BEGIN {
            np = split(ENVIRON["PARTS"], lines, "\n")
            for (i = 1; i <= np; ++i) { k = index(lines[i], "|"); label[i] = substr(lines[i], 1, k - 1); re[i] = substr(lines[i], k + 1) }
        }
        # "1,234,567 (12.34%)  file:function [object]"
        /^ *[0-9,]+ / {
            count = $1; gsub(",", "", count)
            line = $0
            sub(/^ *[0-9,]+ +(\([^)]*\) +)?/, "", line)
            sub(/ \[[^]]*\]$/, "", line)
            k = index(line, ":"); name = substr(line, k + 1)
            for (i = 1; i <= np; ++i) if (name ~ re[i]) { total[i] += count; if (name in ncalls) calls[i] += ncalls[name] }
        }
        END {
            whole = total[1]
            for (i = 1; i <= np; ++i)
                printf "| %s | %s | %.0f | %.1f %% | %s |\n", (i == 1 ? setting : ""), label[i], total[i] / steps, (whole > 0 ? 100 * total[i] / whole : 0), (label[i] ~ /rows|pairs|SOR|contact joints$/ && (i in calls)) ? sprintf("%.1f", calls[i] / steps) : ""
        }' "$out.calls" "$out.txt"
done
