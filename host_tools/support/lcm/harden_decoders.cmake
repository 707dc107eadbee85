# cmake -DHEADER_DIR=<folder of lcm-gen's .hpp files> -P harden_decoders.cmake
#
# lcm-gen 1.3.1's C++ decoder reads a string's length L (terminator
# included) from the message, checks only L <= bytes left, then copies
# L - 1 bytes: L = INT32_MIN overflows L - 1 to INT32_MAX, a 2 GiB read past
# the buffer (test_lcm_messages crashes on it), and L <= 0 asks std::string
# for an impossible size. Every such check becomes 1 <= L <= bytes left, so
# the message fails to decode like any other malformed one. Fails when a
# header copies a string without the check it expects (another lcm-gen).
cmake_minimum_required(VERSION 3.25)

set(check "if\\(__([A-Za-z0-9_]+)_len__ > maxlen - pos\\) return -1")
file(GLOB headers ${HEADER_DIR}/*.hpp)
if(NOT headers)
  message(FATAL_ERROR "harden_decoders.cmake: no headers in ${HEADER_DIR}")
endif()
foreach(header IN LISTS headers)
  file(READ ${header} text)
  string(REGEX MATCHALL "\\.assign\\(" copies "${text}")
  string(REGEX MATCHALL "${check}" checks "${text}")
  list(LENGTH copies copy_count)
  list(LENGTH checks check_count)
  if(NOT copy_count EQUAL check_count)
    message(FATAL_ERROR "${header}: ${copy_count} string copies but ${check_count} length "
                        "checks of the form lcm-gen 1.3.1 writes; review harden_decoders.cmake")
  endif()
  string(REGEX REPLACE "${check}" "if(__\\1_len__ < 1 || __\\1_len__ > maxlen - pos) return -1"
                       text "${text}")
  file(WRITE ${header} "${text}")
endforeach()
