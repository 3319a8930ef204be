# Writes a C++ header holding Lua sources as string literals, so the gaitlab binary carries its
# stdlib and its ready-made worlds. Run with cmake -P and
#   SOURCES  a |-separated list of stdlib files (kStdlibSources)
#   WORLDS   a |-separated list of world files (kWorldSources)
#   OUTPUT   the header to write
string(REPLACE "|" ";" SOURCES "${SOURCES}")
string(REPLACE "|" ";" WORLDS "${WORLDS}")

# appends `array`, holding the files in `files`, to the variable out
function(append_array array files)
    string(APPEND out "inline const StdlibSource ${array}[] = {\n")
    foreach(file IN LISTS files)
        get_filename_component(name "${file}" NAME)
        file(READ "${file}" code)
        string(APPEND out "    {\"${name}\", R\"gaitlab_lua(${code})gaitlab_lua\"},\n")
    endforeach()
    string(APPEND out "    {nullptr, nullptr},\n};\n\n")
    set(out "${out}" PARENT_SCOPE)
endfunction()

set(out "// generated from stdlib/*.lua and worlds/*.lua by cmake/embed_lua.cmake: do not edit\n#pragma once\n\n")
string(APPEND out "namespace gaitlab::scripting {\n\nstruct StdlibSource {\n    const char* name;\n    const char* code;\n};\n\n")
append_array(kStdlibSources "${SOURCES}")
append_array(kWorldSources "${WORLDS}")
string(APPEND out "}  // namespace gaitlab::scripting\n")
file(WRITE "${OUTPUT}.tmp" "${out}")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
