// Direct light alone: emission plus the local shading equation at the camera ray's nearest
// hit. The two integrators that see only direct light, `phong` (no shadows) and `shadow` (one
// shadow ray per light), differ in one compile-time flag, so they are one template; their
// files (phong.cpp, shadow.cpp) document and create them. whitted shades each hit with
// shade_direct too, and runs render_direct_tile itself when the scene has no mirror and
// nothing transmissive.
#pragma once

#include "integrators/local_shading.h"
#include "integrators/parameters.h"
#include "integrators/shading_flags.h"

namespace prism {

// The radiance a hit sends towards the viewer by direct light: its emission (unless F says
// nothing emits, when it is zero) plus the local shading equation, with shadow rays as
// F.shadows says.
template <ShadingFlags F>
Imath::V3f shade_direct(const RenderContext& context, const AmbientLight& ambient,
                        const SurfaceHit& hit, const SurfaceResponse& surface,
                        const Imath::V3f& to_viewer, const ShadingSample& sample,
                        RayCounters* counters) {
  const Imath::V3f local =
      shade_local<F.shadows>(context, ambient, hit, surface, to_viewer, sample, counters);
  if constexpr (F.emission)
    return surface.emission + local;
  else
    return local;
}

// Renders a tile by direct light, shading with shade_direct under flags.shadows and
// flags.emission: the instantiation is picked here, once per tile (direct.cpp).
void render_direct_tile(const ShadingFlags& flags, const RenderContext& context,
                        const AmbientLight& ambient, const TileRect& tile, Image* image,
                        RayCounters* counters);

// The parameter both direct-light integrators take, as their tables declare it.
inline constexpr ParameterInfo kAmbientParameter{
    "ambient",
    ParameterType::real,
    0.0,
    0.0,
    3.4e38,
    "Ambient radiance I_a (the lecture's ambient term), scaled by each surface's albedo"};

// The weight of the environment's irradiance in the ambient term (integrators/local_shading.h).
inline constexpr ParameterInfo kEnvironmentAmbientParameter{
    "environment-ambient",
    ParameterType::real,
    1.0,
    0.0,
    1.0,
    "Share of the environment's irradiance E(N)/pi in the ambient term (0: only rays that "
    "leave the scene see the environment)"};

template <bool Shadows>
class DirectLightIntegrator final : public Integrator {
 public:
  explicit DirectLightIntegrator(const ParameterValues& parameters)
      : ambient_{Imath::V3f(parameters.real("ambient")), AlbedoScope::all_lobes,
                 static_cast<float>(parameters.real("environment-ambient"))} {}

  void render_tile(const RenderContext& context, const TileRect& tile, Image* image,
                   RayCounters* counters) const override {
    ShadingFlags flags = shading_flags(context);
    flags.shadows = flags.shadows && Shadows;
    render_direct_tile(flags, context, ambient_, tile, image, counters);
  }

 private:
  AmbientLight ambient_;
};

}  // namespace prism
