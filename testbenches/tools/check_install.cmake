# ctest cli_install: `cmake --install` puts a working odoloc under a prefix
# (docs/host-tool.md, Installing). -DBUILD_DIR=... -DPREFIX=...
file(REMOVE_RECURSE "${PREFIX}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${PREFIX}"
                        --component host-tool
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}): ${out}${err}")
endif()
if(NOT EXISTS "${PREFIX}/bin/odoloc")
  message(FATAL_ERROR "cmake --install did not install bin/odoloc:\n${out}")
endif()
execute_process(COMMAND "${PREFIX}/bin/odoloc" --version
                RESULT_VARIABLE rc OUTPUT_VARIABLE version ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT version MATCHES "^odoloc [0-9]")
  message(FATAL_ERROR "installed odoloc --version: exit ${rc}: ${version}${err}")
endif()
execute_process(COMMAND "${PREFIX}/bin/odoloc" reg read top.id
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^top.id @ 0x000")
  message(FATAL_ERROR "installed odoloc reg read top.id: exit ${rc}: ${out}${err}")
endif()
file(GLOB docs "${PREFIX}/share/doc/odoloc/host-tool.md")
if(NOT docs)
  message(FATAL_ERROR "cmake --install did not install share/doc/odoloc/host-tool.md")
endif()
file(REMOVE_RECURSE "${PREFIX}")
