// Rule sample "recursion" for hls_lint.py: a circuit has no call stack, so
// HLS tools inline every call and cannot inline a recursive one.
int factorial(int n) {  // expect: recursion
  return n <= 1 ? 1 : n * factorial(n - 1);
}

int is_odd(int n);

int is_even(int n) {  // expect: recursion
  return n == 0 ? 1 : is_odd(n - 1);
}

int is_odd(int n) {  // expect: recursion
  return n == 0 ? 0 : is_even(n - 1);
}

// Recursion among templates at compile time builds no call chain: allowed.
template <int N>
struct Power2 {
  static constexpr int value = 2 * Power2<N - 1>::value;
};
template <>
struct Power2<0> {
  static constexpr int value = 1;
};
constexpr int kSixteen = Power2<4>::value;
