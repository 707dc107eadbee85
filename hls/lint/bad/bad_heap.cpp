// Rule sample "heap" for hls_lint.py (docs/hls.md, "Synthesizability lint"):
// hardware is fixed when it is built, so nothing can be allocated at run
// time. Every line marked `expect:` must be reported with that rule.
#include <alloca.h>

#include <cstdlib>
#include <memory>

int heap_new(int x) {
  int* p = new int(x);  // expect: heap
  const int v = *p;
  delete p;  // expect: heap
  return v;
}

void heap_discarded() {
  (void)new int[4];  // expect: heap
}

int heap_malloc(int n) {
  int* p = static_cast<int*>(std::malloc(sizeof(int)));  // expect: heap
  *p = n;
  const int v = *p;
  std::free(p);  // expect: heap
  return v;
}

int heap_allocator(int n) {
  std::allocator<int> pool;   // expect: heap
  int* p = pool.allocate(1);  // expect: heap
  *p = n;
  const int v = *p;
  pool.deallocate(p, 1);  // expect: heap
  return v;
}

int heap_alloca(int n) {
  int* p = static_cast<int*>(alloca(sizeof(int)));  // expect: heap
  *p = n;
  return *p;
}

int heap_vla(int n) {
  int samples[n];  // expect: heap
  samples[0] = n;
  return samples[0];
}
