// A kernel against its cycle-model reference (hls/verification, found through the kernel
// table of hls/export), call by call: the same seeded stimulus goes into the model and,
// through the kernel's field lists (visit_fields), into the kernel; every output of every call must
// be equal. Used by test_hls_<kernel>_<family>, once per type family.
//
// The number of calls is ODOLOC_HLS_CALLS when set (the hls_long tests set
// 1e8), else the default given, scaled by ODOLOC_TEST_SCALE.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/hls/types.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "test_scale.hpp"

namespace odoloc::tb {

struct KernelCheck {
  std::uint64_t calls = 0;
  std::uint64_t mismatches = 0;
  std::string first_mismatch;  // call, field, kernel and model values
  std::string names_error;     // the kernel's field lists differ from the reference's
};

inline std::uint64_t hls_calls(std::uint64_t default_calls) {
  const char* env = std::getenv("ODOLOC_HLS_CALLS");  // NOLINT(concurrency-mt-unsafe)
  if (env != nullptr && std::strtoull(env, nullptr, 10) > 0)
    return std::strtoull(env, nullptr, 10);
  return scaled(default_calls);
}

// Kernel: Inputs, Outputs, Registers types, their field lists visit_fields
// (found by argument-dependent lookup) and its step(Registers&, const
// Inputs&, Outputs&).
template <class Inputs, class Outputs, class Registers, class Step>
KernelCheck check_kernel(std::string_view kernel_name, std::uint64_t seed, std::uint64_t calls,
                         Step step) {
  KernelCheck result;
  const hls_export::KernelDescription* kernel = hls_export::find_kernel(kernel_name);
  if (kernel == nullptr) {
    result.names_error = "no reference for kernel " + std::string(kernel_name);
    return result;
  }
  const auto reference = kernel->make_reference(seed);
  Inputs in{};
  Outputs out{};
  std::vector<std::string_view> in_names, out_names;
  visit_fields(in, [&](const char* name, auto&) { in_names.emplace_back(name); });
  visit_fields(out, [&](const char* name, auto&) { out_names.emplace_back(name); });
  const auto ref_in = reference->input_names();
  const auto ref_out = reference->output_names();
  if (!std::equal(in_names.begin(), in_names.end(), ref_in.begin(), ref_in.end()) ||
      !std::equal(out_names.begin(), out_names.end(), ref_out.begin(), ref_out.end())) {
    result.names_error = "the kernel's field lists differ from the reference's";
    return result;
  }
  std::vector<std::int64_t> in_row(in_names.size()), want(out_names.size());
  Registers regs{};
  for (std::uint64_t call = 0; call < calls; ++call) {
    reference->stimulus(in_row);
    reference->step(in_row, want);
    std::size_t i = 0;
    visit_fields(in, [&](const char*, auto& field) { field = in_row[i++]; });
    step(regs, in, out);
    std::size_t o = 0;
    visit_fields(out, [&](const char* name, auto& field) {
      const long long got = hls::to_s64(field);
      if (got != want[o] && result.mismatches++ == 0)
        result.first_mismatch = "call " + std::to_string(call) + ", " + name + ": kernel " +
                                std::to_string(got) + ", model " + std::to_string(want[o]);
      ++o;
    });
    ++result.calls;
  }
  std::printf("%.*s (%s): %llu calls, %llu mismatches\n", static_cast<int>(kernel_name.size()),
              kernel_name.data(), hls::kTypeFamily, static_cast<unsigned long long>(result.calls),
              static_cast<unsigned long long>(result.mismatches));
  return result;
}

// The first register in which a kernel and its model differ, or "":
// walk(f) calls f(name, kernel register, model register) for every register
// (a kernel integer of any family, a model UInt or SInt).
template <class Walk>
std::string first_difference(Walk&& walk) {
  std::string first;
  walk([&](const char* name, const auto& kernel, const auto& model) {
    const long long got = hls::to_s64(kernel);
    const auto want = static_cast<long long>(model.value());
    if (first.empty() && got != want)
      first =
          std::string(name) + ": kernel " + std::to_string(got) + ", model " + std::to_string(want);
  });
  return first;
}

}  // namespace odoloc::tb
