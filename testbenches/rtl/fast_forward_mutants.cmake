# test_fast_forward against mutants of every fast-forward rule
# (fast_forward_mutants.txt), all in one binary: each header that holds a
# rule is copied into a private include folder (which shadows the real one)
# with every rule's original expression replaced by
#   (::odoloc::tb::mutant(K) ? (mutated) : (original))
# so that ODOLOC_MUTANT=<name> runs the shipped code with exactly that one
# rule changed (testbenches/support/fast_forward_mutant.hpp). One compile
# instead of one per mutant (docs/development.md). Tests:
#   test_fast_forward_mutants        no mutant on: the copy must pass (the
#                                    control: a mutant's failure is its rule's)
#   test_fast_forward_mutant_<name>  passes when an assertion of
#                                    test_fast_forward fails with it on
# Optimised builds only (the sanitizers add nothing to a test expected to fail).

set(mutant_list ${CMAKE_CURRENT_LIST_DIR}/fast_forward_mutants.txt)
set(rtl_include ${PROJECT_SOURCE_DIR}/rtl_model/include/odoloc/rtl)
set(mutant_dir ${CMAKE_CURRENT_BINARY_DIR}/fast_forward_mutants)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${mutant_list})
file(STRINGS ${mutant_list} mutant_lines REGEX "^[a-z]")

# Sets `out` to where `needle` occurs in `haystack`; fails with `what`
# unless it occurs exactly once.
function(odoloc_find_once haystack needle out what)
  string(FIND "${haystack}" "${needle}" first)
  string(FIND "${haystack}" "${needle}" last REVERSE)
  if(first EQUAL -1 OR NOT first EQUAL last)
    message(FATAL_ERROR "${what} exactly once (${mutant_list})")
  endif()
  set(${out} ${first} PARENT_SCOPE)
endfunction()

set(mutant_names)
set(mutant_headers)
set(index 0)
foreach(line IN LISTS mutant_lines)
  string(REPLACE "@@" ";" fields "${line}")
  list(LENGTH fields field_count)
  if(field_count LESS 4 OR field_count GREATER 5)
    message(FATAL_ERROR "fast-forward mutants: '${line}' is not name@@header@@original@@mutated"
                        "[@@anchor] (${mutant_list})")
  endif()
  list(GET fields 0 name)
  list(GET fields 1 header)
  list(GET fields 2 original)
  list(GET fields 3 mutated)
  set(anchor "${original}")
  if(field_count EQUAL 5)
    list(GET fields 4 anchor)
  endif()
  odoloc_find_once("${anchor}" "${original}" first
                   "fast-forward mutant ${name}: the anchor '${anchor}' must hold '${original}'")
  string(LENGTH "${original}" original_length)
  math(EXPR after_original "${first} + ${original_length}")
  string(SUBSTRING "${anchor}" 0 ${first} before)
  string(SUBSTRING "${anchor}" ${after_original} -1 after)
  set(mutant_${name}_anchor "${anchor}")
  set(mutant_${name}_replacement
      "${before}(::odoloc::tb::mutant(${index}) ? (${mutated}) : (${original}))${after}")
  list(APPEND mutant_names ${name})
  list(APPEND mutant_headers ${header})
  list(APPEND mutants_in_${header} ${name})
  math(EXPR index "${index} + 1")
endforeach()
list(REMOVE_DUPLICATES mutant_headers)

# Writes `text` to `path` only when it changed, so a configure rebuilds nothing.
function(odoloc_write_if_changed path text)
  file(WRITE ${path}.in "${text}")
  configure_file(${path}.in ${path} COPYONLY)
endfunction()

foreach(header IN LISTS mutant_headers)
  set(source ${rtl_include}/${header})
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${source})
  file(READ ${source} text)
  # Each anchor's place in the shipped text, spliced from the last one back
  # so the earlier places stay valid; anchors may not overlap.
  set(places)
  foreach(name IN LISTS mutants_in_${header})
    odoloc_find_once("${text}" "${mutant_${name}_anchor}" first
                     "fast-forward mutant ${name}: ${header} must hold '${mutant_${name}_anchor}'")
    list(APPEND places "${first}:${name}")
  endforeach()
  list(SORT places COMPARE NATURAL ORDER DESCENDING)
  string(LENGTH "${text}" end_of_previous)
  foreach(place IN LISTS places)
    string(REPLACE ":" ";" place "${place}")
    list(GET place 0 first)
    list(GET place 1 name)
    string(LENGTH "${mutant_${name}_anchor}" anchor_length)
    math(EXPR end "${first} + ${anchor_length}")
    if(end GREATER end_of_previous)
      message(FATAL_ERROR "fast-forward mutant ${name}: its anchor overlaps another's in ${header}")
    endif()
    string(SUBSTRING "${text}" 0 ${first} head)
    string(SUBSTRING "${text}" ${end} -1 tail)
    set(text "${head}${mutant_${name}_replacement}${tail}")
    set(end_of_previous ${first})
  endforeach()
  string(FIND "${text}" "#pragma once\n" pragma)
  if(pragma EQUAL -1)
    message(FATAL_ERROR "fast-forward mutants: ${header} has no '#pragma once'")
  endif()
  string(REPLACE "#pragma once\n" "#pragma once\n#include \"fast_forward_mutant.hpp\"\n" text
                 "${text}")
  odoloc_write_if_changed(${mutant_dir}/odoloc/rtl/${header} "${text}")
endforeach()

# A header no rule lives in any more must not shadow the real one.
file(GLOB shadows RELATIVE ${mutant_dir}/odoloc/rtl ${mutant_dir}/odoloc/rtl/*.hpp)
foreach(shadow IN LISTS shadows)
  if(NOT shadow IN_LIST mutant_headers)
    file(REMOVE ${mutant_dir}/odoloc/rtl/${shadow} ${mutant_dir}/odoloc/rtl/${shadow}.in)
  endif()
endforeach()

set(names_text "// Generated by testbenches/rtl/fast_forward_mutants.cmake: do not edit.\n")
string(APPEND names_text "#pragma once\n\nnamespace odoloc::tb {\n\n")
string(APPEND names_text "inline constexpr const char* kFastForwardMutants[] = {\n")
foreach(name IN LISTS mutant_names)
  string(APPEND names_text "    \"${name}\",\n")
endforeach()
string(APPEND names_text "};\n\n}  // namespace odoloc::tb\n")
odoloc_write_if_changed(${mutant_dir}/fast_forward_mutant_names.hpp "${names_text}")

odoloc_add_testbench(test_fast_forward_mutants LABEL rtl SOURCES rtl/test_fast_forward.cpp)
target_include_directories(test_fast_forward_mutants BEFORE PRIVATE ${mutant_dir})
foreach(name IN LISTS mutant_names)
  add_test(NAME test_fast_forward_mutant_${name}
           COMMAND test_fast_forward_mutants --gtest_fail_fast)
  set_tests_properties(test_fast_forward_mutant_${name} PROPERTIES
                       LABELS rtl TIMEOUT 600 ENVIRONMENT ODOLOC_MUTANT=${name}
                       PASS_REGULAR_EXPRESSION "\\[  FAILED  \\] FastForward\\.")
endforeach()
