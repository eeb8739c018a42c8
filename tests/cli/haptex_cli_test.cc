// The `haptex` binary in real processes over loopback UDP.

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <random>
#include <regex>
#include <thread>

#include "libs/net/session_key.h"
#include "libs/net/udp_endpoint.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex {
namespace {

using namespace std::chrono_literals;
using testing::Subprocess;

std::string Haptex() { return testing::BuildDir() + "/cli/haptex"; }

std::string KeyEnv(const net::SessionKey& key) { return "HAPTEX_SESSION_KEY=" + key.ToHex(); }

double JsonNumber(const std::string& json, const std::string& key) {
  const std::regex pattern("\"" + key + "\":(-?[0-9.eE+-]+)");
  std::smatch match;
  if (!std::regex_search(json, match, pattern)) {
    ADD_FAILURE() << "no " << key << " in " << json;
    return -1;
  }
  return std::stod(match[1]);
}

class NetcheckTest : public ::testing::Test {
 protected:
  void StartServer(const net::SessionKey& key) {
    // port 0: the server picks a free port and tells us (parallel tests never collide)
    server_ = std::make_unique<Subprocess>(
        std::vector<std::string>{Haptex(), "netcheck", "serve", "--bind", "127.0.0.1:0", "--seconds", "60"},
        std::vector<std::string>{KeyEnv(key)});
    std::smatch match;
    const std::regex listening("listening on 127\\.0\\.0\\.1:([0-9]+)");
    for (int i = 0; i < 500; ++i) {
      const std::string out = server_->Stdout();
      if (std::regex_search(out, match, listening)) {
        port_ = std::stoi(match[1]);
        return;
      }
      std::this_thread::sleep_for(10ms);
    }
    FAIL() << "server did not start: " << server_->Stderr();
  }
  std::string Address() const { return "127.0.0.1:" + std::to_string(port_); }

  int StopServer() {
    server_->Signal(SIGTERM);
    const auto code = server_->WaitFor(5s);
    EXPECT_TRUE(code.has_value()) << "server ignored SIGTERM";
    return code.value_or(-1);
  }

  net::SessionKey key_ = net::SessionKey::Generate();
  int port_ = 0;
  std::unique_ptr<Subprocess> server_;
};

TEST_F(NetcheckTest, ProbeMeasuresALoopbackLinkWithoutLoss) {
  StartServer(key_);
  Subprocess probe({Haptex(), "netcheck", "probe", "--to", Address(), "--rate", "500", "--seconds", "1", "--json"},
                   {KeyEnv(key_)});
  ASSERT_EQ(probe.WaitFor(30s), 0) << probe.Stdout() << probe.Stderr();
  const std::string json = probe.Stdout();
  EXPECT_EQ(JsonNumber(json, "sent"), 500);
  EXPECT_EQ(JsonNumber(json, "received"), 500);
  EXPECT_EQ(JsonNumber(json, "lost"), 0);
  EXPECT_EQ(JsonNumber(json, "duplicates"), 0);
  EXPECT_GT(JsonNumber(json, "p50"), 0);
  EXPECT_LE(JsonNumber(json, "p50"), JsonNumber(json, "p99"));
  EXPECT_LE(JsonNumber(json, "p99"), JsonNumber(json, "max"));
  EXPECT_TRUE(json.find("\"verdict\":\"good\"") != std::string::npos ||
              json.find("\"verdict\":\"usable\"") != std::string::npos)
      << json;
  EXPECT_EQ(StopServer(), 0);  // SIGTERM is a clean shutdown
  EXPECT_NE(server_->Stdout().find("500 replies"), std::string::npos) << server_->Stdout();
}

TEST_F(NetcheckTest, WrongKeyIsRejectedByTheServerAndReportedAsUnreachable) {
  StartServer(key_);
  Subprocess probe({Haptex(), "netcheck", "probe", "--to", Address(), "--rate", "200", "--seconds", "0.2", "--json",
                    "--grace-ms", "200"},
                   {KeyEnv(net::SessionKey::Generate())});
  EXPECT_EQ(probe.WaitFor(30s), 3);
  EXPECT_NE(probe.Stdout().find("\"verdict\":\"unreachable\""), std::string::npos) << probe.Stdout();
  EXPECT_EQ(StopServer(), 0);
  EXPECT_NE(server_->Stdout().find("bad_mac=40"), std::string::npos) << server_->Stdout();
}

TEST_F(NetcheckTest, ServerSurvivesAFloodOfGarbageAndStillAnswers) {
  StartServer(key_);
  net::UdpEndpoint attacker("127.0.0.1:0");
  const auto target =
      net::UdpEndpoint::Endpoint(asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port_));
  std::mt19937 rng(99);
  std::vector<std::uint8_t> junk;
  for (int i = 0; i < 5000; ++i) {
    junk.resize(rng() % 1500);
    for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
    if (i % 3 == 0 && junk.size() >= 4) junk[0] = 'H', junk[1] = 'P', junk[2] = 'X', junk[3] = 2;
    attacker.SendTo(junk, target);
    if (i % 500 == 0) std::this_thread::sleep_for(1ms);  // let the socket buffer drain
  }
  Subprocess probe({Haptex(), "netcheck", "probe", "--to", Address(), "--rate", "200", "--seconds", "0.5", "--json"},
                   {KeyEnv(key_)});
  ASSERT_EQ(probe.WaitFor(30s), 0) << probe.Stdout();
  EXPECT_EQ(JsonNumber(probe.Stdout(), "lost"), 0);
  EXPECT_EQ(StopServer(), 0);
  const std::string out = server_->Stdout();
  EXPECT_NE(out.find("100 replies"), std::string::npos) << out;
  EXPECT_NE(out.find("bad_mac="), std::string::npos) << out;
}

TEST(HaptexCliTest, MissingKeyExplainsHowToMakeOne) {
  Subprocess probe({Haptex(), "netcheck", "probe", "--to", "127.0.0.1:9"}, {"HAPTEX_SESSION_KEY="});
  // an empty variable is not a key either
  ASSERT_EQ(probe.WaitFor(10s), 2) << probe.Stderr();
  EXPECT_NE(probe.Stderr().find("64 hex digits"), std::string::npos) << probe.Stderr();
}

TEST(HaptexCliTest, BadFlagsAreRefusedWithExitCode2) {
  Subprocess bad_rate({Haptex(), "netcheck", "probe", "--to", "127.0.0.1:9", "--rate", "-5"});
  EXPECT_EQ(bad_rate.WaitFor(10s), 2);
  EXPECT_NE(bad_rate.Stderr().find("--rate"), std::string::npos) << bad_rate.Stderr();
  Subprocess unknown({Haptex(), "fly"});
  EXPECT_EQ(unknown.WaitFor(10s), 2);
  Subprocess bad_address({Haptex(), "netcheck", "serve", "--bind", "127.0.0.1"},
                         {"HAPTEX_SESSION_KEY=" + net::SessionKey::Generate().ToHex()});
  EXPECT_EQ(bad_address.WaitFor(10s), 2);
  EXPECT_NE(bad_address.Stderr().find("no port"), std::string::npos) << bad_address.Stderr();
}

TEST(HaptexCliTest, SceneCheckReportsFileLineColumn) {
  const std::string data_env = "HAPTEX_DATA_DIR=" + testing::SourceDir() + "/tests/scene/testdata";
  const std::string path = ::testing::TempDir() + "/bad_scene.textproto";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    std::fputs("name: \"bad\"\nfabric { database_name: \"test_cotton\" }\ncloth { particles_v: 1000 }\n", f);
    std::fclose(f);
  }
  Subprocess check({Haptex(), "scene", "check", path}, {data_env});
  EXPECT_EQ(check.WaitFor(10s), 2);
  EXPECT_NE(check.Stderr().find(path + ":3:9: particles_v must be in [2, 401]"), std::string::npos) << check.Stderr();
}

TEST(HaptexCliTest, SimWritesParticlesMeshAndSummary) {
  const std::string out = ::testing::TempDir() + "/haptex_sim_" + std::to_string(getpid());
  Subprocess sim({Haptex(), "sim", testing::SourceDir() + "/launch/scenes/hanging.textproto", "--duration", "0.2",
                  "--out", out, "--quiet"});
  ASSERT_EQ(sim.WaitFor(120s), 0) << sim.Stderr();
  const std::string summary = testing::ReadFileOrEmpty(out + "/summary.json");
  EXPECT_EQ(JsonNumber(summary, "steps"), 20);
  EXPECT_EQ(JsonNumber(summary, "nan_count"), 0);
  EXPECT_EQ(JsonNumber(summary, "particles"), 41 * 41);
  EXPECT_GT(JsonNumber(summary, "step_ms_p50"), 0);
  const std::string csv = testing::ReadFileOrEmpty(out + "/particles.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 41 * 41);
  EXPECT_EQ(csv.rfind("id,u,v,x,y,z\n", 0), 0u);
  const std::string obj = testing::ReadFileOrEmpty(out + "/mesh.obj");
  EXPECT_NE(obj.find("\nf "), std::string::npos);
}

TEST(HaptexCliTest, SimRefusesASceneWithoutDuration) {
  const std::string path = ::testing::TempDir() + "/no_duration_" + std::to_string(getpid()) + ".textproto";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    std::fputs("name: \"x\"\nfabric { database_name: \"wang2011_black_denim_11oz\" }\n", f);
    std::fclose(f);
  }
  Subprocess sim({Haptex(), "sim", path});
  EXPECT_EQ(sim.WaitFor(30s), 2);
  EXPECT_NE(sim.Stderr().find("needs a duration"), std::string::npos) << sim.Stderr();
}

TEST(HaptexCliTest, FabricListAndShowPrintTheDatabase) {
  Subprocess list({Haptex(), "fabric", "list"});
  ASSERT_EQ(list.WaitFor(30s), 0) << list.Stderr();
  EXPECT_NE(list.Stdout().find("wang2011_black_denim_11oz"), std::string::npos);
  const std::string png = ::testing::TempDir() + "/denim_" + std::to_string(getpid()) + ".png";
  Subprocess show({Haptex(), "fabric", "show", "wang2011_black_denim_11oz", "--plot", png});
  ASSERT_EQ(show.WaitFor(60s), 0) << show.Stderr();
  EXPECT_NE(show.Stdout().find("strain %"), std::string::npos);
  EXPECT_EQ(testing::ReadFileOrEmpty(png).substr(1, 3), "PNG");
  Subprocess missing({Haptex(), "fabric", "show", "silk"});
  EXPECT_EQ(missing.WaitFor(30s), 2);
  EXPECT_NE(missing.Stderr().find("no fabric 'silk'"), std::string::npos);
}

TEST(HaptexCliTest, TactileBuildWritesATileAndPictures) {
  const std::string dir = ::testing::TempDir() + "/tactile_" + std::to_string(getpid());
  Subprocess build({Haptex(), "tactile", "build", "wang2011_black_denim_11oz", "--out", dir + "/denim.tile", "--png",
                    dir + "/denim", "--warp-pitch-mm", "0.6", "--weft-pitch-mm", "0.6", "--yarn-mm", "0.4", "--smd-um",
                    "3.6"});
  ASSERT_EQ(build.WaitFor(60s), 0) << build.Stderr();
  EXPECT_NE(build.Stdout().find("periodic tile"), std::string::npos);
  EXPECT_GT(testing::ReadFileOrEmpty(dir + "/denim.tile").size(), 100u);
  for (const char* png : {"_tile.png", "_map.png", "_spectrum.png"}) {
    EXPECT_EQ(testing::ReadFileOrEmpty(dir + "/denim" + png).substr(1, 3), "PNG") << png;
  }
  Subprocess missing({Haptex(), "tactile", "build", "wang2011_black_denim_11oz", "--out", dir + "/x.tile"});
  EXPECT_EQ(missing.WaitFor(30s), 2);
  EXPECT_NE(missing.Stderr().find("roughness SMD"), std::string::npos) << missing.Stderr();
}

TEST(HaptexCliTest, KeyGenerateWritesAPrivateKeyFile) {
  const std::string path = ::testing::TempDir() + "/haptex_generated.key";
  std::remove(path.c_str());
  Subprocess generate({Haptex(), "key", "generate", "--out", path});
  ASSERT_EQ(generate.WaitFor(10s), 0);
  EXPECT_NO_THROW(net::SessionKey::FromHex(testing::ReadFileOrEmpty(path)));
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST(HaptexCliTest, MalformedKeyIsBadInput) {
  Subprocess probe({Haptex(), "netcheck", "probe", "--to", "127.0.0.1:9"}, {"HAPTEX_SESSION_KEY=abc"});
  EXPECT_EQ(probe.WaitFor(10s), 2);
  EXPECT_NE(probe.Stderr().find("environment variable HAPTEX_SESSION_KEY"), std::string::npos) << probe.Stderr();
}

TEST_F(NetcheckTest, TwoProbesAtOnceDoNotDisturbEachOther) {
  StartServer(key_);
  std::vector<std::string> argv = {Haptex(), "netcheck", "probe",     "--to", Address(),
                                   "--rate", "300",      "--seconds", "1",    "--json"};
  Subprocess first(argv, {KeyEnv(key_)});
  Subprocess second(argv, {KeyEnv(key_)});
  ASSERT_EQ(first.WaitFor(30s), 0) << first.Stdout();
  ASSERT_EQ(second.WaitFor(30s), 0) << second.Stdout();
  EXPECT_EQ(JsonNumber(first.Stdout(), "lost"), 0);
  EXPECT_EQ(JsonNumber(second.Stdout(), "lost"), 0);
  EXPECT_EQ(StopServer(), 0);
  EXPECT_NE(server_->Stdout().find("600 replies"), std::string::npos) << server_->Stdout();
}

}  // namespace
}  // namespace haptex
