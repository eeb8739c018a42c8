#pragma once
// "Model only what a scene requires": which services a scene needs, each with the reason.

#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "launch/service_table.h"

namespace haptex::launch {

struct PlannedService {
  ServiceKind kind;
  std::string reason;  // why the scene needs it, printed by the launcher
};

/// The services `scene` needs, in start order. The scene must have passed validation.
std::vector<PlannedService> DeriveServices(const v1::Scene& scene);

/// Services the scene does not need, each with why (for the launcher's "not started" lines).
std::vector<PlannedService> OmittedServices(const v1::Scene& scene);

/// The planned services in stop order (models first, the device bridge last of the haptex
/// services, the mock controller after it).
std::vector<PlannedService> StopOrder(std::vector<PlannedService> services);

}  // namespace haptex::launch
