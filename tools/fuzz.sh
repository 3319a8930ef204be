#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (build-fuzz/, ASan + UBSan) and runs the XML reader
# fuzzer for SECONDS (default 60) from a corpus of gaitlab's own files. Exits non-zero on the
# first crash, leak or sanitizer report, leaving the input that caused it in build-fuzz/.
# Usage: tools/fuzz.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
"$root/tools/setup.sh" fuzz
build="$root/build-fuzz"
if [ ! -f "$build/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DGAITLAB_FUZZ=ON -DGAITLAB_BUILD_TESTS=OFF -DGAITLAB_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" --target xml_fuzz --parallel "$(nproc)"

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

cd "$build"
./tests/fuzz/xml_fuzz -max_total_time="$seconds" -max_len=4096 -timeout=10 \
    -print_final_stats=1 "$corpus" 2>&1 | tail -n 15
