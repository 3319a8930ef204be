# cmake -DSTEP=... -DBUILD=<gaitlab build tree> -DSOURCE=<gaitlab source tree> -DWORK=<scratch>
#       -DVERSION=<x.y.z> -DLIBDIR=<CMAKE_INSTALL_LIBDIR> -DCXX=<compiler> [-DLAUNCHER=ccache]
#       [-DSANITIZE=<flags>] -P package_test.cmake
# The steps of the "package:" tests (tests/CMakeLists.txt), on the packages cpack makes from the
# build tree as it is (no second build; nothing is installed into the system):
#   build     cpack -G DEB: gaitlab_VERSION_ARCH.deb and gaitlab-dev_VERSION_ARCH.deb, nothing else
#   info      the control fields: names, version, architecture, maintainer, sections,
#             descriptions; gaitlab's Depends covers every shared library the program needs;
#             gaitlab-dev's covers every module gaitlab.pc requires, and gaitlab itself
#   contents  what each package holds: together, exactly what `cmake --install` installs, under
#             /usr, owned by root; the program, stdlib, worlds, docs and examples in gaitlab;
#             headers, libraries, CMake package and gaitlab.pc in gaitlab-dev
#   run       both packages extracted into a scratch root (dpkg-deb -x): the extracted program
#             runs an extracted example and records it; lua5.4 runs it with the extracted Lua
#             module; examples/embed/embed.cpp builds against the extracted gaitlab-dev through
#             its gaitlab.pc; the snakes move
#   apt       apt-get install --simulate ./gaitlab_*.deb ./gaitlab-dev_*.deb resolves
#   noshlibdeps  cpack where dpkg-shlibdeps cannot be found stops, saying what to install,
#             and makes no package
#   script    tools/package.sh without dpkg-shlibdeps on PATH stops, saying what to install
cmake_minimum_required(VERSION 3.21)
set(debs ${WORK}/debs)
set(root ${WORK}/root)

function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        string(REPLACE ";" " " cmd "${ARGN}")
        message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}\n${err}")
    endif()
    set(out "${out}" PARENT_SCOPE)
endfunction()

run(dpkg --print-architecture)
string(STRIP "${out}" arch)
set(runtime_deb ${debs}/gaitlab_${VERSION}_${arch}.deb)
set(dev_deb ${debs}/gaitlab-dev_${VERSION}_${arch}.deb)

# the Depends field of a package as a list of alternatives ("a (>= 1) | b", ...)
function(depends deb var)
    run(dpkg-deb --field ${deb} Depends)
    string(STRIP "${out}" out)
    string(REPLACE ", " ";" out "${out}")
    set(${var} "${out}" PARENT_SCOPE)
endfunction()

# whether one of the alternatives of `deps` names one of the packages `owners`
function(depends_on deps owners var)
    set(found FALSE)
    foreach(dep IN LISTS deps)
        string(REPLACE " | " ";" alternatives "${dep}")
        foreach(alt IN LISTS alternatives)
            string(REGEX REPLACE " .*" "" name "${alt}")
            if(name IN_LIST owners)
                set(found TRUE)
            endif()
        endforeach()
    endforeach()
    set(${var} ${found} PARENT_SCOPE)
endfunction()

# the packages that own a file whose path ends in /NAME (dpkg-query -S; any architecture)
function(owners name var)
    run(dpkg-query -S "*/${name}")
    string(REGEX MATCHALL "[^\n]+" lines "${out}")
    set(result "")
    foreach(line IN LISTS lines)
        # "pkg[:arch][, pkg[:arch]...]: /path"
        string(FIND "${line}" ": /" at)
        if(at EQUAL -1)
            continue()
        endif()
        string(SUBSTRING "${line}" 0 ${at} packages)
        math(EXPR at "${at} + 2")
        string(SUBSTRING "${line}" ${at} -1 path)
        get_filename_component(file "${path}" NAME)
        if(file STREQUAL name)
            string(REPLACE ", " ";" packages "${packages}")
            list(TRANSFORM packages REPLACE ":.*" "")
            list(APPEND result ${packages})
        endif()
    endforeach()
    set(${var} "${result}" PARENT_SCOPE)
endfunction()

# the files (not directories) of a package, as paths without the leading "."
function(contents deb var)
    run(dpkg-deb --contents ${deb})
    string(REGEX MATCHALL "[^\n]+" lines "${out}")
    set(files "")
    foreach(line IN LISTS lines)
        if(NOT line MATCHES "^[-dl]")
            message(FATAL_ERROR "${deb} holds something that is neither a file, a folder nor a link:\n${line}")
        endif()
        if(NOT line MATCHES "^[-dl][rwxs-]+ root/root ")
            message(FATAL_ERROR "${deb}: not owned by root:\n${line}")
        endif()
        if(line MATCHES "^[-l].* \\./([^ ]+)( -> .*)?$")
            list(APPEND files /${CMAKE_MATCH_1})
        endif()
    endforeach()
    set(${var} "${files}" PARENT_SCOPE)
endfunction()

# the line "moved D m (x X, y Y)..." that the examples print: D must exceed 0.1 m
function(check_moved what out)
    if(NOT out MATCHES "moved ([0-9.]+) m \\(x -?[0-9.]+, y -?[0-9.]+\\)")
        message(FATAL_ERROR "${what} printed no displacement:\n${out}")
    endif()
    if(CMAKE_MATCH_1 LESS_EQUAL 0.1)
        message(FATAL_ERROR "${what}: the snake moved ${CMAKE_MATCH_1} m, expected more than 0.1 m")
    endif()
    message(STATUS "${what}: ${out}")
endfunction()

if(STEP STREQUAL "build")
    file(REMOVE_RECURSE ${WORK})
    # gzip rather than the packages' xz: a sanitizer build's libraries carry debug information
    # (about 250 MB), which xz takes minutes to compress
    run(cpack --config ${BUILD}/CPackConfig.cmake -G DEB -B ${debs}
        -D CPACK_DEBIAN_COMPRESSION_TYPE=gzip)
    file(GLOB made RELATIVE ${debs} ${debs}/*.deb)
    list(SORT made)
    set(expected gaitlab-dev_${VERSION}_${arch}.deb gaitlab_${VERSION}_${arch}.deb)
    if(NOT made STREQUAL expected)
        message(FATAL_ERROR "cpack made '${made}', expected '${expected}'")
    endif()
    message(STATUS "made ${made}")
elseif(STEP STREQUAL "info")
    foreach(deb runtime dev)
        set(file ${${deb}_deb})
        run(dpkg-deb --info ${file})  # dpkg-deb reads the whole control file
        foreach(field Package Version Architecture Maintainer Section Priority Description)
            run(dpkg-deb --field ${file} ${field})
            string(STRIP "${out}" ${deb}_${field})
        endforeach()
    endforeach()
    foreach(check "runtime_Package STREQUAL gaitlab" "dev_Package STREQUAL gaitlab-dev"
                  "runtime_Section STREQUAL science" "dev_Section STREQUAL libdevel")
        separate_arguments(check)
        if(NOT ${check})
            list(GET check 0 name)
            message(FATAL_ERROR "${name} is '${${name}}'")
        endif()
    endforeach()
    foreach(deb runtime dev)
        if(NOT ${deb}_Version STREQUAL VERSION OR NOT ${deb}_Architecture STREQUAL arch)
            message(FATAL_ERROR "${deb}: version '${${deb}_Version}', architecture "
                    "'${${deb}_Architecture}', expected ${VERSION} and ${arch}")
        endif()
        if(NOT ${deb}_Maintainer MATCHES "^[^<>]+ <[^<>@ ]+@[^<>@ ]+>$")
            message(FATAL_ERROR "${deb}: Maintainer '${${deb}_Maintainer}' is not 'Name <email>'")
        endif()
        # a one-line summary, then a description of several lines
        if(NOT ${deb}_Description MATCHES "^[a-z][^\n]+\n [^\n]+\n [^\n]+")
            message(FATAL_ERROR "${deb}: no summary and description:\n${${deb}_Description}")
        endif()
    endforeach()

    # gaitlab: every shared library the program loads comes from a package it depends on
    # (dpkg-shlibdeps found them all), among them those of gaitlab's own dependencies
    depends(${runtime_deb} runtime_depends)
    foreach(pattern "libbullet" "liblua5\\.4-0" "libtinyxml2-" "libfmt" "libedit2" "libpng16"
                    "libstdc\\+\\+6" "libc6")
        if(NOT runtime_depends MATCHES "(^|;)${pattern}")
            message(FATAL_ERROR "gaitlab's Depends lacks ${pattern}: ${runtime_depends}")
        endif()
    endforeach()
    file(MAKE_DIRECTORY ${WORK}/info)
    run(dpkg-deb -x ${runtime_deb} ${WORK}/info)
    file(GLOB_RECURSE elves ${WORK}/info/usr/bin/* ${WORK}/info/usr/lib/*.so)
    foreach(elf IN LISTS elves)
        run(readelf --dynamic ${elf})
        string(REGEX MATCHALL "Shared library: \\[[^]]+\\]" needed "${out}")
        foreach(lib IN LISTS needed)
            string(REGEX REPLACE "Shared library: \\[(.*)\\]" "\\1" lib "${lib}")
            owners(${lib} owned_by)
            depends_on("${runtime_depends}" "${owned_by}" ok)
            if(NOT ok)
                message(FATAL_ERROR "${elf} needs ${lib} (from ${owned_by}), which gaitlab's "
                        "Depends does not name: ${runtime_depends}")
            endif()
        endforeach()
    endforeach()
    if(runtime_depends MATCHES "gaitlab-dev|-dev( |;|$)")
        message(FATAL_ERROR "gaitlab depends on a development package: ${runtime_depends}")
    endif()

    # gaitlab-dev: gaitlab of the same version, the package of every module gaitlab.pc requires
    # (whose .pc files pkg-config finds here), and pkg-config itself
    depends(${dev_deb} dev_depends)
    if(NOT "gaitlab (= ${VERSION})" IN_LIST dev_depends)
        message(FATAL_ERROR "gaitlab-dev does not depend on gaitlab (= ${VERSION}): ${dev_depends}")
    endif()
    depends_on("${dev_depends}" "pkg-config;pkgconf" ok)
    if(NOT ok)
        message(FATAL_ERROR "gaitlab-dev does not depend on pkg-config: ${dev_depends}")
    endif()
    run(dpkg-deb -x ${dev_deb} ${WORK}/info)
    file(GLOB_RECURSE pc ${WORK}/info/usr/*/gaitlab.pc)
    file(STRINGS "${pc}" requires REGEX "^Requires:")
    string(REGEX REPLACE "^Requires:[ ]*" "" requires "${requires}")
    string(REGEX MATCHALL "[^ ,]+" requires "${requires}")
    if(NOT requires)
        message(FATAL_ERROR "${pc} requires nothing")
    endif()
    foreach(module IN LISTS requires)
        run(pkg-config --variable=pcfiledir ${module})
        string(STRIP "${out}" dir)
        owners(${module}.pc owned_by)
        list(FILTER owned_by INCLUDE REGEX ".")
        depends_on("${dev_depends}" "${owned_by}" ok)
        if(NOT ok)
            message(FATAL_ERROR "gaitlab.pc requires ${module} (${dir}/${module}.pc, from "
                    "'${owned_by}'), which gaitlab-dev's Depends does not name: ${dev_depends}")
        endif()
    endforeach()
    message(STATUS "gaitlab: ${runtime_depends}\ngaitlab-dev: ${dev_depends}")
elseif(STEP STREQUAL "contents")
    contents(${runtime_deb} runtime_files)
    contents(${dev_deb} dev_files)
    # together they hold what the install rules install, each file once
    file(REMOVE_RECURSE ${WORK}/installed)
    run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/installed)
    file(GLOB_RECURSE installed LIST_DIRECTORIES false RELATIVE ${WORK}/installed
         ${WORK}/installed/*)
    list(TRANSFORM installed PREPEND /usr/)
    set(packaged ${runtime_files} ${dev_files})
    set(missing ${installed})
    list(REMOVE_ITEM missing ${packaged})
    set(extra ${packaged})
    list(REMOVE_ITEM extra ${installed})
    if(missing OR extra)
        message(FATAL_ERROR "the packages differ from what cmake --install installs:\n"
                "not packaged: ${missing}\nnot installed: ${extra}")
    endif()
    list(LENGTH packaged n)
    list(REMOVE_DUPLICATES packaged)
    list(LENGTH packaged unique)
    if(NOT n EQUAL unique)
        message(FATAL_ERROR "a file is in both packages")
    endif()
    foreach(f /usr/bin/gaitlab /usr/share/gaitlab/stdlib/vec3.lua
              /usr/share/gaitlab/stdlib/templates/sine.lua /usr/share/gaitlab/worlds/flat.lua
              /usr/share/doc/gaitlab/README.md /usr/share/doc/gaitlab/install.md
              /usr/share/doc/gaitlab/embedding.md /usr/share/doc/gaitlab/examples/first_snake.lua
              /usr/share/doc/gaitlab/examples/embed/embed.cpp
              /usr/${LIBDIR}/lua/5.4/gaitlab.so /usr/${LIBDIR}/lua/5.4/gaitlab/core.so)
        if(NOT f IN_LIST runtime_files)
            message(FATAL_ERROR "gaitlab lacks ${f}")
        endif()
    endforeach()
    foreach(f /usr/include/gaitlab/simulation.h /usr/include/gaitlab/controllers/sine.h
              /usr/include/gaitlab/scripting/lua_host.h /usr/${LIBDIR}/libgaitlab-engine.a
              /usr/${LIBDIR}/libgaitlab-controllers.a /usr/${LIBDIR}/libgaitlab-scripting.a
              /usr/${LIBDIR}/cmake/gaitlab/gaitlabConfig.cmake
              /usr/${LIBDIR}/cmake/gaitlab/gaitlabConfigVersion.cmake
              /usr/${LIBDIR}/cmake/gaitlab/gaitlabTargets.cmake
              /usr/${LIBDIR}/pkgconfig/gaitlab.pc)
        if(NOT f IN_LIST dev_files)
            message(FATAL_ERROR "gaitlab-dev lacks ${f}")
        endif()
    endforeach()
    list(LENGTH runtime_files nr)
    list(LENGTH dev_files nd)
    message(STATUS "gaitlab: ${nr} files, gaitlab-dev: ${nd} files, as cmake --install")
elseif(STEP STREQUAL "run")
    file(REMOVE_RECURSE ${root} ${WORK}/cwd)
    file(MAKE_DIRECTORY ${root} ${WORK}/cwd)
    run(dpkg-deb -x ${runtime_deb} ${root})
    run(dpkg-deb -x ${dev_deb} ${root})
    set(gaitlab ${root}/usr/bin/gaitlab)
    run(${gaitlab} --version)
    if(NOT out MATCHES "^gaitlab ${VERSION}")
        message(FATAL_ERROR "the extracted gaitlab --version printed: ${out}")
    endif()
    # the example as the package installs it, recorded into a run folder
    execute_process(COMMAND ${gaitlab} run --record ${WORK}/cwd/run
                            ${root}/usr/share/doc/gaitlab/examples/first_snake.lua
                    WORKING_DIRECTORY ${WORK}/cwd RESULT_VARIABLE rc OUTPUT_VARIABLE out
                    ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "the extracted gaitlab failed (${rc}):\n${out}\n${err}")
    endif()
    check_moved("extracted gaitlab run first_snake.lua" "${out}")
    # the extracted Lua module in lua5.4 (require "gaitlab")
    set(cpath ${root}/usr/${LIBDIR}/lua/5.4/?.so)
    set(env LUA_CPATH=${cpath} LUA_CPATH_5_4=${cpath} LUA_INIT= LUA_INIT_5_4=)
    if(LUA_ENV)
        list(APPEND env "${LUA_ENV}")
    endif()
    execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env} lua5.4 -e "gaitlab = require 'gaitlab'"
                            ${root}/usr/share/doc/gaitlab/examples/first_snake.lua
                    WORKING_DIRECTORY ${WORK}/cwd RESULT_VARIABLE rc OUTPUT_VARIABLE out
                    ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "lua5.4 with the extracted Lua module failed (${rc}):\n${out}\n${err}")
    endif()
    check_moved("lua5.4 with the extracted module, first_snake.lua" "${out}")
    foreach(f run.json data.csv series.csv config/first_snake.lua)
        if(NOT EXISTS ${WORK}/cwd/run/${f})
            message(FATAL_ERROR "the run folder lacks ${f}")
        endif()
    endforeach()
    # a C++ program built against the extracted gaitlab-dev alone (its gaitlab.pc finds the
    # headers and libraries where dpkg-deb put them)
    file(GLOB_RECURSE pc ${root}/usr/*/gaitlab.pc)
    get_filename_component(pcdir "${pc}" DIRECTORY)
    set(ENV{PKG_CONFIG_PATH} ${pcdir})
    run(pkg-config --cflags --libs gaitlab)
    string(STRIP "${out}" flags)
    if(NOT flags MATCHES "-I${root}/usr/")
        message(FATAL_ERROR "gaitlab.pc does not point into the extracted tree: ${flags}")
    endif()
    separate_arguments(flags UNIX_COMMAND "${flags}")
    run(${LAUNCHER} ${CXX} -std=c++17 -O1 ${SANITIZE}
        ${root}/usr/share/doc/gaitlab/examples/embed/embed.cpp ${flags} -o ${WORK}/embed)
    run(${WORK}/embed)
    check_moved("embed.cpp built against gaitlab-dev" "${out}")
elseif(STEP STREQUAL "apt")
    # what `apt install ./gaitlab_*.deb` would do, without doing it (works without root)
    execute_process(COMMAND apt-get install --simulate --no-install-recommends
                            ./gaitlab_${VERSION}_${arch}.deb ./gaitlab-dev_${VERSION}_${arch}.deb
                    WORKING_DIRECTORY ${debs} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                    ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR err MATCHES "(^|\n)E: " OR out MATCHES "unmet dependencies")
        message(FATAL_ERROR "apt would not install the packages (${rc}):\n${out}\n${err}")
    endif()
    foreach(name gaitlab gaitlab-dev)
        if(NOT out MATCHES "(Inst|Conf) ${name} \\(${VERSION} "
           AND NOT out MATCHES "${name} is already the newest version \\(${VERSION}\\)")
            message(FATAL_ERROR "apt would not install ${name}:\n${out}")
        endif()
    endforeach()
    message(STATUS "apt-get install --simulate resolves:\n${out}")
elseif(STEP STREQUAL "noshlibdeps")
    # find_program then sees none of the system's programs, dpkg-shlibdeps among them
    set(broken ${WORK}/noshlibdeps)
    file(REMOVE_RECURSE ${broken})
    execute_process(COMMAND cpack --config ${BUILD}/CPackConfig.cmake -G DEB -B ${broken}
                            -D "CMAKE_IGNORE_PATH=/usr/local/bin;/usr/bin;/bin;/usr/sbin;/sbin"
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    string(REGEX REPLACE "[ \n]+" " " text "${out} ${err}")
    if(rc EQUAL 0 OR NOT text MATCHES "'dpkg-shlibdeps' not found.*apt install dpkg-dev")
        message(FATAL_ERROR "cpack without dpkg-shlibdeps (exit ${rc}) did not say so:\n${out}\n${err}")
    endif()
    file(GLOB made ${broken}/*.deb)
    if(made)
        message(FATAL_ERROR "cpack without dpkg-shlibdeps made ${made}")
    endif()
    message(STATUS "refused as expected")
elseif(STEP STREQUAL "script")
    # a PATH with what tools/package.sh needs before its check (bash, and tools/setup.sh's
    # dpkg-query, grep, npm and the lock-file stamp's tools), but no dpkg-shlibdeps
    set(bin ${WORK}/script-bin)
    file(REMOVE_RECURSE ${bin})
    file(MAKE_DIRECTORY ${bin})
    foreach(tool bash cat cut dirname dpkg-query grep id npm sha256sum)
        find_program(path_${tool} ${tool} REQUIRED)
        file(CREATE_LINK ${path_${tool}} ${bin}/${tool} SYMBOLIC)
    endforeach()
    execute_process(COMMAND ${CMAKE_COMMAND} -E env PATH=${bin} ${SOURCE}/tools/package.sh
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(rc EQUAL 0 OR NOT err MATCHES "'dpkg-shlibdeps' not found.*apt install dpkg-dev")
        message(FATAL_ERROR "tools/package.sh without dpkg-shlibdeps (exit ${rc}) did not say so:\n${out}\n${err}")
    endif()
    message(STATUS "refused as expected: ${err}")
else()
    message(FATAL_ERROR "unknown STEP '${STEP}'")
endif()
