#pragma once
// "host:port" strings, as written in scenes and on command lines.

#include <string>
#include <string_view>

#include <asio/ip/udp.hpp>

namespace haptex::net {

/// Parses "host:port", "[v6]:port" or ":port" (all interfaces) and resolves the host (may block
/// on DNS: call at configuration time only). Throws std::invalid_argument naming the problem.
asio::ip::udp::endpoint ResolveUdpAddress(std::string_view address);

/// "1.2.3.4:5" / "[::1]:5".
std::string FormatUdpAddress(const asio::ip::udp::endpoint& endpoint);

}  // namespace haptex::net
