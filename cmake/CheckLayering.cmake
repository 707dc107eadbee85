# cmake -DSOURCE_DIR=<repo> [-DLINKS_FILE=<file>] -P CheckLayering.cmake
#
# The layering of the tree (README "What is here", docs/conventions.md):
#
#   rtl_model/          the C++ standard library, odoloc/rtl/..., odoloc/logic/...
#                       and the generated odoloc/regs.hpp and odoloc/ports.hpp only
#   rtl_model/include/odoloc/logic  the blocks' logic, written once for the model
#                       and HLS: odoloc/logic/ and the C++14 constant headers
#                       (odoloc/rtl/*_constants.hpp) only
#   soc_software/       never odoloc/rtl/, odoloc/world/, odoloc/board/, odoloc/cli/
#   host_tools/sim/world/
#                       the C++ standard library and odoloc/world/... only
#   host_tools/sim/board/
#                       never odoloc/cli/
#   host_tools/tools/sweep/
#                       never odoloc/cli/ (the host tool sits on the sweep library)
#   host_tools/support/lcm/
#                       never odoloc/rtl/ (transport code does not know the model)
#   host_tools/tools/plot/
#                       the standard library, fmt, LCM, odoloc/lcm/ and its
#                       generated odoloc_lcm/, odoloc/process/, odoloc/output/
#                       and odoloc/plot/ only: it reads logs, it knows nothing of the model
#   host_tools/sim/system/
#                       never odoloc/cli/ (the host tool's `sim` sits on it)
#   hls/verification/
#                       never odoloc/hls_export/, odoloc/cli/: the kernels'
#                       references and stimulus are verification, the exporter uses them
#   host_tools/tools/bridge/
#                       never odoloc/rtl/, odoloc/world/, odoloc/board/, odoloc/cli/: the
#                       register bridge knows LCM, sw::RegisterBus and the register map
#   hls/include, hls/src  the standard library, odoloc/hls/, the blocks' logic
#                       (odoloc/logic/), the model's C++14 constant headers
#                       (odoloc/rtl/*_constants.hpp) and the
#                       vendors' type headers only: kernels are exported alone
#   testbenches/world/  never odoloc/rtl/, odoloc/sw/, odoloc/board/ (the
#                       world is tested without the model)
#
# Every #include line of every source is checked; each violation is printed
# as file:line and the script fails. LINKS_FILE (written at configure time by
# testbenches/CMakeLists.txt) holds what the layer targets link, so the CMake
# targets are checked the same way: odoloc_world links nothing but the
# warning flags, odoloc_rtl and the SoC software's libraries (odoloc_sw and
# its subsystems) link no host-tool target and not each other, odoloc_bridge links neither the model nor the board, odoloc_plot
# only the LCM layer, odoloc_process, odoloc_output and fmt.
cmake_minimum_required(VERSION 3.25)

if(NOT SOURCE_DIR)
  message(FATAL_ERROR "CheckLayering.cmake: pass -DSOURCE_DIR=<repository root>")
endif()

set(violations 0)
set(files_checked 0)

# <angle> includes without '/' or '.' are the C++ standard library.
function(is_standard_header kind header out)
  if(kind STREQUAL "<" AND header MATCHES "^[a-z_0-9]+$")
    set(${out} TRUE PARENT_SCOPE)
  else()
    set(${out} FALSE PARENT_SCOPE)
  endif()
endfunction()

# check_layer(<dir> <description> [ALLOW_STD] [ALLOW <regex>...] [DENY <regex>...])
# With ALLOW_STD or ALLOW, an include must be standard (ALLOW_STD) or match an
# ALLOW regex; every include must match no DENY regex.
function(check_layer dir description)
  cmake_parse_arguments(L "ALLOW_STD" "" "ALLOW;DENY" ${ARGN})
  file(GLOB_RECURSE sources LIST_DIRECTORIES false
       ${SOURCE_DIR}/${dir}/*.hpp ${SOURCE_DIR}/${dir}/*.cpp ${SOURCE_DIR}/${dir}/*.h
       ${SOURCE_DIR}/${dir}/*.c ${SOURCE_DIR}/${dir}/*.inc)
  list(SORT sources)
  set(count 0)
  set(bad 0)
  foreach(file IN LISTS sources)
    math(EXPR count "${count} + 1")
    file(READ ${file} text)
    # One list element per line: neutralise what CMake lists treat specially.
    string(REPLACE "\\" "/" text "${text}")
    string(REPLACE ";" "," text "${text}")
    string(REPLACE "[" "(" text "${text}")
    string(REPLACE "]" ")" text "${text}")
    string(REPLACE "\n" ";" lines "${text}")
    file(RELATIVE_PATH relative ${SOURCE_DIR} ${file})
    set(number 0)
    foreach(line IN LISTS lines)
      math(EXPR number "${number} + 1")
      if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*([<\"])([^>\"]*)[>\"]")
        continue()
      endif()
      set(kind "${CMAKE_MATCH_1}")
      set(header "${CMAKE_MATCH_2}")
      set(ok TRUE)
      if(L_ALLOW_STD OR L_ALLOW)
        set(ok FALSE)
        if(L_ALLOW_STD)
          is_standard_header("${kind}" "${header}" ok)
        endif()
        foreach(pattern IN LISTS L_ALLOW)
          if(header MATCHES "${pattern}")
            set(ok TRUE)
          endif()
        endforeach()
      endif()
      foreach(pattern IN LISTS L_DENY)
        if(header MATCHES "${pattern}")
          set(ok FALSE)
        endif()
      endforeach()
      if(NOT ok)
        if(kind STREQUAL "<")
          set(close ">")
        else()
          set(close "\"")
        endif()
        message(NOTICE "${relative}:${number}: ${description}: #include ${kind}${header}${close}")
        math(EXPR bad "${bad} + 1")
      endif()
    endforeach()
  endforeach()
  if(count EQUAL 0)
    message(NOTICE "${dir}: no sources found")
    math(EXPR bad "${bad} + 1")
  endif()
  math(EXPR total "${violations} + ${bad}")
  set(violations ${total} PARENT_SCOPE)
  math(EXPR checked "${files_checked} + ${count}")
  set(files_checked ${checked} PARENT_SCOPE)
endfunction()

check_layer(rtl_model
            "the model includes only the standard library, odoloc/rtl/, odoloc/logic/ and the generated headers"
            ALLOW_STD ALLOW "^odoloc/rtl/" "^odoloc/logic/" "^odoloc/regs\\.hpp$" "^odoloc/ports\\.hpp$")
check_layer(rtl_model/include/odoloc/logic
            "the blocks' logic includes only odoloc/logic/ and the model's C++14 constant headers"
            ALLOW_STD ALLOW "^odoloc/logic/" "^odoloc/rtl/[a-z_0-9]+_constants\\.hpp$")
check_layer(soc_software "the SoC software never includes the model, the world, the board or the tool"
            DENY "^odoloc/rtl/" "^odoloc/world/" "^odoloc/board/" "^odoloc/cli/")
check_layer(host_tools/sim/world "the world includes only the standard library and odoloc/world/"
            ALLOW_STD ALLOW "^odoloc/world/")
check_layer(host_tools/sim/board "the board never includes the host tool"
            DENY "^odoloc/cli/")
check_layer(host_tools/tools/sweep "the sweep library never includes the host tool"
            DENY "^odoloc/cli/")
check_layer(host_tools/support/lcm "the LCM message layer never includes the model"
            DENY "^odoloc/rtl/")
check_layer(host_tools/tools/plot
            "the plot library includes only the standard library, fmt, LCM, its message layer, odoloc/process/, odoloc/output/ and odoloc/plot/"
            ALLOW_STD ALLOW "^odoloc/plot/" "^odoloc/lcm/" "^odoloc_lcm/" "^odoloc/process/"
                            "^odoloc/output/"
                            "^lcm/" "^fmt/" "^(stdlib|unistd)\\.h$")
check_layer(host_tools/sim/system "the simulator never includes the host tool" DENY "^odoloc/cli/")
check_layer(hls/verification
            "the kernels' verification never includes the exporter or the host tool"
            DENY "^odoloc/hls_export/" "^odoloc/cli/")
check_layer(host_tools/tools/bridge
            "the register bridge never includes the model, the world, the board or the tool"
            DENY "^odoloc/rtl/" "^odoloc/world/" "^odoloc/board/" "^odoloc/cli/")
foreach(dir hls/include hls/src)
  check_layer(${dir} "a kernel includes only odoloc/hls/, the blocks' logic, the model's constant headers and the vendor's"
              ALLOW_STD ALLOW "^odoloc/hls/" "^odoloc/logic/" "^odoloc/rtl/[a-z_0-9]+_constants\\.hpp$"
                              "^ap_int\\.h$" "^ac_int\\.h$" "^HLS/(hls|ac_int)\\.h$")
endforeach()
check_layer(testbenches/world "the world's tests never include the model, the software or the board"
            DENY "^odoloc/rtl/" "^odoloc/sw/" "^odoloc/board/" "^odoloc/regs\\.hpp$")

# The targets: what each layer links (LINK_LIBRARIES and
# INTERFACE_LINK_LIBRARIES, $<LINK_ONLY:...> unwrapped).
function(check_links target description)
  cmake_parse_arguments(L "" "" "ALLOW;DENY" ${ARGN})
  if(NOT DEFINED LINKS_${target})
    message(NOTICE "${LINKS_FILE}: no link information for ${target}")
    math(EXPR total "${violations} + 1")
    set(violations ${total} PARENT_SCOPE)
    return()
  endif()
  set(links)
  foreach(link IN LISTS LINKS_${target})
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
    list(APPEND links "${link}")
  endforeach()
  list(REMOVE_DUPLICATES links)
  set(bad 0)
  foreach(link IN LISTS links)
    set(ok TRUE)
    if(L_ALLOW)
      set(ok FALSE)
      foreach(allowed IN LISTS L_ALLOW)
        if(link STREQUAL allowed)
          set(ok TRUE)
        endif()
      endforeach()
    endif()
    if(link IN_LIST L_DENY)
      set(ok FALSE)
    endif()
    if(NOT ok)
      message(NOTICE "target ${target}: ${description}: links ${link}")
      math(EXPR bad "${bad} + 1")
    endif()
  endforeach()
  math(EXPR total "${violations} + ${bad}")
  set(violations ${total} PARENT_SCOPE)
endfunction()

if(LINKS_FILE)
  include(${LINKS_FILE})
  set(host_tool_targets odoloc_world odoloc_board odoloc_sweep odoloc_plot odoloc_sim
                        odoloc_cli_lib)
  check_links(odoloc_world "the world links nothing but the warning flags"
              ALLOW odoloc_warnings)
  check_links(odoloc_rtl "the model links no software or host-tool target"
              DENY odoloc_sw ${host_tool_targets})
  foreach(sw odoloc_sw odoloc_sw_bus odoloc_sw_odometry odoloc_sw_tof odoloc_sw_locate
             odoloc_sw_fuse odoloc_sw_station odoloc_sw_localiser)
    check_links(${sw} "the SoC software links no model or host-tool target"
                DENY odoloc_rtl ${host_tool_targets})
  endforeach()
  check_links(odoloc_plot
              "the plot library links only the LCM layer, process, output, fmt and the warnings"
              ALLOW odoloc_lcm odoloc_process odoloc_output fmt::fmt odoloc_warnings)
  check_links(odoloc_bridge "the register bridge links no model, world, board or tool target"
              DENY odoloc_rtl ${host_tool_targets})
endif()

if(violations GREATER 0)
  message(FATAL_ERROR "layering: ${violations} violation(s); ${files_checked} files checked")
endif()
message(STATUS "layering: ${files_checked} files, no violation")
