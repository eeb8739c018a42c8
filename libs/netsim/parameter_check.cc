#include "libs/netsim/parameter_check.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace haptex::netsim {
namespace {

std::string Show(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

[[noreturn]] void Refuse(std::string_view name, const std::string& what, double value) {
  throw std::invalid_argument(std::string(name) + " must be " + what + ", got " + Show(value));
}

}  // namespace

void CheckFinite(std::string_view name, double value) {
  if (!std::isfinite(value)) Refuse(name, "a finite number", value);
}

void CheckProbability(std::string_view name, double value) {
  CheckFinite(name, value);
  if (value < 0.0 || value > 1.0) Refuse(name, "a probability within [0, 1]", value);
}

void CheckRange(std::string_view name, double value, double min, double max) {
  CheckFinite(name, value);
  if (value < min || value > max) Refuse(name, "within [" + Show(min) + ", " + Show(max) + "]", value);
}

void CheckWholeNumber(std::string_view name, double value, double min, double max) {
  CheckRange(name, value, min, max);
  if (value != std::floor(value)) Refuse(name, "a whole number", value);
}

}  // namespace haptex::netsim
