#!/usr/bin/env bash
# interrupt_test.sh stop|catch WORK GAITLAB C_HOST LUA CPATH SCRIPT [VAR=value for lua5.4]
# Ctrl-C (SIGINT) in the middle of a long sim:run, sent once the script says "running":
#   gaitlab run and c_host (the C core) stop with "gaitlab: interrupted (SIGINT)", status 130,
#     whether or not the script catches errors (a host's interrupt holds until the end);
#   lua5.4 with the module stops the run with the error "interrupted (SIGINT)": uncaught, lua5.4
#     reports it (status 1); caught ("catch"), the script goes on, runs Lua code and
#     simulations again, and the debug hook it had set is its own again; its recording is
#     closed as "interrupted" (SIGINT) when the interrupt is raised, caught or not.
set -u
mode=$1 work=$2 gaitlab=$3 c_host=$4 lua=$5 cpath=$6 script=$7 lua_env=${8:-}
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

# run NAME CMD...: runs CMD, sends SIGINT once "running" is on its stderr, waits for it
run() {
    local name=$1
    shift
    "$@" >"$name.out" 2>"$name.err" &
    local pid=$! waited=0
    until grep -q running "$name.err" 2>/dev/null; do
        if ! kill -0 $pid 2>/dev/null || [ $waited -ge 1200 ]; then
            echo "FAIL: $name ended or never said running:" >&2
            cat "$name.err" >&2
            exit 1
        fi
        sleep 0.1
        waited=$((waited + 1))
    done
    sleep 0.2  # the script said it from inside sim:run
    kill -INT $pid
    # it must stop within a minute, not at the end of its 1e6 simulated seconds
    for _ in $(seq 600); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
    if kill -0 $pid 2>/dev/null; then
        kill -KILL $pid
        echo "FAIL: $name did not stop at SIGINT" >&2
        exit 1
    fi
    wait $pid
    echo $? >"$name.rc"
}

args=()
[ "$mode" = catch ] && args=(catch)
run gaitlab "$gaitlab" run --no-record "$script" "${args[@]}"
run c_host "$c_host" "$script" "${args[@]}"
env LUA_CPATH="$cpath" LUA_CPATH_5_4="$cpath" ${lua_env:+"$lua_env"} true  # the variable is valid
run lua env LUA_CPATH="$cpath" LUA_CPATH_5_4="$cpath" ${lua_env:+"$lua_env"} INTERRUPT_RECORD=rec \
    "$lua" -e "gaitlab = require 'gaitlab'" "$script" "${args[@]}"

status=0
check() {  # check WHAT CONDITION...
    local what=$1
    shift
    if ! "$@"; then
        echo "FAIL: $what" >&2
        status=1
    fi
}
for host in gaitlab c_host; do
    check "$host exits with 130: $(cat $host.rc)" [ "$(cat $host.rc)" = 130 ]
    check "$host says interrupted: $(cat $host.err)" \
        [ "$(cat $host.err)" = "$(printf 'running\ngaitlab: interrupted (SIGINT)')" ]
    check "$host prints nothing after the interrupt: $(cat $host.out)" [ ! -s $host.out ]
done
if [ "$mode" = stop ]; then
    check "lua5.4 exits with 1: $(cat lua.rc)" [ "$(cat lua.rc)" = 1 ]
    check "lua5.4 reports the interrupt: $(cat lua.err)" \
        grep -qE "^$lua: ([^ ]*interrupt.lua:[0-9]+: )?interrupted \(SIGINT\)$" lua.err
else
    check "lua5.4 exits with 0: $(cat lua.rc) $(cat lua.err)" [ "$(cat lua.rc)" = 0 ]
    check "lua5.4's script caught the interrupt: $(cat lua.out)" \
        grep -qE "^caught:	false	([^ ]*interrupt.lua:[0-9]+: )?interrupted \(SIGINT\)$" lua.out
    check "lua5.4's script runs again: $(cat lua.out)" grep -q "^runs again:	true$" lua.out
    check "lua5.4's script has its hook back: $(cat lua.out)" grep -q "^hook kept:	true$" lua.out
fi
# gaitlab raised the interrupt: the recording says so (not "finished"), caught or not
check "lua5.4's recording is closed as interrupted: $("$gaitlab" data rec 2>&1 | sed -n 2p)" \
    grep -q '"status": "interrupted"' rec/run.json
check "lua5.4's recording names the signal" grep -q '"message": "SIGINT"' rec/run.json
for f in *.out *.err; do echo "--- $f"; cat "$f"; done
exit $status
