#pragma once

#include <limits>

#include <Imath/ImathVec.h>

namespace prism {

struct Ray {
  Imath::V3f origin;
  Imath::V3f direction;  // unit length
  float tnear = 0.0f;
  float tfar = std::numeric_limits<float>::infinity();
};

}  // namespace prism
