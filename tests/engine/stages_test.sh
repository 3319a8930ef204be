#!/bin/sh
# Tests tools/check_stages.sh, the check that the engine's includes point down its stages, on
# the fixture trees of tests/engine/stages/: a tree that keeps the rule passes; a tree that
# breaks it in every way the checker knows is reported line by line (FILE:LINE: what is wrong),
# and nothing else is; the order of the stages file alone decides what is up; a broken stages
# file and a missing engine folder are reported, never passed.
# Usage: stages_test.sh CHECKER FIXTURES
set -u
checker=$1
fixtures=$2
failures=0

fail() {
    printf 'FAIL: %s\n' "$1"
    failures=$((failures + 1))
}
# check STATUS ARGS...: runs the checker on ARGS, keeps what it prints in $out and fails unless it
# exits with STATUS
check() {
    expected=$1
    shift
    out=$(sh "$checker" "$@" 2>&1)
    status=$?
    if [ "$status" -ne "$expected" ]; then
        fail "check_stages.sh $* exited $status, expected $expected; it printed:
$out"
    fi
}
# has TEXT: the last output holds a line with TEXT
has() {
    printf '%s\n' "$out" | grep -qF -- "$1" || fail "no line with '$1' in:
$out"
}
# lines N: the last output has N lines
lines() {
    n=$(printf '%s\n' "$out" | grep -c .)
    [ "$n" -eq "$1" ] || fail "$n lines where $1 were expected:
$out"
}

good=$fixtures/good
bad=$fixtures/bad

# includes down and within a stage, relative or not, quoted or <gaitlab/...>, and a stage's own
# libraries pass
check 0 "$good"
has "$good: 6 files in 2 stages (low < high), every include down or within its stage"
lines 1

# every way up is reported at its line, and nothing else is
check 1 "$bad"
up="of stage high, above it; stages, bottom to top: low < high ($bad/stages.txt)"
has "$bad/src/low/up.cpp:3: stage low includes \"high/b.h\" $up"
has "$bad/src/low/up.cpp:4: stage low includes \"gaitlab/high.h\" $up"
has "$bad/src/low/up.cpp:5: stage low includes <gaitlab/high.h> $up"
has "$bad/src/low/up.cpp:6: stage low includes \"../high/b.h\" $up"
has "$bad/include/gaitlab/low.h:2: stage low includes \"gaitlab/high.h\" $up"
has "$bad/src/high/b.cpp:3: includes <liblow/x.h>, which only stage low includes ($bad/stages.txt:4)"
has "$bad/src/high/b.cpp:7: includes \"nowhere.h\", which is neither in $bad/src/ nor a public header in $bad/include/"
has "$bad/src/high/b.cpp:8: an #include whose name is not closed: #include \"unclosed.h"
has "$bad/src/loose.cpp: not in a stage: engine sources go in src/STAGE/, STAGE one of low < high"
has "$bad/src/extra/e.cpp: folder src/extra/ is not a stage of $bad/stages.txt (low < high)"
has "$bad/include/gaitlab/stray.h: public header listed with no stage in $bad/stages.txt"
lines 11

# the stages file alone says what is up: the good tree with its stages the other way round
check 1 "$good" "$good/reversed.txt"
up="of stage low, above it; stages, bottom to top: high < low ($good/reversed.txt)"
has "$good/src/high/b.h:5: stage high includes \"low/a.h\" $up"
has "$good/src/high/b.cpp:5: stage high includes \"../low/a.h\" $up"
has "$good/src/high/b.cpp:7: stage high includes \"gaitlab/low.h\" $up"
has "$good/include/gaitlab/high.h:3: stage high includes \"gaitlab/low.h\" $up"
lines 4

# a broken stages file is reported at its lines
check 1 "$good" "$good/broken.txt"
has "$good/broken.txt:1: a line that starts with blanks goes on with the stage above it, but there is none"
has "$good/broken.txt:3: no public header $good/include/gaitlab/gone.h"
has "$good/broken.txt:4: stage \"low\" is named twice (first on line 2)"
has "$good/broken.txt:5: \"not-a-header\" is neither a public header (NAME.h in include/gaitlab/) nor a library (<PREFIX)"
has "$good/broken.txt:6: \"Bad\" is not a stage name"
lines 5

# a stages file that names no stage passes nothing
empty=$(mktemp)
printf '# nothing but a comment\n' >"$empty"
check 1 "$good" "$empty"
has "$empty: names no stage"
rm -f "$empty"

# what cannot be read is an error of its own (status 2), not a pass
check 2 "$fixtures/no_such_engine"
has "check_stages: $fixtures/no_such_engine/src: no such folder"
check 2 "$good" "$good/no_such_stages.txt"
has "check_stages: $good/no_such_stages.txt: cannot read the stages file"

if [ "$failures" -gt 0 ]; then
    echo "$failures check(s) failed"
    exit 1
fi
echo "check_stages.sh: every fixture gave what was expected"
