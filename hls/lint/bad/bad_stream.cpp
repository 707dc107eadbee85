// Rule sample "stream" for hls_lint.py: iostreams, printf and files have no
// hardware; testbench output stays in the testbench (or under
// #ifndef __SYNTHESIS__, which the lint defines as the HLS tools do).
#include <cstdio>
#include <iostream>
#include <sstream>

void trace(int x) {
  std::cout << x << '\n';  // expect: stream
}

int parse(const char* text) {
  std::istringstream in(text);  // expect: stream, container (text becomes a std::string)
  int value = 0;
  in >> value;  // expect: stream
  return value;
}

void log_value(int x) {
  std::printf("%d\n", x);  // expect: stream
}

void dump(int x) {
  std::FILE* file = std::fopen("dump.txt", "w");  // expect: stream
  std::fclose(file);                              // expect: stream
  (void)x;
}

int simulation_only(int x) {
#ifndef __SYNTHESIS__
  std::printf("%d\n", x);  // C simulation only: not seen by the lint
#endif
  return x;
}
