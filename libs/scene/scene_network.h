#pragma once
// A scene's network section: the links between services that the launcher puts through an
// impairment relay. The checks of one link (shared by the scene loader and `haptex launch
// --impair`, so a bad value is refused with the same words wherever it comes from), which pairs of
// services exchange datagrams, which services a scene runs, and what each direction of a link
// does to datagrams (netsim configs for `haptex relay`).

#include <cstdint>
#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "libs/netsim/impairment_config.h"
#include "libs/scene/text_proto.h"

namespace haptex::scene {

using ServiceKind = v1::ServicePlacement::Service;

/// One problem with a LinkImpairment: the field it is about, as a path inside the link
/// ({"forward", "loss"}; empty: the link as a whole), and what is wrong.
struct LinkIssue {
  std::vector<std::string> field;
  std::string message;
};

/// "device_bridge" for SERVICE_DEVICE_BRIDGE (the launcher's service names).
std::string ServiceName(ServiceKind kind);
/// "device_bridge-local_contact": a, then b.
std::string LinkName(const v1::LinkImpairment& link);

/// True when the scene runs the service (the launcher's launch/service_set.cc says why).
bool SceneRunsService(const v1::Scene& scene, ServiceKind kind);
/// Why the scene does not run `kind` ("the scene has no fingers"); "" when it does.
std::string NotRunBecause(const v1::Scene& scene, ServiceKind kind);
/// True when the two services send each other anything, in either direction.
bool ExchangeDatagrams(ServiceKind x, ServiceKind y);
/// True when a and b name the same pair, in either order.
bool SamePair(const v1::LinkImpairment& x, const v1::LinkImpairment& y);

/// Values: NaN, infinities, ranges, words, rtt_ms given with delay_ms. Names in messages are the
/// link's field names ("forward.loss", "burst_loss.r").
std::vector<LinkIssue> CheckLinkValues(const v1::LinkImpairment& link);
/// Ends: each a service of the scene (not the launcher), two different ones that exchange
/// datagrams. Issues are about field "a" or "b".
std::vector<LinkIssue> CheckLinkServices(const v1::LinkImpairment& link, const v1::Scene& scene);

/// Every issue of the scene's network section at its file:line:column (for ValidateScene).
std::vector<TextIssue> ValidateNetwork(const v1::Scene& scene, const FieldLocator& where);

/// What each direction of a checked link does: the link's values, a direction's own values over
/// them, rtt_ms split evenly.
struct LinkDirections {
  netsim::ImpairmentConfig forward;  // a -> b
  netsim::ImpairmentConfig back;     // b -> a
  std::uint64_t forward_seed = 1;
  std::uint64_t back_seed = 2;
};
/// Throws std::invalid_argument for a link that CheckLinkValues refuses.
LinkDirections ResolveLink(const v1::LinkImpairment& link);

}  // namespace haptex::scene
