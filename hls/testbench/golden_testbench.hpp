// The C-simulation testbench of an exported kernel tree (odoloc export-hls):
// replays golden vectors made by the cycle model through the top function and
// compares every output of every call. C++14 and the C library only, so it
// builds with g++ alone and inside Vitis HLS (csim), Catapult (SCVerify) and
// Intel HLS (i++ -march=x86-64).
//
// Golden vector file (text):
//   # any comment
//   # in: NAME NAME ...     the Inputs fields, in visit_fields order
//   # out: NAME NAME ...    the Outputs fields, in visit_fields order
//   V V ... V              per call: the inputs, then the outputs after the
//                          call, as decimal integers (signed fields signed)
// run_golden() returns 0 when the names match the kernel's, at least one call
// was replayed and no output differed; else it prints why and returns 1.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace odoloc {
namespace hls {
namespace golden {

constexpr int kMaxLine = 8192;
constexpr int kMaxReportedMismatches = 10;

// Checks that a "# in:" / "# out:" line names the struct's fields in order.
struct NameCheck {
  const char* cursor;
  bool ok;
  template <class Field>
  void operator()(const char* name, Field&) {
    while (*cursor == ' ' || *cursor == '\t')
      ++cursor;
    const std::size_t n = std::strlen(name);
    if (std::strncmp(cursor, name, n) != 0 ||
        (cursor[n] != ' ' && cursor[n] != '\t' && cursor[n] != '\n' && cursor[n] != '\r' &&
         cursor[n] != '\0'))
      ok = false;
    else
      cursor += n;
  }
};

// Reads the next integer of a row into a field.
struct ReadField {
  const char* cursor;
  bool ok;
  template <class Field>
  void operator()(const char*, Field& field) {
    char* end = nullptr;
    const long long v = std::strtoll(cursor, &end, 10);
    if (end == cursor)
      ok = false;
    cursor = end;
    field = v;
  }
};

// Compares the next integer of a row with a field.
struct CompareField {
  const char* cursor;
  bool ok;
  long call;
  int* mismatches;
  template <class Field>
  void operator()(const char* name, Field& field) {
    char* end = nullptr;
    const long long want = std::strtoll(cursor, &end, 10);
    if (end == cursor)
      ok = false;
    cursor = end;
    const long long got = to_s64(field);
    if (ok && got != want) {
      if (*mismatches < kMaxReportedMismatches)
        std::printf("MISMATCH call %ld, %s: kernel %lld, golden %lld\n", call, name, got, want);
      ++*mismatches;
    }
  }
};

inline bool at_end(const char* cursor) {
  while (*cursor == ' ' || *cursor == '\t' || *cursor == '\r' || *cursor == '\n')
    ++cursor;
  return *cursor == '\0';
}

// Top: void top(const Inputs&, Outputs&), the kernel's top function.
template <class Inputs, class Outputs, class Top>
int run_golden(const char* path, Top top) {
  std::FILE* file = std::fopen(path, "r");
  if (file == nullptr) {
    std::printf("FAIL: cannot open golden vectors %s\n", path);
    return 1;
  }
  static char line[kMaxLine];
  Inputs in = Inputs();
  Outputs out = Outputs();
  bool have_in = false, have_out = false, ok = true;
  long calls = 0, number = 0;
  int mismatches = 0;
  while (ok && std::fgets(line, kMaxLine, file) != nullptr) {
    ++number;
    if (std::strchr(line, '\n') == nullptr && !std::feof(file)) {
      std::printf("FAIL: %s:%ld: line longer than %d characters\n", path, number, kMaxLine - 1);
      ok = false;
    } else if (std::strncmp(line, "# in:", 5) == 0 || std::strncmp(line, "# out:", 6) == 0) {
      const bool is_in = line[2] == 'i';
      NameCheck check = {line + (is_in ? 5 : 6), true};
      if (is_in)
        visit_fields(in, check);
      else
        visit_fields(out, check);
      if (!check.ok || !at_end(check.cursor)) {
        std::printf("FAIL: %s:%ld: the columns are not this kernel's %s fields\n", path, number,
                    is_in ? "input" : "output");
        ok = false;
      }
      (is_in ? have_in : have_out) = true;
    } else if (line[0] == '#' || at_end(line)) {
      continue;
    } else if (!have_in || !have_out) {
      std::printf("FAIL: %s:%ld: a row before the '# in:' and '# out:' lines\n", path, number);
      ok = false;
    } else {
      ReadField read = {line, true};
      visit_fields(in, read);
      top(in, out);
      CompareField compare = {read.cursor, read.ok, calls, &mismatches};
      visit_fields(out, compare);
      if (!compare.ok || !at_end(compare.cursor)) {
        std::printf("FAIL: %s:%ld: malformed row\n", path, number);
        ok = false;
      }
      ++calls;
    }
  }
  std::fclose(file);
  if (ok && calls == 0) {
    std::printf("FAIL: %s holds no vectors\n", path);
    ok = false;
  }
  if (!ok)
    return 1;
  if (mismatches != 0) {
    std::printf("FAIL: %d of the outputs of %ld calls differ from the golden vectors\n", mismatches,
                calls);
    return 1;
  }
  std::printf("PASS: %ld calls, every output equals the golden vectors\n", calls);
  return 0;
}

}  // namespace golden
}  // namespace hls
}  // namespace odoloc
