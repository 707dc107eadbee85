# odoloc_add_testbench(<name> LABEL <rtl|hls|sw|tools|scenario|fuzz>
#                      SOURCES <files...> [LIBS <targets...>] [ARGS <args...>]
#                      [TIMEOUT <seconds>])
# One call = one GoogleTest executable, the project warnings, one ctest entry
# with its label. Every testbench in the tree goes through here. Under
# ODOLOC_SANITIZE a scenario testbench is not defined at all.
function(odoloc_add_testbench name)
  cmake_parse_arguments(TB "" "LABEL;TIMEOUT" "SOURCES;LIBS;ARGS" ${ARGN})
  if(NOT TB_LABEL)
    message(FATAL_ERROR "odoloc_add_testbench(${name}): LABEL is required")
  endif()
  set(known_labels rtl hls sw tools scenario fuzz)
  if(NOT TB_LABEL IN_LIST known_labels)
    message(FATAL_ERROR "odoloc_add_testbench(${name}): unknown LABEL '${TB_LABEL}'")
  endif()
  # The sanitize build's test preset never runs the scenario tests
  # (docs/development.md), so it does not compile them either.
  if(ODOLOC_SANITIZE AND TB_LABEL STREQUAL "scenario")
    return()
  endif()
  add_executable(${name} ${TB_SOURCES})
  target_link_libraries(${name} PRIVATE odoloc_warnings odoloc_tb_support ${TB_LIBS}
                                        GTest::gtest GTest::gtest_main)
  add_test(NAME ${name} COMMAND ${name} ${TB_ARGS})
  if(NOT TB_TIMEOUT)
    set(TB_TIMEOUT 600)
  endif()
  set_tests_properties(${name} PROPERTIES LABELS ${TB_LABEL} TIMEOUT ${TB_TIMEOUT})
endfunction()
