#include "libs/scene/session_key_source.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace haptex::scene {
namespace {

constexpr char kHex[] = "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff";

TEST(SessionKeySourceTest, HexEnvAndFile) {
  v1::SessionKey source;
  source.set_hex(kHex);
  EXPECT_EQ(ResolveSessionKey(source).ToHex(), kHex);

  setenv("HAPTEX_TEST_KEY", kHex, 1);
  source.set_env("HAPTEX_TEST_KEY");
  EXPECT_EQ(ResolveSessionKey(source).ToHex(), kHex);

  const std::string path = ::testing::TempDir() + "/haptex_key_test";
  std::ofstream(path) << kHex << "\n";
  source.set_file(path);
  EXPECT_EQ(ResolveSessionKey(source).ToHex(), kHex);
  std::remove(path.c_str());
}

TEST(SessionKeySourceTest, GenerateAndUnsetMakeFreshKeys) {
  v1::SessionKey source;
  const auto a = ResolveSessionKey(source);
  source.set_generate(true);
  EXPECT_NE(a.ToHex(), ResolveSessionKey(source).ToHex());
}

TEST(SessionKeySourceTest, FailuresNameTheSource) {
  v1::SessionKey source;
  source.set_env("HAPTEX_NO_SUCH_VARIABLE");
  try {
    ResolveSessionKey(source);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("HAPTEX_NO_SUCH_VARIABLE"), std::string::npos);
  }
  source.set_file("/nonexistent/key");
  EXPECT_THROW(ResolveSessionKey(source), std::runtime_error);
  // a device is refused before it is read (it would never end)
  source.set_file("/dev/zero");
  try {
    ResolveSessionKey(source);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace haptex::scene

namespace haptex::scene {
namespace {

TEST(LoadSessionKeyTest, FileFirstThenEnvironmentElseAClearError) {
  constexpr char kFileKey[] = "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff";
  constexpr char kOther[] = "ffeeddccbbaa99887766554433221100ffeeddccbbaa99887766554433221100";
  setenv("HAPTEX_SESSION_KEY", kOther, 1);
  const std::string path = ::testing::TempDir() + "/haptex_load_key_test";
  std::ofstream(path) << kFileKey << "\n";
  EXPECT_EQ(LoadSessionKey(path).ToHex(), kFileKey);
  EXPECT_EQ(LoadSessionKey("").ToHex(), kOther);
  setenv("HAPTEX_SESSION_KEY", "", 1);
  try {
    LoadSessionKey("");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("haptex key generate"), std::string::npos);
  }
  EXPECT_THROW(LoadSessionKey("/nonexistent/key"), std::invalid_argument);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace haptex::scene
