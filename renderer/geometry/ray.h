#pragma once

#include <limits>

#include <Imath/ImathVec.h>

namespace prism {

struct Ray {
  Imath::V3f origin;
  Imath::V3f direction;  // unit length
  float tnear = 0.0f;
  float tfar = std::numeric_limits<float>::infinity();
  // Made by Camera::generate_ray: it does not see back faces of single-sided materials
  // (renderer/geometry/alpha_filter.h). Secondary and shadow rays see both sides.
  bool from_camera = false;
  // The cone of directions the ray stands for (the pixel it samples), for texture
  // filtering: its width across the ray at distance t is cone_width + cone_spread * t.
  // Zero (the default) for rays that do not say: textures are then magnified.
  float cone_width = 0.0f;
  float cone_spread = 0.0f;  // radians
};

}  // namespace prism
