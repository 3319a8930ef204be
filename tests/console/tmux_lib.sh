# Helpers of the console's tmux tests, sourced by them: gaitlab runs in a tmux pane of a private
# tmux server (a user's tmux is never touched), keys are sent to it and the screen is read until
# the expected text appears (or a timeout fails the test).
# The sourcing test sets $gaitlab and $tmp (a fresh folder, the current directory) first.

session=0
sock="gaitlab-tmux-test-$$-0"
cleanup() {
    tmux -L "$sock" kill-server 2>/dev/null || true
    rm -rf "$tmp"
}
trap cleanup EXIT
export XDG_STATE_HOME="$tmp/state"

# screen: the whole pane, scrollback included, wrapped lines joined
screen() { tmux -L "$sock" capture-pane -p -J -S - 2>/dev/null; }

fail() {
    echo "FAIL: $1" >&2
    echo "--- screen ---" >&2
    screen >&2 || cat "$tmp/screen" >&2 2>/dev/null || true
    exit 1
}

# start [ARGS...]: gaitlab in a fresh 120x40 pane; its exit status goes to $tmp/status
start() {
    rm -f "$tmp/status"
    tmux -L "$sock" kill-server 2>/dev/null || true
    session=$((session + 1))
    sock="gaitlab-tmux-test-$$-$session"
    tmux -L "$sock" new-session -d -x 120 -y 40 \
        "$gaitlab $* ; echo \$? > $tmp/status; tmux -L $sock capture-pane -p -S - > $tmp/screen; sleep 30"
    wait_for '^>( |$)' "the prompt"
}

# wait_for REGEX WHAT [SECONDS]: polls the screen until a line matches
wait_for() {
    n=0
    limit=$(( ${3:-10} * 20 ))
    while ! screen | grep -Eq -- "$1"; do
        n=$((n + 1))
        [ "$n" -lt "$limit" ] || fail "no $2 (waited for /$1/)"
        sleep 0.05
    done
}

# wait_exit STATUS: the program ended with this status
wait_exit() {
    n=0
    while [ ! -s "$tmp/status" ]; do
        n=$((n + 1))
        [ "$n" -lt 200 ] || fail "gaitlab did not exit"
        sleep 0.05
    done
    [ "$(cat "$tmp/status")" = "$1" ] || fail "exit status $(cat "$tmp/status"), expected $1"
}

keys() { tmux -L "$sock" send-keys "$@"; }
# type TEXT: types TEXT literally (tmux would take "end" for the End key), no Enter
type_text() { tmux -L "$sock" send-keys -l -- "$1"; }
# line TEXT: types TEXT, then Enter
line() {
    type_text "$1"
    keys Enter
}

# value MARK: the last word after "MARK" on a line of the screen that starts with MARK
# (print("MARK", x) shows "MARK<spaces>x")
value() {
    screen | sed -n "s/^$1[[:space:]]\{1,\}\([^[:space:]]*\).*/\1/p" | tail -n 1
}

# ask MARK EXPR: prints EXPR at the console as "MARK value", waits for it and echoes the value
ask() {
    line "print(\"$1\", $2)"
    wait_for "^$1[[:space:]]" "the value of $2"
    value "$1"
}

# now: wall seconds
now() { date +%s.%N; }
# check CONDITION WHAT: an awk condition on numbers (check "$a > 2 * $b" "...")
check() { awk "BEGIN { exit !($1) }" || fail "$2 ($1)"; }

# last_line: the last line of the pane that is not empty (wrapped rows joined)
last_line() { tmux -L "$sock" capture-pane -p -J | grep -v '^[[:space:]]*$' | tail -n 1; }
