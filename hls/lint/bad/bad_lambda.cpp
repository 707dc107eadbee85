// Rule sample "lambda" for hls_lint.py: Intel HLS rejects lambdas in
// components (docs/hls.md, the kernel convention); write a named inline
// function instead.
int scaled_sum(const int (&samples)[4], int gain) {
  auto scale = [gain](int x) { return gain * x; };  // expect: lambda
  int sum = 0;
  for (int k = 0; k < 4; ++k)
    sum += scale(samples[k]);
  return sum;
}
