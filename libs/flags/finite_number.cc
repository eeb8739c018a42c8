#include "libs/flags/finite_number.h"

#include <cmath>
#include <cstdlib>
#include <string>

namespace haptex::flags {

CLI::Validator FiniteNumber() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const char* begin = input.c_str();
        char* end = nullptr;
        const double value = std::strtod(begin, &end);
        if (end == begin) return "";  // not a number: the option's conversion refuses it
        if (!std::isfinite(value)) return "'" + input + "' is not a finite number";
        return "";
      },
      "", "FINITE");
}

void RefuseNonFiniteNumbers(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    const std::string type = option->get_type_name();
    const std::string base = type.substr(0, type.find(':'));
    if (base == "FLOAT" || base == "INT" || base == "UINT") option->check(FiniteNumber());
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) RefuseNonFiniteNumbers(*sub);
}

}  // namespace haptex::flags
