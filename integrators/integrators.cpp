#include "integrators/integrators.h"

namespace prism {

const char* to_string(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::phong:
      return "phong";
    case IntegratorKind::shadow:
      return "shadow";
    case IntegratorKind::whitted:
      return "whitted";
  }
  return "?";
}

bool parse_integrator(const std::string& text, IntegratorKind* out) {
  for (IntegratorKind k :
       {IntegratorKind::phong, IntegratorKind::shadow, IntegratorKind::whitted}) {
    if (text == to_string(k)) {
      *out = k;
      return true;
    }
  }
  return false;
}

std::unique_ptr<Integrator> make_integrator(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::phong:
      return make_phong_integrator();
    case IntegratorKind::shadow:
      return make_shadow_integrator();
    case IntegratorKind::whitted:
      return make_whitted_integrator();
  }
  return nullptr;
}

}  // namespace prism
