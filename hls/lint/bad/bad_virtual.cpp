// Rule sample "virtual" for hls_lint.py: a virtual call is an indirect call
// through a vtable, which a circuit cannot have; templates give the same
// reuse at compile time.
struct Filter {                        // expect: virtual
  virtual ~Filter() {}                 // expect: virtual
  virtual int apply(int x) const = 0;  // expect: virtual
};

struct Gain : Filter {                               // expect: virtual
  int apply(int x) const override { return 2 * x; }  // expect: virtual
};

struct Shared : virtual Gain {};  // expect: virtual

int run(const Filter& filter, int x) {
  return filter.apply(x);  // expect: virtual
}
