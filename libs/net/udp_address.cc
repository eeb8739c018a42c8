#include "libs/net/udp_address.h"

#include <asio/io_context.hpp>
#include <asio/ip/address.hpp>

#include <charconv>
#include <stdexcept>

namespace haptex::net {

asio::ip::udp::endpoint ResolveUdpAddress(std::string_view address) {
  const std::string quoted = "'" + std::string(address) + "'";
  const auto colon = address.rfind(':');
  if (colon == std::string_view::npos) {
    throw std::invalid_argument("address " + quoted + " has no port: write host:port");
  }
  std::string_view host = address.substr(0, colon);
  const std::string_view port_text = address.substr(colon + 1);
  unsigned port = 0;
  const auto [end, ec] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (ec != std::errc() || end != port_text.data() + port_text.size() || port > 65535) {
    throw std::invalid_argument("address " + quoted + " has an invalid port '" + std::string(port_text) +
                                "' (0..65535)");
  }
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  if (host.empty()) host = "0.0.0.0";

  asio::error_code error;
  const auto literal = asio::ip::make_address(std::string(host), error);
  if (!error) return {literal, static_cast<unsigned short>(port)};

  asio::io_context io;
  asio::ip::udp::resolver resolver(io);
  const auto results = resolver.resolve(asio::ip::udp::v4(), std::string(host), std::to_string(port), error);
  if (error || results.empty()) {
    throw std::invalid_argument("cannot resolve host '" + std::string(host) + "' in address " + quoted + ": " +
                                (error ? error.message() : "no address"));
  }
  return results.begin()->endpoint();
}

std::string FormatUdpAddress(const asio::ip::udp::endpoint& endpoint) {
  const auto address = endpoint.address();
  if (address.is_v6()) return "[" + address.to_string() + "]:" + std::to_string(endpoint.port());
  return address.to_string() + ":" + std::to_string(endpoint.port());
}

}  // namespace haptex::net
