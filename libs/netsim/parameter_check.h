#pragma once
// Checks of configuration numbers, shared by the model's validation and the command line, so a
// bad value is refused with the same words wherever it comes from. Each throws
// std::invalid_argument naming the parameter (a config field or a flag) and the value.

#include <string_view>

namespace haptex::netsim {

/// Finite (not NaN, not infinite).
void CheckFinite(std::string_view name, double value);
/// Finite and within [0, 1].
void CheckProbability(std::string_view name, double value);
/// Finite and within [min, max].
void CheckRange(std::string_view name, double value, double min, double max);
/// A whole number within [min, max].
void CheckWholeNumber(std::string_view name, double value, double min, double max);

}  // namespace haptex::netsim
