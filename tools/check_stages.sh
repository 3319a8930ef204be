#!/bin/sh
# Checks that the engine's includes point down its stages (docs/architecture.md): a file of a
# stage (engine/src/STAGE/..., or a public header engine/include/gaitlab/H.h listed with STAGE in
# the stages file) includes ("..." or <gaitlab/...>) only files of its own stage and of the
# stages listed before it, and a library listed with a stage (<bt, <tinyxml2.h> ...) is
# included by that stage only. Every engine source must sit in a stage's folder and every public
# header must be listed with a stage.
#
# Usage: tools/check_stages.sh [ENGINE_DIR [STAGES_FILE]]
#   ENGINE_DIR   the folder holding src/ and include/ (default: the engine/ beside tools/)
#   STAGES_FILE  the stages, bottom to top (default: ENGINE_DIR/stages.txt; its format is
#                described at its top)
# Prints one line per problem, "FILE:LINE: what is wrong", and exits 1 if there is any, 2 if
# the engine folder or the stages file cannot be read, 0 otherwise.
set -eu

engine=${1:-$(cd "$(dirname "$0")/.." && pwd)/engine}
stages=${2:-$engine/stages.txt}
engine=${engine%/}
if [ ! -d "$engine/src" ]; then
    echo "check_stages: $engine/src: no such folder (give the engine folder, which holds src/" \
        "and include/)" >&2
    exit 2
fi
if [ ! -f "$stages" ] || [ ! -r "$stages" ]; then
    echo "check_stages: $stages: cannot read the stages file" \
        "(the engine's stages, bottom to top)" >&2
    exit 2
fi

# every C++ file of the engine, relative to it
list=$(cd "$engine" && find src include -type f \( -name '*.h' -o -name '*.hpp' -o -name '*.cpp' \
    -o -name '*.cc' -o -name '*.inl' \) 2>/dev/null | LC_ALL=C sort)

printf '%s\n' "$list" | LC_ALL=C awk -v root="$engine" -v stages="$stages" '
function problem(where, what) {
    print where ": " what
    bad++
}
# `path` with "." and ".." resolved; "" if it climbs out of the engine folder
function normal(path,    n, parts, out, k, i) {
    n = split(path, parts, "/")
    k = 0
    for (i = 1; i <= n; i++) {
        if (parts[i] == "" || parts[i] == ".") continue
        if (parts[i] == "..") {
            if (k == 0) return ""
            k--
            continue
        }
        out[++k] = parts[i]
    }
    path = ""
    for (i = 1; i <= k; i++) path = path (i > 1 ? "/" : "") out[i]
    return path
}
function folder_of(path) {
    return sub(/\/[^\/]*$/, "", path) ? path : ""
}
# the stage of an engine file ("" if it has none)
function stage_of(path,    parts) {
    if (path ~ /^src\//) {
        split(path, parts, "/")
        return (parts[2] in rank && path ~ /^src\/[^\/]+\/./) ? parts[2] : ""
    }
    return (path in header_stage) ? header_stage[path] : ""
}
BEGIN {
    # the stages file: "STAGE HEADER.h ... <LIBRARY ...", bottom to top; a line that starts
    # with blanks goes on with the stage of the line before; "#" starts a comment
    n_stages = 0
    line_no = 0
    current = ""
    while ((status = (getline line < stages)) > 0) {
        line_no++
        sub(/#.*/, "", line)
        if (line !~ /[^ \t\r]/) continue
        # word[1] is the stage, or "" on a line that goes on with the stage above
        n = split(line, word, /[ \t\r]+/)
        where = stages ":" line_no
        if (word[1] == "") {
            if (current == "") {
                problem(where, "a line that starts with blanks goes on with the stage above it," \
                    " but there is none")
                continue
            }
        } else {
            current = word[1]
            if (current !~ /^[a-z][a-z0-9_]*$/) {
                problem(where, "\"" current "\" is not a stage name (lowercase letters, digits" \
                    " and _, as its folder in src/)")
                current = ""
                continue
            }
            if (current in rank) {
                problem(where, "stage \"" current "\" is named twice (first on line " \
                    stage_line[current] ")")
                current = ""
                continue
            }
            rank[current] = ++n_stages
            name[n_stages] = current
            stage_line[current] = line_no
        }
        for (i = 2; i <= n; i++) {
            w = word[i]
            if (w == "") continue
            if (w ~ /^</) {
                lib = substr(w, 2)
                if (lib == "") {
                    problem(where, "\"<\" names no library: write the start of its headers," \
                        " as <bt or <tinyxml2.h>")
                } else if (lib in lib_stage) {
                    problem(where, "library <" lib " is listed twice (first on line " \
                        lib_line[lib] ")")
                } else {
                    lib_stage[lib] = current
                    lib_line[lib] = line_no
                }
            } else if (w ~ /^[A-Za-z0-9_.\/-]+\.(h|hpp)$/ && w !~ /(^|\/)\.\.?(\/|$)/) {
                h = "include/gaitlab/" w
                if (h in header_stage) {
                    problem(where, "public header " w " is listed twice (first on line " \
                        header_line[h] ")")
                } else {
                    header_stage[h] = current
                    header_line[h] = line_no
                    headers[++n_headers] = h
                }
            } else {
                problem(where, "\"" w "\" is neither a public header (NAME.h in include/gaitlab/)" \
                    " nor a library (<PREFIX)")
            }
        }
    }
    if (status < 0) {
        print "check_stages: " stages ": cannot read the stages file" > "/dev/stderr"
        fatal = 1
        exit 2
    }
    close(stages)
    if (n_stages == 0) {
        problem(stages, "names no stage (one line per stage, bottom to top:" \
            " STAGE HEADER.h ... <LIBRARY ...)")
    }
    order = ""
    for (i = 1; i <= n_stages; i++) order = order (i > 1 ? " < " : "") name[i]
    rule = "stages, bottom to top: " order " (" stages ")"
}
# the list of files, one per line
$0 != "" { files[++n_files] = $0; exists[$0] = 1 }
END {
    if (fatal) exit 2
    if (n_stages == 0) exit 1
    for (i = 1; i <= n_headers; i++) {
        h = headers[i]
        if (!(h in exists)) problem(stages ":" header_line[h], "no public header " root "/" h)
    }
    for (f = 1; f <= n_files; f++) {
        path = files[f]
        where = root "/" path
        stage = stage_of(path)
        if (stage == "") {
            if (path ~ /^src\/[^\/]+\/./) {
                split(path, parts, "/")
                problem(where, "folder src/" parts[2] "/ is not a stage of " stages " (" order ")")
            } else if (path ~ /^src\//) {
                problem(where, "not in a stage: engine sources go in src/STAGE/, STAGE one of " \
                    order " (" stages ")")
            } else {
                problem(where, "public header listed with no stage in " stages)
            }
            continue
        }
        here = folder_of(path)
        line_no = 0
        while ((status = (getline line < (root "/" path))) > 0) {
            line_no++
            if (line !~ /^[ \t]*#[ \t]*include[ \t]*[<"]/) continue
            text = line
            sub(/^[ \t]*#[ \t]*include[ \t]*/, "", text)
            quote = substr(text, 1, 1)
            close_mark = quote == "<" ? ">" : "\""
            end = index(substr(text, 2), close_mark)
            if (end == 0) {
                problem(where ":" line_no, "an #include whose name is not closed: " line)
                continue
            }
            inc = substr(text, 2, end - 1)
            shown = quote inc close_mark
            target = ""
            if (quote == "\"") {
                # as the compiler looks: next to the file, then the include folders
                candidate = normal((here == "" ? "" : here "/") inc)
                if (!(candidate != "" && candidate in exists)) candidate = normal("src/" inc)
                if (!(candidate != "" && candidate in exists)) candidate = normal("include/" inc)
                if (!(candidate != "" && candidate in exists)) {
                    problem(where ":" line_no, "includes " shown ", which is neither in " root \
                        "/src/ nor a public header in " root "/include/")
                    continue
                }
                target = candidate
            } else {
                candidate = normal("include/" inc)
                if (inc ~ /^gaitlab\// && candidate in exists) {
                    target = candidate
                } else {
                    for (lib in lib_stage) {
                        if (substr(inc, 1, length(lib)) == lib && lib_stage[lib] != stage) {
                            problem(where ":" line_no, "includes " shown ", which only stage " \
                                lib_stage[lib] " includes (" stages ":" lib_line[lib] ")")
                        }
                    }
                    continue
                }
            }
            other = stage_of(target)
            if (other != "" && rank[other] > rank[stage]) {
                problem(where ":" line_no, "stage " stage " includes " shown " of stage " other \
                    ", above it; " rule)
            }
        }
        if (status < 0) problem(where, "cannot read it")
        close(root "/" path)
    }
    if (bad) exit 1
    print root ": " n_files " files in " n_stages " stages (" order ")," \
        " every include down or within its stage"
}
'
