#include "renderer/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "renderer/math.h"

namespace prism {
namespace {

V3d row_axis(const M44d& m, int row) {
  return V3d(m[row][0], m[row][1], m[row][2]).normalized();
}

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

}  // namespace

V3d camera_position(const CameraDescription& description) {
  const M44d& m = description.camera_to_world;
  return V3d(m[3][0], m[3][1], m[3][2]);
}

Imath::Box3d scene_bounds(const SceneDescription& scene) {
  std::vector<Imath::Box3d> mesh_bounds(scene.meshes.size());
  for (size_t i = 0; i < scene.meshes.size(); ++i)
    for (const Primitive& p : scene.meshes[i].primitives)
      for (const V3f& v : p.positions) mesh_bounds[i].extendBy(V3d(v));
  Imath::Box3d bounds;
  for (const MeshInstance& instance : scene.instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= mesh_bounds.size()) continue;
    const Imath::Box3d& b = mesh_bounds[static_cast<size_t>(instance.mesh)];
    if (b.isEmpty()) continue;
    for (int corner = 0; corner < 8; ++corner) {
      const V3d p((corner & 1) ? b.max.x : b.min.x, (corner & 2) ? b.max.y : b.min.y,
                  (corner & 4) ? b.max.z : b.min.z);
      V3d q;
      instance.object_to_world.multVecMatrix(p, q);
      bounds.extendBy(q);
    }
  }
  for (const Sphere& s : scene.spheres) {
    bounds.extendBy(s.centre - V3d(s.radius));
    bounds.extendBy(s.centre + V3d(s.radius));
  }
  return bounds;
}

V3d rebasing_origin(const Imath::Box3d& bounds, const CameraDescription& camera) {
  const V3d eye = camera_position(camera);
  if (bounds.isEmpty()) return eye;
  V3d origin;
  const V3d size = bounds.size();
  if (std::max({size.x, size.y, size.z}) <= kSharedOriginExtent)
    origin = bounds.center();
  else
    for (int i = 0; i < 3; ++i) origin[i] = std::clamp(eye[i], bounds.min[i], bounds.max[i]);
  // Non-finite bounds (a hostile file's transform) would make every coordinate NaN.
  return std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z) ? origin
                                                                                       : eye;
}

OrthographicFit fit_orthographic(const CameraDescription& description, int width, int height) {
  OrthographicFit fit;
  fit.ymag = description.ymag;
  fit.xmag = description.ymag * static_cast<double>(width) / static_cast<double>(height);
  // The default resolution rounds 480 * xmag / ymag to whole pixels.
  if (description.xmag > 0.0 && std::isfinite(description.xmag) && description.ymag > 0.0 &&
      std::fabs(static_cast<double>(width) -
                static_cast<double>(height) * description.xmag / description.ymag) <= 0.5) {
    fit.xmag = description.xmag;
  } else {
    fit.xmag_changed = true;
  }
  return fit;
}

std::string describe_fit(const CameraDescription& description, const OrthographicFit& fit) {
  return "ymag kept, xmag " + number(description.xmag) +
         (fit.xmag > description.xmag ? " widened to " : " narrowed to ") + number(fit.xmag);
}

Camera::Camera(const CameraDescription& description, int image_width, int image_height,
               const V3d& world_origin, const Imath::Box3f& scene_bounds)
    : description_(description),
      width_(image_width),
      height_(image_height),
      world_origin_(world_origin) {
  const M44d& m = description.camera_to_world;
  // glTF forbids scale on camera nodes but files have it; the axes are renormalised so
  // that a scaled camera still sees what its field of view says.
  right_ = row_axis(m, 0);
  up_ = row_axis(m, 1);
  forward_ = -row_axis(m, 2);
  origin_ = V3d(m[3][0], m[3][1], m[3][2]) - world_origin_;
  if (description.projection == Projection::perspective) {
    // The image's own aspect ratio decides the horizontal extent, so pixels stay square
    // whatever aspectRatio the file states.
    half_height_ = std::tan(0.5 * description.yfov);
    half_width_ = half_height_ * static_cast<double>(width_) / static_cast<double>(height_);
  } else {
    const OrthographicFit fit = fit_orthographic(description, width_, height_);
    half_width_ = fit.xmag;
    half_height_ = fit.ymag;
  }
  if (!scene_bounds.isEmpty()) {
    // The margin keeps a surface on the bounds' face, and the origin's rounding to float,
    // on the far side of the ray's start.
    const V3d lo(scene_bounds.min), hi(scene_bounds.max);
    const double size = (hi - lo).length();
    const double largest = std::max({std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z),
                                     std::fabs(hi.x), std::fabs(hi.y), std::fabs(hi.z)});
    const double margin = 0x1.0p-10 * size + 0x1.0p-20 * largest;
    if (std::isfinite(margin)) bounds_ = Imath::Box3d(lo - V3d(margin), hi + V3d(margin));
  }
  pixel_width_ = 2.0 * half_height_ / height_;
  advance_ = bounds_.isEmpty() ? 0.0 : distance_to_bounds(description.projection);
}

// One advance for every ray, the least of their distances to the bounds, so that none starts
// past where it enters them (the geometry in front of it) and none needs a slab test of its
// own: a perspective camera's distance to the box (0 inside it), and for an orthographic one,
// whose rays leave the view plane along forward_, how far in front of that plane the box's
// nearest corner lies (0 when the box reaches behind it).
double Camera::distance_to_bounds(Projection projection) const {
  if (projection == Projection::perspective) {
    V3d gap(0.0);
    for (int i = 0; i < 3; ++i)
      gap[i] = std::max({0.0, bounds_.min[i] - origin_[i], origin_[i] - bounds_.max[i]});
    return gap.length();
  }
  double nearest = std::numeric_limits<double>::infinity();
  for (int corner = 0; corner < 8; ++corner) {
    const V3d p((corner & 1) ? bounds_.max.x : bounds_.min.x,
                (corner & 2) ? bounds_.max.y : bounds_.min.y,
                (corner & 4) ? bounds_.max.z : bounds_.min.z);
    nearest = std::min(nearest, (p - origin_).dot(forward_));
  }
  return std::max(0.0, nearest);
}

Ray Camera::generate_ray(float px, float py) const {
  const double u = (2.0 * px / width_ - 1.0) * half_width_;
  const double v = (1.0 - 2.0 * py / height_) * half_height_;
  const bool perspective = description_.projection == Projection::perspective;
  V3d origin, direction;
  if (perspective) {
    origin = origin_;
    direction = (forward_ + u * right_ + v * up_).normalized();
  } else {
    origin = origin_ + u * right_ + v * up_;
    direction = forward_;
  }
  Ray ray;
  ray.origin = V3f(origin + advance_ * direction);
  ray.direction = V3f(direction);
  ray.from_camera = true;
  // The pixel's cone, for texture filtering (docs/materials.md): a pixel's width on the
  // image plane at distance 1, seen from the eye along this ray, whose distance to that plane
  // point is 1 / cos(angle off the axis) = 1 / (direction . forward). A ray moved forward
  // starts with the width the cone has there.
  if (perspective) {
    const double spread = pixel_width_ * direction.dot(forward_);
    ray.cone_spread = static_cast<float>(spread);
    ray.cone_width = static_cast<float>(spread * advance_);
  } else {
    ray.cone_width = static_cast<float>(pixel_width_);
  }
  return ray;
}

M44d Camera::world_to_camera() const {
  const V3d position = origin_ + world_origin_;
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
