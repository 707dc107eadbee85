// Rule sample "container" for hls_lint.py: the standard containers, strings,
// smart pointers and std::function allocate on the heap or call through
// pointers; kernels use fixed-size arrays. A type is reported where it is used.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

int first(const std::vector<int>& samples) {  // expect: container
  return samples.front();                     // expect: container
}

int length(const std::string& text) {    // expect: container
  return static_cast<int>(text.size());  // expect: container
}

int lookup(const std::map<int, int>& table) {  // expect: container
  return table.find(0)->second;                // expect: container
}

int deref(const std::unique_ptr<int>& owner) {  // expect: container
  return *owner;                                // expect: container
}

int call(const std::function<int()>& callback) {  // expect: container
  return callback();                              // expect: container
}

using Samples = std::vector<short>;
int count(const Samples& samples) {         // expect: container
  return static_cast<int>(samples.size());  // expect: container
}
