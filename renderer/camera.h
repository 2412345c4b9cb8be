// Pinhole perspective and orthographic cameras in glTF's convention (looking down local -Z,
// +Y up), generating one ray per image-plane position.
#pragma once

#include <Imath/ImathMatrix.h>

#include "renderer/ray.h"
#include "renderer/scene_description.h"

namespace prism {

class Camera {
 public:
  Camera(const CameraDescription& description, int image_width, int image_height);

  // A ray through the image-plane position (px, py) in pixels, (0, 0) the top-left corner
  // of the image: a pixel's centre is (x + 0.5, y + 0.5).
  Ray generate_ray(float px, float py) const;

  const CameraDescription& description() const { return description_; }
  // For the EXR metadata (OpenEXR's worldToCamera and worldToNDC), row-vector convention.
  M44d world_to_camera() const;
  M44d world_to_ndc() const;

 private:
  CameraDescription description_;
  int width_, height_;
  V3f origin_, right_, up_, forward_;  // orthonormal, in world space
  float half_width_, half_height_;     // of the image plane at distance 1, or of the view
};

}  // namespace prism
