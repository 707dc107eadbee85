# odoloc_warnings: the one warning set every odoloc target links. The same
# set under clang (the fuzz preset): clang's -Wconversion also turns on
# -Wsign-conversion, which GCC's leaves out for C++.
add_library(odoloc_warnings INTERFACE)
target_compile_options(odoloc_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wcast-align -Wnull-dereference
  -Wimplicit-fallthrough $<$<CXX_COMPILER_ID:Clang>:-Wno-sign-conversion>
  $<$<COMPILE_LANGUAGE:CXX>:-Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual>
  $<$<BOOL:${ODOLOC_WERROR}>:-Werror>)
