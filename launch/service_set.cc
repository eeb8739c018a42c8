#include "launch/service_set.h"

#include <algorithm>

#include "libs/codec/message_conversion.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;

std::string FingerList(const v1::Scene& scene) {
  std::string names;
  for (const v1::FingerSpec& f : scene.fingers()) {
    if (!names.empty()) names += " and ";
    names += codec::FingerName(f.finger());
  }
  return names;
}

// The need for each service: a reason when needed, else an empty string and why not.
struct Need {
  bool needed;
  std::string why;
};

Need NeedOf(ServiceKind kind, const v1::Scene& scene) {
  const int fingers = scene.fingers_size();
  const bool mock = scene.device().has_mock();
  const bool tactile = scene.tactile().enabled();
  switch (kind) {
    case P::SERVICE_GLOBAL_SIM:
      return {true, fingers == 0 ? "the fabric, with no fingers: global_sim alone"
                                 : "the whole fabric (" +
                                       (scene.fabric().has_inline_fabric() ? std::string("inline fabric")
                                                                           : scene.fabric().database_name()) +
                                       ") at the global rate, cutting the local patches"};
    case P::SERVICE_LOCAL_CONTACT:
      if (fingers == 0) return {false, "no fingers: no contact models"};
      return {true, fingers == 1
                        ? "one finger (" + FingerList(scene) + "): one-finger contact models only (I, IV, V), no pinch"
                        : "two fingers (" + FingerList(scene) + "): contact models I-IX on the local patch"};
    case P::SERVICE_DEVICE_BRIDGE:
      if (fingers == 0) return {false, "no fingers: no device"};
      return {true,
              mock ? "fingers on a device: the bridge owns it (mock controller)"
                   : "fingers on a device: the bridge owns the GRAB at " + scene.device().grab().controller_address()};
    case P::SERVICE_MOCK_GRAB:
      if (fingers == 0) return {false, "no fingers: no device"};
      if (!mock) return {false, "a real GRAB controller at " + scene.device().grab().controller_address()};
      return {true, "the scene asks for the mock controller (user script " +
                        v1::MockUserScript::Kind_Name(scene.device().mock().user().kind()) + ")"};
    case P::SERVICE_TACTILE:
      if (!tactile) return {false, "tactile display off"};
      return {true, "tactile display on: pin amplitudes from the touch traces"};
    case P::SERVICE_MOCK_PINS:
      if (!tactile) return {false, "tactile display off"};
      if (!scene.tactile().mock_display()) return {false, "a real pin display at " + scene.tactile().display_address()};
      return {true, "tactile display on with mock_display: the mock pin display"};
    case P::SERVICE_VIEWER:
      if (!scene.viewer().enabled()) return {false, "viewer off"};
      return {true, "viewer on: the fabric, fingers and forces in a web page and for Foxglove"};
    default:
      return {false, "not a launched service"};
  }
}

}  // namespace

std::vector<PlannedService> DeriveServices(const v1::Scene& scene) {
  std::vector<const ServiceSpec*> specs;
  for (const ServiceSpec& spec : ServiceTable()) specs.push_back(&spec);
  std::stable_sort(specs.begin(), specs.end(),
                   [](const ServiceSpec* a, const ServiceSpec* b) { return a->start_rank < b->start_rank; });
  std::vector<PlannedService> planned;
  for (const ServiceSpec* spec : specs) {
    Need need = NeedOf(spec->kind, scene);
    if (need.needed) planned.push_back({spec->kind, std::move(need.why)});
  }
  return planned;
}

std::vector<PlannedService> OmittedServices(const v1::Scene& scene) {
  std::vector<PlannedService> omitted;
  for (const ServiceSpec& spec : ServiceTable()) {
    Need need = NeedOf(spec.kind, scene);
    if (!need.needed) omitted.push_back({spec.kind, std::move(need.why)});
  }
  return omitted;
}

std::vector<PlannedService> StopOrder(std::vector<PlannedService> services) {
  std::stable_sort(services.begin(), services.end(), [](const PlannedService& a, const PlannedService& b) {
    return Spec(a.kind).stop_rank < Spec(b.kind).stop_rank;
  });
  return services;
}

}  // namespace haptex::launch
