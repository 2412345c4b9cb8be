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

// The camera-to-world matrix of a camera at `eye` looking at `target` (its -Z), with +Y as
// near `world_up` as can be; the right vector is +X when `world_up` is along the view.
M44d look_at(const V3d& eye, const V3d& target, const V3d& world_up);

// A perspective camera (yfov 0.8 rad) named `name`, looking at the centre of the scene's
// bounds from the front (+Z), a little above and to the right, far enough to see all of them.
CameraDescription framing_camera(const SceneDescription& scene, const std::string& name);

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
