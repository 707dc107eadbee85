# odoloc_warnings: the one warning set every odoloc target links.
add_library(odoloc_warnings INTERFACE)
target_compile_options(odoloc_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wcast-align -Wnull-dereference
  -Wimplicit-fallthrough
  $<$<COMPILE_LANGUAGE:CXX>:-Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual>
  $<$<BOOL:${ODOLOC_WERROR}>:-Werror>)
