#pragma once
// The text form of a stall, as `haptex launch --stall` takes it:
//
//   TARGET@AT:DURATION     e.g. local_contact@4.5s:30ms, all@4.5s:30ms, device_bridge@4500ms:0.03s
//
// TARGET is a service's launcher name, or `all` (every service this launcher starts, at once); AT
// is when the pause begins, from the run's start (force enabled), and DURATION how long it lasts,
// each a number with its unit, `s` or `ms`. They are the fields of the scene's Stall
// (proto/haptex/v1/scene.proto), checked by the same checks (libs/scene/scene_stalls.h), so the
// command line and the scene file refuse a stall in the same words. Pure.

#include <string>
#include <string_view>
#include <vector>

#include "haptex/v1/scene.pb.h"

namespace haptex::launch {

/// One --stall value as a stall. Throws std::invalid_argument naming --stall, the text and what
/// is wrong: not TARGET@AT:DURATION, an unknown service, a number without its unit or that is not
/// a number, or a time the stall checks refuse (NaN, infinity, out of range). Whether the scene
/// runs the service is checked with the scene (RunStalls).
v1::Stall ParseStallOption(std::string_view text);

/// The stall in the --stall form, in seconds ("local_contact@1.5s:0.1s"): it reads back as the
/// same stall.
std::string StallText(const v1::Stall& stall);

struct PlannedStall {
  v1::Stall stall;
  std::string source;  // "scene" or "--stall"
  std::string text;    // the --stall as given; the scene's in that form (StallText)
};

/// The scene's stalls (checked by the scene loader), then each --stall added to them and checked
/// as the loader checks the scene's: a service the scene runs, times in range, at most
/// scene::kMaxStalls, none overlapping another of the same process. Throws std::invalid_argument
/// naming the --stall.
std::vector<PlannedStall> RunStalls(const v1::Scene& scene, const std::vector<std::string>& stall_options);

}  // namespace haptex::launch
