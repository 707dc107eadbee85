// Rule sample "float" for hls_lint.py: floating point in code that runs on
// the fabric costs a floating-point core per operation; kernels compute in
// fixed-width integers. Compile-time arithmetic (constexpr variables, and
// constexpr functions only compile-time code calls) is exempt: the compiler
// folds it to integers.
float scale(float x) {  // expect: float
  return x * 0.5F;      // expect: float
}

int to_fixed(int x) {
  return static_cast<int>(x * 1.5);  // expect: float
}

struct Sample {
  double value;  // expect: float
};

constexpr double kHalf = 0.5;
constexpr int kHalfQ8 = static_cast<int>(kHalf * 256);  // folded: allowed
int halve_q8(int x) {
  return x * kHalfQ8;
}

int halve(int x) {
  return static_cast<int>(x * kHalf);  // expect: float
}

// Called from run-time code: its floating point runs on the fabric.
constexpr int three_halves(int x) {
  return static_cast<int>(x * 1.5);  // expect: float
}
int use_three_halves(int x) {
  return three_halves(x);
}
