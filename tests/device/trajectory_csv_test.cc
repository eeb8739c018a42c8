#include "libs/device/trajectory_csv.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

const std::string kHeader = std::string(kTrajectoryCsvHeader) + "\n";

void ExpectError(const std::string& text, const std::string& fragment) {
  try {
    ParseTrajectoryCsv(text);
    FAIL() << "expected std::invalid_argument containing '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(TrajectoryCsvTest, ParsesRowsCommentsAndCrLf) {
  const std::string text = "# recorded 2026-11-21\r\n" + kHeader +
                           "0.0,0.01,-0.03,0,0.01,0.03,0\r\n"
                           "\n"
                           "0.5, 0.012 ,-0.02,0.001,0.01,0.02,-1e-3\n";
  const auto samples = ParseTrajectoryCsv(text);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples[1].t_s, 0.5);
  EXPECT_EQ(samples[1].thumb_D_m, Eigen::Vector3d(0.012, -0.02, 0.001));
  EXPECT_EQ(samples[1].index_D_m, Eigen::Vector3d(0.01, 0.02, -0.001));
}

TEST(TrajectoryCsvTest, BadInputNamesTheLine) {
  ExpectError("", "empty");
  ExpectError("t,x\n0,1\n", "line 1: expected header");
  ExpectError(kHeader + "0,0,0,0,0,0,0\n1,0,0,0,0,0\n", "line 3: expected 7 fields, got 6");
  ExpectError(kHeader + "0,0,0,0,0,0,0,0\n", "line 2: expected 7 fields, got 8");
  ExpectError(kHeader + "0,0,abc,0,0,0,0\n1,0,0,0,0,0,0\n", "line 2: field 3 is not a number: 'abc'");
  ExpectError(kHeader + "0,0,,0,0,0,0\n", "line 2: field 3 is not a number");
  ExpectError(kHeader + "0,0,0,nan,0,0,0\n", "line 2: field 4 is not finite");
  ExpectError(kHeader + "0,0,0,0,0,0,0\n0,0,0,0,0,0,0\n", "line 3: t_s must increase strictly");
  ExpectError(kHeader + "0,0,0,0,0,0,0\n", "at least 2 samples");
}

TEST(TrajectoryCsvTest, LoadReportsThePath) {
  EXPECT_THROW(LoadTrajectoryCsv("/nonexistent/trajectory.csv"), std::invalid_argument);
  EXPECT_THROW(LoadTrajectoryCsv("/dev/zero"), std::invalid_argument);  // refused, not read
  EXPECT_THROW(LoadTrajectoryCsv(::testing::TempDir()), std::invalid_argument);
  const std::string path = ::testing::TempDir() + "/haptex_device_trajectory.csv";
  {
    std::ofstream out(path);
    out << kHeader << "0,0,0,0,0,0,0\n0.1,0,0,1e9x,0,0,0\n";
  }
  try {
    LoadTrajectoryCsv(path);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": line 3"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace haptex::device
