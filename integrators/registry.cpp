#include "integrators/registry.h"

#include <stdexcept>
#include <vector>

namespace prism {

// Each defined in its own file.
extern const IntegratorInfo kPhongIntegrator;
extern const IntegratorInfo kShadowIntegrator;
extern const IntegratorInfo kWhittedIntegrator;
extern const IntegratorInfo kPathIntegrator;

namespace {

// The registry: one entry per integrator.
const IntegratorInfo* const kIntegrators[] = {
    &kPhongIntegrator,
    &kShadowIntegrator,
    &kWhittedIntegrator,
    &kPathIntegrator,
};

}  // namespace

std::span<const IntegratorInfo* const> integrator_registry() {
  return kIntegrators;
}

const IntegratorInfo* find_integrator(std::string_view name) {
  for (const IntegratorInfo* info : kIntegrators)
    if (name == info->name) return info;
  return nullptr;
}

std::string integrator_choices(std::string_view last_separator) {
  std::string text;
  const size_t n = std::size(kIntegrators);
  for (size_t i = 0; i < n; ++i) {
    if (i > 0) text += i + 1 == n ? last_separator : std::string_view(", ");
    text += kIntegrators[i]->name;
  }
  return text;
}

std::span<const ParameterInfo* const> all_integrator_parameters() {
  static const std::vector<const ParameterInfo*> all = [] {
    std::vector<const ParameterInfo*> list;
    for (const IntegratorInfo* info : kIntegrators)
      for (const ParameterInfo& p : info->parameters) {
        bool seen = false;
        for (const ParameterInfo* q : list) seen = seen || std::string_view(q->name) == p.name;
        if (!seen) list.push_back(&p);
      }
    return list;
  }();
  return all;
}

bool takes_parameter(const IntegratorInfo& info, std::string_view parameter) {
  for (const ParameterInfo& p : info.parameters)
    if (parameter == p.name) return true;
  return false;
}

ConfiguredIntegrator configure_integrator(const IntegratorInfo& info,
                                          const ParameterSettings& given) {
  ConfiguredIntegrator c;
  c.info = &info;
  c.parameters = ParameterValues(info.parameters, given);
  c.integrator = info.make(c.parameters);
  return c;
}

std::unique_ptr<Integrator> make_integrator(std::string_view name, const ParameterSettings& given) {
  const IntegratorInfo* info = find_integrator(name);
  if (!info)
    throw std::invalid_argument("no integrator " + std::string(name) + " (there are " +
                                integrator_choices() + ")");
  return configure_integrator(*info, given).integrator;
}

}  // namespace prism
