# odoloc_warnings: the one warning set every odoloc target links.
add_library(odoloc_warnings INTERFACE)
target_compile_options(odoloc_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough
  $<$<BOOL:${ODOLOC_WERROR}>:-Werror>)
