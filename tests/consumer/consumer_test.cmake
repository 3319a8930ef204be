# cmake -DSTEP=... -DBUILD=<gaitlab build tree> -DSOURCE=<gaitlab source tree> -DWORK=<scratch>
#       -DCXX=<compiler> [-DLAUNCHER=ccache] -DGENERATOR=... -P consumer_test.cmake
# The steps of the "consumer:" tests (tests/CMakeLists.txt):
#   install    cmake --install into WORK/staged, then move the tree to WORK/prefix: what follows
#              uses the moved tree, so an absolute path left in an installed file fails; and
#              docs/embedding.md shows examples/embed/embed.cpp as it is
#   cmake      configure, build and run tests/consumer with find_package(gaitlab)
#   pkgconfig  compile examples/embed/embed.cpp with `pkg-config --cflags --libs gaitlab`
#   version    find_package(gaitlab 99 REQUIRED) fails with the version message
#   missing    with a pkg-config that finds nothing, find_package(gaitlab) names what is missing
#   luamodule  lua5.4 runs examples/first_snake.lua with the installed Lua module
#              (LIBDIR/lua/5.4/gaitlab.so and gaitlab/core.so) on LUA_CPATH
cmake_minimum_required(VERSION 3.21)
set(prefix ${WORK}/prefix)

function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        string(REPLACE ";" " " cmd "${ARGN}")
        message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}\n${err}")
    endif()
    set(out "${out}" PARENT_SCOPE)
endfunction()

# the embed example's line "moved D m (x X, y Y) in T s": it must have crawled forward
function(check_moved out)
    if(NOT out MATCHES "moved [0-9.]+ m \\(x (-?[0-9.]+), y -?[0-9.]+\\) in 5.0 s")
        message(FATAL_ERROR "embed printed no displacement:\n${out}")
    endif()
    set(x ${CMAKE_MATCH_1})
    if(x LESS_EQUAL 0.1)
        message(FATAL_ERROR "the snake moved x ${x} m in 5 s, expected more than 0.1 m forward")
    endif()
    message(STATUS "embed: ${out}")
endfunction()

if(STEP STREQUAL "install")
    file(REMOVE_RECURSE ${WORK})
    run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/staged)
    file(RENAME ${WORK}/staged ${prefix})
    foreach(f bin/gaitlab include/gaitlab/simulation.h include/gaitlab/controllers/sine.h
              include/gaitlab/scripting/lua_host.h share/gaitlab/stdlib/vec3.lua
              share/gaitlab/stdlib/templates/sine.lua share/gaitlab/worlds/flat.lua
              share/doc/gaitlab/embedding.md share/doc/gaitlab/examples/embed/embed.cpp)
        if(NOT EXISTS ${prefix}/${f})
            message(FATAL_ERROR "not installed: ${f}")
        endif()
    endforeach()
    file(GLOB_RECURSE config ${prefix}/*/gaitlabConfig.cmake)
    file(GLOB_RECURSE pc ${prefix}/*/gaitlab.pc)
    if(NOT config OR NOT pc)
        message(FATAL_ERROR "no gaitlabConfig.cmake or gaitlab.pc under ${prefix}")
    endif()
    # no installed text file may name the build tree, the source tree or where it was installed
    file(GLOB_RECURSE texts ${prefix}/*.cmake ${prefix}/*.pc ${prefix}/*.h)
    foreach(f IN LISTS texts)
        file(READ ${f} text)
        foreach(path ${BUILD} ${SOURCE} ${WORK}/staged)
            string(FIND "${text}" "${path}" at)
            if(NOT at EQUAL -1)
                message(FATAL_ERROR "${f} names ${path}: the installed tree cannot move")
            endif()
        endforeach()
    endforeach()
    # docs/embedding.md shows examples/embed/embed.cpp from its first #include on, as it is
    file(READ ${SOURCE}/examples/embed/embed.cpp example)
    file(READ ${SOURCE}/docs/embedding.md doc)
    string(FIND "${example}" "#include" at)
    string(SUBSTRING "${example}" ${at} -1 example)
    string(FIND "${doc}" "${example}" at)
    if(at EQUAL -1)
        message(FATAL_ERROR "docs/embedding.md does not show examples/embed/embed.cpp as it is")
    endif()
    run(${prefix}/bin/gaitlab --version)
    message(STATUS "installed and moved to ${prefix}: ${out}")
elseif(STEP STREQUAL "cmake")
    set(launcher "")
    if(LAUNCHER)
        set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
    endif()
    file(REMOVE_RECURSE ${WORK}/consumer)
    run(${CMAKE_COMMAND} -S ${SOURCE}/tests/consumer -B ${WORK}/consumer -G ${GENERATOR}
        -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX} ${launcher}
        -DCMAKE_PREFIX_PATH=${prefix} "-DCMAKE_CXX_FLAGS=${SANITIZE}"
        "-DCMAKE_EXE_LINKER_FLAGS=${SANITIZE}")
    if(NOT out MATCHES "gaitlab [0-9.]+ from ${prefix}/")
        message(FATAL_ERROR "find_package(gaitlab) did not use ${prefix}:\n${out}")
    endif()
    run(${CMAKE_COMMAND} --build ${WORK}/consumer)
    run(${WORK}/consumer/embed/embed)
    check_moved("${out}")
    run(${WORK}/consumer/host)
    if(NOT out MATCHES "lua moved x ([0-9.]+) m\nerror: host:1: on purpose")
        message(FATAL_ERROR "the Lua host printed:\n${out}")
    endif()
    if(CMAKE_MATCH_1 LESS_EQUAL 0.1)
        message(FATAL_ERROR "the Lua snake moved x ${CMAKE_MATCH_1} m in 5 s")
    endif()
elseif(STEP STREQUAL "pkgconfig")
    file(GLOB_RECURSE pc ${prefix}/*/gaitlab.pc)
    get_filename_component(pcdir "${pc}" DIRECTORY)
    set(ENV{PKG_CONFIG_PATH} ${pcdir})
    run(pkg-config --cflags --libs gaitlab)
    string(STRIP "${out}" flags)
    separate_arguments(flags UNIX_COMMAND "${flags}")
    file(MAKE_DIRECTORY ${WORK}/pkgconfig)
    run(${LAUNCHER} ${CXX} -std=c++17 -O1 ${SANITIZE} ${SOURCE}/examples/embed/embed.cpp
        ${flags} -o ${WORK}/pkgconfig/embed)
    run(${WORK}/pkgconfig/embed)
    check_moved("${out}")
elseif(STEP STREQUAL "version")
    execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/tests/consumer/version
                            -B ${WORK}/version -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX}
                            -DCMAKE_PREFIX_PATH=${prefix}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(rc EQUAL 0)
        message(FATAL_ERROR "find_package(gaitlab 99 REQUIRED) succeeded against ${prefix}")
    endif()
    string(REGEX REPLACE "[ \n]+" " " err "${err}")  # CMake wraps its messages
    if(NOT err MATCHES "compatible with requested version \"99\"" OR NOT err MATCHES "version: [0-9.]+")
        message(FATAL_ERROR "no version message:\n${err}")
    endif()
    message(STATUS "refused as expected")
elseif(STEP STREQUAL "missing")
    # pkg-config that finds nothing: the package says which dependency is missing
    file(MAKE_DIRECTORY ${WORK}/no-pc)
    set(ENV{PKG_CONFIG_LIBDIR} ${WORK}/no-pc)
    set(ENV{PKG_CONFIG_PATH} "")
    execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/tests/consumer -B ${WORK}/missing
                            -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    string(REGEX REPLACE "[ \n]+" " " err "${err}")
    if(rc EQUAL 0 OR NOT err MATCHES "gaitlab needs bullet, which pkg-config does not find")
        message(FATAL_ERROR "no message about the missing dependency (exit ${rc}):\n${err}")
    endif()
    message(STATUS "refused as expected")
elseif(STEP STREQUAL "luamodule")
    file(GLOB_RECURSE entry ${prefix}/*/lua/5.4/gaitlab.so)
    list(LENGTH entry n)
    if(NOT n EQUAL 1)
        message(FATAL_ERROR "no LIBDIR/lua/5.4/gaitlab.so under ${prefix}: '${entry}'")
    endif()
    get_filename_component(dir ${entry} DIRECTORY)
    if(NOT EXISTS ${dir}/gaitlab/core.so)
        message(FATAL_ERROR "${dir}/gaitlab/core.so is not installed next to gaitlab.so")
    endif()
    set(env LUA_CPATH=${dir}/?.so LUA_CPATH_5_4=${dir}/?.so LUA_INIT= LUA_INIT_5_4=)
    if(LUA_ENV)
        list(APPEND env "${LUA_ENV}")
    endif()
    # from elsewhere than the build tree, which the installed module must not need
    file(MAKE_DIRECTORY ${WORK}/luamodule)
    execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env} lua5.4 -e "gaitlab = require 'gaitlab'"
                            ${SOURCE}/examples/first_snake.lua
                    WORKING_DIRECTORY ${WORK}/luamodule
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT out MATCHES "^moved ([0-9.]+) m \\(x -?[0-9.]+, y -?[0-9.]+\\)\n$")
        message(FATAL_ERROR "lua5.4 with the installed module (${rc}):\n${out}\n${err}")
    endif()
    if(CMAKE_MATCH_1 LESS_EQUAL 0.1)
        message(FATAL_ERROR "the snake moved ${CMAKE_MATCH_1} m with the installed module")
    endif()
    message(STATUS "lua5.4 with ${entry}: ${out}")
else()
    message(FATAL_ERROR "unknown STEP '${STEP}'")
endif()
