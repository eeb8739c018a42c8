#include "libs/net/udp_address.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace haptex::net {
namespace {

TEST(UdpAddressTest, ParsesLiteralsAndNames) {
  EXPECT_EQ(FormatUdpAddress(ResolveUdpAddress("127.0.0.1:5000")), "127.0.0.1:5000");
  EXPECT_EQ(FormatUdpAddress(ResolveUdpAddress("[::1]:6000")), "[::1]:6000");
  EXPECT_EQ(FormatUdpAddress(ResolveUdpAddress(":7000")), "0.0.0.0:7000");
  EXPECT_EQ(ResolveUdpAddress("localhost:8000").port(), 8000);
}

TEST(UdpAddressTest, BadAddressesSayWhatIsWrong) {
  auto message = [](const char* address) {
    try {
      ResolveUdpAddress(address);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("127.0.0.1").find("no port"), std::string::npos);
  EXPECT_NE(message("127.0.0.1:99999").find("invalid port"), std::string::npos);
  EXPECT_NE(message("127.0.0.1:http").find("invalid port"), std::string::npos);
  EXPECT_NE(message("no-such-host.invalid:5").find("cannot resolve"), std::string::npos);
}

}  // namespace
}  // namespace haptex::net
