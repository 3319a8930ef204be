#!/bin/sh
# `gaitlab new` in a real terminal (tmux), driven as a person would drive it.
#   wizard_tmux.sh GAITLAB WORKDIR enter   answers a few questions, presses Enter for the rest,
#                                          and sees the robot move
#   wizard_tmux.sh GAITLAB WORKDIR ctrl-c  presses Ctrl-C at the third question and checks that
#                                          nothing was left behind
# Each run has its own tmux server (-L), polled with capture-pane, never slept on for long.
set -eu
gaitlab=$1
work=$2
mode=$3
sock="gaitlab-wizard-$$"
rm -rf "$work"
mkdir -p "$work"
cleanup() { tmux -L "$sock" kill-server 2>/dev/null || true; }
trap cleanup EXIT

tmux -L "$sock" -f /dev/null new-session -d -x 160 -y 50 -c "$work" \
    "env -u EDITOR '$gaitlab' new 2>&1; echo WIZARD-EXIT=\$?; sleep 60"

screen() { tmux -L "$sock" capture-pane -p -J -S - ; }

fail() {
    echo "FAILED: $1"
    echo "---- the terminal:"
    screen
    exit 1
}

# waits (up to 20 s) until the terminal shows text matching the regular expression $1
wait_for() {
    i=0
    until screen | grep -q -E "$1"; do
        i=$((i + 1))
        [ "$i" -lt 200 ] || fail "timed out waiting for '$1'"
        sleep 0.1
    done
}

# waits for the question matching $1 to be the last line, then types $2 and Enter
answer() {
    wait_for "$1"
    i=0
    until screen | grep -v '^$' | tail -n 1 | grep -q -E "$1"; do
        i=$((i + 1))
        [ "$i" -lt 200 ] || fail "'$1' is not the question asked"
        sleep 0.1
    done
    if [ -n "$2" ]; then tmux -L "$sock" send-keys -l "$2"; fi
    tmux -L "$sock" send-keys Enter
}

answer 'Robot name \[snake\]: ?$' 'worm'
answer 'Number of modules \[8\]: ?$' '6'

case "$mode" in
enter)
    # Enter for every other question, as each appears
    answered=2
    i=0
    while ! screen | grep -q 'WIZARD-EXIT='; do
        asked=$(screen | grep -c -E '\[[^]]*\]: ?' || true)
        last=$(screen | grep -v '^$' | tail -n 1)
        if [ "$asked" -gt "$answered" ] && echo "$last" | grep -q -E '\[[^]]*\]: ?$'; then
            tmux -L "$sock" send-keys Enter
            answered=$asked
        fi
        i=$((i + 1))
        [ "$i" -lt 400 ] || fail "the wizard did not finish"
        sleep 0.1
    done
    screen | grep -q 'WIZARD-EXIT=0' || fail "the wizard failed"
    distance=$(screen | sed -n 's/^worm: moved \([0-9.]*\) m.*/\1/p')
    [ -n "$distance" ] || fail "no distance printed"
    awk "BEGIN { exit !($distance > 0.05) }" || fail "the robot moved only $distance m"
    [ -f "$work/worm/simulation.xml" ] || fail "no project folder worm/"
    screen | grep -q 'The recording is in worm/runs/worm-' || fail "no recording"
    echo "the robot moved $distance m"
    ;;
ctrl-c)
    wait_for 'Connection \[pitch-pitch\]: ?$'
    tmux -L "$sock" send-keys C-c
    wait_for 'WIZARD-EXIT='
    screen | grep -q 'WIZARD-EXIT=130' || fail "exit status is not 130"
    screen | grep -q 'interrupted (SIGINT); nothing was written' || fail "no message"
    left=$(ls -A "$work")
    [ -z "$left" ] || fail "left behind: $left"
    echo "interrupted, nothing left"
    ;;
*)
    fail "unknown mode $mode"
    ;;
esac
