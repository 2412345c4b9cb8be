// What a scene without a camera or without lights gets, so it never renders silently black
// or from nowhere. Each default added is reported in SceneDescription::warnings.
#pragma once

#include <Imath/ImathBox.h>

#include "renderer/scene_description.h"

namespace prism {

// The world-space bounds of every mesh instance and sphere (empty box for an empty scene).
Imath::Box3d world_bounds(const SceneDescription& scene);

// True when a placed mesh or a sphere has a material with a non-zero emissive factor: the
// scene is lit by its own surfaces even without a punctual light.
bool has_emissive_geometry(const SceneDescription& scene);

// With no camera: a perspective camera (yfov 0.8 rad) looking at the centre of the bounds
// from the front (+Z), a little above and to the right, far enough to see all of them.
// With no light and no emissive geometry, lighting relative to the first camera (the one a
// render uses unless told otherwise): a directional key light of pi lux from over the
// camera's right shoulder, so a white Lambertian surface facing it renders with radiance
// equal to its albedo, and a dim sky (SceneDescription::default_sky, kDefaultSky) that
// lights every surface the key light misses. docs/lights.md states both.
// The session moves the key light to whichever camera a render uses (default_key_light).
inline constexpr SkyDescription kDefaultSky{0.15f, 0.05f};
void add_scene_defaults(SceneDescription* scene);

// The default key light for renders from `camera`: travelling along
// -(back + 0.5 up + 0.35 right) of the camera's frame, pi lux.
Light default_key_light(const CameraDescription& camera);

}  // namespace prism
