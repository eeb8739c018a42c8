#include "launch/impaired_links.h"

#include <algorithm>
#include <stdexcept>

#include "launch/impair_option.h"
#include "libs/scene/scene_network.h"

namespace haptex::launch {

std::vector<ImpairedLink> ImpairedLinks(const v1::Scene& scene, const std::vector<std::string>& impair_options) {
  std::vector<ImpairedLink> links;
  for (const v1::LinkImpairment& link : scene.network().links()) links.push_back({link, "scene"});
  std::vector<v1::LinkImpairment> given;
  for (const std::string& option : impair_options) {
    v1::LinkImpairment link = ParseImpairOption(option);
    for (const auto& earlier : given) {
      if (scene::SamePair(earlier, link)) {
        throw std::invalid_argument("--impair '" + option + "': link " + scene::LinkName(link) +
                                    " is given twice; one --impair per pair of services");
      }
    }
    std::vector<std::string> problems;
    for (const scene::LinkIssue& issue : scene::CheckLinkServices(link, scene)) problems.push_back(issue.message);
    if (!problems.empty()) {
      std::string what;
      for (const std::string& p : problems) what += (what.empty() ? "" : "; ") + p;
      throw std::invalid_argument("--impair '" + option + "': " + what);
    }
    given.push_back(link);
    const auto same =
        std::find_if(links.begin(), links.end(), [&](const ImpairedLink& l) { return scene::SamePair(l.link, link); });
    if (same != links.end()) {
      *same = {link, "--impair"};  // the command line replaces the scene's link
    } else {
      links.push_back({link, "--impair"});
    }
  }
  return links;
}

std::vector<v1::LinkImpairment> LinksOf(const std::vector<ImpairedLink>& links) {
  std::vector<v1::LinkImpairment> out;
  for (const ImpairedLink& l : links) out.push_back(l.link);
  return out;
}

}  // namespace haptex::launch
