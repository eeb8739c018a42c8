// CPU-feature detection: stable answers, each wider feature implying the narrower ones the kernels
// pair it with, and on x86-64 Linux the same answer as the kernel's /proc/cpuinfo flags (the kernel
// clears a flag whose register state the OS does not save, as the detection does).
#include "libs/base/cpu_features.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace haptex::base {
namespace {

TEST(CpuFeaturesTest, AnswersAreStable) {
  const bool avx = CpuHasAvx(), avx2 = CpuHasAvx2(), avx512vl = CpuHasAvx512Vl();
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(CpuHasAvx(), avx);
    EXPECT_EQ(CpuHasAvx2(), avx2);
    EXPECT_EQ(CpuHasAvx512Vl(), avx512vl);
  }
}

TEST(CpuFeaturesTest, WiderFeaturesImplyNarrowerOnes) {
  EXPECT_TRUE(!CpuHasAvx2() || CpuHasAvx());
  // The 32-register kernels are the AVX2 ones on AVX-512 registers: they need both.
  EXPECT_TRUE(!CpuHasAvx512Vl() || CpuHasAvx2());
}

#ifdef HAPTEX_X86_KERNELS
std::set<std::string> CpuinfoFlags() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("flags", 0) != 0) continue;
    std::istringstream words(line.substr(line.find(':') + 1));
    std::set<std::string> flags;
    for (std::string w; words >> w;) flags.insert(w);
    return flags;
  }
  return {};
}

TEST(CpuFeaturesTest, AgreesWithTheKernel) {
  const std::set<std::string> flags = CpuinfoFlags();
  if (flags.empty()) GTEST_SKIP() << "no /proc/cpuinfo flags";
  EXPECT_EQ(CpuHasAvx(), flags.count("avx") == 1);
  EXPECT_EQ(CpuHasAvx2(), flags.count("avx2") == 1);
  EXPECT_EQ(CpuHasAvx512Vl(), flags.count("avx512f") == 1 && flags.count("avx512vl") == 1);
}
#else
TEST(CpuFeaturesTest, NoVectorKernelsWithoutX86) {
  EXPECT_FALSE(CpuHasAvx());
  EXPECT_FALSE(CpuHasAvx2());
  EXPECT_FALSE(CpuHasAvx512Vl());
}
#endif

}  // namespace
}  // namespace haptex::base
