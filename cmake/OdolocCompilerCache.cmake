# Compiles through Debian's ccache when it is installed and ODOLOC_CCACHE is
# on (the default), unless a launcher is already set (-D or the environment's
# CMAKE_<LANG>_COMPILER_LAUNCHER). Nothing depends on it: without ccache the
# compilers run as they are. docs/development.md, "Compiler cache".
#
# CCACHE_BASEDIR is the source tree, so ccache hashes the tree's paths
# relative to the build folder and a second clone, or CI's clone in another
# folder, hits the first one's entries; CCACHE_NOHASHDIR lets the -g builds
# (sanitize) hit across clones too, at the price of debug info that names the
# build folder of the clone that filled the entry.
#
# ODOLOC_COMPILER_LAUNCHER holds the launcher (empty without ccache) for
# the custom commands that run a compiler themselves (the clang fuzzers).
set(ODOLOC_COMPILER_LAUNCHER "")
if(ODOLOC_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER AND NOT CMAKE_C_COMPILER_LAUNCHER)
  find_program(ODOLOC_CCACHE_PROGRAM ccache DOC "ccache, the compiler cache (ODOLOC_CCACHE)")
  if(ODOLOC_CCACHE_PROGRAM)
    set(ODOLOC_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR}
                                 CCACHE_NOHASHDIR=true ${ODOLOC_CCACHE_PROGRAM})
    set(CMAKE_C_COMPILER_LAUNCHER ${ODOLOC_COMPILER_LAUNCHER})
    set(CMAKE_CXX_COMPILER_LAUNCHER ${ODOLOC_COMPILER_LAUNCHER})
    message(STATUS "Compiler cache: ${ODOLOC_CCACHE_PROGRAM}")
  else()
    message(STATUS "Compiler cache: none (install ccache to reuse compiles)")
  endif()
endif()
