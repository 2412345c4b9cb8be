#include "renderer/shading/material.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/image/colour.h"
#include "renderer/math.h"

namespace prism {
namespace {

using Imath::V2f;
using Imath::V4f;

const Texture* texture_or_null(int index, const std::vector<Texture>& textures) {
  return index >= 0 && index < static_cast<int>(textures.size()) ? &textures[index] : nullptr;
}

Rgb to_rgb(const C3f& c) {
  return Rgb(c.x, c.y, c.z);
}

TextureSlot make_slot(int index, const TextureMapping& mapping,
                      const std::vector<Texture>& textures) {
  TextureSlot slot;
  slot.texture = texture_or_null(index, textures);
  slot.texcoord = mapping.texcoord == 1 ? 1 : 0;
  // KHR_texture_transform's matrix T(offset) R(rotation) S(scale) with R = [cos sin;
  // -sin cos]: "counter-clockwise" as seen in the image, whose v axis points down. This is
  // the sense Khronos' TextureTransformTest asset checks (its arrow must reach the green
  // marker); the transposed R, read off the extension's GLSL as column-major, reaches the
  // red "opposite direction" marker.
  const float c = std::cos(mapping.rotation), s = std::sin(mapping.rotation);
  slot.row0 = V2f(c * mapping.scale.x, s * mapping.scale.y);
  slot.row1 = V2f(-s * mapping.scale.x, c * mapping.scale.y);
  slot.offset = mapping.offset;
  slot.footprint_scale = std::sqrt(std::fabs(mapping.scale.x * mapping.scale.y));
  return slot;
}

// The width of the pixel's footprint on the surface in UV units of coordinate set `set`:
// the ray cone's width at the hit, stretched by 1 / cos(incidence) along the surface, times
// the hit triangle's UV length per world length, sqrt(UV area / area). This is the
// isotropic ray-cone estimate (Akenine-Moller et al., "Texture Level of Detail Strategies
// for Real-Time Ray Tracing", Ray Tracing Gems, 2019) with the stretched axis taken for
// both: at grazing angles it blurs across the stretch rather than aliasing along it.
// 0 (magnify) when the ray has no cone or the triangle has no UV area.
float uv_footprint(const SurfaceHit& hit, int set) {
  if (!(hit.cone_width > 0.0f) || !hit.attributes) return 0.0f;
  const std::vector<V2f>& uv = hit.attributes->texcoords[set];
  if (uv.empty()) return 0.0f;
  const V3f* p = hit.attributes->positions;
  const uint32_t* v = hit.vertices;
  V3f e1 = p[v[1]] - p[v[0]], e2 = p[v[2]] - p[v[0]];
  if (hit.object_to_world) {
    V3f w1, w2;
    hit.object_to_world->multDirMatrix(e1, w1);
    hit.object_to_world->multDirMatrix(e2, w2);
    e1 = w1;
    e2 = w2;
  }
  const float area = e1.cross(e2).length();
  const V2f t1 = uv[v[1]] - uv[v[0]], t2 = uv[v[2]] - uv[v[0]];
  const float uv_area = std::fabs(t1.x * t2.y - t1.y * t2.x);
  if (!(area > 0.0f)) return 0.0f;
  return hit.cone_width / std::max(hit.cos_incidence, 1e-6f) * std::sqrt(uv_area / area);
}

// The texture lookups of one evaluate: a coordinate set is interpolated, and its footprint
// estimated, once, and only when a slot reads it.
class SlotReader {
 public:
  explicit SlotReader(const SurfaceHit& hit) : hit_(hit) {}

  V4f sample(const TextureSlot& slot) {
    const int set = slot.texcoord;
    if (!ready_[set]) {
      ready_[set] = true;
      uv_[set] = hit_.texcoord(set);
      footprint_[set] = uv_footprint(hit_, set);
    }
    return slot.texture->sample(slot.transform(uv_[set]), footprint_[set] * slot.footprint_scale);
  }

 private:
  const SurfaceHit& hit_;
  bool ready_[2] = {false, false};
  V2f uv_[2];
  float footprint_[2] = {0.0f, 0.0f};
};

// The shading normal bent by a tangent-space normal-map texel (glTF's normalTexture: x and
// y scaled by `scale`, +Y towards decreasing v), in the hit's tangent frame: the tangent
// made orthogonal to the shading normal, the bitangent cross(normal, tangent) x w. Kept
// unit and on the geometric normal's side (a map may tilt it past the surface's horizon).
// A hit without tangents keeps its normal.
V3f bend_normal(const SurfaceHit& hit, const V4f& texel, float scale) {
  const V3f& n = hit.shading_normal;
  if (!hit.attributes || hit.attributes->tangents.empty()) return n;
  const V4f t4 = hit.interpolate(hit.attributes->tangents);
  V3f t(t4.x, t4.y, t4.z);
  float handedness = t4.w < 0.0f ? -1.0f : 1.0f;
  if (hit.object_to_world) {
    V3f w;
    hit.object_to_world->multDirMatrix(t, w);
    t = w;
    // A mirroring instance flips the bitangent relative to the surface (bake_tangents).
    if (hit.object_to_world->determinant() < 0.0f) handedness = -handedness;
  }
  t -= n * n.dot(t);
  const float t_len2 = t.length2();
  if (!(t_len2 > 1e-20f) || !std::isfinite(t_len2)) return n;
  t /= std::sqrt(t_len2);
  const V3f b = n.cross(t) * handedness;
  const V3f m((2.0f * texel.x - 1.0f) * scale, (2.0f * texel.y - 1.0f) * scale,
              2.0f * texel.z - 1.0f);
  V3f bent = t * m.x + b * m.y + n * m.z;
  const float len = bent.length();
  if (!(len > 0.0f) || !std::isfinite(len)) return n;
  bent /= len;
  const V3f& ng = hit.geometric_normal;
  constexpr float kMinCos = 1e-3f;
  const float below = kMinCos - bent.dot(ng);
  if (below > 0.0f) bent = (bent + ng * below).normalized();
  return bent;
}

// emissiveFactor x emissiveTexture.
Rgb emission_of(const Material& material, SlotReader& read) {
  if (!material.emissive_texture.texture) return material.emissive;
  const V4f t = read.sample(material.emissive_texture);
  return hadamard(material.emissive, Rgb(t.x, t.y, t.z));
}

// The clearcoat (weight x R, roughness x G, its own normal map or the hit's unbent normal)
// and the sheen (colour x RGB, roughness x A) at the hit.
SurfaceLayers layers_of(const Material& material, const SurfaceHit& hit, SlotReader& read) {
  SurfaceLayers l;
  l.clearcoat = material.clearcoat;
  if (l.clearcoat > 0.0f) {
    float roughness = material.clearcoat_roughness;
    if (material.clearcoat_texture.texture)
      l.clearcoat *= read.sample(material.clearcoat_texture).x;
    if (material.clearcoat_roughness_texture.texture)
      roughness *= read.sample(material.clearcoat_roughness_texture).y;
    l.clearcoat_alpha = roughness * roughness;
    l.clearcoat_mirror = roughness <= kMirrorRoughness;
    l.clearcoat_normal = material.clearcoat_normal_texture.texture
                             ? bend_normal(hit, read.sample(material.clearcoat_normal_texture),
                                           material.clearcoat_normal_scale)
                             : hit.shading_normal;
  }
  l.sheen_colour = material.sheen_colour;
  if (l.sheen_colour.x > 0.0f || l.sheen_colour.y > 0.0f || l.sheen_colour.z > 0.0f) {
    float roughness = material.sheen_roughness;
    if (material.sheen_colour_texture.texture) {
      const V4f t = read.sample(material.sheen_colour_texture);
      l.sheen_colour = hadamard(l.sheen_colour, Rgb(t.x, t.y, t.z));
    }
    if (material.sheen_roughness_texture.texture)
      roughness *= read.sample(material.sheen_roughness_texture).w;
    l.sheen_alpha = std::max(roughness * roughness, kMinSheenAlpha);
  }
  return l;
}

// evaluate() without the uniform response: every slot read at the hit.
SurfaceResponse evaluate_in_full(const Material& material, const SurfaceHit& hit) {
  SlotReader read(hit);
  Rgb base = material.base_colour;
  float alpha = material.alpha;
  if (material.base_colour_texture.texture) {
    const V4f t = read.sample(material.base_colour_texture);
    base = hadamard(base, Rgb(t.x, t.y, t.z));
    alpha *= t.w;
  }
  if (hit.attributes && !hit.attributes->colours.empty()) {
    const V4f c = hit.interpolate(hit.attributes->colours);
    base = hadamard(base, Rgb(c.x, c.y, c.z) * material.rec709_to_working);
    alpha *= c.w;
  }
  float metallic = material.metallic, roughness = material.roughness;
  if (material.metallic_roughness_texture.texture) {
    const V4f t = read.sample(material.metallic_roughness_texture);
    roughness *= t.y;  // glTF: roughness in green, metallic in blue
    metallic *= t.z;
  }
  if (material.unlit) {
    // No lobe: the base colour is what the surface sends, whatever lights it.
    SurfaceResponse r;
    r.bsdf = Bsdf(hit.shading_normal, BsdfLobes{});
    r.emission = base;
    r.alpha = alpha;
    return r;
  }
  const Rgb emission = emission_of(material, read);

  // glTF's mix(dielectric_brdf, metal_brdf, metallic): the metal's layer reflects the base
  // colour (conductor_fresnel), the dielectric's F0 from the ior, tinted and weighted by
  // KHR_materials_specular, with F90 its weight (fresnel_mix), over a base that is Lambert
  // where it is not transmissive.
  const float f0_ior = dielectric_f0(material.ior);
  const Rgb f0(std::min(f0_ior * material.specular_colour.x, 1.0f) * material.specular,
               std::min(f0_ior * material.specular_colour.y, 1.0f) * material.specular,
               std::min(f0_ior * material.specular_colour.z, 1.0f) * material.specular);
  const float dielectric = 1.0f - metallic;
  BsdfLobes lobes;
  lobes.model = material.brdf;
  lobes.transmission = dielectric * material.transmission;
  lobes.diffuse_albedo = base * (dielectric * (1.0f - material.transmission));
  lobes.dielectric_f0 = f0;
  lobes.dielectric_f90 = material.specular;
  lobes.specular_f0 = f0 * dielectric + base * metallic;
  lobes.specular_f90 = Rgb(material.specular * dielectric + metallic);
  lobes.alpha = roughness * roughness;
  lobes.phong_exponent = phong_exponent_from_roughness(roughness);
  lobes.mirror = roughness <= kMirrorRoughness;
  lobes.ior = material.ior;
  lobes.transmission_tint = base;
  if (material.clearcoat > 0.0f || material.sheen_colour.x > 0.0f ||
      material.sheen_colour.y > 0.0f || material.sheen_colour.z > 0.0f)
    lobes.layers = layers_of(material, hit, read);
  lobes.thin_walled = material.thin_walled;
  SurfaceResponse r;
  r.bsdf = Bsdf(material.normal_texture.texture
                    ? bend_normal(hit, read.sample(material.normal_texture), material.normal_scale)
                    : hit.shading_normal,
                lobes);
  r.emission = emission;
  if (material.occlusion_texture.texture) {
    const float occlusion = read.sample(material.occlusion_texture).x;  // glTF: red
    r.ambient_occlusion =
        std::clamp(1.0f + material.occlusion_strength * (occlusion - 1.0f), 0.0f, 1.0f);
  }
  r.alpha = alpha;
  return r;
}

}  // namespace

Rgb emitted_radiance(const Material& material, const SurfaceHit& hit) {
  SlotReader read(hit);
  return emission_of(material, read);
}

float phong_exponent_from_roughness(float roughness) {
  const float alpha = std::max(roughness * roughness, 1e-4f);
  // Walter et al.'s n_H = 2 / alpha^2 - 2 is for (N.H)^n; R.V turns twice as fast as N.H
  // near the mirror direction, so the same lobe width in (R.V)^n takes n_H / 4.
  return std::clamp(0.5f / (alpha * alpha) - 0.5f, 0.0f, kMaxPhongExponent);
}

float dielectric_f0(float ior) {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

Rgb absorption_coefficient(const Rgb& attenuation_colour, float attenuation_distance) {
  Rgb sigma(0.0f);
  if (!(attenuation_distance < std::numeric_limits<float>::infinity())) return sigma;
  for (int i = 0; i < 3; ++i) {
    const float c = std::clamp(attenuation_colour[i], 0.0f, 1.0f);
    sigma[i] =
        c > 0.0f ? -std::log(c) / attenuation_distance : std::numeric_limits<float>::infinity();
  }
  return sigma;
}

Rgb transmittance(const Rgb& sigma_a, float distance) {
  Rgb t(1.0f);
  if (!(distance > 0.0f)) return t;
  for (int i = 0; i < 3; ++i)
    if (sigma_a[i] > 0.0f) t[i] = std::exp(-sigma_a[i] * distance);
  return t;
}

Material make_material(const MaterialDescription& d, const std::vector<Texture>& textures,
                       const ColourPipeline& colour, BrdfModel brdf) {
  Material m;
  m.brdf = brdf;
  m.base_colour = to_rgb(colour.from_linear_rec709(d.base_colour));
  m.alpha = std::clamp(d.alpha, 0.0f, 1.0f);
  m.base_colour_texture = make_slot(d.base_colour_texture, d.base_colour_mapping, textures);
  m.metallic = std::clamp(d.metallic, 0.0f, 1.0f);
  m.roughness = std::clamp(d.roughness, 0.0f, 1.0f);
  m.metallic_roughness_texture =
      make_slot(d.metallic_roughness_texture, d.metallic_roughness_mapping, textures);
  m.emissive = to_rgb(colour.from_linear_rec709(d.emissive));
  m.emissive_texture = make_slot(d.emissive_texture, d.emissive_mapping, textures);
  m.normal_texture = make_slot(d.normal_texture, d.normal_mapping, textures);
  m.normal_scale = std::isfinite(d.normal_scale) ? d.normal_scale : 1.0f;
  m.occlusion_texture = make_slot(d.occlusion_texture, d.occlusion_mapping, textures);
  m.occlusion_strength = std::clamp(d.occlusion_strength, 0.0f, 1.0f);
  // The conversion is linear: its rows are the images of the Rec.709 primaries.
  for (int i = 0; i < 3; ++i) {
    C3f primary(0.0f, 0.0f, 0.0f);
    primary[i] = 1.0f;
    const C3f row = colour.from_linear_rec709(primary);
    for (int j = 0; j < 3; ++j) m.rec709_to_working[i][j] = row[j];
  }
  m.transmission = std::clamp(d.transmission, 0.0f, 1.0f);
  m.ior = d.ior >= 1.0f ? d.ior : 1.5f;
  m.thin_walled = !(d.thickness > 0.0f);
  if (!m.thin_walled) {
    m.absorption = absorption_coefficient(to_rgb(colour.from_linear_rec709(d.attenuation_colour)),
                                          d.attenuation_distance);
  }
  m.specular = std::clamp(d.specular, 0.0f, 1.0f);
  m.specular_colour = to_rgb(colour.from_linear_rec709(d.specular_colour));
  m.clearcoat = std::clamp(d.clearcoat, 0.0f, 1.0f);
  m.clearcoat_roughness = std::clamp(d.clearcoat_roughness, 0.0f, 1.0f);
  m.clearcoat_texture = make_slot(d.clearcoat_texture, d.clearcoat_mapping, textures);
  m.clearcoat_roughness_texture =
      make_slot(d.clearcoat_roughness_texture, d.clearcoat_roughness_mapping, textures);
  m.clearcoat_normal_texture =
      make_slot(d.clearcoat_normal_texture, d.clearcoat_normal_mapping, textures);
  m.clearcoat_normal_scale =
      std::isfinite(d.clearcoat_normal_scale) ? d.clearcoat_normal_scale : 1.0f;
  // Clamped after the conversion: a saturated colour may leave [0, 1] in a wider space.
  const Rgb sheen = to_rgb(colour.from_linear_rec709(d.sheen_colour));
  m.sheen_colour = Rgb(std::clamp(sheen.x, 0.0f, 1.0f), std::clamp(sheen.y, 0.0f, 1.0f),
                       std::clamp(sheen.z, 0.0f, 1.0f));
  m.sheen_roughness = std::clamp(d.sheen_roughness, 0.0f, 1.0f);
  m.sheen_colour_texture = make_slot(d.sheen_colour_texture, d.sheen_colour_mapping, textures);
  m.sheen_roughness_texture =
      make_slot(d.sheen_roughness_texture, d.sheen_roughness_mapping, textures);
  m.unlit = d.unlit;
  const TextureSlot* const slots[] = {&m.base_colour_texture,
                                      &m.metallic_roughness_texture,
                                      &m.emissive_texture,
                                      &m.normal_texture,
                                      &m.occlusion_texture,
                                      &m.clearcoat_texture,
                                      &m.clearcoat_roughness_texture,
                                      &m.clearcoat_normal_texture,
                                      &m.sheen_colour_texture,
                                      &m.sheen_roughness_texture};
  const bool textured = std::any_of(std::begin(slots), std::end(slots),
                                    [](const TextureSlot* s) { return s->texture; });
  if (!textured && !(m.clearcoat > 0.0f)) {
    // Read nowhere but for the shading normal, which evaluate() replaces.
    SurfaceHit anywhere;
    anywhere.shading_normal = anywhere.geometric_normal = V3f(0.0f, 0.0f, 1.0f);
    m.uniform_response = evaluate_in_full(m, anywhere);
  }
  return m;
}

float base_colour_alpha(const Material& material, const SurfaceHit& hit) {
  float alpha = material.alpha;
  if (material.base_colour_texture.texture) {
    const TextureSlot& slot = material.base_colour_texture;
    alpha *= slot.texture->sample(slot.transform(hit.texcoord(slot.texcoord))).w;
  }
  return alpha * hit.vertex_colour().w;
}

SurfaceResponse evaluate(const Material& material, const SurfaceHit& hit) {
  if (material.uniform_response && !(hit.attributes && !hit.attributes->colours.empty())) {
    SurfaceResponse r = *material.uniform_response;
    r.bsdf = r.bsdf.with_shading_normal(hit.shading_normal);
    return r;
  }
  return evaluate_in_full(material, hit);
}

}  // namespace prism
