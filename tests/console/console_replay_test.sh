#!/bin/sh
# gaitlab replay of runs recorded from the console: after the script, the replay steps the
# simulation on as the typed commands did (to each recorded change, a reset starting the ticks
# again, then to the run's last tick) and reproduces the session bit for bit; a changed event
# makes it differ.
#   console_replay_test.sh GAITLAB
set -eu
gaitlab=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
fail() {
    echo "FAIL: $1" >&2
    exit 1
}
cat > snake.lua <<'LUA'
local world = gaitlab.world{}
robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
world:add(robot)
ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{})
sim = gaitlab.simulation{ world = world }
sim:run(0.1)
LUA

# session N CHANGES LINES: the console runs LINES after snake.lua into runN; its replay is
# identical with CHANGES recorded changes applied
session() {
    printf "$3" | "$gaitlab" -i snake.lua --record "run$1" > /dev/null 2>&1 || fail "session $1"
    "$gaitlab" replay "run$1" > "replay$1.txt" 2>&1 || fail "replay of session $1: $(cat "replay$1.txt")"
    grep -q "replay identical: .* bit for bit; $2 recorded changes\? applied" "replay$1.txt" ||
        fail "replay of session $1: $(cat "replay$1.txt")"
}
# changes between runs, and after the last one
session 1 2 'sim:run(0.5)\nctl.phase = 90\nsim:step(70)\nctl.amplitude = 20\n'
# a reset, and the session ends before the tick of the reset
session 2 2 'sim:run(0.5)\nctl.phase = 90\nsim:reset()\nsim:run(0.2)\n'
# several resets, changes at tick 0
session 3 3 'sim:run(0.5)\nsim:reset()\nctl.phase = 30\nsim:reset()\nsim:run(0.1)\n'
grep -q '"status": *"finished"' run3/run.json || fail "run3 not finished"

# a change the run did not make: the replay differs and says where
cp -r run1 bad
sed 's/sine.phase,90,/sine.phase,45,/' run1/events.csv > bad/events.csv
if "$gaitlab" replay bad > bad.txt 2>&1; then fail "a changed event replayed identical"; fi
grep -q 'replay differs: first difference at t = 0\.6' bad.txt || fail "bad replay: $(cat bad.txt)"
echo "console replay tests passed"
