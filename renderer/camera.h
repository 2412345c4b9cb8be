// Pinhole perspective and orthographic cameras in glTF's convention (looking down local -Z,
// +Y up), generating one ray per image-plane position.
#pragma once

#include <Imath/ImathMatrix.h>

#include "renderer/geometry/ray.h"
#include "renderer/scene_description.h"

namespace prism {

// The camera's position in world space: the best world origin for rebasing the scene.
V3d camera_position(const CameraDescription& description);

class Camera {
 public:
  // `world_origin` is the world point that the geometry was shifted to (0, 0, 0) by
  // (GeometryOptions::world_origin, EmbreeScene::world_origin()): rays are generated in that
  // shifted frame, the camera's position subtracted in double, so a camera 1e6 m from the
  // world's origin still aims its rays to float precision near itself.
  // Not defaulted on purpose: a camera shifted differently from its geometry renders a
  // wrong image, so RenderScene::camera, which passes the geometry's origin, is the usual
  // way to make one.
  Camera(const CameraDescription& description, int image_width, int image_height,
         const V3d& world_origin);

  // A ray through the image-plane position (px, py) in pixels, (0, 0) the top-left corner
  // of the image: a pixel's centre is (x + 0.5, y + 0.5).
  Ray generate_ray(float px, float py) const;

  const CameraDescription& description() const { return description_; }
  // For the EXR metadata (OpenEXR's worldToCamera and worldToNDC), row-vector convention,
  // in true (unshifted) world coordinates.
  M44d world_to_camera() const;
  M44d world_to_ndc() const;

 private:
  CameraDescription description_;
  int width_, height_;
  V3d world_origin_;
  V3f origin_;                      // in the shifted frame (world - world_origin_)
  V3f right_, up_, forward_;        // orthonormal, in world space
  float half_width_, half_height_;  // of the image plane at distance 1, or of the view
};

}  // namespace prism
