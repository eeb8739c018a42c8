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
}

}  // namespace
}  // namespace haptex::scene
