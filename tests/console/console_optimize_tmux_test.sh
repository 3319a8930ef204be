#!/bin/sh
# gaitlab.optimize{...} typed at the console, through tmux (tmux_lib.sh): a progress line while
# it runs, Ctrl-C stops it at once and the console goes on with its globals, resume = true
# continues the interrupted run, and a run to its end returns the best.
#   console_optimize_tmux_test.sh GAITLAB
set -eu
gaitlab=$1
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
cd "$tmp"
. "$here/tmux_lib.sh"

# tests/cli's small spec (a 3-module snake, GA, 5 + 3 + 3 evaluations of half a second) for the
# run to its end, and the same with long evaluations and many generations for the one Ctrl-C
# stops
cp "$here/../cli/scripts/optimize_small.lua" small.lua
sed -e 's/duration = 0.5/duration = 5/' -e 's/generations = 3/generations = 200/' small.lua > long.lua

start console --no-record
line 'x = 42'
line 'r = gaitlab.optimize{ spec = "long.lua", out = "long", workers = 2 }'
# on a terminal, the progress line (rewritten after each evaluation)
wait_for 'generation [0-9]+/200: [0-9]+/[0-9]+ evaluated, best ' "the progress line" 60
t0=$(now)
keys C-c
wait_for 'optimization interrupted: the evaluations so far are in long \(go on with gaitlab.optimize\{ \.\.\., out = "long", resume = true \}\)' "where the evaluations went"
wait_for 'interrupted \(SIGINT\)' "the interrupt"
wait_for '^>( |$)' "the prompt again"
t1=$(now)
check "$t1 - $t0 < 5" "Ctrl-C stopped the optimization at once"
# the console goes on, its globals as they were
line 'print("alive", x, r)'
wait_for '^alive +42 +nil$' "the console going on"
[ -f long/state.json ] || fail "no long/state.json to resume from"
[ ! -f long/best.json ] || fail "an interrupted run wrote best.json"
# resume = true goes on from it (stopped again: it is long)
line 'r = gaitlab.optimize{ spec = "long.lua", out = "long", workers = 2, resume = true }'
wait_for 'generation [0-9]+/200: [0-9]+/[0-9]+ evaluated' "the progress line of the resumed run" 60
keys C-c
wait_for '^>( |$)' "the prompt after the second Ctrl-C"
# a run to its end: the best, and the progress line gone
line 'r = gaitlab.optimize{ spec = "small.lua", out = "small" }'
line 'print("best", r.evaluations, r.method, r.fitness > 0)'
wait_for '^best +11 +ga +true$' "the result of a run to its end" 60
screen | grep -q 'generation 3/3: 3/3 evaluated' && fail "the progress line stayed after the end"
keys C-d
wait_exit 0
echo "console optimize tmux tests passed"
