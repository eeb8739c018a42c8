#include "launch/service_table.h"

#include <stdexcept>

#include "libs/net/peer_names.h"

namespace haptex::launch {

const std::vector<ServiceSpec>& ServiceTable() {
  using P = v1::ServicePlacement;
  // Start order: the device bridge first (it holds zero force until the launcher enables it), its
  // controller, then what feeds it, the viewer last. Stop order: the viewer, the models, the bridge
  // last of the haptex services; the mock controller stands in for the hardware and stops after the
  // bridge, so its force log shows the bridge's zero commands.
  namespace peer = net::peer;
  static const std::vector<ServiceSpec> table = {
      {P::SERVICE_DEVICE_BRIDGE,
       "device_bridge",
       "services/device_bridge/haptex-device-bridge",
       "services/device_bridge",
       0,
       5,
       3,
       4,
       0,  // rt_rank: 5 kHz
       {{peer::kLauncher, P::SERVICE_LAUNCHER},
        {peer::kLocalContact, P::SERVICE_LOCAL_CONTACT},
        {peer::kGlobalSim, P::SERVICE_GLOBAL_SIM},
        {peer::kViewer, P::SERVICE_VIEWER}}},
      {P::SERVICE_MOCK_GRAB,
       "mock_grab",
       "services/mock_grab/haptex-mock-grab",
       "services/mock_grab",
       1,
       6,
       6,
       7,
       0,  // rt_rank: 5 kHz
       {{peer::kLauncher, P::SERVICE_LAUNCHER}}},
      {P::SERVICE_MOCK_PINS,
       "mock_pins",
       "services/mock_pins/haptex-mock-pins",
       "services/mock_pins",
       2,
       4,
       8,
       -1,
       2,  // rt_rank: 40 Hz frames, 320 Hz pins
       {{peer::kLauncher, P::SERVICE_LAUNCHER}}},
      {P::SERVICE_TACTILE,
       "tactile",
       "services/tactile/haptex-tactile",
       "services/tactile",
       3,
       3,
       5,
       -1,
       2,  // rt_rank: 320 Hz
       {{peer::kLauncher, P::SERVICE_LAUNCHER},
        {peer::kDisplay, P::SERVICE_MOCK_PINS},
        {peer::kViewer, P::SERVICE_VIEWER}}},
      {P::SERVICE_GLOBAL_SIM,
       "global_sim",
       "services/global_sim/haptex-global-sim",
       "services/global_sim",
       4,
       2,
       1,
       -1,
       3,  // rt_rank: 100 Hz
       {{peer::kLauncher, P::SERVICE_LAUNCHER},
        {peer::kLocalContact, P::SERVICE_LOCAL_CONTACT},
        {peer::kViewer, P::SERVICE_VIEWER}}},
      {P::SERVICE_LOCAL_CONTACT,
       "local_contact",
       "services/local_contact/haptex-local-contact",
       "services/local_contact",
       5,
       1,
       2,
       -1,
       1,  // rt_rank: 1 kHz
       {{peer::kLauncher, P::SERVICE_LAUNCHER},
        {peer::kGlobalSim, P::SERVICE_GLOBAL_SIM},
        {peer::kBridge, P::SERVICE_DEVICE_BRIDGE},
        {peer::kTactile, P::SERVICE_TACTILE},
        {peer::kViewer, P::SERVICE_VIEWER}}},
      // Started last and stopped first: it only watches.
      {P::SERVICE_VIEWER,
       "viewer",
       "services/viewer/haptex-viewer",
       "services/viewer",
       6,
       0,
       9,
       -1,
       kNotRealTime,  // a person watches at 30-60 Hz; never ahead of a haptic loop
       {{peer::kLauncher, P::SERVICE_LAUNCHER}}},
  };
  return table;
}

const ServiceSpec& Spec(ServiceKind kind) {
  for (const ServiceSpec& spec : ServiceTable()) {
    if (spec.kind == kind) return spec;
  }
  throw std::out_of_range("no launcher table entry for service " + v1::ServicePlacement::Service_Name(kind));
}

const ServiceSpec* FindSpec(std::string_view name) {
  for (const ServiceSpec& spec : ServiceTable()) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

}  // namespace haptex::launch
