# Run by cpack before it makes each Debian package (CPACK_PRE_BUILD_SCRIPTS, cmake/package.cmake):
# without dpkg-shlibdeps and the file utility, CPack would make a package whose Depends lacks
# every shared library the program needs, saying so only in passing; stop instead.
if(CPACK_GENERATOR STREQUAL "DEB")
    foreach(tool dpkg-shlibdeps file)
        find_program(gaitlab_tool_${tool} ${tool})
        if(NOT gaitlab_tool_${tool})
            message(FATAL_ERROR "gaitlab packaging: '${tool}' not found: it computes the shared "
                    "libraries the Debian package depends on. Install it "
                    "(apt install dpkg-dev file) and run cpack again.")
        endif()
    endforeach()
endif()
