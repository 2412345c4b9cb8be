// Spheres in all three modes (analytic user geometry, icosphere mesh, Embree's sphere points),
// the robust ray/sphere test against the textbook one, the icosphere's topology and error
// bound, and the --spheres option string.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include "renderer/geometry/sphere_geometry.h"
#include "renderer/geometry/sphere_intersect.h"
#include "renderer/geometry/sphere_mesh.h"

namespace prism {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The form found in most textbooks (and in Embree's tutorial sphere): a t^2 + b t + c = 0
// solved with b^2 - 4ac and (-b -+ sqrt) / 2a. It exists only to show, below, what
// intersect_sphere's reformulation buys; nothing in the renderer uses it.
std::optional<float> intersect_sphere_textbook(const V3f& o, const V3f& d, const V3f& centre,
                                               float radius, float tnear, float tfar) {
  const V3f f = o - centre;
  const float a = d.dot(d);
  const float b = 2.0f * f.dot(d);
  const float c = f.dot(f) - radius * radius;
  const float disc = b * b - 4.0f * a * c;
  if (disc < 0.0f) return std::nullopt;
  const float root = std::sqrt(disc);
  const float t0 = (-b - root) / (2.0f * a);
  const float t1 = (-b + root) / (2.0f * a);
  if (t0 >= tnear && t0 <= tfar) return t0;
  if (t1 >= tnear && t1 <= tfar) return t1;
  return std::nullopt;
}

// The exact near root for the given float inputs, in long double (64-bit significand): the
// products of floats are exact there and the remaining rounding is ~1e-19 relative.
std::optional<long double> reference_root(const V3f& o, const V3f& d, const V3f& centre,
                                          float radius) {
  const long double fx = (long double)o.x - centre.x, fy = (long double)o.y - centre.y,
                    fz = (long double)o.z - centre.z;
  const long double a = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z;
  const long double fd = fx * d.x + fy * d.y + fz * d.z;
  const long double lx = fx - fd / a * d.x, ly = fy - fd / a * d.y, lz = fz - fd / a * d.z;
  const long double delta = (long double)radius * radius - (lx * lx + ly * ly + lz * lz);
  if (delta < 0) return std::nullopt;
  return (-fd - std::sqrt(a * delta)) / a;
}

// The exact outward offset hit - centre at the near root, in long double.
std::optional<std::array<long double, 3>> reference_offset(const V3f& o, const V3f& d,
                                                           const V3f& centre, float radius) {
  const auto t = reference_root(o, d, centre, radius);
  if (!t) return std::nullopt;
  return std::array<long double, 3>{(long double)o.x - centre.x + *t * d.x,
                                    (long double)o.y - centre.y + *t * d.y,
                                    (long double)o.z - centre.z + *t * d.z};
}

// Angle in radians between v and the exact direction e; atan2 of |cross| and dot, because
// acos of a dot product near 1 would bury it under the rounding of the lengths.
double angle_to(const V3f& v, const std::array<long double, 3>& e) {
  const long double cx = v.y * e[2] - v.z * e[1], cy = v.z * e[0] - v.x * e[2],
                    cz = v.x * e[1] - v.y * e[0];
  const long double dot = v.x * e[0] + v.y * e[1] + v.z * e[2];
  return double(std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot));
}

// Distance of x from the exact value in units of the float spacing at the exact value.
double ulps(float x, long double exact) {
  const float e = float(exact);
  const double spacing = double(std::nextafter(std::abs(e), kInf)) - std::abs(e);
  return double(std::abs((long double)x - exact)) / spacing;
}

V3f to_f(const V3d& v) {
  return V3f(float(v.x), float(v.y), float(v.z));
}

// ---------------------------------------------------------------------------------------
// intersect_sphere alone

TEST(IntersectSphere, HeadOnHitIsExact) {
  const auto r = intersect_sphere(V3f(0, 0, 0), V3f(0, 0, -1), V3f(0, 0, -5), 1.0f, 0.0f, kInf);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->t, 4.0f);
  EXPECT_FALSE(r->exiting);
  EXPECT_EQ(r->offset, V3f(0, 0, 1));
}

TEST(IntersectSphere, UnnormalisedDirectionScalesT) {
  const auto r = intersect_sphere(V3f(0, 0, 0), V3f(0, 0, -2), V3f(0, 0, -5), 1.0f, 0.0f, kInf);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->t, 2.0f);
  EXPECT_EQ(r->offset, V3f(0, 0, 1));
}

TEST(IntersectSphere, FromInsideReturnsTheFarRootAndExits) {
  const auto r =
      intersect_sphere(V3f(0, 0, -5), V3f(0.6f, 0.8f, 0), V3f(0, 0, -5), 2.0f, 0.0f, kInf);
  ASSERT_TRUE(r);
  EXPECT_FLOAT_EQ(r->t, 2.0f);
  EXPECT_TRUE(r->exiting);
  EXPECT_NEAR(r->offset.x, 1.2f, 1e-6f);
  EXPECT_NEAR(r->offset.y, 1.6f, 1e-6f);
  EXPECT_EQ(r->offset.z, 0.0f);
}

TEST(IntersectSphere, TnearSkipsTheEntryAndTfarCutsTheRay) {
  const V3f o(0, 0, 0), d(0, 0, -1), c(0, 0, -5);
  // Entry at 4, exit at 6.
  auto r = intersect_sphere(o, d, c, 1.0f, 4.5f, kInf);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->t, 6.0f);
  EXPECT_TRUE(r->exiting);
  EXPECT_EQ(r->offset, V3f(0, 0, -1));
  EXPECT_FALSE(intersect_sphere(o, d, c, 1.0f, 0.0f, 3.99f));
  EXPECT_FALSE(intersect_sphere(o, d, c, 1.0f, 6.01f, kInf));
  // Both ends of the range are closed.
  ASSERT_TRUE(intersect_sphere(o, d, c, 1.0f, 0.0f, 4.0f));
  r = intersect_sphere(o, d, c, 1.0f, 6.0f, kInf);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->t, 6.0f);
}

TEST(IntersectSphere, MissesBehindAndBeside) {
  EXPECT_FALSE(intersect_sphere(V3f(0, 0, 0), V3f(0, 0, 1), V3f(0, 0, -5), 1.0f, 0.0f, kInf));
  EXPECT_FALSE(intersect_sphere(V3f(0, 0, 0), V3f(1, 0, 0), V3f(0, 0, -5), 1.0f, 0.0f, kInf));
  EXPECT_FALSE(intersect_sphere(V3f(0, 0, 0), V3f(0, 0, 0), V3f(0, 0, -5), 1.0f, 0.0f, kInf));
}

TEST(IntersectSphere, TangentAtTheOriginIsADoubleRootAtZero) {
  // b' = 0 and delta = 0 make q = 0; c / q would be 0 / 0.
  const auto r = intersect_sphere(V3f(1, 0, -5), V3f(0, 0, -1), V3f(0, 0, -5), 1.0f, 0.0f, kInf);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->t, 0.0f);
  EXPECT_FALSE(std::isnan(r->offset.x));
}

// ---------------------------------------------------------------------------------------
// The three modes inside an Embree scene

struct Hit {
  bool hit = false;
  float t = kInf;
  V3f ng;
  unsigned prim = RTC_INVALID_GEOMETRY_ID;
  unsigned geom = RTC_INVALID_GEOMETRY_ID;
};

class SphereScene {
 public:
  SphereScene(const std::vector<Sphere>& spheres, const SphereOptions& options,
              RTCSceneFlags flags = RTC_SCENE_FLAG_NONE)
      : options_(options) {
    device_ = rtcNewDevice(nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, flags);
    switch (options.mode) {
      case SphereMode::analytic:
        geom_id_ = attach_analytic_spheres(device_, scene_, spheres);
        break;
      case SphereMode::embree_points:
        geom_id_ = attach_point_spheres(device_, scene_, spheres);
        break;
      case SphereMode::mesh: {
        // All spheres in one triangle geometry, as the renderer does for a baked mesh.
        std::vector<Primitive> prims;
        size_t vertices = 0, indices = 0;
        for (const Sphere& s : spheres) {
          prims.push_back(tessellate_sphere(s, options.mesh_level));
          vertices += prims.back().positions.size();
          indices += prims.back().indices.size();
        }
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices));
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), indices / 3));
        unsigned base = 0;
        for (const Primitive& p : prims) {
          for (const V3f& q : p.positions) {
            *v++ = q.x;
            *v++ = q.y;
            *v++ = q.z;
          }
          for (uint32_t i : p.indices) *idx++ = base + i;
          base += unsigned(p.positions.size());
        }
        rtcCommitGeometry(g);
        geom_id_ = rtcAttachGeometry(scene_, g);
        rtcReleaseGeometry(g);
        break;
      }
    }
    rtcCommitScene(scene_);
    EXPECT_EQ(rtcGetDeviceError(device_), RTC_ERROR_NONE);
  }
  ~SphereScene() {
    if (options_.mode == SphereMode::analytic) release_analytic_spheres(scene_, geom_id_);
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  SphereScene(const SphereScene&) = delete;
  SphereScene& operator=(const SphereScene&) = delete;

  Hit trace(const V3f& o, const V3f& d, float tnear = 0.0f, float tfar = kInf,
            RTCIntersectContext* context = nullptr) const {
    RTCIntersectContext own;
    rtcInitIntersectContext(&own);
    RTCRayHit rh{};
    rh.ray.org_x = o.x;
    rh.ray.org_y = o.y;
    rh.ray.org_z = o.z;
    rh.ray.dir_x = d.x;
    rh.ray.dir_y = d.y;
    rh.ray.dir_z = d.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, context ? context : &own, &rh);
    Hit h;
    h.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    if (h.hit) {
      h.t = rh.ray.tfar;
      h.ng = V3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
      h.prim = rh.hit.primID;
      h.geom = rh.hit.geomID;
      EXPECT_EQ(rh.hit.instID[0], RTC_INVALID_GEOMETRY_ID);
    } else {
      EXPECT_EQ(rh.ray.tfar, tfar);  // a miss leaves the ray alone
    }
    return h;
  }

  bool occluded(const V3f& o, const V3f& d, float tnear = 0.0f, float tfar = kInf,
                RTCIntersectContext* context = nullptr) const {
    RTCIntersectContext own;
    rtcInitIntersectContext(&own);
    RTCRay ray{};
    ray.org_x = o.x;
    ray.org_y = o.y;
    ray.org_z = o.z;
    ray.dir_x = d.x;
    ray.dir_y = d.y;
    ray.dir_z = d.z;
    ray.tnear = tnear;
    ray.tfar = tfar;
    ray.mask = ~0u;
    rtcOccluded1(scene_, context ? context : &own, &ray);
    return ray.tfar == -kInf;
  }

  unsigned geom_id() const { return geom_id_; }

 private:
  SphereOptions options_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  unsigned geom_id_ = RTC_INVALID_GEOMETRY_ID;
};

constexpr int kTestMeshLevel = 5;

class SphereModeTest : public ::testing::TestWithParam<SphereMode> {
 protected:
  SphereOptions options() const { return {GetParam(), kTestMeshLevel}; }
  bool is_mesh() const { return GetParam() == SphereMode::mesh; }
  // How much farther a ray through the centre may travel before meeting the mesh, and the
  // least cosine between a mesh face normal and the true normal under it.
  double gap(double radius) const {
    return is_mesh() ? tessellation_max_error(radius, kTestMeshLevel) : 0.0;
  }
  double min_cos(double radius) const {
    return is_mesh() ? 1.0 - gap(radius) / radius : 1.0 - 1e-6;
  }
};

// Float rounding of t near 5 units from the origin: a few ulps of 4..6.
constexpr float kTEps = 4e-6f;

double cos_angle(const V3f& a, const V3f& b) {
  return a.dot(b) / (a.length() * b.length());
}

TEST_P(SphereModeTest, HeadOnHit) {
  const SphereScene scene({{V3d(0, 0, -5), 1.0, 7, "s"}}, options());
  const Hit h = scene.trace(V3f(0, 0, 0), V3f(0, 0, -1));
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.geom, scene.geom_id());
  if (is_mesh()) {
    EXPECT_GE(h.t, 4.0f - kTEps);
    EXPECT_LE(h.t, 4.0 + gap(1.0) + kTEps);
  } else {
    EXPECT_NEAR(h.t, 4.0f, 1e-6f);
    EXPECT_EQ(h.prim, 0u);
  }
  EXPECT_GE(cos_angle(h.ng, V3f(0, 0, 1)), min_cos(1.0));
  EXPECT_TRUE(scene.occluded(V3f(0, 0, 0), V3f(0, 0, -1)));
  EXPECT_FALSE(scene.occluded(V3f(0, 0, 0), V3f(0, 0, -1), 0.0f, 3.9f));
}

TEST_P(SphereModeTest, TangentSkim) {
  const SphereScene scene({{V3d(0, 0, -5), 1.0, -1, "s"}}, options());
  // A mesh is inside the sphere by up to gap(): it is only guaranteed to be hit that far in,
  // and is certainly missed by anything outside the sphere.
  const float inside = is_mesh() ? float(2.0 * gap(1.0)) : 1e-6f;
  const float outside = 1e-6f;
  for (const V3f& side : {V3f(1, 0, 0), V3f(0, -1, 0), V3f(0.6f, 0.8f, 0)}) {
    SCOPED_TRACE(testing::Message() << "side " << side);
    const Hit in = scene.trace((1.0f - inside) * side, V3f(0, 0, -1));
    ASSERT_TRUE(in.hit);
    // Entering a sphere at distance 1 - e from the axis, the surface is nearly parallel to
    // the ray: z = -5 + sqrt(1 - (1 - e)^2) ~ -5 + sqrt(2 e).
    const double expected = 5.0 - std::sqrt(1.0 - std::pow(1.0 - double(inside), 2));
    EXPECT_NEAR(in.t, expected, is_mesh() ? 0.05 : 1e-4);
    // The normal points sideways, nearly perpendicular to the ray.
    EXPECT_GT(cos_angle(in.ng, side), 0.9);
    EXPECT_TRUE(scene.occluded((1.0f - inside) * side, V3f(0, 0, -1)));
    EXPECT_FALSE(scene.trace((1.0f + outside) * side, V3f(0, 0, -1)).hit);
    EXPECT_FALSE(scene.occluded((1.0f + outside) * side, V3f(0, 0, -1)));
  }
}

TEST_P(SphereModeTest, StartInsideHitsTheFarSideFacingOut) {
  const SphereScene scene({{V3d(0, 0, -5), 1.0, -1, "s"}}, options());
  for (const V3f& d : {V3f(0, 0, -1), V3f(0, 0, 1), V3f(0.48f, -0.6f, 0.64f)}) {
    SCOPED_TRACE(testing::Message() << "direction " << d);
    const Hit h = scene.trace(V3f(0, 0, -5), d);
    ASSERT_TRUE(h.hit);
    EXPECT_LE(h.t, 1.0f + kTEps);
    EXPECT_GE(h.t, 1.0 - gap(1.0) - kTEps);
    EXPECT_GT(h.ng.dot(d), 0.0f) << "Ng must point out of the sphere, so along d when exiting";
    EXPECT_GE(cos_angle(h.ng, d), min_cos(1.0));
  }
}

TEST_P(SphereModeTest, Miss) {
  const SphereScene scene({{V3d(0, 0, -5), 1.0, -1, "s"}}, options());
  EXPECT_FALSE(scene.trace(V3f(0, 0, 0), V3f(1, 0, 0)).hit);
  EXPECT_FALSE(scene.trace(V3f(0, 0, 0), V3f(0.3f, 0, -1)).hit);  // passes 1.47 from the centre
  EXPECT_FALSE(scene.trace(V3f(0, 2, 0), V3f(0, 0, -1)).hit);
  EXPECT_FALSE(scene.occluded(V3f(0, 2, 0), V3f(0, 0, -1)));
}

TEST_P(SphereModeTest, SphereBehindTheRay) {
  const SphereScene scene({{V3d(0, 0, -5), 1.0, -1, "s"}}, options());
  EXPECT_FALSE(scene.trace(V3f(0, 0, 0), V3f(0, 0, 1)).hit);
  EXPECT_FALSE(scene.occluded(V3f(0, 0, 0), V3f(0, 0, 1)));
  // Past the sphere looking away, and with tnear beyond the exit.
  EXPECT_FALSE(scene.trace(V3f(0, 0, -7), V3f(0, 0, -1)).hit);
  EXPECT_FALSE(scene.trace(V3f(0, 0, 0), V3f(0, 0, -1), 6.5f).hit);
}

TEST_P(SphereModeTest, OffsetScaledSphere) {
  const V3d centre(3.25, -2.5, -40.0);
  const double radius = 2.5;
  const SphereScene scene({{V3d(0, 0, -5), 1.0, -1, "a"}, {centre, radius, -1, "b"}}, options());
  const V3f o(0.5f, 1.0f, 2.0f);
  // Through the centre: the mesh is off by at most gap along this ray.
  const V3f d = (to_f(centre) - o).normalized();
  const auto exact = reference_root(o, d, to_f(centre), float(radius));
  ASSERT_TRUE(exact);
  const Hit h = scene.trace(o, d);
  ASSERT_TRUE(h.hit);
  // The second sphere: primID 1, or for a mesh one of the second block of triangles.
  EXPECT_EQ(h.prim / (is_mesh() ? 20u << (2 * kTestMeshLevel) : 1u), 1u);
  const double t_eps = 4e-6 * double(*exact);
  EXPECT_GE(h.t, *exact - t_eps);
  EXPECT_LE(h.t, *exact + gap(radius) + t_eps);
  EXPECT_GE(cos_angle(h.ng, -d), min_cos(radius));

  if (!is_mesh()) {
    // Off-centre, where the normal is not along the ray.
    const V3f target = to_f(centre) + V3f(1.5f, 1.0f, 0.5f);
    const V3f d2 = (target - o).normalized();
    const auto exact2 = reference_root(o, d2, to_f(centre), float(radius));
    ASSERT_TRUE(exact2);
    const Hit h2 = scene.trace(o, d2);
    ASSERT_TRUE(h2.hit);
    EXPECT_LE(ulps(h2.t, *exact2), 4.0);
    const V3d p = V3d(o.x, o.y, o.z) + double(*exact2) * V3d(d2.x, d2.y, d2.z);
    EXPECT_GE(cos_angle(h2.ng, to_f((p - centre) / radius)), 1.0 - 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(AllModes, SphereModeTest,
                         ::testing::Values(SphereMode::analytic, SphereMode::mesh,
                                           SphereMode::embree_points),
                         [](const auto& info) {
                           std::string s = to_string(SphereOptions{info.param, kTestMeshLevel});
                           std::replace_if(
                               s.begin(), s.end(), [](char c) { return !std::isalnum(c); }, '_');
                           return s;
                         });

TEST(AnalyticSpheres, PrimIdIsTheIndexAndManySpheresShareOneGeometry) {
  std::vector<Sphere> spheres;
  for (int i = 0; i < 50; ++i) spheres.push_back({V3d(3.0 * i, 0, -10), 1.0, i, "s"});
  const SphereScene scene(spheres, {SphereMode::analytic, 0});
  for (int i = 0; i < 50; i += 7) {
    const Hit h = scene.trace(V3f(3.0f * i, 0, 0), V3f(0, 0, -1));
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.prim, unsigned(i));
    EXPECT_EQ(h.geom, scene.geom_id());
    EXPECT_FLOAT_EQ(h.t, 9.0f);
  }
  EXPECT_FALSE(scene.trace(V3f(1.5f, 0, 0), V3f(0, 0, -1)).hit);  // between two spheres
}

struct FilterContext {
  RTCIntersectContext context;  // first, so Embree's pointer is ours
  bool accept = true;
  int calls = 0;
  float seen_t = 0.0f;
};

void record_filter(const RTCFilterFunctionNArguments* args) {
  auto* self = reinterpret_cast<FilterContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    ++self->calls;
    self->seen_t = RTCRayN_tfar(args->ray, args->N, i);
    if (!self->accept) args->valid[i] = 0;
  }
}

TEST(AnalyticSpheres, ContextFilterSeesTheCandidateAndCanRejectIt) {
  const SphereScene scene({{V3d(0, 0, -5), 1.0, -1, "s"}}, {SphereMode::analytic, 0},
                          RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  FilterContext fc;
  rtcInitIntersectContext(&fc.context);
  fc.context.filter = record_filter;
  Hit h = scene.trace(V3f(0, 0, 0), V3f(0, 0, -1), 0.0f, kInf, &fc.context);
  EXPECT_TRUE(h.hit);
  EXPECT_EQ(fc.calls, 1);
  EXPECT_EQ(fc.seen_t, 4.0f);
  fc.accept = false;
  fc.calls = 0;
  h = scene.trace(V3f(0, 0, 0), V3f(0, 0, -1), 0.0f, kInf, &fc.context);
  EXPECT_FALSE(h.hit);
  EXPECT_EQ(fc.calls, 1);
  EXPECT_FALSE(scene.occluded(V3f(0, 0, 0), V3f(0, 0, -1), 0.0f, kInf, &fc.context));
  EXPECT_EQ(fc.calls, 2);
}

TEST(AnalyticSpheres, PacketRaysHonourTheValidMask) {
  // rtcIntersect4 goes through the N = 4 path of the callback; lane 2 is switched off and
  // must come back untouched, lane 3 misses.
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene s = rtcNewScene(device);
  const unsigned id = attach_analytic_spheres(device, s, {{V3d(0, 0, -5), 1.0, -1, "s"}});
  rtcCommitScene(s);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(16) RTCRayHit4 rh{};
  const float xs[4] = {0.0f, 0.5f, 0.0f, 3.0f};
  for (int i = 0; i < 4; ++i) {
    rh.ray.org_x[i] = xs[i];
    rh.ray.dir_z[i] = -1.0f;
    rh.ray.tfar[i] = kInf;
    rh.ray.mask[i] = ~0u;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
  }
  alignas(16) const int valid[4] = {-1, -1, 0, -1};
  rtcIntersect4(valid, s, &context, &rh);
  EXPECT_EQ(rh.hit.geomID[0], id);
  EXPECT_EQ(rh.ray.tfar[0], 4.0f);
  EXPECT_EQ(rh.hit.geomID[1], id);
  EXPECT_NEAR(rh.ray.tfar[1], 5.0f - std::sqrt(0.75f), 1e-6f);
  EXPECT_NEAR(rh.hit.Ng_x[1], 0.5f, 1e-6f);
  EXPECT_EQ(rh.hit.geomID[2], RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ(rh.ray.tfar[2], kInf);
  EXPECT_EQ(rh.hit.geomID[3], RTC_INVALID_GEOMETRY_ID);
  release_analytic_spheres(s, id);
  release_analytic_spheres(s, id);  // harmless
  rtcReleaseScene(s);
  rtcReleaseDevice(device);
}

// ---------------------------------------------------------------------------------------
// Small spheres far away: robust against textbook

struct FarStats {
  double robust_max_ulps = 0;
  double textbook_max_ulps = 0;
  double embree_analytic_max_ulps = 0;
  double embree_points_max_ulps = 0;
  double analytic_normal_max_rad = 0;
  double points_normal_max_rad = 0;
  double naive_normal_max_rad = 0;  // normalize(o + t d - centre) in float, for comparison
  int rays = 0;
  int textbook_misses = 0;
  int robust_misses = 0;
};

FarStats measure_far_sphere(double distance) {
  FarStats stats;
  // A direction with no zero or repeated component, so no product below is exact by luck.
  const V3f centre = to_f(distance * V3d(0.267261241912424, 0.534522483824849, -0.801783725737273));
  const float radius = 1.0f;
  const V3f o(0.125f, -0.25f, 0.0625f);
  std::vector<V3f> dirs;
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 7; ++j) {
      // Aim points spread over the disc of radius 0.9 r around the centre.
      const V3f offset(0.27f * float(i - 3), 0.27f * float(j - 3), 0.1f * float((i + j) % 3 - 1));
      if (offset.length() > 0.9f) continue;
      dirs.push_back((centre + offset - o).normalized());
    }
  }
  const SphereScene analytic({{V3d(centre.x, centre.y, centre.z), radius, -1, ""}},
                             {SphereMode::analytic, 0});
  const SphereScene points({{V3d(centre.x, centre.y, centre.z), radius, -1, ""}},
                           {SphereMode::embree_points, 0});
  for (const V3f& d : dirs) {
    const auto exact = reference_root(o, d, centre, radius);
    if (!exact) continue;
    ++stats.rays;
    const auto robust = intersect_sphere(o, d, centre, radius, 0.0f, kInf);
    const auto textbook = intersect_sphere_textbook(o, d, centre, radius, 0.0f, kInf);
    if (robust) {
      stats.robust_max_ulps = std::max(stats.robust_max_ulps, ulps(robust->t, *exact));
    } else {
      ++stats.robust_misses;
    }
    if (textbook) {
      stats.textbook_max_ulps = std::max(stats.textbook_max_ulps, ulps(*textbook, *exact));
    } else {
      ++stats.textbook_misses;
    }
    const Hit ha = analytic.trace(o, d);
    const Hit hp = points.trace(o, d);
    stats.embree_analytic_max_ulps =
        std::max(stats.embree_analytic_max_ulps, ha.hit ? ulps(ha.t, *exact) : 1e30);
    stats.embree_points_max_ulps =
        std::max(stats.embree_points_max_ulps, hp.hit ? ulps(hp.t, *exact) : 1e30);
    const auto normal = *reference_offset(o, d, centre, radius);
    stats.analytic_normal_max_rad =
        std::max(stats.analytic_normal_max_rad, ha.hit ? angle_to(ha.ng, normal) : 1e30);
    stats.points_normal_max_rad =
        std::max(stats.points_normal_max_rad, hp.hit ? angle_to(hp.ng, normal) : 1e30);
    if (robust) {
      stats.naive_normal_max_rad =
          std::max(stats.naive_normal_max_rad, angle_to(o + robust->t * d - centre, normal));
    }
  }
  return stats;
}

TEST(FarSphere, RobustStaysWithinAFewUlpsWhereTheTextbookFails) {
  std::printf("%9s %5s %12s %14s %8s %14s %12s %13s %12s %12s\n", "distance", "rays", "robust ulps",
              "textbook ulps", "tb miss", "analytic ulps", "points ulps", "analytic Ng",
              "points Ng", "o+td-c Ng");
  for (double distance : {1e2, 1e3, 1e4, 1e5}) {
    SCOPED_TRACE(testing::Message() << "distance " << distance);
    const FarStats s = measure_far_sphere(distance);
    std::printf("%9.0e %5d %12.2f %14.2f %8d %14.2f %12.2f %13.2e %12.2e %12.2e\n", distance,
                s.rays, s.robust_max_ulps, s.textbook_max_ulps, s.textbook_misses,
                s.embree_analytic_max_ulps, s.embree_points_max_ulps, s.analytic_normal_max_rad,
                s.points_normal_max_rad, s.naive_normal_max_rad);
    ASSERT_GT(s.rays, 20);
    EXPECT_EQ(s.robust_misses, 0);
    EXPECT_LE(s.robust_max_ulps, 4.0);
    EXPECT_LE(s.embree_analytic_max_ulps, 4.0);
    EXPECT_LE(s.embree_points_max_ulps, 4.0);
    // The analytic normal is the exact one rounded to float, whatever the distance
    // (radians; a float vector resolves ~6e-8).
    EXPECT_LE(s.analytic_normal_max_rad, 2e-7);
    if (distance >= 1e3) {
      // The textbook form is off by hundreds of ulps or loses the sphere altogether.
      EXPECT_TRUE(s.textbook_misses > 0 || s.textbook_max_ulps > 100.0)
          << s.textbook_misses << " misses, " << s.textbook_max_ulps << " ulps";
    }
  }
}

TEST(FarSphere, HeadOnTextbookLosesTheRadius) {
  // At 10^4 the textbook c = 10^8 - 1 rounds to 10^8 (float spacing 8 there), the
  // discriminant to 0, and t to the distance of the centre: 1 unit = ~1000 ulps too far.
  const V3f o(0, 0, 0), d(0, 0, -1), centre(0, 0, -1e4f);
  const auto robust = intersect_sphere(o, d, centre, 1.0f, 0.0f, kInf);
  const auto textbook = intersect_sphere_textbook(o, d, centre, 1.0f, 0.0f, kInf);
  ASSERT_TRUE(robust);
  ASSERT_TRUE(textbook);
  EXPECT_EQ(robust->t, 9999.0f);
  EXPECT_EQ(*textbook, 10000.0f);
}

TEST(SmallRoot, OriginNearTheSurfaceKeepsItsRelativeAccuracy) {
  // Secondary rays start on surfaces, so one root is near 0. The textbook (-b + sqrt) / 2a
  // then subtracts two numbers of size r to get one of size delta; c / q does not.
  const V3f centre(0.3f, -0.2f, -5.0f);
  const float radius = 1.0f;
  const V3f n = V3f(0.48f, 0.6f, 0.64f).normalized();
  const V3f tangent = (V3f(0.7f, -0.5f, 0.3f) - n.dot(V3f(0.7f, -0.5f, 0.3f)) * n).normalized();
  std::printf("%8s %8s %12s %14s\n", "offset", "side", "robust ulps", "textbook ulps");
  double textbook_worst = 0;
  for (float delta : {1e-2f, 1e-3f, 1e-4f}) {
    for (bool outside : {true, false}) {
      SCOPED_TRACE(testing::Message() << "delta " << delta << (outside ? " outside" : " inside"));
      // Outside: heading in at 45 degrees, the small root is the entry. Inside: heading out,
      // the small root is the exit.
      const V3f o = centre + (outside ? radius + delta : radius - delta) * n;
      const V3f d = ((outside ? -n : n) + tangent).normalized();
      const auto robust = intersect_sphere(o, d, centre, radius, 0.0f, kInf);
      const auto textbook = intersect_sphere_textbook(o, d, centre, radius, 0.0f, kInf);
      const auto exact = reference_root(o, d, centre, radius);
      ASSERT_TRUE(robust && textbook && exact);
      // reference_root gives the near root; from inside, the wanted one is the far root.
      long double wanted = *exact;
      if (!outside) {
        const long double fx = (long double)o.x - centre.x, fy = (long double)o.y - centre.y,
                          fz = (long double)o.z - centre.z;
        const long double fdotd = fx * d.x + fy * d.y + fz * d.z;
        const long double a =
            (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z;
        wanted = -2.0L * fdotd / a - *exact;  // the two roots sum to -2 f.d / a
      }
      ASSERT_LT(wanted, 2.0L * delta);
      EXPECT_EQ(robust->exiting, !outside);
      const double robust_ulps = ulps(robust->t, wanted);
      const double textbook_ulps = ulps(*textbook, wanted);
      std::printf("%8.0e %8s %12.2f %14.2f\n", delta, outside ? "outside" : "inside", robust_ulps,
                  textbook_ulps);
      EXPECT_LE(robust_ulps, 4.0);
      if (delta <= 1e-3f) textbook_worst = std::max(textbook_worst, textbook_ulps);
    }
  }
  // Any one textbook result can round luckily (9.6 ulps for delta = 1e-4 inside); the worst
  // is hundreds of ulps.
  EXPECT_GT(textbook_worst, 100.0);
}

// ---------------------------------------------------------------------------------------
// Tessellation

TEST(SphereMesh, CountsRadiiAndNormals) {
  for (int level = 0; level <= 6; ++level) {
    SCOPED_TRACE(testing::Message() << "level " << level);
    const UnitIcosphere unit = make_unit_icosphere(level);
    const size_t four_l = size_t(1) << (2 * level);
    EXPECT_EQ(unit.vertices.size(), 10 * four_l + 2);
    EXPECT_EQ(unit.indices.size(), 3 * 20 * four_l);
    double worst = 0;
    for (const V3d& v : unit.vertices) worst = std::max(worst, std::abs(v.length() - 1.0));
    EXPECT_LT(worst, 1e-12);
    // No duplicates: every position is distinct.
    std::set<std::tuple<double, double, double>> distinct;
    for (const V3d& v : unit.vertices) distinct.emplace(v.x, v.y, v.z);
    EXPECT_EQ(distinct.size(), unit.vertices.size());
  }
}

TEST(SphereMesh, WorldPositionsSitOnTheSphere) {
  const Sphere s{V3d(3.25, -2.5, -40.0), 2.5, 4, "b"};
  const Primitive p = tessellate_sphere(s, 4);
  EXPECT_EQ(p.material, 4);
  ASSERT_EQ(p.normals.size(), p.positions.size());
  EXPECT_TRUE(p.uv0.empty());
  // The only error left is the rounding to float: coordinates are below 64, where half an
  // ulp is 2^-19, so a position is at most sqrt(3) 2^-19 from where double put it.
  const double tolerance = std::sqrt(3.0) * std::ldexp(1.0, -19);
  for (size_t i = 0; i < p.positions.size(); ++i) {
    const V3f& q = p.positions[i];
    const V3d offset = V3d(q.x, q.y, q.z) - s.centre;
    ASSERT_NEAR(offset.length(), s.radius, tolerance) << i;
    ASSERT_NEAR(p.normals[i].length(), 1.0f, 1e-6f) << i;
    const V3f& n = p.normals[i];
    ASSERT_LT((V3d(n.x, n.y, n.z) - offset / s.radius).length(), tolerance / s.radius + 1e-7) << i;
  }
  for (uint32_t i : p.indices) ASSERT_LT(i, p.positions.size());
}

TEST(SphereMesh, ClosedAndWoundOutward) {
  for (int level = 0; level <= 5; ++level) {
    SCOPED_TRACE(testing::Message() << "level " << level);
    const UnitIcosphere unit = make_unit_icosphere(level);
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t t = 0; t < unit.indices.size(); t += 3) {
      const uint32_t a = unit.indices[t], b = unit.indices[t + 1], c = unit.indices[t + 2];
      ASSERT_TRUE(a != b && b != c && a != c);
      const V3d& pa = unit.vertices[a];
      const V3d& pb = unit.vertices[b];
      const V3d& pc = unit.vertices[c];
      // Counter-clockwise seen from outside = the right-hand normal points away from the centre.
      ASSERT_GT((pb - pa).cross(pc - pa).dot(pa + pb + pc), 0.0) << "triangle " << t / 3;
      ++directed[{a, b}];
      ++directed[{b, c}];
      ++directed[{c, a}];
    }
    // Closed and consistently oriented: each edge is used once in each direction, i.e. by
    // exactly two triangles. Euler: E = 30 * 4^level.
    EXPECT_EQ(directed.size(), 2 * 30 * (size_t(1) << (2 * level)));
    for (const auto& [edge, count] : directed) {
      ASSERT_EQ(count, 1);
      ASSERT_EQ(directed.count({edge.second, edge.first}), 1u);
    }
  }
}

TEST(SphereMesh, EmbreeFaceNormalsPointOutward) {
  // The winding convention is only useful if Embree agrees: shoot at every face's centroid
  // from outside and from the centre and look at Ng.
  const Sphere s{V3d(1, 2, -5), 1.5, -1, "s"};
  const Primitive p = tessellate_sphere(s, 2);
  const SphereScene scene({s}, {SphereMode::mesh, 2});
  const V3f c = to_f(s.centre);
  for (size_t t = 0; t < p.indices.size(); t += 3) {
    const V3f centroid = (p.positions[p.indices[t]] + p.positions[p.indices[t + 1]] +
                          p.positions[p.indices[t + 2]]) /
                         3.0f;
    const V3f out = (centroid - c).normalized();
    const Hit from_outside = scene.trace(c + 3.0f * out, -out);
    ASSERT_TRUE(from_outside.hit);
    ASSERT_EQ(from_outside.prim, t / 3);
    ASSERT_GT(from_outside.ng.dot(out), 0.0f) << "triangle " << t / 3;
    const Hit from_inside = scene.trace(c, out);
    ASSERT_TRUE(from_inside.hit);
    ASSERT_GT(from_inside.ng.dot(out), 0.0f) << "triangle " << t / 3;
  }
}

TEST(SphereMesh, MaxErrorMatchesTheMeasuredGap) {
  for (int level = 0; level <= 6; ++level) {
    SCOPED_TRACE(testing::Message() << "level " << level);
    const double bound = tessellation_max_error(1.0, level);
    const UnitIcosphere unit = make_unit_icosphere(level);
    double centroid_gap = 0;
    for (size_t t = 0; t < unit.indices.size(); t += 3) {
      const V3d centroid = (unit.vertices[unit.indices[t]] + unit.vertices[unit.indices[t + 1]] +
                            unit.vertices[unit.indices[t + 2]]) /
                           3.0;
      centroid_gap = std::max(centroid_gap, 1.0 - centroid.length());
    }
    // A centroid is never deeper than the face's nearest point, the circumcentre; they
    // coincide for equilateral faces, and the deepest face, the centre of an icosahedron
    // face's subdivision, is equilateral by symmetry, so the two measures agree.
    EXPECT_NEAR(centroid_gap, bound, 1e-15);  // unit sphere: a few roundings of 1 - |c|
    // And it scales with the radius and falls about 4x per level.
    EXPECT_DOUBLE_EQ(tessellation_max_error(2.5, level), 2.5 * bound);
    if (level > 0) {
      const double ratio = tessellation_max_error(1.0, level - 1) / bound;
      EXPECT_GT(ratio, 3.0);
      EXPECT_LT(ratio, 4.5);
    }
  }
  EXPECT_NEAR(tessellation_max_error(1.0, 0), 1.0 - 0.79465447229176612, 1e-12);
  EXPECT_THROW(tessellation_max_error(1.0, -1), std::out_of_range);
  EXPECT_THROW(tessellation_max_error(1.0, kMaxSphereMeshLevel + 1), std::out_of_range);
  EXPECT_THROW(make_unit_icosphere(kMaxSphereMeshLevel + 1), std::out_of_range);
}

// ---------------------------------------------------------------------------------------
// --spheres option strings

TEST(SphereOptions, ParseAndPrintRoundTrip) {
  struct Case {
    const char* text;
    SphereMode mode;
    int level;
    const char* printed;
  };
  const Case cases[] = {
      {"analytic", SphereMode::analytic, 3, "analytic"},
      {"mesh", SphereMode::mesh, 3, "mesh:3"},
      {"mesh:0", SphereMode::mesh, 0, "mesh:0"},
      {"mesh:5", SphereMode::mesh, 5, "mesh:5"},
      {"mesh:8", SphereMode::mesh, 8, "mesh:8"},
      {"embree-points", SphereMode::embree_points, 3, "embree-points"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    SphereOptions o;
    std::string error = "untouched";
    ASSERT_TRUE(parse_sphere_options(c.text, &o, &error));
    EXPECT_EQ(error, "untouched");
    EXPECT_EQ(o.mode, c.mode);
    EXPECT_EQ(o.mesh_level, c.level);
    EXPECT_EQ(to_string(o), c.printed);
    SphereOptions again;
    ASSERT_TRUE(parse_sphere_options(to_string(o), &again, nullptr));
    EXPECT_EQ(again.mode, o.mode);
    if (o.mode == SphereMode::mesh) {
      EXPECT_EQ(again.mesh_level, o.mesh_level);
    }
  }
}

TEST(SphereOptions, RejectsBadStringsAndLeavesTheOptionsAlone) {
  const std::pair<const char*, const char*> bad[] = {
      {"mesh:abc", "must be a number"},    {"mesh:", "must be a number"},
      {"mesh:3x", "must be a number"},     {"mesh: 3", "must be a number"},
      {"mesh:+3", "must be a number"},     {"mesh:99", "must be 0 to 8"},
      {"mesh:-1", "must be 0 to 8"},       {"mesh:99999999999999999999", "must be 0 to 8"},
      {"cubes", "unknown sphere mode"},    {"", "unknown sphere mode"},
      {"Analytic", "unknown sphere mode"}, {"embree_points", "unknown sphere mode"},
  };
  for (const auto& [text, message] : bad) {
    SCOPED_TRACE(text);
    SphereOptions o{SphereMode::embree_points, 7};
    std::string error;
    EXPECT_FALSE(parse_sphere_options(text, &o, &error));
    EXPECT_NE(error.find(message), std::string::npos) << error;
    EXPECT_NE(error.find(std::string("'") + text + "'"), std::string::npos) << error;
    EXPECT_EQ(o.mode, SphereMode::embree_points);
    EXPECT_EQ(o.mesh_level, 7);
    EXPECT_FALSE(parse_sphere_options(text, &o, nullptr));  // no error string is fine too
  }
}

}  // namespace
}  // namespace prism
