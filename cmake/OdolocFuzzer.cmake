# odoloc_add_fuzzer(<name> SOURCES <files...> [INCLUDES <dirs...>] [LIBS <-lx...>]
#                   [RUNS <n>] [DEPENDS <targets...>])
# A libFuzzer target built with Debian's clang (the rest of the tree may use
# GCC), with ASan and UBSan, and a bounded, seeded run as a ctest (label
# fuzz). The corpus grows in the build tree; see docs/fuzzing.md for long runs.
find_program(ODOLOC_CLANGXX NAMES clang++-14 clang++)
if(NOT ODOLOC_CLANGXX)
  message(FATAL_ERROR "clang++ not found: run scripts/setup-debian.sh (the fuzz tests need "
                      "Debian's clang and libclang-rt-14-dev), or configure with -DODOLOC_FUZZ=OFF")
endif()

function(odoloc_add_fuzzer name)
  cmake_parse_arguments(FZ "" "RUNS" "SOURCES;INCLUDES;LIBS;DEPENDS" ${ARGN})
  set(binary ${CMAKE_CURRENT_BINARY_DIR}/fuzz/${name})
  set(corpus ${CMAKE_CURRENT_BINARY_DIR}/fuzz/${name}.corpus)
  set(flags -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
            -Wall -Wextra -Werror)
  set(include_flags)
  foreach(dir IN LISTS FZ_INCLUDES)
    list(APPEND include_flags -I${dir})
  endforeach()
  # Headers are not tracked one by one: any header of the tree rebuilds it.
  file(GLOB_RECURSE headers CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/rtl_model/include/*.hpp
       ${PROJECT_SOURCE_DIR}/soc_software/include/*.hpp
       ${PROJECT_SOURCE_DIR}/host_tools/board/include/*.hpp)
  add_custom_command(
    OUTPUT ${binary}
    COMMAND ${ODOLOC_CLANGXX} ${flags} ${include_flags} ${FZ_SOURCES} ${FZ_LIBS} -o ${binary}
    DEPENDS ${FZ_SOURCES} ${headers} ${FZ_DEPENDS}
    COMMENT "Building fuzzer ${name} with clang"
    VERBATIM)
  add_custom_target(${name} ALL DEPENDS ${binary})
  if(NOT FZ_RUNS)
    set(FZ_RUNS 2000)
  endif()
  file(MAKE_DIRECTORY ${corpus})
  add_test(NAME ${name} COMMAND ${binary} -seed=1 -runs=${FZ_RUNS} -max_len=1024 ${corpus})
  set_tests_properties(${name} PROPERTIES LABELS fuzz TIMEOUT 600)
endfunction()
