# odoloc_add_fuzzer(<name> SOURCES <files...> LIBS <targets...> [RUNS <n>] [MAX_LEN <bytes>])
# A libFuzzer executable linked with the project's own library targets, and a
# bounded, seeded run as a ctest (label fuzz). Only in the fuzz preset
# (ODOLOC_FUZZ): Debian's clang, every target of the build compiled with
# -fsanitize=fuzzer-no-link,address,undefined (the top-level CMakeLists.txt),
# so the fuzzer runs the libraries the product links, not copies of their
# sources. The corpus grows in the build tree; see docs/fuzzing.md for long
# runs.
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "ODOLOC_FUZZ needs clang (libFuzzer): use the fuzz preset "
                      "(cmake --preset fuzz; scripts/setup-debian.sh installs clang and "
                      "libclang-rt-14-dev)")
endif()
add_custom_target(odoloc_fuzzers)

function(odoloc_add_fuzzer name)
  cmake_parse_arguments(FZ "" "RUNS;MAX_LEN" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${FZ_SOURCES})
  target_link_libraries(${name} PRIVATE ${FZ_LIBS} odoloc_warnings)
  target_link_options(${name} PRIVATE -fsanitize=fuzzer)
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY
                                           ${CMAKE_CURRENT_BINARY_DIR}/fuzz)
  add_dependencies(odoloc_fuzzers ${name})
  if(NOT FZ_RUNS)
    set(FZ_RUNS 2000)
  endif()
  if(NOT FZ_MAX_LEN)
    set(FZ_MAX_LEN 1024)
  endif()
  set(corpus ${CMAKE_CURRENT_BINARY_DIR}/fuzz/${name}.corpus)
  file(MAKE_DIRECTORY ${corpus})
  add_test(NAME ${name} COMMAND ${name} -seed=1 -runs=${FZ_RUNS} -max_len=${FZ_MAX_LEN} ${corpus})
  set_tests_properties(${name} PROPERTIES LABELS fuzz TIMEOUT 600)
endfunction()
