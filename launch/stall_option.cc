#include "launch/stall_option.h"

#include <charconv>
#include <stdexcept>

#include "launch/impair_option.h"
#include "launch/service_table.h"
#include "libs/scene/scene_stalls.h"

namespace haptex::launch {
namespace {

constexpr char kForm[] = "expected TARGET@AT:DURATION, e.g. local_contact@4.5s:30ms or all@4.5s:30ms";

[[noreturn]] void Refuse(std::string_view text, const std::string& what) {
  throw std::invalid_argument("--stall '" + std::string(text) + "': " + what);
}

std::string KnownTargets() {
  std::string names = "all";
  for (const ServiceSpec& spec : ServiceTable()) {
    if (spec.kind != v1::ServicePlacement::SERVICE_VIEWER) names += ", " + std::string(spec.name);
  }
  return names;
}

std::string Joined(const std::vector<scene::StallIssue>& issues) {
  std::string what;
  for (const scene::StallIssue& issue : issues) what += (what.empty() ? "" : "; ") + issue.message;
  return what;
}

// "4.5s", "30ms", "1e3ms": seconds. NaN and infinity are the stall checks' to refuse, in their words.
double ParseSeconds(std::string_view text, std::string_view name, std::string_view value) {
  std::string_view number = value;
  double scale = 1.0;
  if (value.ends_with("ms")) {
    number.remove_suffix(2);
    scale = 1e-3;
  } else if (value.ends_with("s")) {
    number.remove_suffix(1);
  } else {
    Refuse(text, std::string(name) + " '" + std::string(value) + "' needs its unit, s or ms (e.g. 4.5s or 30ms)");
  }
  double seconds = 0.0;
  const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), seconds);
  if (number.empty() || end != number.data() + number.size() || error == std::errc::invalid_argument) {
    Refuse(text, std::string(name) + ": '" + std::string(number) + "' is not a number");
  }
  if (error == std::errc::result_out_of_range) {
    Refuse(text, std::string(name) + ": '" + std::string(number) + "' is beyond the range of a number");
  }
  return seconds * scale;
}

// "the scene's stall local_contact@1.5s:0.1s", "--stall 'local_contact@1.5s:100ms'"
std::string Origin(const PlannedStall& planned) {
  return planned.source == "scene" ? "the scene's stall " + planned.text : "--stall '" + planned.text + "'";
}

}  // namespace

v1::Stall ParseStallOption(std::string_view text) {
  const std::size_t at = text.find('@');
  const std::size_t colon = at == std::string_view::npos ? at : text.find(':', at + 1);
  if (at == std::string_view::npos || colon == std::string_view::npos || text.find('@', at + 1) != text.npos ||
      text.find(':', colon + 1) != text.npos) {
    Refuse(text, kForm);
  }
  const std::string_view target = text.substr(0, at);
  const std::string_view when = text.substr(at + 1, colon - at - 1);
  const std::string_view length = text.substr(colon + 1);
  if (target.empty() || when.empty() || length.empty()) Refuse(text, kForm);

  v1::Stall stall;
  if (target == "all") {
    stall.set_all(true);
  } else {
    const ServiceSpec* spec = FindSpec(target);
    if (spec == nullptr) {
      Refuse(text, "unknown service '" + std::string(target) + "' (targets: " + KnownTargets() + ")");
    }
    stall.set_service(spec->kind);
  }
  stall.set_at_s(ParseSeconds(text, "AT", when));
  stall.set_duration_s(ParseSeconds(text, "DURATION", length));
  const std::vector<scene::StallIssue> issues = scene::CheckStallTimes(stall);
  if (!issues.empty()) Refuse(text, Joined(issues));
  return stall;
}

std::string StallText(const v1::Stall& stall) {
  return scene::StallTarget(stall) + "@" + ExactNumber(stall.at_s()) + "s:" + ExactNumber(stall.duration_s()) + "s";
}

std::vector<PlannedStall> RunStalls(const v1::Scene& scene, const std::vector<std::string>& stall_options) {
  std::vector<PlannedStall> stalls;
  for (const v1::Stall& stall : scene.stalls()) stalls.push_back({stall, "scene", StallText(stall)});
  for (const std::string& option : stall_options) {
    const v1::Stall stall = ParseStallOption(option);
    const std::vector<scene::StallIssue> issues = scene::CheckStall(stall, scene);
    if (!issues.empty()) Refuse(option, Joined(issues));
    if (stalls.size() >= static_cast<std::size_t>(scene::kMaxStalls)) {
      Refuse(option, "at most " + std::to_string(scene::kMaxStalls) + " stalls per run (the scene has " +
                         std::to_string(scene.stalls_size()) + ")");
    }
    for (const PlannedStall& earlier : stalls) {
      if (!scene::StallsOverlap(earlier.stall, stall)) continue;
      Refuse(option,
             "overlaps " + Origin(earlier) + ": stalls that pause one process (all pauses every one) must not overlap");
    }
    stalls.push_back({stall, "--stall", option});
  }
  return stalls;
}

}  // namespace haptex::launch
