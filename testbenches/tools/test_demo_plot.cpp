// The main job's plot step, run the way the demo and its users run it: the
// script sits next to its CSV, gnuplot runs in that directory (also when the
// directory was given as a relative path), a PNG of the promised size appears,
// and a failing plot reports gnuplot's own message. Skips without gnuplot
// (scripts/setup-debian.sh installs gnuplot-nox).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "odoloc/demo/plot.hpp"
#include "png_size.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::demo::PlotSeries;
using odoloc::tb::png_size;
using odoloc::tb::PngSize;

bool have_gnuplot() {
  return odoloc::process::run_program("gnuplot", {"--version"}, fs::current_path()).ok();
}

// A small trajectories.csv: the truth on a circle and one variant beside it.
void write_csv(const fs::path& file) {
  std::ofstream out(file);
  out << "time_s,truth_x_m,truth_y_m,truth_theta_rad,a_x_m,a_y_m,a_error_mm\n";
  for (int i = 0; i <= 100; ++i) {
    const double t = i * 0.01;
    out << t << ',' << std::cos(t) << ',' << std::sin(t) << ",0," << std::cos(t) + 0.001 << ','
        << std::sin(t) << ",1\n";
  }
}

class DemoPlot : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_gnuplot())
      GTEST_SKIP() << "gnuplot is not installed";
    root_ = fs::temp_directory_path() /
            ("odoloc-plot-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "odoloc-demo");
    write_csv(root_ / "odoloc-demo" / "trajectories.csv");
    previous_ = fs::current_path();
    fs::current_path(root_);  // the demo's default output is relative to where it runs
  }
  void TearDown() override {
    if (!previous_.empty())
      fs::current_path(previous_);
    fs::remove_all(root_);
  }
  fs::path root_, previous_;
};

TEST_F(DemoPlot, RelativeOutputDirectoryGivesAPngOfThePromisedSize) {
  const fs::path script = odoloc::demo::write_plot_script(
      "odoloc-demo", "trajectories.csv", "trajectories.png", "test", {{"a", 5, 7}});
  const auto result = odoloc::demo::run_gnuplot(script);
  ASSERT_TRUE(result.ok()) << result.message;
  const fs::path png = root_ / "odoloc-demo" / "trajectories.png";
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 1000U);
  const PngSize size = png_size(png);
  EXPECT_EQ(size.width, static_cast<std::uint32_t>(odoloc::demo::kPlotWidth));
  EXPECT_EQ(size.height, static_cast<std::uint32_t>(odoloc::demo::kPlotHeight));
}

// The advice the demo prints on failure: cd into the directory and run gnuplot.
TEST_F(DemoPlot, TheScriptRunsFromItsOwnDirectory) {
  odoloc::demo::write_plot_script("odoloc-demo", "trajectories.csv", "trajectories.png", "test",
                                  {{"a", 5, 7}});
  const auto result =
      odoloc::process::run_program("gnuplot", {"trajectories.gp"}, root_ / "odoloc-demo");
  ASSERT_TRUE(result.ok()) << result.message;
  EXPECT_GT(png_size(root_ / "odoloc-demo" / "trajectories.png").width, 0U);
}

TEST_F(DemoPlot, AFailingPlotReportsGnuplotsOwnMessage) {
  const fs::path script = odoloc::demo::write_plot_script(
      "odoloc-demo", "no-such.csv", "trajectories.png", "test", {{"a", 5, 7}});
  const auto result = odoloc::demo::run_gnuplot(script);
  EXPECT_TRUE(result.launched);
  EXPECT_NE(result.exit_status, 0);
  EXPECT_NE(result.message.find("no-such.csv"), std::string::npos) << result.message;
}

TEST(RunProgram, AMissingProgramIsReportedNotLaunched) {
  const auto result =
      odoloc::process::run_program("odoloc-no-such-program", {}, fs::temp_directory_path());
  EXPECT_FALSE(result.launched);
  EXPECT_NE(result.message.find("odoloc-no-such-program"), std::string::npos);
}

}  // namespace
