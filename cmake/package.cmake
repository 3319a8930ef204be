# Debian packages through CPack: `cpack -G DEB` in a build tree (tools/package.sh does it all,
# from configuring for /usr to build/packages/) makes
#   gaitlab_<version>_<arch>.deb      the install component `runtime`: the program, the Lua
#                                     stdlib, templates and worlds, the Lua module for lua5.4,
#                                     the docs and examples, and
#                                     whatever else cmake/install.cmake installs without naming
#                                     a component
#   gaitlab-dev_<version>_<arch>.deb  the component `dev`: the static libraries, the public
#                                     headers, the CMake package and gaitlab.pc
# Both install under /usr. The files come from the install rules, never from a list here, so
# whatever cmake/install.cmake installs is packaged. Included last by the top CMakeLists.txt,
# when every install rule is known.
#
# Dependencies: dpkg-shlibdeps computes the shared libraries' packages of every executable and
# shared object (libbullet*, liblua5.4-0, libfmt9, libtinyxml2-9, libpng16-16, libedit2 ...);
# gaitlab-dev adds what a program linking the static libraries needs to find and link them, as
# gaitlabConfig.cmake and gaitlab.pc name it (tests/package checks that each of gaitlab.pc's
# modules comes from one of these packages).
set(GAITLAB_DEV_DEPENDS
    "libbullet-dev, libfmt-dev, liblua5.4-dev, libtinyxml2-dev, libpng-dev, pkg-config")

# who built the package, "Name <email>" (tools/package.sh takes DEBFULLNAME and DEBEMAIL, as
# Debian's own tools do)
set(GAITLAB_PACKAGE_MAINTAINER "gaitlab developers <gaitlab@localhost>"
    CACHE STRING "Maintainer field of the Debian packages: Name <email>")

# every install rule must belong to one of the packages: a rule with a component of its own
# would be packaged nowhere
get_cmake_property(gaitlab_components COMPONENTS)
foreach(component IN LISTS gaitlab_components)
    if(NOT component MATCHES "^(runtime|dev)$")
        message(FATAL_ERROR "an install rule names the component '${component}': the Debian "
                "packages (cmake/package.cmake) take 'runtime' (gaitlab) and 'dev' (gaitlab-dev); "
                "give the rule one of these, or none for 'runtime'")
    endif()
endforeach()

set(CPACK_PACKAGE_NAME gaitlab)
set(CPACK_PACKAGE_VENDOR gaitlab)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${GAITLAB_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR}/packages)
set(CPACK_COMPONENTS_ALL runtime dev)
# an install rule with an absolute destination would be left out of the packages: stop instead
set(CPACK_ERROR_ON_ABSOLUTE_INSTALL_DESTINATION ON)
set(CPACK_STRIP_FILES ON)

find_program(GAITLAB_DPKG dpkg)
mark_as_advanced(GAITLAB_DPKG)
if(GAITLAB_DPKG)
    set(CPACK_GENERATOR DEB)
else()
    set(CPACK_GENERATOR TGZ)
endif()

set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # <name>_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${GAITLAB_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)
# gaitlab-dev depends on gaitlab of the same version (CPACK_COMPONENT_DEV_DEPENDS)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME gaitlab)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION science)
# plots (`gaitlab data DIR --plot`, run:plot) are drawn by gnuplot
set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "gnuplot-nox | gnuplot")
# the Lua module (LIBDIR/lua/5.4/gaitlab.so) is for the stock interpreter, which provides its Lua
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "lua5.4")
# the first line is the summary (CPACK_PACKAGE_DESCRIPTION_SUMMARY stays unset: CPack would put it
# before each package's own); lines stay under 80 columns, as Debian's tools show them
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION
    "modular-robot simulation with Lua scripting
gaitlab simulates modular robots, chains of servo modules that move by
coordinated joint oscillation (snakes, caterpillars, rolling robots), on
Bullet physics with a deterministic fixed-step scheduler. Robots, worlds and
locomotion controllers (sine waves, central pattern generators, or
controllers written in Lua that reload while the simulation runs) are Lua
scripts or XML files; every run is recorded to a folder of CSV series and
replays bit for bit.
This package holds the gaitlab program (script runner, console, wizard, data
tools), its Lua library, controller templates and worlds, the gaitlab module
for the lua5.4 interpreter, the documentation and the examples.")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME gaitlab-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "${GAITLAB_DEV_DEPENDS}")
set(CPACK_COMPONENT_DEV_DEPENDS runtime)
set(CPACK_DEBIAN_DEV_DESCRIPTION
    "modular-robot simulation with Lua scripting - C++ libraries
The gaitlab engine, its built-in controllers and its Lua host as static
libraries, for C++17 programs that build robots and worlds, step simulations
or run gaitlab's Lua scripts: the public headers, libgaitlab-engine.a,
libgaitlab-controllers.a and libgaitlab-scripting.a, the CMake package
(find_package(gaitlab)) and the pkg-config file gaitlab.pc.")

# dpkg-shlibdeps computes the Depends: a package built without it would install and then fail
# to start, so the packaging stops, saying what to install (runs before each package is made)
set(CPACK_PRE_BUILD_SCRIPTS ${PROJECT_SOURCE_DIR}/cmake/package_check.cmake)

# `cpack --config CPackSourceConfig.cmake` (a source tarball): the tracked sources only
set(CPACK_SOURCE_GENERATOR TGZ)
set(CPACK_SOURCE_IGNORE_FILES "/\\\\.git/" "/build[^/]*/" "/runs/" "/out/" "\\\\.swp$")

include(CPack)
