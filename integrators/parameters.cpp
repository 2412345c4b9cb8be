#include "integrators/parameters.h"

#include <cmath>
#include <cstdio>

namespace prism {
namespace {

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace

ParameterValues::ParameterValues(std::span<const ParameterInfo> table,
                                 const ParameterSettings& given) {
  for (const ParameterInfo& p : table) values_[p.name] = p.default_value;
  for (const auto& [name, value] : given) {
    const ParameterInfo* info = nullptr;
    for (const ParameterInfo& p : table)
      if (name == p.name) info = &p;
    if (!info) throw ParameterError(name, "no such parameter");
    if (!std::isfinite(value) || value < info->min || value > info->max)
      throw ParameterError(name, number(value) + ": must be " + to_string(info->type) + " from " +
                                     number(info->min) + " to " + number(info->max));
    if (info->type == ParameterType::integer && value != std::floor(value))
      throw ParameterError(name, number(value) + ": must be a whole number");
    values_[name] = value;
  }
}

double ParameterValues::real(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw std::logic_error("integrator parameter not declared: " + name);
  return it->second;
}

int ParameterValues::integer(const std::string& name) const {
  return static_cast<int>(real(name));
}

}  // namespace prism
