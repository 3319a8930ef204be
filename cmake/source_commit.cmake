# Writes OUTPUT, a .cpp defining gaitlab::source_commit(): `git describe --always --dirty` of
# SOURCE_DIR, or "unknown" when SOURCE_DIR is not the top of a git work tree (a release tarball
# unpacked inside some other repository does not take that repository's commit). Run at every
# build (engine/CMakeLists.txt); configure_file rewrites OUTPUT only when the text changes, so a
# new commit recompiles this one file and nothing else.
set(commit "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
    execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" rev-parse --show-toplevel
        OUTPUT_VARIABLE top RESULT_VARIABLE rc ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(rc EQUAL 0)
        file(REAL_PATH "${top}" top)
        file(REAL_PATH "${SOURCE_DIR}" source)
    endif()
    if(rc EQUAL 0 AND top STREQUAL source)
        execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" describe --always --dirty
            OUTPUT_VARIABLE described RESULT_VARIABLE rc ERROR_QUIET
            OUTPUT_STRIP_TRAILING_WHITESPACE)
        if(rc EQUAL 0 AND NOT described STREQUAL "")
            set(commit "${described}")
        endif()
    endif()
endif()
# a tag may hold any byte a C string must escape
string(REPLACE "\\" "\\\\" commit "${commit}")
string(REPLACE "\"" "\\\"" commit "${commit}")
configure_file("${CMAKE_CURRENT_LIST_DIR}/source_commit.cpp.in" "${OUTPUT}" @ONLY)
