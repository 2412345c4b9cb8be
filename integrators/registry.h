// Every integrator Prism offers, in one table: its name, one line on what it does, its
// parameter table (parameters.h) and its factory. Command lines, help texts, error
// messages and the job API (session/) take their choices from here.
//
// Adding an integrator: one file in integrators/ that defines its IntegratorInfo (with the
// parameter table at the top of the file), and one entry in registry.cpp's list.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "integrators/parameters.h"
#include "renderer/integrator.h"

namespace prism {

struct IntegratorInfo {
  const char* name;
  const char* summary;
  std::span<const ParameterInfo> parameters;
  std::unique_ptr<Integrator> (*make)(const ParameterValues& values);
};

// In the order the help lists them.
std::span<const IntegratorInfo* const> integrator_registry();
// Null for a name that is not registered.
const IntegratorInfo* find_integrator(std::string_view name);
// "phong, shadow or whitted".
std::string integrator_choices(std::string_view last_separator = " or ");

// The parameter tables' entries by name over every integrator, each once (the first
// declaration wins; integrators that share a name share its meaning): the flags a command
// line offers.
std::span<const ParameterInfo* const> all_integrator_parameters();
// Whether `info` declares `parameter`.
bool takes_parameter(const IntegratorInfo& info, std::string_view parameter);

// An integrator ready to render, with the values it was made with (for metadata).
struct ConfiguredIntegrator {
  const IntegratorInfo* info = nullptr;
  ParameterValues parameters;
  std::unique_ptr<Integrator> integrator;
};
// Throws ParameterError naming a parameter `info` does not take or a bad value.
ConfiguredIntegrator configure_integrator(const IntegratorInfo& info,
                                          const ParameterSettings& given = {});
// By name, with the defaults: std::invalid_argument for an unknown name. For tests and tools.
std::unique_ptr<Integrator> make_integrator(std::string_view name,
                                            const ParameterSettings& given = {});

}  // namespace prism
