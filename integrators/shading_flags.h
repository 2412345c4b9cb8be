// What the integrators may leave out for a scene, as a compile-time parameter: each
// integrator picks its instantiation once per tile from the scene's feature set
// (renderer/scene_features.h), so the per-ray code carries no test for work the scene cannot
// need (issue 5, as Cycles' kernel feature bits do).
//
// A flag that is false removes code whose result the feature set proves to be zero or
// unchanged, so a specialised render is bit-identical to the general one
// (tests/integrator_specialisation_test.cpp). RenderSettings::specialise = false forces the
// general code, with every flag true. docs/info.md, "What each feature flag skips".
#pragma once

#include "renderer/integrator.h"
#include "renderer/scene_features.h"

namespace prism {

struct ShadingFlags {
  bool shadows = true;       // shadow rays (false: nothing can block one)
  bool emission = true;      // adding the surface's emitted radiance (false: nothing emits)
  bool mirror = true;        // whitted: mirror reflection rays (false: no mirror material)
  bool transmission = true;  // whitted: Fresnel and refraction (false: nothing refracts)

  // Whether whitted can trace any ray beyond the shadow rays.
  constexpr bool secondary() const { return mirror || transmission; }
  bool operator==(const ShadingFlags&) const = default;
};

// Every flag on: the general code, right for any scene.
inline constexpr ShadingFlags kGeneralShading{};

inline ShadingFlags shading_flags(const SceneFeatures& f) {
  return ShadingFlags{f.shadows, f.emission, f.mirror, f.transmission};
}

// The flags a render uses: the scene's, unless the settings ask for the general code.
inline ShadingFlags shading_flags(const RenderContext& context) {
  return context.settings.specialise ? shading_flags(context.scene.features()) : kGeneralShading;
}

}  // namespace prism
