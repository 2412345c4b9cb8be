// Pinhole perspective and orthographic cameras in glTF's convention (looking down local -Z,
// +Y up), generating one ray per image-plane position.
#pragma once

#include <string>

#include <Imath/ImathBox.h>
#include <Imath/ImathMatrix.h>

#include "renderer/geometry/ray.h"
#include "renderer/scene_description.h"

namespace prism {

// The camera's position in world space.
V3d camera_position(const CameraDescription& description);

// The bounds of the scene's meshes (each instance's object-space box, transformed) and
// spheres in world space; empty when it has neither.
Imath::Box3d scene_bounds(const SceneDescription& scene);

// The world point to rebase the scene on for renders from `camera`
// (GeometryOptions::world_origin). Floats are finest near 0, so the origin belongs where the
// hits are. A scene whose bounds are at most kSharedOriginExtent across is rebased on their
// centre, whatever the camera: every hit is then within 32 m of 0, where the ray offset
// (256 ulps) is below 1 mm, and every camera of the scene shares one BVH (a batch renders all
// of a file's cameras from one build). A larger scene is rebased on the camera's position
// clamped into its bounds: a camera inside them is its own best origin (what it sees nearby
// is rounded finest), and one outside, however far, would otherwise leave every hit with the
// rounding error, and so the ray offset, of its distance from the camera: 1.6 cm for a
// sphere 1 km away (docs/accuracy.md, "Precision far from the camera").
// `bounds` are the scene's (scene_bounds), which a caller rendering many frames of one scene
// computes once: on a big mesh they are a pass over every vertex.
inline constexpr double kSharedOriginExtent = 64.0;
V3d rebasing_origin(const Imath::Box3d& bounds, const CameraDescription& camera);

// How an orthographic camera's xmag and ymag fit an image of `width` x `height`. glTF gives
// both; pixels stay square, so both are honoured only when the image has their ratio (to
// half a pixel of width, as the default resolution, 480 high at that ratio, has). Otherwise
// ymag is kept, as a perspective camera keeps yfov, and xmag follows the image.
struct OrthographicFit {
  double xmag = 1.0, ymag = 1.0;  // the half extents rendered
  bool xmag_changed = false;      // the file's xmag was widened or narrowed to fit
};
OrthographicFit fit_orthographic(const CameraDescription& description, int width, int height);
// "ymag kept, xmag 3 widened to 4", for a fit whose xmag changed.
std::string describe_fit(const CameraDescription& description, const OrthographicFit& fit);

class Camera {
 public:
  // `world_origin` is the world point that the geometry was shifted to (0, 0, 0) by
  // (GeometryOptions::world_origin, EmbreeScene::world_origin()): rays are generated in that
  // shifted frame in double, so a camera 1e6 m from the world's origin still aims its rays
  // to float precision.
  // Not defaulted on purpose: a camera shifted differently from its geometry renders a
  // wrong image, so RenderScene::camera, which passes the geometry's origin, is the usual
  // way to make one.
  //
  // `scene_bounds` (in the shifted frame; EmbreeScene::bounds()): from outside them, every
  // ray starts moved forward in double by the camera's distance to them, so that its float
  // origin is near the geometry rather than near a camera that may stand 1 km away; what
  // lies nearer than the bounds is empty space. Empty: rays start at the camera.
  Camera(const CameraDescription& description, int image_width, int image_height,
         const V3d& world_origin, const Imath::Box3f& scene_bounds = Imath::Box3f());

  // A ray through the image-plane position (px, py) in pixels, (0, 0) the top-left corner
  // of the image: a pixel's centre is (x + 0.5, y + 0.5).
  Ray generate_ray(float px, float py) const;

  const CameraDescription& description() const { return description_; }
  // For the EXR metadata (OpenEXR's worldToCamera and worldToNDC), row-vector convention,
  // in true (unshifted) world coordinates.
  M44d world_to_camera() const;
  M44d world_to_ndc() const;

 private:
  double distance_to_bounds(Projection projection) const;

  CameraDescription description_;
  int width_, height_;
  V3d world_origin_;
  V3d origin_;                       // in the shifted frame (world - world_origin_)
  V3d right_, up_, forward_;         // orthonormal, in world space
  double half_width_, half_height_;  // of the image plane at distance 1, or of the view
  Imath::Box3d bounds_;              // scene_bounds with a margin; empty = no advance
  // Constants of every ray, computed once.
  double pixel_width_ = 0.0;  // a pixel's width on the image plane at 1
  double advance_ = 0.0;      // how far every ray starts in front of the camera
};

}  // namespace prism
