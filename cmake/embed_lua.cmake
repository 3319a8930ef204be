# Writes a C++ header holding the Lua sources given in SOURCES (a ;-list of files) as string
# literals, so the gaitlab binary carries its stdlib. Run with cmake -P.
set(out "// generated from stdlib/*.lua by cmake/embed_lua.cmake: do not edit\n#pragma once\n\n")
string(APPEND out "namespace gaitlab::scripting {\n\nstruct StdlibSource {\n    const char* name;\n    const char* code;\n};\n\n")
string(APPEND out "inline const StdlibSource kStdlibSources[] = {\n")
foreach(file IN LISTS SOURCES)
    get_filename_component(name "${file}" NAME)
    file(READ "${file}" code)
    string(APPEND out "    {\"${name}\", R\"gaitlab_lua(${code})gaitlab_lua\"},\n")
endforeach()
string(APPEND out "    {nullptr, nullptr},\n};\n\n}  // namespace gaitlab::scripting\n")
file(WRITE "${OUTPUT}.tmp" "${out}")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
