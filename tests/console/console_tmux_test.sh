#!/bin/sh
# The console as a person uses it, through tmux (tmux_lib.sh: a private tmux server, keys sent,
# the screen read until the expected text appears or a timeout fails the test).
#   console_tmux_test.sh GAITLAB
set -eu
gaitlab=$1
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
cd "$tmp"
. "$here/tmux_lib.sh"

# --- an expression, =expr, an error and going on, multi-line input, completion
start console --no-record
line '6 * 7'
wait_for '^42$' "result of a bare expression"
line '= 2^10, "x"'
wait_for '^1024.0 +x$' "tab-separated results of =expr"
line 'error("boom")'
wait_for '^console:1: boom$' "error message"
wait_for 'stack traceback:' "traceback"
line 'for i = 1, 2 do'
wait_for '^>>( |$)' "continuation prompt"
line 'print("line", i)'
line 'end'
wait_for '^line +2$' "output of the multi-line chunk"
line 'robot = gaitlab.robot.chain{ name = "snake", modules = 4 }'
keys 'robot:gr' Tab
wait_for '^> robot:group\($' "completion of robot:gr"
line '"pitch")'
wait_for '^group of 4 joints: 1, 2, 3, 4$' "the group"
keys 'gaitlab.sim' Tab
wait_for '^> gaitlab.simulation$' "completion of gaitlab.sim"
# Ctrl-C at the prompt drops the typed text
keys C-c
wait_for '^> gaitlab.simulation\^C$' "the discarded line"
line '=robot'
wait_for "^robot 'snake': 4 y1 modules, pitch-pitch$" "the robot's description"
keys C-d
wait_exit 0

# --- history after a restart
start console --no-record
keys Up
wait_for '^> =robot$' "the last line of the previous session"
keys C-u
line '1 + 1'
wait_for '^2$' "a line after the history"

# --- Ctrl-C stops a long sim:run; the simulation goes on afterwards
line 'world = gaitlab.world{}'
line 'robot = gaitlab.robot.chain{ name = "snake", modules = 4 }'
line 'world:add(robot)'
line 'ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{})'
line 'sim = gaitlab.simulation{ world = world }'
line 'sim:run(1e6)'
sleep 0.5
keys C-c
wait_for 'interrupted \(SIGINT\)' "the interrupt"
line 't0 = sim.time; sim:run(0.5); print("advanced", sim.time - t0 > 0.49, ctl.failed)'
wait_for '^advanced +true +false$' "the simulation running on"
keys C-d
wait_exit 0

# --- a pasted line of 5000 characters, recalled and edited: the line editor's buffer grows
# (libedit's readline emulation wrote into its freed first buffer past about 1000 bytes, and a
# paste of 3100 characters aborted the console)
start console --no-record
awk 'BEGIN { printf "long = \""; for (i = 0; i < 5000; i++) printf "a"; printf "\"" }' > long.txt
tmux -L "$sock" load-buffer long.txt
tmux -L "$sock" paste-buffer
keys Enter
line '=#long'
wait_for '^5000$' "the length of the pasted string"
keys Up Up C-e BSpace BSpace
type_text 'b"'
keys Enter
line '=long:sub(-3), #long'
wait_for '^aab +5000$' "the recalled line, edited at its end"
keys C-d
wait_exit 0

# --- -i FILE.lua: its globals stay; a typed change is recorded with origin console; Ctrl-D
# closes the recording as finished
cat > walk.lua <<'EOF'
local world = gaitlab.world{}
robot = gaitlab.robot.chain{ name = "walker", modules = 4 }
world:add(robot)
ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{})
sim = gaitlab.simulation{ world = world }
sim:run(0.3)
EOF
start -i walk.lua --record run1
line 'ctl.phase = 90'
line 'sim:run(0.3)'
line '=sim.time'
wait_for '^0.6' "the time after the run"
keys C-d
wait_exit 0
grep -q '^300,0.3,console,param,sine.phase,90,' run1/events.csv || fail "event of origin console: $(cat run1/events.csv)"
grep -q '"status": *"finished"' run1/run.json || fail "run.json not finished: $(cat run1/run.json)"

# --- os.exit() typed at the console keeps the session's history (it skipped the save)
start console --no-record
line '=40 + 2'
wait_for '^42$' "a line before os.exit"
line 'os.exit(0)'
wait_exit 0
start console --no-record
keys Up
wait_for '^> =40 \+ 2$' "the line typed before os.exit, in the history"
keys C-u C-d
wait_exit 0

# --- SIGTERM at the prompt closes the recording as interrupted
start -i walk.lua --record run2
type_text 'ctl.phase' # something typed
pkill_target=$(tmux -L "$sock" list-panes -F '#{pane_pid}')
kill -TERM "$(pgrep -P "$pkill_target" gaitlab)"
wait_exit 143
grep -q '"status": *"interrupted"' run2/run.json || fail "run.json not interrupted: $(cat run2/run.json)"
echo "console tmux tests passed"
