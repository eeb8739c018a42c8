#pragma once
// A scene's stalls: pauses on purpose, which the launcher carries out by stopping a service's
// process (SIGSTOP) or every service of its host at once, and letting it go on (SIGCONT), as a host
// that pauses would (docs/launch.md, "Stalls"). The checks of one stall and of a list of them,
// shared by the scene loader and `haptex launch --stall`, so a bad stall is refused with the same
// words wherever it comes from.

#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "libs/scene/text_proto.h"

namespace haptex::scene {

/// The most stalls one run takes.
inline constexpr int kMaxStalls = 32;
/// The longest stall [s]: a host that pauses longer has stopped, which is a different test.
inline constexpr double kMaxStallDuration_s = 10.0;
/// The latest a stall may start [s]: the longest run a scene may ask for (7 days).
inline constexpr double kMaxStallAt_s = 7 * 24 * 3600.0;

/// One problem with a stall: the field it is about ("service", "all", "at_s", "duration_s"; empty:
/// the stall as a whole), and what is wrong.
struct StallIssue {
  std::string field;
  std::string message;
};

/// What the stall pauses: "all", or the service's name ("local_contact").
std::string StallTarget(const v1::Stall& stall);

/// Its times: at_s a finite number of seconds in [0, kMaxStallAt_s], duration_s finite, in
/// (0, kMaxStallDuration_s].
std::vector<StallIssue> CheckStallTimes(const v1::Stall& stall);
/// One stall against the scene: exactly one of service and all; the service one the scene runs,
/// not the launcher or the viewer; and its times (CheckStallTimes).
std::vector<StallIssue> CheckStall(const v1::Stall& stall, const v1::Scene& scene);

/// Whether two stalls would pause one process at the same time: the same target, or either of them
/// `all`, and their times [at_s, at_s + duration_s) intersect (one may start where the other ends).
bool StallsOverlap(const v1::Stall& x, const v1::Stall& y);

/// Every issue of the scene's stalls at file:line:column (for ValidateScene): each stall's own
/// (CheckStall), more than kMaxStalls, and a stall that overlaps an earlier one.
std::vector<TextIssue> ValidateStalls(const v1::Scene& scene, const FieldLocator& where);

}  // namespace haptex::scene
