#pragma once
// The links of a run that go through an impairment relay: the scene's network section, with each
// `--impair` replacing the scene's link of the same pair of services (in either order) or adding
// one. Pure.

#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"

namespace haptex::launch {

struct ImpairedLink {
  v1::LinkImpairment link;
  std::string source;  // "scene" or "--impair"
};

/// The scene's links (in its order, replaced where an --impair names the same pair), then the
/// --impair links it does not have. Throws std::invalid_argument for a bad --impair value, two
/// --impair values for one pair, or a link the scene cannot carry (a service it does not run, two
/// services that exchange no datagrams).
std::vector<ImpairedLink> ImpairedLinks(const v1::Scene& scene, const std::vector<std::string>& impair_options);

/// Just the links, for the port plan.
std::vector<v1::LinkImpairment> LinksOf(const std::vector<ImpairedLink>& links);

}  // namespace haptex::launch
