#include "renderer/camera.h"

#include <cmath>

#include "renderer/math.h"

namespace prism {
namespace {

V3f row_axis(const M44d& m, int row) {
  return V3f(static_cast<float>(m[row][0]), static_cast<float>(m[row][1]),
             static_cast<float>(m[row][2]));
}

}  // namespace

Camera::Camera(const CameraDescription& description, int image_width, int image_height,
               const V3d& world_origin)
    : description_(description),
      width_(image_width),
      height_(image_height),
      world_origin_(world_origin) {
  const M44d& m = description.camera_to_world;
  // glTF forbids scale on camera nodes but files have it; the axes are renormalised so
  // that a scaled camera still sees what its field of view says.
  right_ = normalize(row_axis(m, 0));
  up_ = normalize(row_axis(m, 1));
  forward_ = -normalize(row_axis(m, 2));
  // Subtracted in double, then rounded: the camera near the shifted frame's origin.
  origin_ = V3f(V3d(m[3][0], m[3][1], m[3][2]) - world_origin_);
  // The image's own aspect ratio decides the horizontal extent, so pixels stay square
  // whatever aspectRatio the file states.
  const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
  if (description.projection == Projection::perspective) {
    half_height_ = static_cast<float>(std::tan(0.5 * description.yfov));
  } else {
    half_height_ = static_cast<float>(description.ymag);
  }
  half_width_ = half_height_ * aspect;
}

V3d camera_position(const CameraDescription& description) {
  const M44d& m = description.camera_to_world;
  return V3d(m[3][0], m[3][1], m[3][2]);
}

Ray Camera::generate_ray(float px, float py) const {
  const float u = (2.0f * px / static_cast<float>(width_) - 1.0f) * half_width_;
  const float v = (1.0f - 2.0f * py / static_cast<float>(height_)) * half_height_;
  Ray ray;
  if (description_.projection == Projection::perspective) {
    ray.origin = origin_;
    ray.direction = normalize(forward_ + u * right_ + v * up_);
  } else {
    ray.origin = origin_ + u * right_ + v * up_;
    ray.direction = forward_;
  }
  ray.from_camera = true;
  // The pixel's cone, for texture filtering (docs/materials.md): a pixel's width on the
  // image plane at distance 1, seen from the eye along this ray, whose distance to that plane
  // point is 1 / cos(angle off the axis) = 1 / (direction . forward).
  const float pixel = 2.0f * half_height_ / static_cast<float>(height_);
  if (description_.projection == Projection::perspective)
    ray.cone_spread = pixel * dot(ray.direction, forward_);
  else
    ray.cone_width = pixel;
  return ray;
}

M44d Camera::world_to_camera() const {
  const V3d position = V3d(origin_) + world_origin_;
  M44d camera_to_world(right_.x, right_.y, right_.z, 0.0,  //
                       up_.x, up_.y, up_.z, 0.0,           //
                       -forward_.x, -forward_.y, -forward_.z, 0.0, position.x, position.y,
                       position.z, 1.0);
  return camera_to_world.inverse();
}

M44d Camera::world_to_ndc() const {
  // Camera space to NDC in [-1, 1]^2 (x right, y up), in the row-vector convention.
  M44d projection;  // identity
  if (description_.projection == Projection::perspective) {
    const double znear = description_.znear > 0.0 ? description_.znear : 1e-3;
    projection = M44d(1.0 / half_width_, 0, 0, 0,   //
                      0, 1.0 / half_height_, 0, 0,  //
                      0, 0, -1, -1,                 //
                      0, 0, -2.0 * znear, 0);       // infinite far plane
  } else {
    projection = M44d(1.0 / half_width_, 0, 0, 0,   //
                      0, 1.0 / half_height_, 0, 0,  //
                      0, 0, -1, 0,                  //
                      0, 0, 0, 1);
  }
  return world_to_camera() * projection;
}

}  // namespace prism
