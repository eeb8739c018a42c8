#include "libs/netsim/gilbert_elliott.h"

#include <stdexcept>
#include <string>

#include "libs/netsim/parameter_check.h"

namespace haptex::netsim {

void ValidateGilbertElliott(const GilbertElliottConfig& config, const char* prefix) {
  const std::string name(prefix);
  CheckProbability(name + "p", config.p_good_to_bad);
  CheckProbability(name + "r", config.p_bad_to_good);
  CheckProbability(name + "loss_good", config.loss_good);
  CheckProbability(name + "loss_bad", config.loss_bad);
  if (config.p_good_to_bad > 0.0 && config.p_bad_to_good == 0.0) {
    throw std::invalid_argument(name + "r must be > 0 when " + name + "p > 0: the bad state would never end");
  }
}

bool GilbertElliott::Step(double u_loss, double u_transition) {
  const bool lost = u_loss < (bad_ ? config_.loss_bad : config_.loss_good);
  bad_ = bad_ ? !(u_transition < config_.p_bad_to_good) : u_transition < config_.p_good_to_bad;
  return lost;
}

}  // namespace haptex::netsim
