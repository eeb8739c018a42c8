#pragma once
// The names services call each other by (`--peer NAME=HOST:PORT`): the launcher writes them into
// each service's command line and the services look their peers up by them, so both sides use
// these constants.

#include <string_view>

namespace haptex::net::peer {

inline constexpr std::string_view kLauncher = "launcher";
inline constexpr std::string_view kBridge = "bridge";  ///< local_contact's name for the device bridge
inline constexpr std::string_view kLocalContact = "local_contact";
inline constexpr std::string_view kGlobalSim = "global_sim";
inline constexpr std::string_view kTactile = "tactile";
inline constexpr std::string_view kDisplay = "display";  ///< tactile's pin display (haptex-mock-pins or real)
inline constexpr std::string_view kViewer = "viewer";    ///< global_sim's ClothFrame consumer

}  // namespace haptex::net::peer
