#pragma once
// The names services call each other by (`--peer NAME=HOST:PORT`): the launcher writes them into
// each service's command line and the services look their peers up by them, so both sides use
// these constants.

#include <string>
#include <string_view>
#include <vector>

namespace haptex::net::peer {

inline constexpr std::string_view kLauncher = "launcher";
inline constexpr std::string_view kBridge = "bridge";  ///< local_contact's name for the device bridge
inline constexpr std::string_view kLocalContact = "local_contact";
inline constexpr std::string_view kGlobalSim = "global_sim";
inline constexpr std::string_view kTactile = "tactile";
inline constexpr std::string_view kDisplay = "display";  ///< tactile's pin display (haptex-mock-pins or real)
inline constexpr std::string_view kViewer = "viewer";    ///< global_sim's ClothFrame consumer

/// The names a service answers to besides its own (Envelope.destination): what its peers call it.
inline std::vector<std::string> AlsoKnownAs(std::string_view service_name) {
  if (service_name == "device_bridge") return {std::string(kBridge)};
  if (service_name == "mock_pins") return {std::string(kDisplay)};
  return {};
}

}  // namespace haptex::net::peer
