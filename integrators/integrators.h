// The integrators Prism offers, by name.
#pragma once

#include <memory>
#include <string>

#include "renderer/integrator.h"

namespace prism {

enum class IntegratorKind { phong, shadow, whitted };

const char* to_string(IntegratorKind kind);
bool parse_integrator(const std::string& text, IntegratorKind* out);
std::unique_ptr<Integrator> make_integrator(IntegratorKind kind);

// One per file in integrators/.
std::unique_ptr<Integrator> make_phong_integrator();
std::unique_ptr<Integrator> make_shadow_integrator();
std::unique_ptr<Integrator> make_whitted_integrator();

}  // namespace prism
