#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (build-fuzz/, ASan + UBSan) and runs each for SECONDS
# (default 60): the XML reader fuzzer (robot, actuation, environment and simulation files, and
# URDF) from a corpus of gaitlab's own files, then the Lua API
# fuzzer (tests/fuzz/lua_fuzz.cpp) from its seed corpus, the examples and the inputs that once
# crashed it. Exits non-zero on the first crash, leak, sanitizer report or timeout, leaving the
# input that caused it in build-fuzz/ (crash-*, leak-*, timeout-*, oom-*).
# Usage: tools/fuzz.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
"$root/tools/setup.sh" fuzz
build="$root/build-fuzz"
# -O1 and line tables only (libFuzzer's own advice is -O1 -g): a shorter build, and the
# sanitizers' reports need no more than file and line
if [ ! -f "$build/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DGAITLAB_FUZZ=ON \
        -DGAITLAB_BUILD_TESTS=OFF -DGAITLAB_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" --target xml_fuzz lua_fuzz --parallel "$(nproc)"

# the seed corpus: every XML file of the repository, behind the byte that picks its reader
corpus="$build/corpus"
mkdir -p "$corpus"
n=0
while IFS= read -r -d '' f; do
    kind=""
    grep -q '<robot' "$f" && kind='\x00'
    grep -q '<actuation' "$f" && kind='\x01'
    grep -q '<environment' "$f" && kind='\x02'
    grep -q '<simulation' "$f" && kind='\x03'
    [ -n "$kind" ] || continue
    { printf "$kind"; cat "$f"; } > "$corpus/seed-$n"
    n=$((n + 1))
done < <(find "$root/examples" "$root/tests" "$root/worlds" -name '*.xml' -print0 2>/dev/null)
# and the URDF files (their root element is <robot> too, so they go by their extension)
while IFS= read -r -d '' f; do
    { printf '\x04'; cat "$f"; } > "$corpus/seed-$n"
    n=$((n + 1))
done < <(find "$root/examples" "$root/tests" -name '*.urdf' -print0 2>/dev/null)

cd "$build"
./tests/fuzz/xml_fuzz -max_total_time="$seconds" -max_len=4096 -timeout=10 \
    -print_final_stats=1 "$corpus" 2>&1 | tail -n 15

# the Lua fuzzer's working corpus: the hand-written seeds, the examples and the regressions
# (scripts start with "--": they run as they are), plus what earlier runs found. Each script
# runs in a folder of its own under the temporary folder and becomes its current directory:
# the paths given to libFuzzer must be absolute.
lua_corpus="$build/corpus-lua"
mkdir -p "$lua_corpus"
for f in "$root"/tests/fuzz/corpus/lua/*; do cp "$f" "$lua_corpus/seed-${f##*/}"; done
for f in "$root"/examples/*.lua; do cp "$f" "$lua_corpus/example-${f##*/}"; done
for f in "$root"/tests/fuzz/regressions/lua/*; do
    [ "${f##*.}" = md ] || cp "$f" "$lua_corpus/regression-${f##*/}"
done
# a script is interrupted after 2 s of wall time (the harness's watchdog): -timeout catches C
# code that never returns; stdout is closed (scripts may io.write). Undefined behaviour stops
# the run like a crash, and so do leaks (tests/fuzz/lsan.supp may hide a known one while it is
# being fixed).
UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}" \
LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
./tests/fuzz/lua_fuzz -max_total_time="$seconds" -max_len=4096 -timeout=25 -close_fd_mask=1 \
    -dict="$root/tests/fuzz/lua.dict" -artifact_prefix="$build/" -print_final_stats=1 \
    "$lua_corpus" 2>&1 | tail -n 15
