# odoloc_add_fuzzer(<name> SOURCES <files...> [INCLUDES <dirs...>] [LIBS <-lx...>]
#                   [RUNS <n>] [DEPENDS <targets or files...>])
# A libFuzzer target built with Debian's clang (the rest of the tree may use
# GCC), with ASan and UBSan, and a bounded, seeded run as a ctest (label
# fuzz). The corpus grows in the build tree; see docs/fuzzing.md for long runs.
# Each source is compiled on its own, through the compiler cache when there
# is one (ODOLOC_COMPILER_LAUNCHER), with the headers it includes tracked by
# clang's depfile; then the objects are linked.
find_program(ODOLOC_CLANGXX NAMES clang++-14 clang++)
if(NOT ODOLOC_CLANGXX)
  message(FATAL_ERROR "clang++ not found: run scripts/setup-debian.sh (the fuzz tests need "
                      "Debian's clang and libclang-rt-14-dev), or configure with -DODOLOC_FUZZ=OFF")
endif()

function(odoloc_add_fuzzer name)
  cmake_parse_arguments(FZ "" "RUNS" "SOURCES;INCLUDES;LIBS;DEPENDS" ${ARGN})
  set(binary ${CMAKE_CURRENT_BINARY_DIR}/fuzz/${name})
  set(object_dir ${CMAKE_CURRENT_BINARY_DIR}/fuzz/${name}.objects)
  set(corpus ${CMAKE_CURRENT_BINARY_DIR}/fuzz/${name}.corpus)
  set(flags -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
            -Wall -Wextra -Werror)
  set(include_flags)
  foreach(dir IN LISTS FZ_INCLUDES)
    list(APPEND include_flags -I${dir})
  endforeach()
  set(objects)
  foreach(source IN LISTS FZ_SOURCES)
    get_filename_component(stem ${source} NAME_WE)
    set(object ${object_dir}/${stem}.o)
    if(object IN_LIST objects)
      message(FATAL_ERROR "odoloc_add_fuzzer(${name}): two sources named ${stem}")
    endif()
    add_custom_command(
      OUTPUT ${object}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${object_dir}
      COMMAND ${ODOLOC_COMPILER_LAUNCHER} ${ODOLOC_CLANGXX} ${flags} ${include_flags}
              -MD -MF ${object}.d -c ${source} -o ${object}
      DEPENDS ${source} ${FZ_DEPENDS}
      DEPFILE ${object}.d
      COMMENT "Compiling ${stem} for fuzzer ${name} with clang"
      VERBATIM)
    list(APPEND objects ${object})
  endforeach()
  add_custom_command(
    OUTPUT ${binary}
    COMMAND ${ODOLOC_CLANGXX} ${flags} ${objects} ${FZ_LIBS} -o ${binary}
    DEPENDS ${objects}
    COMMENT "Linking fuzzer ${name} with clang"
    VERBATIM)
  add_custom_target(${name} ALL DEPENDS ${binary})
  if(NOT FZ_RUNS)
    set(FZ_RUNS 2000)
  endif()
  file(MAKE_DIRECTORY ${corpus})
  add_test(NAME ${name} COMMAND ${binary} -seed=1 -runs=${FZ_RUNS} -max_len=1024 ${corpus})
  set_tests_properties(${name} PROPERTIES LABELS fuzz TIMEOUT 600)
endfunction()
