# `cmake --install build --prefix P`: the program, the libraries and their public headers, a CMake
# package (find_package(gaitlab)) and a pkg-config file, the Lua stdlib, templates and worlds, the
# docs and examples. Every installed file names other installed files by paths relative to itself
# (the CMake package through ${PACKAGE_PREFIX_DIR}, gaitlab.pc through ${pcfiledir}), so the tree
# may be moved after it is installed (tests/consumer checks this).
#
# The libraries are static (the default of add_library, BUILD_SHARED_LIBS off): at 0.x their ABI
# changes with every release, so a shared library would need a new soname and a new Debian
# package per release for no user's benefit; static archives, as Debian accepts in a -dev
# package, are linked into the program that uses them and cannot mismatch at run time. They are
# position-independent (CMAKE_POSITION_INDEPENDENT_CODE), so a shared object (the Lua C module)
# may link them.
#
# Two install components, which are the two Debian packages (cmake/package.cmake): `dev` (the
# libraries, headers, CMake package and pkg-config file: gaitlab-dev) and `runtime` (everything
# else: gaitlab). A rule that names no component is `runtime`
# (CMAKE_INSTALL_DEFAULT_COMPONENT_NAME, set in the top CMakeLists.txt before any subdirectory).
include(CMakePackageConfigHelpers)

set(GAITLAB_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/gaitlab)
set(GAITLAB_DATA_DIR ${CMAKE_INSTALL_DATADIR}/gaitlab)

install(TARGETS gaitlab RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS gaitlab_engine gaitlab_controllers gaitlab_scripting gaitlab_optimize
        EXPORT gaitlabTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# the public headers: include/gaitlab/*.h (engine), include/gaitlab/controllers/*.h,
# include/gaitlab/scripting/*.h, include/gaitlab/optimize/*.h; they include only each other and
# the standard library
foreach(dir engine controllers scripting optimize)
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/include/
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev FILES_MATCHING PATTERN "*.h")
endforeach()

install(EXPORT gaitlabTargets NAMESPACE gaitlab:: DESTINATION ${GAITLAB_CMAKE_DIR} COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/gaitlabConfig.cmake.in
    ${PROJECT_BINARY_DIR}/gaitlabConfig.cmake INSTALL_DESTINATION ${GAITLAB_CMAKE_DIR})
# 0.x: a minor release may break the API, so 0.1.2 satisfies find_package(gaitlab 0.1) but not
# 0.2 or 1; from 1.0 on this becomes SameMajorVersion
write_basic_package_version_file(${PROJECT_BINARY_DIR}/gaitlabConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/gaitlabConfig.cmake
              ${PROJECT_BINARY_DIR}/gaitlabConfigVersion.cmake
        DESTINATION ${GAITLAB_CMAKE_DIR} COMPONENT dev)

# the Lua module for the stock interpreter (scripting/module): `require "gaitlab"` in lua5.4
# finds LIBDIR/lua/5.4/gaitlab.so, which loads gaitlab/core.so next to it. Debian's lua5.4
# looks in /usr/lib/<multiarch>/lua/5.4 and /usr/local/lib/lua/5.4, where --prefix /usr and
# --prefix /usr/local put them; any other prefix goes on LUA_CPATH (docs/embedding.md)
set(GAITLAB_LUA_MODULE_DIR ${CMAKE_INSTALL_LIBDIR}/lua/5.4)
install(TARGETS gaitlab_lua_module LIBRARY DESTINATION ${GAITLAB_LUA_MODULE_DIR})
install(TARGETS gaitlab_lua_core LIBRARY DESTINATION ${GAITLAB_LUA_MODULE_DIR}/gaitlab)

# pkg-config: one gaitlab.pc for the four libraries; its prefix is found from where it lies
file(RELATIVE_PATH GAITLAB_PC_TO_PREFIX
     /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
string(REGEX REPLACE "/$" "" GAITLAB_PC_TO_PREFIX "${GAITLAB_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/gaitlab.pc.in ${PROJECT_BINARY_DIR}/gaitlab.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/gaitlab.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
        COMPONENT dev)

# the Lua sources the program embeds, for reading and copying: stdlib/, stdlib/templates/
# (what ctl.new_file starts from) and the ready-made worlds
install(DIRECTORY ${PROJECT_SOURCE_DIR}/stdlib/ DESTINATION ${GAITLAB_DATA_DIR}/stdlib)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/worlds/ DESTINATION ${GAITLAB_DATA_DIR}/worlds)

install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples)
