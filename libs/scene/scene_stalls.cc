#include "libs/scene/scene_stalls.h"

#include <cmath>
#include <sstream>

#include "libs/scene/scene_network.h"

namespace haptex::scene {
namespace {

using P = v1::ServicePlacement;

std::string Number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// "local_contact at 1.5 s for 0.1 s"
std::string Described(const v1::Stall& stall) {
  return StallTarget(stall) + " at " + Number(stall.at_s()) + " s for " + Number(stall.duration_s()) + " s";
}

void CheckTarget(const v1::Stall& stall, const v1::Scene& scene, std::vector<StallIssue>* issues) {
  const ServiceKind kind = stall.service();
  if (stall.all()) {
    if (kind != P::SERVICE_UNSPECIFIED) {
      issues->push_back({"all", "give either `service: SERVICE_...` or `all: true`, not both"});
    }
    return;
  }
  if (kind == P::SERVICE_UNSPECIFIED) {
    issues->push_back({"", "a stall needs a target: `service: SERVICE_...` or `all: true`"});
    return;
  }
  if (!P::Service_IsValid(kind)) return;  // the generic enum check reports it, at the field
  if (kind == P::SERVICE_LAUNCHER) {
    issues->push_back({"service", "the launcher carries the stalls out and cannot pause itself: name a service"});
    return;
  }
  if (kind == P::SERVICE_VIEWER) {
    issues->push_back({"service", "the viewer only shows the run: a stall pauses a haptex service"});
    return;
  }
  const std::string why = NotRunBecause(scene, kind);
  if (!why.empty()) issues->push_back({"service", "the scene does not run " + ServiceName(kind) + " (" + why + ")"});
}

void CheckTimes(const v1::Stall& stall, std::vector<StallIssue>* issues) {
  if (!std::isfinite(stall.at_s())) {
    issues->push_back({"at_s", "at_s must be a finite number, got " + Number(stall.at_s())});
  } else if (stall.at_s() < 0.0 || stall.at_s() > kMaxStallAt_s) {
    issues->push_back({"at_s", "at_s must be in [0, " + Number(kMaxStallAt_s) +
                                   "] s from the run's start (force enabled), got " + Number(stall.at_s())});
  }
  if (!std::isfinite(stall.duration_s())) {
    issues->push_back({"duration_s", "duration_s must be a finite number, got " + Number(stall.duration_s())});
  } else if (!(stall.duration_s() > 0.0) || stall.duration_s() > kMaxStallDuration_s) {
    issues->push_back({"duration_s", "duration_s must be in (0, " + Number(kMaxStallDuration_s) + "] s, got " +
                                         Number(stall.duration_s())});
  }
}

}  // namespace

std::string StallTarget(const v1::Stall& stall) { return stall.all() ? "all" : ServiceName(stall.service()); }

std::vector<StallIssue> CheckStallTimes(const v1::Stall& stall) {
  std::vector<StallIssue> issues;
  CheckTimes(stall, &issues);
  return issues;
}

std::vector<StallIssue> CheckStall(const v1::Stall& stall, const v1::Scene& scene) {
  std::vector<StallIssue> issues;
  CheckTarget(stall, scene, &issues);
  CheckTimes(stall, &issues);
  return issues;
}

bool StallsOverlap(const v1::Stall& x, const v1::Stall& y) {
  const bool one_process = x.all() || y.all() || x.service() == y.service();
  return one_process && x.at_s() < y.at_s() + y.duration_s() && y.at_s() < x.at_s() + x.duration_s();
}

std::vector<TextIssue> ValidateStalls(const v1::Scene& scene, const FieldLocator& where) {
  std::vector<TextIssue> issues;
  std::vector<bool> usable;  // no issue of its own: worth comparing with the others
  for (int i = 0; i < scene.stalls_size(); ++i) {
    const v1::Stall& stall = scene.stalls(i);
    const FieldLocator at = where.Nested(scene, "stalls", i);
    const std::vector<StallIssue> own = CheckStall(stall, scene);
    for (const StallIssue& issue : own) {
      issues.push_back(issue.field.empty() ? at.Here(issue.message) : at.At(stall, issue.field, -1, issue.message));
    }
    usable.push_back(own.empty());
    if (i == kMaxStalls) {
      issues.push_back(at.Here("at most " + std::to_string(kMaxStalls) + " stalls per scene"));
    }
    if (!own.empty()) continue;
    for (int j = 0; j < i; ++j) {
      if (!usable[j] || !StallsOverlap(scene.stalls(j), stall)) continue;
      const int first_line = where.Nested(scene, "stalls", j).Here("").line;
      issues.push_back(at.At(stall, "at_s", -1,
                             "the stall of " + Described(stall) + " overlaps the one of " + Described(scene.stalls(j)) +
                                 " (line " + std::to_string(first_line) +
                                 "): stalls that pause one process (all pauses every one) must not overlap"));
      break;
    }
  }
  return issues;
}

}  // namespace haptex::scene
