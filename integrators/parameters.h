// An integrator's parameters: each integrator declares them in a table at the top of its
// file (name, type, default, range, one line of documentation), as Mitsuba's plugins do; the
// registry (registry.h) checks what a caller gives against the table and hands the factory a
// complete set of values. The command line's flags, help and errors come from the tables.
#pragma once

#include <map>
#include <span>
#include <stdexcept>
#include <string>

#include "renderer/enum_names.h"

namespace prism {

enum class ParameterType { integer, real };
inline constexpr EnumName<ParameterType> kParameterTypeNames[] = {
    {ParameterType::integer, "integer"}, {ParameterType::real, "number"}};
constexpr std::span<const EnumName<ParameterType>> enum_names(ParameterType) {
  return kParameterTypeNames;
}

struct ParameterInfo {
  const char* name;  // spelled as its command-line flag without the dashes: "max-depth"
  ParameterType type;
  double default_value;
  double min, max;  // inclusive
  const char* description;
};

// A parameter the caller gave that the integrator cannot take; `parameter` names it.
struct ParameterError : std::invalid_argument {
  ParameterError(std::string parameter_name, const std::string& message)
      : std::invalid_argument(message), parameter(std::move(parameter_name)) {}
  std::string parameter;
};

// Values given by a caller, by name; any subset of an integrator's table.
using ParameterSettings = std::map<std::string, double>;

// Every parameter of one integrator's table with its value: given, or the default.
class ParameterValues {
 public:
  ParameterValues() = default;
  // Throws ParameterError for a name not in `table`, a value out of its range, or a
  // fraction for an integer.
  ParameterValues(std::span<const ParameterInfo> table, const ParameterSettings& given);

  // The value of a parameter of the table; std::logic_error for any other name (a typo in
  // the integrator's own code, not the user's).
  double real(const std::string& name) const;
  int integer(const std::string& name) const;
  // In table order, as "name" -> "value", for metadata and cache keys.
  const std::map<std::string, double>& values() const { return values_; }

 private:
  std::map<std::string, double> values_;
};

}  // namespace prism
