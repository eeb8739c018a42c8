#pragma once
// The text form of an impaired link, as `haptex launch --impair` takes it:
//
//   SERVICE-SERVICE[:KEY=VALUE,...]     e.g. device_bridge-local_contact:rtt_ms=100,jitter_ms=5,loss=0.05
//
// The services are the launcher's names (either order; the first is `a`: forward is a -> b, and
// the relay runs on a's host). The keys are the fields of the scene's LinkImpairment
// (proto/haptex/v1/scene.proto), so the command line and the scene file say the same thing the
// same way: rtt_ms, delay_ms, jitter_ms, jitter_distribution, loss, burst_loss, reorder,
// reorder_delay_ms, duplicate, rate_kbps, seed; `forward.KEY` or `back.KEY` for one direction;
// burst_loss=P/R[/LOSS_BAD[/LOSS_GOOD]]. Pure.

#include <string>
#include <string_view>

#include "haptex/v1/scene.pb.h"

namespace haptex::launch {

/// One --impair value as a link. Throws std::invalid_argument naming --impair, the text and what
/// is wrong: an unknown service or key, a key given twice, a value that is not a number, or one
/// the link checks refuse (libs/scene/scene_network.h: NaN, infinity, out of range). Whether the
/// scene runs the two services is checked with the scene (launch/impaired_links.h).
v1::LinkImpairment ParseImpairOption(std::string_view text);

/// The link's values in the --impair form, without the services ("rtt_ms=20,loss=0.02,seed=1";
/// "" when it sets none): what was asked, for the launcher's output and summary.json.
std::string ImpairmentText(const v1::LinkImpairment& link);

/// The shortest text that reads back as the same double ("0.1", "1e-05"): values handed on to
/// `haptex relay` arrive exactly as asked.
std::string ExactNumber(double value);

}  // namespace haptex::launch
