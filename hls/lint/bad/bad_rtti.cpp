// Rule sample "rtti" for hls_lint.py: HLS tools compile without run-time
// type information. (dynamic_cast needs a polymorphic class, so "virtual"
// fires too.)
#include <typeinfo>

struct Base {         // expect: virtual
  virtual ~Base() {}  // expect: virtual
};
struct Derived : Base {  // expect: virtual
  int value = 1;
};

int type_name_length() {
  return typeid(int).name()[0];  // expect: rtti
}

int value_of(Base& base) {
  Derived* derived = dynamic_cast<Derived*>(&base);  // expect: rtti
  return derived ? derived->value : 0;
}
