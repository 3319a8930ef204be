# cmake -DSTEP=... -DSOURCE=<source tree> -DGAITLAB=<gaitlab> -DC_HOST=<c_host> -DLUA=<lua5.4>
#       -DCPATH=<build>/lua/?.so -DENTRY=<gaitlab.so> -DCORE=<gaitlab/core.so> -DLUA_ENV=<VAR=value
#       for lua5.4, or ""> -DOTHER_LUAS=lua5.3,... -DWORK=<scratch> [-DSCRIPT=...] -P module_test.cmake
# The steps of the "lua_module:" and "lua_fuzz_replay_c:" tests (tests/lua_module/CMakeLists.txt).
cmake_minimum_required(VERSION 3.21)

# runs a command in `dir`; sets <prefix>_rc, <prefix>_out, <prefix>_err
function(capture prefix dir)
    execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${dir} TIMEOUT 240
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    set(${prefix}_rc "${rc}" PARENT_SCOPE)
    set(${prefix}_out "${out}" PARENT_SCOPE)
    set(${prefix}_err "${err}" PARENT_SCOPE)
endfunction()

# the command that runs lua5.4 (or another interpreter) with the module on its C path
function(interpreter var lua)
    set(env LUA_CPATH=${CPATH} LUA_CPATH_5_4=${CPATH} LUA_CPATH_5_3=${CPATH} LUA_PATH=
            LUA_PATH_5_4= LUA_PATH_5_3= LUA_INIT= LUA_INIT_5_4= LUA_INIT_5_3=)
    if(LUA_ENV)
        list(APPEND env "${LUA_ENV}")
    endif()
    set(${var} ${CMAKE_COMMAND} -E env ${env} ${lua} PARENT_SCOPE)
endfunction()

function(fail message)
    message(FATAL_ERROR "${message}")
endfunction()

# what `gaitlab run` printed (prefix g) and what lua5.4 printed (prefix m) must be the same:
# the output, the reports, and the error, which lua5.4 prints as "lua5.4: MESSAGE" and a
# traceback where gaitlab prints "gaitlab: MESSAGE"
function(same_as_gaitlab what)
    if(NOT m_out STREQUAL g_out)
        fail("${what} printed other output than gaitlab run:\n--- gaitlab run\n${g_out}\n--- ${what}\n${m_out}")
    endif()
    if(NOT m_rc STREQUAL g_rc)
        fail("${what} exited with ${m_rc}, gaitlab run with ${g_rc}:\n${m_err}")
    endif()
    # lua5.4's tracebacks end in the frame of lua.c that ran the script
    string(REPLACE "\n\t[C]: in ?" "" m_err "${m_err}")
    set(expected "${m_err}")
    set(name ${LUA})  # lua.c names itself as it was run
    string(FIND "${m_err}" "${name}: " at REVERSE)
    if(at GREATER -1)
        string(SUBSTRING "${m_err}" 0 ${at} reports)
        string(LENGTH "${name}: " skip)
        math(EXPR from "${at} + ${skip}")
        string(SUBSTRING "${m_err}" ${from} -1 message)
        string(FIND "${message}" "\nstack traceback:" cut)
        if(cut GREATER -1)
            string(SUBSTRING "${message}" 0 ${cut} message)
        else()
            string(REGEX REPLACE "\n$" "" message "${message}")
        endif()
        set(expected "${reports}gaitlab: ${message}\n")
    endif()
    if(NOT expected STREQUAL g_err)
        fail("${what}'s messages are not gaitlab run's:\n--- gaitlab run\n${g_err}\n--- ${what}\n${m_err}")
    endif()
endfunction()

if(STEP STREQUAL "elf")
    # no Lua library: the interpreter's core runs gaitlab, never a second one
    foreach(file ${ENTRY} ${CORE})
        capture(elf ${SOURCE} readelf -d ${file})
        if(NOT elf_rc EQUAL 0 OR NOT elf_out MATCHES "NEEDED")
            fail("readelf -d ${file} failed:\n${elf_err}")
        endif()
        if(elf_out MATCHES "NEEDED[^\n]*lua")
            fail("${file} needs a Lua library:\n${elf_out}")
        endif()
    endforeach()
    # the entry uses nothing of Lua's but luaL_error (every Lua has it, unchanged since 5.1)
    capture(sym ${SOURCE} nm -D --undefined-only ${ENTRY})
    string(REGEX MATCHALL "[ \n]U lua[A-Za-z_0-9]*" used "${sym_out}")
    if(NOT used MATCHES "^[ \n]U luaL_error$")
        fail("gaitlab.so uses more of Lua than luaL_error:\n${sym_out}")
    endif()
    # core.so takes the Lua API from the interpreter, defines none of it, and exports only its
    # luaopen (gaitlab's C++ symbols stay inside)
    capture(sym ${SOURCE} nm -D --defined-only ${CORE})
    if(sym_out MATCHES " lua_" OR sym_out MATCHES " luaL_")
        fail("core.so defines Lua API functions (a Lua core of its own?):\n${sym_out}")
    endif()
    string(REGEX MATCHALL "[^\n ]*gaitlab[^\n ]*" exported "${sym_out}")
    if(NOT exported STREQUAL "luaopen_gaitlab_core")
        fail("core.so exports more than luaopen_gaitlab_core: ${exported}")
    endif()
    capture(sym ${SOURCE} nm -D --undefined-only ${CORE})
    if(NOT sym_out MATCHES " U lua_newuserdatauv\n")
        fail("core.so does not take lua_newuserdatauv from the interpreter:\n${sym_out}")
    endif()
    message(STATUS "no liblua in DT_NEEDED; the entry uses luaL_error only")
elseif(STEP STREQUAL "first_snake")
    interpreter(lua ${LUA})
    capture(m ${SOURCE} ${lua} -e "gaitlab = require 'gaitlab'" examples/first_snake.lua)
    capture(g ${SOURCE} ${GAITLAB} run --no-record examples/first_snake.lua)
    if(NOT m_rc EQUAL 0 OR NOT m_out MATCHES "^moved ([0-9.]+) m \\(x -?[0-9.]+, y -?[0-9.]+\\)\n$")
        fail("lua5.4 with the module did not run examples/first_snake.lua (${m_rc}):\n${m_out}\n${m_err}")
    endif()
    if(CMAKE_MATCH_1 LESS_EQUAL 0.1)
        fail("the snake moved ${CMAKE_MATCH_1} m in lua5.4, expected more than 0.1 m")
    endif()
    same_as_gaitlab("lua5.4")
    message(STATUS "lua5.4 and gaitlab run: ${m_out}")
elseif(STEP STREQUAL "same_physics")
    set(script ${SOURCE}/tests/lua_module/scripts/trajectory.lua)
    interpreter(lua ${LUA})
    capture(m ${SOURCE} ${lua} -e "gaitlab = require 'gaitlab'" ${script})
    capture(g ${SOURCE} ${GAITLAB} run --no-record ${script})
    capture(c ${SOURCE} ${C_HOST} ${script})
    if(NOT g_rc EQUAL 0 OR NOT g_out MATCHES "moved 0x")
        fail("gaitlab run failed (${g_rc}):\n${g_out}\n${g_err}")
    endif()
    foreach(other m c)
        if(NOT ${other}_out STREQUAL g_out OR NOT ${other}_rc EQUAL 0)
            fail("not the same run to the last bit (${other}):\n--- gaitlab run\n${g_out}\n--- ${other} (${${other}_rc})\n${${other}_out}\n${${other}_err}")
        endif()
    endforeach()
    message(STATUS "the same to the last bit:\n${g_out}")
elseif(STEP STREQUAL "defaults")
    file(REMOVE_RECURSE ${WORK})
    file(COPY ${SOURCE}/tests/lua_module/scripts/defaults.lua DESTINATION ${WORK})
    interpreter(lua ${LUA})
    capture(m ${WORK} ${lua} defaults.lua)
    string(JOIN "\n" expected
        "version\tstring"
        "no global\ttrue"
        "same table\ttrue"
        "opened again: same table\ttrue"
        "print and os.exit are the interpreter's\ttrue\ttrue"
        "guarded: xpcall, coroutine.resume, string.find\ttrue\ttrue\ttrue"
        "string.find still finds\t5\t7"
        "pairs and table.sort are the interpreter's\ttrue\ttrue"
        "a sandbox's order\tk1,k10,k11 bdac"
        "optimize\tdefaults.lua:37: gaitlab.optimize: no optimizer here: call it from a script run by gaitlab run FILE.lua or in the console (gaitlab, gaitlab -i FILE.lua), or run the spec with gaitlab optimize SPEC.lua"
        "records only when asked\ttrue"
        "record_dir\truns/defaults-NNNNNNNN-NNNNNN\n")
    if(NOT m_rc EQUAL 0 OR NOT m_out STREQUAL expected)
        fail("lua5.4 defaults.lua (${m_rc}):\n${m_out}${m_err}\n--- expected\n${expected}")
    endif()
    # the run folder was closed when lua5.4 closed its state at the end of the script
    file(GLOB meta ${WORK}/runs/defaults-*/run.json)
    list(LENGTH meta n)
    if(NOT n EQUAL 1)
        fail("no run folder runs/defaults-*/ with a run.json")
    endif()
    file(READ ${meta} json)
    string(JSON status GET "${json}" status)
    if(NOT status STREQUAL "finished")
        fail("the recording is '${status}', expected 'finished':\n${json}")
    endif()
    message(STATUS "${m_out}")
elseif(STEP STREQUAL "missing_core")
    # gaitlab.so copied without gaitlab/core.so (a broken install): a message naming the file
    file(REMOVE_RECURSE ${WORK})
    file(COPY ${ENTRY} DESTINATION ${WORK}/lib)
    set(CPATH ${WORK}/lib/?.so)
    set(LUA_ENV "")  # only the entry loads, and it is not sanitized
    interpreter(lua ${LUA})
    capture(m ${WORK} ${lua} -e "require 'gaitlab'")
    if(NOT m_rc EQUAL 1 OR NOT m_err MATCHES
       "^${LUA}: gaitlab: cannot load ${WORK}/lib/gaitlab/core.so: [^\n]*No such file or directory\n")
        fail("lua5.4 with gaitlab.so alone: exit status ${m_rc}, expected 1 and a message naming gaitlab/core.so:\n${m_err}")
    endif()
    string(REGEX MATCH "^[^\n]*" line "${m_err}")
    message(STATUS "${line}")
elseif(STEP STREQUAL "other_luas")
    string(REPLACE "," ";" luas "${OTHER_LUAS}")
    foreach(name ${luas})
        find_program(other ${name} NO_CACHE)
        if(NOT other)
            fail("${name} is not installed (tools/setup.sh installs it)")
        endif()
        set(LUA_ENV "")  # the entry is not sanitized: nothing to preload
        interpreter(lua ${other})
        capture(o ${SOURCE} ${lua} -e "require 'gaitlab'")
        # a clear message and a failure status, not a crash (a signal) or the dynamic
        # linker's "undefined symbol"
        if(NOT o_rc EQUAL 1 OR NOT o_err MATCHES
           "^${other}: gaitlab needs Lua 5.4, and this interpreter runs (Lua 5\\.[0-3]|LuaJIT)[0-9.]*: run the script with lua5.4\n")
            fail("${name}: exit status ${o_rc}, expected 1 and a message that gaitlab needs Lua 5.4:\n${o_err}")
        endif()
        string(REGEX MATCH "^[^\n]*" line "${o_err}")
        message(STATUS "${line}")
    endforeach()
elseif(STEP STREQUAL "compare")
    # a copy of the script's folder (a script may write files next to itself, and lua5.4 records
    # what it asks to record)
    get_filename_component(dir ${SCRIPT} DIRECTORY)
    get_filename_component(name ${SCRIPT} NAME)
    file(REMOVE_RECURSE ${WORK})
    file(COPY ${dir}/ DESTINATION ${WORK})
    capture(g ${WORK} ${GAITLAB} run --no-record ${name})
    capture(c ${WORK} ${C_HOST} ${name})
    interpreter(lua ${LUA})
    capture(m ${WORK} ${lua} -e "gaitlab = require 'gaitlab'" ${name})
    if(NOT g_rc MATCHES "^[01]$")
        fail("gaitlab run ${name} ended with ${g_rc}:\n${g_err}")
    endif()
    # the C core gives what the C++ core gives, byte for byte
    if(NOT c_rc STREQUAL g_rc OR NOT c_out STREQUAL g_out OR NOT c_err STREQUAL g_err)
        fail("on the C core (c_host) ${name} gives other results than gaitlab run:\n--- gaitlab run (${g_rc})\n${g_out}${g_err}\n--- c_host (${c_rc})\n${c_out}${c_err}")
    endif()
    same_as_gaitlab("lua5.4")
    string(REGEX MATCH "[^\n]*\n?$" last "${g_err}")
    message(STATUS "the same in gaitlab run, c_host and lua5.4: ${last}")
elseif(STEP STREQUAL "fuzz")
    # the fuzzer's harness on the C core: no finding, no leak, and the outcome of the C++ core
    capture(cxx ${SOURCE} ${REPLAY} ${INPUT})
    capture(c ${SOURCE} ${REPLAY_C} ${INPUT})
    if(NOT c_rc EQUAL 0)
        fail("lua_fuzz_replay_c ${INPUT} failed (${c_rc}):\n${c_out}\n${c_err}")
    endif()
    # the watchdog's interrupt (2 s of wall time) depends on the machine's speed, not on the
    # core: a script it stopped in either run is compared no further
    if(NOT cxx_rc EQUAL 0 OR (NOT c_out STREQUAL cxx_out AND
                              NOT "${c_out}${cxx_out}" MATCHES ": interrupted: interrupted \\(SIGALRM\\)"))
        fail("the C core's outcome is not the C++ core's:\n--- lua_fuzz_replay (${cxx_rc})\n${cxx_out}${cxx_err}\n--- lua_fuzz_replay_c\n${c_out}")
    endif()
    message(STATUS "${c_out}")
else()
    fail("unknown STEP '${STEP}'")
endif()
