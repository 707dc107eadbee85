// Rule sample "unbounded-loop" for hls_lint.py: a loop becomes hardware
// (unrolled, or a state machine with a fixed latency), so its trip count must
// be known when the circuit is built: for (int i = C0; i < C1; ++i) with
// constants C0 and C1. Loops in constexpr functions that only compile-time
// code calls are exempt: the compiler runs them, not the circuit.
int count_bits(unsigned x) {
  int n = 0;
  while (x != 0) {  // expect: unbounded-loop
    n += static_cast<int>(x & 1U);
    x >>= 1;
  }
  return n;
}

int poll(const volatile int* status) {
  int tries = 0;
  do {  // expect: unbounded-loop
    ++tries;
  } while (*status == 0);
  return tries;
}

int sum_to(int n) {
  int sum = 0;
  for (int i = 0; i < n; ++i)  // expect: unbounded-loop
    sum += i;
  return sum;
}

int skip_ahead(int x) {
  int sum = 0;
  for (int i = 0; i < 8; ++i) {  // expect: unbounded-loop
    if (x > i)
      i += 2;
    sum += i;
  }
  return sum;
}

int wrong_way() {
  int sum = 0;
  for (int i = 0; i < 8; --i)  // expect: unbounded-loop
    sum += i;
  return sum;
}

int forever(const volatile int* status) {
  for (;;) {  // expect: unbounded-loop
    if (*status != 0)
      return *status;
  }
}

int retry(int x) {
again:
  if (--x > 0)
    goto again;  // expect: unbounded-loop
  return x;
}

// A constexpr function that run-time code calls is run-time code.
constexpr int popcount(unsigned x) {
  int n = 0;
  while (x != 0) {  // expect: unbounded-loop
    n += static_cast<int>(x & 1U);
    x >>= 1;
  }
  return n;
}
int ones(unsigned x) {
  return popcount(x);
}

// Compile time only: exempt.
constexpr int clog2(int n) {
  int bits = 0;
  while ((1 << bits) < n)
    ++bits;
  return bits;
}
constexpr int kAddressBits = clog2(100);
static_assert(clog2(1024) == 10, "compile-time loop");
