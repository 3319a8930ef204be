#!/bin/sh
# A simulation that plays while a person types at the console (sim:play()), driven through tmux:
# typing slowly while it plays, changing a parameter (recorded, and replayed bit for bit), its
# pace (sim.speed, sim.delay, sim:pause(), Ctrl-C), a controller failing while a line is being
# typed, a controller file saved while it plays, sim:status().
#   console_play_tmux_test.sh GAITLAB
set -eu
gaitlab=$1
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
cd "$tmp"
. "$here/tmux_lib.sh"

cat > snake.lua <<'LUA'
local world = gaitlab.world{}
robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
world:add(robot)
ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{})
sim = gaitlab.simulation{ world = world }
LUA

# --- typing slowly while it plays: the line arrives whole and runs; simulated time follows the
# wall clock while the prompt waits; a parameter typed while it plays is recorded; Ctrl-D
# closes the run as finished
start -i snake.lua --record run1
line 'sim:play()'
t1=$(ask T1 sim.time)
w1=$(now)
type_text 'print("T2", sim.ti'
sleep 0.3
type_text 'me, "typed'
sleep 0.3
type_text ' slowly")'
wait_for '^> print\("T2", sim.time, "typed slowly"\)$' "the typed line, intact"
keys Enter
wait_for '^T2 +[0-9.]+ +typed slowly$' "the slowly typed line's output"
w2=$(now)
t2=$(value T2)
# at speed 1, simulated time is wall time (a loaded machine may lag: a wide margin)
check "$t2 - $t1 > 0.3 * ($w2 - $w1) && $t2 - $t1 < ($w2 - $w1) + 0.3" \
    "simulated time $t1 -> $t2 in $w1 -> $w2 s of wall time"
line 'ctl.phase = 90'
t3=$(ask T3 sim.time)
check "$t3 > $t2" "time goes on after the change"
keys C-d
wait_exit 0
grep -Eq '^[0-9]+,[0-9.]+,console,param,sine.phase,90,' run1/events.csv ||
    fail "no console event: $(cat run1/events.csv)"
awk -F, '$3 == "console" && $5 == "sine.phase" { found = 1; if (!($2 > 0)) exit 1 }
         END { exit !found }' run1/events.csv || fail "the change at t = 0: $(cat run1/events.csv)"
grep -q '"status": *"finished"' run1/run.json || fail "run.json not finished: $(cat run1/run.json)"
# the replay steps on after the script as the console did, the change applying at its tick
"$gaitlab" replay run1 > replay1.txt 2>&1 || fail "replay of run1: $(cat replay1.txt)"
grep -q 'replay identical: .* bit for bit; 1 recorded change applied' replay1.txt ||
    fail "replay of run1: $(cat replay1.txt)"

# --- pace: as fast as possible, slowed by a delay, paused; Ctrl-C at the prompt pauses
start -i snake.lua --no-record
line 'sim.speed = math.huge; sim:play()'
a=$(ask F1 sim.time)
wa=$(now)
sleep 0.5
b=$(ask F2 sim.time)
wb=$(now)
check "$b - $a > 2 * ($wb - $wa)" "math.huge plays faster than real time: $a -> $b in $wa -> $wb"
line 'sim.speed = 1; sim.delay = 0.01'
a=$(ask D1 sim.time)
wa=$(now)
sleep 0.5
b=$(ask D2 sim.time)
wb=$(now)
check "$b - $a > 0 && $b - $a < 0.4 * ($wb - $wa)" \
    "sim.delay = 0.01 plays slower than real time: $a -> $b in $wa -> $wb"
line 'sim.delay = 0; sim:pause()'
a=$(ask P1 sim.time)
sleep 0.3
b=$(ask P2 sim.time)
check "$a == $b" "a paused simulation keeps its time: $a -> $b"
line 'sim:play()'
sleep 0.2
keys C-c
wait_for '^paused 1 simulation' "the message of Ctrl-C pausing"
a=$(ask C1 sim.time)
sleep 0.3
b=$(ask C2 "sim.time, sim.playing")
check "$a == $b" "Ctrl-C paused the simulation: $a -> $b"
wait_for '^C2 +[0-9.]+ +false$' "sim.playing false after Ctrl-C"
# sim:status() while it plays: its time goes up
line 'sim:play()'
sleep 0.2
line 'sim:status()'
wait_for '^simulation 1: t = [0-9.]+ s, playing' "the status"
s1=$(screen | sed -n 's/^simulation 1: t = \([0-9.]*\) s, playing.*/\1/p' | tail -n 1)
sleep 0.3
line 'sim:status()'
n=0
while :; do
    s2=$(screen | sed -n 's/^simulation 1: t = \([0-9.]*\) s, playing.*/\1/p' | tail -n 1)
    [ "$s2" = "$s1" ] || break
    n=$((n + 1))
    [ "$n" -lt 100 ] || fail "sim:status() shows the same time $s1"
    sleep 0.05
done
check "$s2 > $s1" "the status time goes up: $s1 -> $s2"
keys C-d
wait_exit 0

# --- a controller that fails while it plays: its error comes on a line of its own above the
# prompt, the line being typed is drawn again below it and still runs; the simulation pauses
cat > failing.lua <<'LUA'
return gaitlab.controller{
  name = "failing",
  params = { after = { 1, min = 0, max = 100, unit = "s" } },
  step = function(self, dt)
    self.t = (self.t or 0) + dt
    if self.t > self.after then error("gave up after " .. self.after .. " s") end
  end,
}
LUA
cat > fails.lua <<'LUA'
local world = gaitlab.world{}
robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
world:add(robot)
Failing = gaitlab.controller.load("failing.lua")
ctl = robot:group("pitch"):drive(Failing{})
sim = gaitlab.simulation{ world = world }
LUA
start -i fails.lua --no-record
line 'sim:play()'
# longer than the pane is wide: the typed text takes two rows
long=$(printf 'x%.0s' $(seq 130))
typed="print(\"still\", #\"$long\" +"
type_text "$typed"
wait_for 'failing.lua:6: gave up after 1' "the controller's error" 5
wait_for '^gaitlab: simulation 1 paused at t = (0.9|1\.)' "the pause"
[ "$(last_line)" = "> $typed" ] || fail "the typed text is not on the last line: '$(last_line)'"
# the error starts a line of its own, and nothing of the typed text stays above it
[ "$(screen | grep -c 'print("still"')" = 1 ] || fail "the typed text is on the screen twice"
type_text ' 1)'
keys Enter
wait_for '^still +131$' "the typed line running"
line 'print("P", sim.playing, ctl.failed)'
wait_for '^P +false +true$' "the paused simulation and failed controller"
keys C-d
wait_exit 0

# --- a controller file saved while it plays reloads and acts without a restart
cat > hot.lua <<'LUA'
return gaitlab.controller{
  name = "hot",
  params = { a = { 1, min = 0, max = 10 } },
  step = function(self, dt) end,
}
LUA
cat > hots.lua <<'LUA'
local world = gaitlab.world{}
robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
world:add(robot)
Hot = gaitlab.controller.load("hot.lua")
ctl = robot:group("pitch"):drive(Hot{})
sim = gaitlab.simulation{ world = world }
LUA
start -i hots.lua --record run2
line 'sim:play()'
v0=$(ask V Hot.version)
line 'print("B", pcall(function() return ctl.b end))'
wait_for '^B +false' "no parameter b in the first version"
sleep 0.1
cat > hot.lua.new <<'LUA'
return gaitlab.controller{
  name = "hot",
  params = { a = { 1, min = 0, max = 10 }, b = { 7, min = 0, max = 10 } },
  on_reload = function(self, snap) print("now version two") end,
  step = function(self, dt) end,
}
LUA
mv hot.lua.new hot.lua
wait_for '^now version two$' "the new version's message" 5
line 'print("W", Hot.version, ctl.b, sim.playing)'
wait_for "^W +$((v0 + 1)) +7(\.0)? +true$" "the new parameter's default, the simulation still playing"
keys C-d
wait_exit 0
grep -Eq '^[0-9]+,[0-9.]+,file,reload,' run2/events.csv || fail "no reload event: $(cat run2/events.csv)"
# the replay runs the saved version from the recorded tick
"$gaitlab" replay run2 > replay2.txt 2>&1 || fail "replay of run2: $(cat replay2.txt)"
grep -q 'replay identical: .* bit for bit; 1 recorded change applied' replay2.txt ||
    fail "replay of run2: $(cat replay2.txt)"

echo "console play tmux tests passed"
