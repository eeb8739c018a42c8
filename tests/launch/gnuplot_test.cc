// gnuplot runs inside the plot's folder with fixed file names, and labels cannot carry code.
#include "launch/gnuplot.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/launch/hostile_names.h"
#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

namespace fs = std::filesystem;

TEST(LaunchGnuplotTest, LabelsKeepOnlyPlainText) {
  EXPECT_EQ(GnuplotLabel("denim 11oz (warp)"), "'denim 11oz (warp)'");
  EXPECT_EQ(GnuplotLabel("a'b\nc`d@e!f\\g\"h"), "'a_b_c_d_e_f_g_h'");
  for (const std::string& name : testing::HostileNames("/tmp/never")) {
    const std::string label = GnuplotLabel(name);
    ASSERT_GE(label.size(), 2u);
    EXPECT_LE(label.size(), 82u);
    const std::string inner = label.substr(1, label.size() - 2);
    EXPECT_EQ(inner.find_first_of("'\"`@!$\\\n\r"), std::string::npos) << inner;
    for (const char c : inner) EXPECT_GE(static_cast<unsigned char>(c), 0x20) << label;
  }
}

TEST(LaunchGnuplotTest, RunsInsideItsFolderWhateverTheFolderIsCalled) {
  const std::string marker = testing::FreshDir("gnuplot_marker") + "/injected";
  const std::string dir = testing::FreshDir("gnuplot_run") + "/it's\n!touch " + marker + "\n'";
  fs::create_directories(dir);
  testing::WriteText(dir + "/p.dat", "0 1\n1 2\n");
  testing::WriteText(
      dir + "/p.gp",
      "set terminal pngcairo size 200,100\nset output 'p.png'\nplot 'p.dat' using 1:2 with lines title " +
          GnuplotLabel("x\n!touch " + marker) + "\n");
  EXPECT_EQ(RunGnuplot(dir, "p.gp"), "");
  EXPECT_TRUE(fs::exists(dir + "/p.png"));
  EXPECT_FALSE(fs::exists(dir + "/p.gp.log")) << "the log is removed on success";
  EXPECT_FALSE(fs::exists(marker));
}

TEST(LaunchGnuplotTest, AFailureKeepsItsLog) {
  const std::string dir = testing::FreshDir("gnuplot_fail");
  testing::WriteText(dir + "/bad.gp", "this is not gnuplot\n");
  EXPECT_NE(RunGnuplot(dir, "bad.gp").find("gnuplot failed"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir + "/bad.gp.log"));
}

}  // namespace
}  // namespace haptex::launch
