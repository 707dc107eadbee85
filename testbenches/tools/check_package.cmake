# ctest cli_package: CPack makes the Debian package of the host tool
# (cmake/OdolocPackage.cmake) and this checks it as Debian would:
#  - lintian: no E: or W: tag (all tags, I: and P: too, are printed);
#  - the contents: the program, the man page, copyright, changelog, the
#    manuals, every examples/ file and .lcm definition of the source tree,
#    all root-owned, 0644/0755, and no development program;
#  - the fields: Version is the project's, Depends has libc6, Recommends
#    gnuplot and the LCM tools; the control members are 0644;
#  - unpacked (dpkg-deb -x): md5sums match, the program runs and says the
#    version, the changelog parses with that version, both .gz files are
#    gzip -n (no name, no time stamp), and groff renders the man page without
#    a warning, naming every command the program's own --help lists.
# -DBUILD_DIR=... -DOUT=... -DSOURCE_DIR=... -DVERSION=... Prints "SKIPPED"
# (the test's SKIP_REGULAR_EXPRESSION) without dpkg-deb, dpkg-shlibdeps,
# dpkg-parsechangelog or groff, or when help2man was not there to make the
# man page; lintian is skipped alone (with a note) where it is not installed.
cmake_minimum_required(VERSION 3.25)  # IN_LIST and the other policies of the project
foreach(var BUILD_DIR OUT SOURCE_DIR VERSION)
  if(NOT ${var})
    message(FATAL_ERROR "check_package.cmake: -D${var}=... is required")
  endif()
endforeach()
find_program(DPKG_DEB dpkg-deb)
find_program(DPKG_SHLIBDEPS dpkg-shlibdeps)
find_program(DPKG_PARSECHANGELOG dpkg-parsechangelog)
find_program(GROFF groff)
find_program(LINTIAN lintian)
if(NOT DPKG_DEB OR NOT DPKG_SHLIBDEPS OR NOT DPKG_PARSECHANGELOG OR NOT GROFF)
  message("SKIPPED: dpkg-deb, dpkg-shlibdeps, dpkg-parsechangelog or groff not found")
  return()
endif()
load_cache("${BUILD_DIR}" READ_WITH_PREFIX cache_ ODOLOC_HELP2MAN)
if(NOT cache_ODOLOC_HELP2MAN)
  message("SKIPPED: help2man was not found when ${BUILD_DIR} was configured: no man page")
  return()
endif()

function(run what)  # run(<what> COMMAND ...): the command's stdout in `run_out`
  execute_process(${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}${err}")
  endif()
  set(run_out "${out}" PARENT_SCOPE)
  set(run_err "${err}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
run(cpack COMMAND cpack --config "${BUILD_DIR}/CPackConfig.cmake" -B "${OUT}")
set(cpack_out "${run_out}")
file(GLOB debs "${OUT}/odoloc_*.deb")
list(LENGTH debs n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "expected one odoloc_*.deb in ${OUT}, found: ${debs}\n${cpack_out}")
endif()
set(deb "${debs}")

# lintian: every tag printed, E: and W: fail.
if(LINTIAN)
  execute_process(COMMAND "${LINTIAN}" -I -E --pedantic --tag-display-limit 0
                          --fail-on error,warning "${deb}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE tags ERROR_VARIABLE err)
  string(REGEX MATCHALL "(^|\n)[EW]: [^\n]*" bad "${tags}")
  # Exit 2 is --fail-on's "E: or W: tags found", 1 lintian failing.
  if(NOT (rc EQUAL 0 OR (rc EQUAL 2 AND bad)))
    message(FATAL_ERROR "lintian failed (${rc}):\n${tags}${err}")
  endif()
  message("lintian ${deb}:\n${tags}")
  if(bad)
    message(FATAL_ERROR "lintian reports errors or warnings:\n${tags}")
  endif()
else()
  message("lintian not installed: the package was not linted (scripts/setup-debian.sh --tests)")
endif()

# The contents: `dpkg-deb -c` lines are "MODE OWNER SIZE DATE TIME PATH".
run("dpkg-deb --contents" COMMAND "${DPKG_DEB}" --contents "${deb}")
set(contents "${run_out}")
set(doc ./usr/share/doc/odoloc)
set(expected ./usr/bin/odoloc ./usr/share/man/man1/odoloc.1.gz ${doc}/copyright
             ${doc}/changelog.gz)
foreach(md host-tool simulator lcm hls sweep spi register-map)
  list(APPEND expected ${doc}/${md}.md)
endforeach()
file(GLOB_RECURSE examples RELATIVE "${SOURCE_DIR}/examples" "${SOURCE_DIR}/examples/*")
file(GLOB lcmtypes RELATIVE "${SOURCE_DIR}/host_tools/support/lcm/lcmtypes"
     "${SOURCE_DIR}/host_tools/support/lcm/lcmtypes/*.lcm")
if(NOT examples OR NOT lcmtypes)
  message(FATAL_ERROR "no examples/ files or no .lcm files under ${SOURCE_DIR}")
endif()
list(TRANSFORM examples PREPEND ${doc}/examples/)
# The Python reader and types (one module per .lcm); with -DLCM_SPY=ON (the
# build found a JDK and liblcm-java) the Java types jar and the launcher
# with its man page.
set(python ./usr/lib/python3/dist-packages)
list(APPEND expected ${python}/odoloc_lcmlog.py ${python}/odoloc_lcm/__init__.py)
if(LCM_SPY)
  list(APPEND expected ./usr/bin/odoloc-lcm-spy ./usr/share/man/man1/odoloc-lcm-spy.1.gz
       ./usr/share/odoloc/java/odoloc_lcm_types.jar)
endif()
foreach(lcm IN LISTS lcmtypes)
  string(REGEX REPLACE "\\.lcm$" ".py" module "${lcm}")
  list(APPEND expected ${python}/odoloc_lcm/${module})
endforeach()
list(TRANSFORM lcmtypes PREPEND ./usr/share/odoloc/lcmtypes/)
list(APPEND expected ${examples} ${lcmtypes})
string(REPLACE "\n" ";" lines "${contents}")
set(paths "")
foreach(line IN LISTS lines)
  if(NOT line MATCHES "^([-dlrwxst]+) ([^ ]+) +[0-9]+ [0-9-]+ [0-9:]+ (.*)$")
    continue()
  endif()
  set(mode "${CMAKE_MATCH_1}")
  set(owner "${CMAKE_MATCH_2}")
  string(REGEX REPLACE "/$" "" path "${CMAKE_MATCH_3}")
  list(APPEND paths "${path}")
  if(mode MATCHES "^d")
    set(want drwxr-xr-x)
  elseif(path MATCHES "^\\./usr/bin/" OR path MATCHES "\\.sbatch$")
    set(want -rwxr-xr-x)
  else()
    set(want -rw-r--r--)
  endif()
  if(NOT mode STREQUAL want OR NOT owner STREQUAL "root/root")
    message(FATAL_ERROR "${path}: ${mode} ${owner}, expected ${want} root/root")
  endif()
endforeach()
foreach(path IN LISTS expected)
  if(NOT path IN_LIST paths)
    message(FATAL_ERROR "the package has no ${path}:\n${contents}")
  endif()
endforeach()
if(contents MATCHES "test_|odoloc_demo|odoloc_bench")
  message(FATAL_ERROR "the package carries development programs:\n${contents}")
endif()

# The fields and the control members.
run("dpkg-deb --field" COMMAND "${DPKG_DEB}" --field "${deb}" Package Version Depends Recommends)
set(fields "${run_out}")
string(REGEX REPLACE "\n$" "" fields_shown "${fields}")
foreach(want "Package: odoloc\n" "Version: ${VERSION}\n" "Depends: [^\n]*libc6"
             "Recommends: [^\n]*gnuplot-nox \\| gnuplot[,\n]" "Recommends: [^\n]*liblcm-bin")
  if(NOT fields MATCHES "${want}")
    message(FATAL_ERROR "the package's fields do not match '${want}':\n${fields_shown}")
  endif()
endforeach()
run("dpkg-deb --ctrl-tarfile | tar" COMMAND "${DPKG_DEB}" --ctrl-tarfile "${deb}"
    COMMAND tar -tvf -)
foreach(member control md5sums)
  if(NOT run_out MATCHES "-rw-r--r-- root/root [^\n]* \\./${member}\n")
    message(FATAL_ERROR "control member ${member} missing or not 0644 root/root:\n${run_out}")
  endif()
endforeach()

# Unpacked.
set(root "${OUT}/root")
run("dpkg-deb --extract" COMMAND "${DPKG_DEB}" --extract "${deb}" "${root}")
run("dpkg-deb --control" COMMAND "${DPKG_DEB}" --control "${deb}" "${OUT}/DEBIAN")
run("md5sum -c DEBIAN/md5sums" COMMAND md5sum --quiet -c "${OUT}/DEBIAN/md5sums"
    WORKING_DIRECTORY "${root}")
run("the packaged odoloc --version" COMMAND "${root}/usr/bin/odoloc" --version)
if(NOT run_out MATCHES "^odoloc ${VERSION} ")
  message(FATAL_ERROR "the packaged odoloc --version says '${run_out}', not ${VERSION}")
endif()

# gzip -n: deflate, no flags (so no FNAME) and MTIME (bytes 4-7) zero.
foreach(gz usr/share/doc/odoloc/changelog.gz usr/share/man/man1/odoloc.1.gz)
  file(READ "${root}/${gz}" head LIMIT 8 HEX)
  if(NOT head STREQUAL "1f8b080000000000")
    message(FATAL_ERROR "${gz} is not gzip -n (name or time stamp stored): header ${head}")
  endif()
endforeach()
run("gzip -dc changelog.gz" COMMAND gzip -dc "${root}/usr/share/doc/odoloc/changelog.gz"
    OUTPUT_FILE "${OUT}/changelog")
run(dpkg-parsechangelog COMMAND "${DPKG_PARSECHANGELOG}" -l "${OUT}/changelog" -S Version)
if(NOT run_out STREQUAL "${VERSION}\n")
  message(FATAL_ERROR "the changelog's latest entry is '${run_out}', not ${VERSION} "
                      "(add an entry to packaging/changelog.in)")
endif()

# The man page: groff with every warning on, as `man` renders it.
run("gzip -dc odoloc.1.gz" COMMAND gzip -dc "${root}/usr/share/man/man1/odoloc.1.gz"
    OUTPUT_FILE "${OUT}/odoloc.1")
# -P-cbou: plain text, no bold or underline.
run("groff -man" COMMAND "${GROFF}" -man -Tutf8 -wall -P-cbou "${OUT}/odoloc.1")
set(page "${run_out}")
if(run_err)
  message(FATAL_ERROR "groff warns about the man page:\n${run_err}")
endif()
file(READ "${OUT}/odoloc.1" source)
if(NOT source MATCHES "\n\\.TH ODOLOC \"1\" \"[^\"]+\" \"odoloc ${VERSION}\""
   OR NOT source MATCHES "\n\\.SH NAME\nodoloc \\\\- [^\n]+\n")
  message(FATAL_ERROR "the man page's title or NAME line is wrong:\n${source}")
endif()
run("the packaged odoloc --help" COMMAND "${root}/usr/bin/odoloc" --help)
# The commands: the lines "  NAME   summary" after "Subcommands:", up to a
# blank line.
# (Brackets out first: a ";" between "[" and "]" would not split the list.)
string(REGEX REPLACE "[][]" "" lines "${run_out}")
string(REPLACE "\n" ";" lines "${lines}")
set(commands "")
set(in_list OFF)
foreach(line IN LISTS lines)
  if(line STREQUAL "Subcommands:")
    set(in_list ON)
  elseif(line STREQUAL "")
    set(in_list OFF)
  elseif(in_list AND line MATCHES "^  ([a-z][a-z-]*) ")
    list(APPEND commands "${CMAKE_MATCH_1}")
  endif()
endforeach()
list(LENGTH commands n)
if(n LESS 5)
  message(FATAL_ERROR "found ${n} commands in odoloc --help:\n${run_out}")
endif()
foreach(command IN LISTS commands)
  if(NOT page MATCHES "\n       ${command}[ \n]")
    message(FATAL_ERROR "the man page does not list the command ${command}:\n${page}")
  endif()
endforeach()
message("${deb}: ${n} commands in the man page, all checks passed")
file(REMOVE_RECURSE "${OUT}")
