// The exported trees' testbench (hls/testbench/golden_testbench.hpp) as a
// parser of golden-vector files: a valid file passes; every malformed one
// (wrong or missing column names, short, long or non-numeric rows, over-long
// lines, no rows, no file) fails with its reason; and thousands of random
// mutations of a valid file never crash it (the sanitize preset runs this
// under ASan and UBSan) and mostly fail. Runs on the CORDIC kernel.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "golden_testbench.hpp"
#include "odoloc/hls/cordic_kernel.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "text_mutation.hpp"

namespace {

namespace fs = std::filesystem;
namespace hc = odoloc::hls::cordic;

// The top function as the exported tree has it: a kernel with static state.
hc::Registers top_registers;
void top(const hc::Inputs& in, hc::Outputs& out) {
  hc::step(top_registers, in, out);
}

std::string valid_file(int calls) {
  const auto reference = odoloc::hls_export::find_kernel("cordic")->make_reference(3);
  std::ostringstream text;
  text << "# a comment\n# in: load angle clear_flags reset\n# out: busy ready load_ignored sin "
          "cos\n";
  std::vector<std::int64_t> in(4), out(5);
  for (int call = 0; call < calls; ++call) {
    reference->stimulus(in);
    reference->step(in, out);
    for (auto v : in)
      text << v << ' ';
    for (std::size_t i = 0; i < out.size(); ++i)
      text << out[i] << (i + 1 < out.size() ? " " : "\n");
  }
  return text.str();
}

// run_golden() on this text, from power-on state; its printed lines in `printed`.
int run(const std::string& text, std::string* printed = nullptr) {
  const fs::path path = fs::path(::testing::TempDir()) / "golden_vectors.txt";
  std::ofstream(path, std::ios::binary) << text;
  top_registers = hc::Registers();
  ::testing::internal::CaptureStdout();
  const int status = odoloc::hls::golden::run_golden<hc::Inputs, hc::Outputs>(path.c_str(), top);
  const std::string output = ::testing::internal::GetCapturedStdout();
  if (printed != nullptr)
    *printed = output;
  return status;
}

void expect_fails(const std::string& text, const std::string& reason) {
  std::string printed;
  EXPECT_EQ(run(text, &printed), 1) << reason;
  EXPECT_NE(printed.find(reason), std::string::npos) << printed;
}

TEST(GoldenTestbench, AValidFilePasses) {
  std::string printed;
  EXPECT_EQ(run(valid_file(500), &printed), 0);
  EXPECT_NE(printed.find("PASS: 500 calls"), std::string::npos) << printed;
}

TEST(GoldenTestbench, MalformedFilesFailWithTheirReason) {
  const std::string good = valid_file(50);
  const auto first_row = good.find('\n', good.find("# out:")) + 1;
  const std::string header = good.substr(0, first_row);
  const std::string rows = good.substr(first_row);
  expect_fails(header, "holds no vectors");
  expect_fails(rows, "a row before the '# in:' and '# out:' lines");
  std::string renamed = good;
  renamed.replace(renamed.find("angle"), 5, "angel");
  expect_fails(renamed, "the columns are not this kernel's input fields");
  std::string extra = good;
  extra.replace(extra.find("cos\n"), 4, "cos tan\n");
  expect_fails(extra, "the columns are not this kernel's output fields");
  expect_fails(header + "1 2 3\n", "malformed row");
  expect_fails(header + "0 0 0 0 0 0 0 0 0 0\n", "malformed row");
  expect_fails(header + "0 0 0 0 0 0 0 0 x\n", "malformed row");
  expect_fails(header + std::string(9000, '0') + "\n", "line longer than");
  std::string changed = good;
  changed.replace(changed.rfind(' ') + 1, std::string::npos, "12345\n");
  expect_fails(changed, "MISMATCH call 49, cos");
  const int missing =
      odoloc::hls::golden::run_golden<hc::Inputs, hc::Outputs>("/nonexistent/vectors.txt", top);
  EXPECT_EQ(missing, 1);
}

TEST(GoldenTestbench, RandomMutationsNeverCrash) {
  const std::string good = valid_file(40);
  std::mt19937_64 rng(11);
  const std::string alphabet = "0123456789 -#\nx\t";
  int failed = 0;
  for (int n = 0; n < 2000; ++n) {
    const int status = run(odoloc::tb::mutated(good, rng, alphabet, 4, 8));
    ASSERT_TRUE(status == 0 || status == 1);
    failed += status;
  }
  EXPECT_GT(failed, 1500);  // most mutations break a value or a row
}

}  // namespace
