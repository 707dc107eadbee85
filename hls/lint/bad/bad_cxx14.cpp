// Rule sample "cxx14" for hls_lint.py: kernels are ISO C++14, the newest
// standard every HLS front end accepts; clang takes these later forms and
// extensions in C++14 mode with only a warning, which the lint makes an error.
namespace odoloc::lint_sample {  // expect: cxx14

inline constexpr int kTaps = 4;  // expect: cxx14

template <typename T>
int width() {
  if constexpr (sizeof(T) > 2)  // expect: cxx14
    return 32;
  return 16;
}

struct Port {
  int data;
  int valid;
};
constexpr Port kIdle{.data = 0, .valid = 0};  // expect: cxx14

}  // namespace odoloc::lint_sample
