// What a scene without a camera or without lights gets, so it never renders silently black
// or from nowhere. Each default added is reported in SceneDescription::warnings.
#pragma once

#include <Imath/ImathBox.h>

#include "renderer/scene_description.h"

namespace prism {

// The world-space bounds of every mesh instance and sphere (empty box for an empty scene).
Imath::Box3d world_bounds(const SceneDescription& scene);

// The camera-to-world matrix of a camera at `eye` looking at `target` (its -Z), with +Y as
// near `world_up` as can be; the right vector is +X when `world_up` is along the view.
M44d look_at(const V3d& eye, const V3d& target, const V3d& world_up);

// A perspective camera (yfov 0.8 rad) named `name`, looking at the centre of the scene's
// bounds from the front (+Z), a little above and to the right, far enough to see all of them.
CameraDescription framing_camera(const SceneDescription& scene, const std::string& name);

// With no camera: a perspective camera (yfov 0.8 rad) looking at the centre of the bounds
// from the front (+Z), a little above and to the right, far enough to see all of them.
// With no light: a directional "key" light of pi lux travelling along the camera's view,
// tilted down and to the right, so a white Lambertian surface facing it renders with
// radiance close to its albedo. Returns the index of the camera to render with.
void add_scene_defaults(SceneDescription* scene);

}  // namespace prism
