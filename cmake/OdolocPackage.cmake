# Installation and packaging of the host tool (docs/host-tool.md, Installing):
#   cmake --build --preset default --target odoloc odoloc_package_docs  # or all
#   cmake --install build/default                 # /usr/local/bin/odoloc
#   cmake --install build/default --prefix ~/.local
#   cmake --build --preset default --target package   # odoloc_<version>_<arch>.deb
# Only the `host-tool` component is installed and packaged: the programs and
# testbenches used during development stay in the build tree. The Debian
# package is lintian-clean; the ctest cli_package checks it (lintian, the
# contents, the fields, the man page rendered by groff).
include(GNUInstallDirs)

# Debian wants a maintainer address (lintian: not on localhost). The
# repository names no mailing list; the default is the address its commits
# carry, under the reserved .example domain: it reaches no one, but no
# stranger either. Set the real one with -D when there is one.
set(ODOLOC_PACKAGE_MAINTAINER "odoloc maintainers <maintainers@users.noreply.h-seed-e9aa43ed.example>"
    CACHE STRING "Maintainer of the Debian package, as 'Name <address>'")

# Plain files 0644, directories (named or made on the way) 0755, whatever the
# umask of the checkout: lintian rejects group-writable ones.
set(odoloc_file_perms OWNER_READ OWNER_WRITE GROUP_READ WORLD_READ)
set(odoloc_dir_perms OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ
                     WORLD_EXECUTE)
set(CMAKE_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS ${odoloc_dir_perms})

# Debian's hardening (lintian's hardening-no-bindnow): resolve every symbol at
# load so that the GOT can be read-only. Only the shipped program's link.
target_link_options(odoloc PRIVATE LINKER:-z,relro,-z,now)

install(TARGETS odoloc RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT host-tool)
# A stripped install (CPack's, `cmake --install --strip`) also drops what
# Debian's dh_strip drops: the compilers' .comment and .note sections.
install(CODE "if(CMAKE_INSTALL_DO_STRIP)
  execute_process(COMMAND \"${CMAKE_STRIP}\" --remove-section=.comment --remove-section=.note
                          \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}/odoloc\"
                  COMMAND_ERROR_IS_FATAL ANY)
endif()" COMPONENT host-tool)
install(FILES docs/host-tool.md docs/simulator.md docs/lcm.md docs/hls.md docs/sweep.md
              docs/spi.md docs/register-map.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR} PERMISSIONS ${odoloc_file_perms} COMPONENT host-tool)
# examples/: the scenario files, the locate inputs, the sweep specs and the Slurm array template
# (kept executable: it is a script users submit).
install(DIRECTORY examples/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples COMPONENT host-tool
        FILE_PERMISSIONS ${odoloc_file_perms} DIRECTORY_PERMISSIONS ${odoloc_dir_perms}
        PATTERN "*.sbatch" PERMISSIONS ${odoloc_file_perms} OWNER_EXECUTE GROUP_EXECUTE
                                       WORLD_EXECUTE)
# The LCM message definitions, for lcm-gen in other languages. Their own
# folder, so that generated bindings can sit beside them later.
install(DIRECTORY host_tools/support/lcm/lcmtypes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/odoloc/lcmtypes
        COMPONENT host-tool FILE_PERMISSIONS ${odoloc_file_perms}
        DIRECTORY_PERMISSIONS ${odoloc_dir_perms} FILES_MATCHING PATTERN "*.lcm")

# The Debian changelog and the man page, compressed as Debian wants (gzip -9n:
# no name, no time stamp). The version is native (no Debian revision: the
# packaging lives upstream), so the changelog is changelog.gz, not
# changelog.Debian.gz. The man page is help2man's rendering of the built
# binary's --help plus packaging/odoloc.h2m. Its version is the project's:
# the whole of `odoloc --version` (with the register map's id) overprints
# the date in the page's 80-column footer; cli_package checks that the two agree.
set(odoloc_pkg_dir ${PROJECT_BINARY_DIR}/packaging)
configure_file(packaging/copyright.in ${odoloc_pkg_dir}/copyright @ONLY)
configure_file(packaging/changelog.in ${odoloc_pkg_dir}/changelog @ONLY)
# A version bump needs an entry (cli_package fails without; this says it early).
file(STRINGS ${odoloc_pkg_dir}/changelog odoloc_changelog_head LIMIT_COUNT 1)
string(REGEX MATCH "^odoloc \\(([^)]*)\\)" odoloc_changelog_head "${odoloc_changelog_head}")
if(NOT CMAKE_MATCH_1 STREQUAL PROJECT_VERSION)
  message(WARNING "packaging/changelog.in: the latest entry is for '${CMAKE_MATCH_1}', not for "
                  "${PROJECT_VERSION} (project(VERSION)): add an entry for ${PROJECT_VERSION}")
endif()
add_custom_command(OUTPUT ${odoloc_pkg_dir}/changelog.gz
                   COMMAND gzip -9nkf changelog
                   DEPENDS ${odoloc_pkg_dir}/changelog
                   WORKING_DIRECTORY ${odoloc_pkg_dir}
                   COMMENT "Compressing the Debian changelog" VERBATIM)
set(odoloc_pkg_outputs ${odoloc_pkg_dir}/changelog.gz)

find_program(ODOLOC_HELP2MAN help2man DOC "help2man, for the man page odoloc.1")
if(ODOLOC_HELP2MAN)
  add_custom_command(OUTPUT ${odoloc_pkg_dir}/odoloc.1.gz
                     COMMAND ${ODOLOC_HELP2MAN} --no-info --section=1
                             --version-string=${PROJECT_VERSION}
                             --include=${PROJECT_SOURCE_DIR}/packaging/odoloc.h2m
                             --output=odoloc.1 $<TARGET_FILE:odoloc>
                     COMMAND gzip -9nf odoloc.1
                     DEPENDS odoloc packaging/odoloc.h2m
                     WORKING_DIRECTORY ${odoloc_pkg_dir}
                     COMMENT "Generating the man page odoloc.1 with help2man" VERBATIM)
  list(APPEND odoloc_pkg_outputs ${odoloc_pkg_dir}/odoloc.1.gz)
  if(ODOLOC_LCM_SPY)  # host_tools/support/lcm: the lcm-spy launcher, when Java is there
    add_custom_command(OUTPUT ${odoloc_pkg_dir}/odoloc-lcm-spy.1.gz
                       COMMAND ${ODOLOC_HELP2MAN} --no-info --section=1
                               --include=${PROJECT_SOURCE_DIR}/packaging/odoloc-lcm-spy.h2m
                               --output=odoloc-lcm-spy.1 ${ODOLOC_LCM_SPY}
                       COMMAND gzip -9nf odoloc-lcm-spy.1
                       DEPENDS ${ODOLOC_LCM_SPY} packaging/odoloc-lcm-spy.h2m
                       WORKING_DIRECTORY ${odoloc_pkg_dir}
                       COMMENT "Generating the man page odoloc-lcm-spy.1 with help2man" VERBATIM)
    list(APPEND odoloc_pkg_outputs ${odoloc_pkg_dir}/odoloc-lcm-spy.1.gz)
  endif()
else()
  message(STATUS "help2man not found: the host tool is installed without its man page")
endif()
# In `all`: `cmake --install` and CPack take these from the build tree.
add_custom_target(odoloc_package_docs ALL DEPENDS ${odoloc_pkg_outputs})

# A clear message, rather than CMake's "cannot find", when only `odoloc` was
# built (scripts/demo.sh builds just that) and then installed.
foreach(generated IN LISTS odoloc_pkg_outputs)
  install(CODE "if(NOT EXISTS \"${generated}\")
  message(FATAL_ERROR \"${generated} is not built: build the target odoloc_package_docs (or all) first\")
endif()" COMPONENT host-tool)
endforeach()
install(FILES ${odoloc_pkg_dir}/copyright ${odoloc_pkg_dir}/changelog.gz
        DESTINATION ${CMAKE_INSTALL_DOCDIR} PERMISSIONS ${odoloc_file_perms} COMPONENT host-tool)
if(ODOLOC_HELP2MAN)
  list(FILTER odoloc_pkg_outputs INCLUDE REGEX "\\.1\\.gz$")
  install(FILES ${odoloc_pkg_outputs} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1
          PERMISSIONS ${odoloc_file_perms} COMPONENT host-tool)
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME odoloc)
set(CPACK_PACKAGE_VENDOR odoloc)
set(CPACK_PACKAGE_CONTACT "${ODOLOC_PACKAGE_MAINTAINER}")
# The synopsis (under 80 characters) and the extended description.
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "FPGA/SoC robot localisation simulator and host tool")
# Read here, not through CPACK_PACKAGE_DESCRIPTION_FILE: CPack escapes that
# one for XML (an apostrophe becomes &apos; in the control file).
file(READ packaging/description.txt CPACK_DEBIAN_PACKAGE_DESCRIPTION)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS packaging/description.txt)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_COMPONENTS_ALL host-tool)
set(CPACK_DEB_COMPONENT_INSTALL OFF)  # one package holding the host-tool component
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION electronics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # Depends: from the linked shared libraries (libfmt, libc)
# Recommends, not Depends: gnuplot draws the plots (sim --out, plot, locate
# --plot, sweep merge) and the LCM tools record and replay what sim publishes,
# but registers, locate, sweep run, export-hls and `sim --no-plot` work
# without them, e.g. on a headless board host. apt installs Recommends by
# default, so the main job works out of the box; gnuplot-nox first: no X.
# The Java runtime and libraries for odoloc-lcm-spy, likewise.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS
    "gnuplot-nox | gnuplot, liblcm-bin, liblcm-java, libjchart2d-java, default-jre | java11-runtime")
# The Python reader and types (lib/python3/dist-packages) need the
# interpreter: a real dependency of those files (lintian), and on every
# Debian system anyway.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3:any")
set(CPACK_STRIP_FILES ON)  # Debian ships stripped programs
set(CPACK_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS ${odoloc_dir_perms})
include(CPack)
