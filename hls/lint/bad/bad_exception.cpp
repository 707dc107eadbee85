// Rule sample "exception" for hls_lint.py: HLS tools compile without
// exceptions (a circuit cannot unwind); report errors in an output port.
int checked_div(int a, int b) {
  if (b == 0)
    throw 1;  // expect: exception
  return a / b;
}

int safe_div(int a, int b) {
  try {  // expect: exception
    return checked_div(a, b);
  } catch (...) {
    return 0;
  }
}
