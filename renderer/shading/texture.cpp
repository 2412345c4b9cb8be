#include "renderer/shading/texture.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <utility>

#include <tbb/parallel_for.h>

#include "renderer/image/colour.h"

namespace prism {

using Imath::V2f;
using Imath::V4f;

namespace {

// Texel index for an integer coordinate outside [0, size) under a wrap mode.
int wrap_index(long long i, int size, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::clamp_to_edge:
      return static_cast<int>(std::clamp<long long>(i, 0, size - 1));
    case TextureWrap::mirrored_repeat: {
      const long long period = 2LL * size;
      long long m = i % period;
      if (m < 0) m += period;
      return static_cast<int>(m < size ? m : period - 1 - m);
    }
    case TextureWrap::repeat:
    default: {
      long long m = i % size;
      return static_cast<int>(m < 0 ? m + size : m);
    }
  }
}

// One axis of a box-filtered reduction from `from` to `to` texels: output texel i averages
// the input over [i r, (i + 1) r), r = from / to, with fractional weights at the ends, so
// every level keeps the image's mean exactly (up to rounding) whatever its size, odd or not.
struct BoxTap {
  int first = 0;
  std::vector<float> weights;
};

std::vector<BoxTap> box_taps(int from, int to) {
  std::vector<BoxTap> taps(static_cast<size_t>(to));
  const double r = static_cast<double>(from) / to;
  for (int i = 0; i < to; ++i) {
    const double a = i * r, b = (i + 1) * r;
    BoxTap& tap = taps[static_cast<size_t>(i)];
    tap.first = static_cast<int>(std::floor(a));
    for (int j = tap.first; j < from && j < b; ++j) {
      const double overlap = std::min<double>(j + 1, b) - std::max<double>(j, a);
      tap.weights.push_back(static_cast<float>(overlap / r));
    }
  }
  return taps;
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

}  // namespace

Texture::CodeTables Texture::code_tables(const ColourPipeline& colour) {
  auto linear = std::make_shared<CodeTable>();
  for (int v = 0; v < 256; ++v) {
    const float value = TextureImage::code_value(static_cast<uint8_t>(v));
    for (auto& channel : linear->colour) channel[static_cast<size_t>(v)] = value;
    linear->alpha[static_cast<size_t>(v)] = value;
  }
  CodeTables tables;
  tables.linear = linear;
  if (const std::optional<ColourPipeline::CodeTable> srgb = colour.srgb_texture_code_table()) {
    auto table = std::make_shared<CodeTable>(*linear);
    table->colour = *srgb;
    tables.srgb = std::move(table);
  }
  return tables;
}

// Grey when every texel's three colours are the same bits, opaque when every alpha is 1:
// the layout then drops what it can rebuild exactly (an opaque image's mips have alpha 1
// wherever their box weights sum to 1 exactly, which a power-of-two side guarantees).
Texture::Level Texture::exact_level(int width, int height, const std::vector<V4f>& texels) {
  bool grey = true, opaque = true;
  for (const V4f& t : texels) {
    grey = grey && same_bits(t.x, t.y) && same_bits(t.y, t.z);
    opaque = opaque && same_bits(t.w, 1.0f);
    if (!grey && !opaque) break;
  }
  Level level;
  level.width = width;
  level.height = height;
  level.channels = grey ? (opaque ? 1 : 2) : (opaque ? 3 : 4);
  level.values.reserve(texels.size() * static_cast<size_t>(level.channels));
  for (const V4f& t : texels) {
    level.values.push_back(t.x);
    if (!grey) {
      level.values.push_back(t.y);
      level.values.push_back(t.z);
    }
    if (!opaque) level.values.push_back(t.w);
  }
  return level;
}

std::shared_ptr<const Texture::Pyramid> Texture::build_pyramid(const TextureImage& image,
                                                               const ColourPipeline& colour,
                                                               const CodeTables& tables) {
  auto pyramid = std::make_shared<Pyramid>();
  std::vector<Level>& levels = pyramid->levels;
  const size_t count = static_cast<size_t>(image.width) * image.height;
  const int c = image.channels;
  const std::shared_ptr<const CodeTable>& table =
      image.encoding == TextureEncoding::srgb ? tables.srgb : tables.linear;
  if (image.shared_codes && table && image.shared_codes->size() >= count * c) {
    pyramid->codes = image.shared_codes;
    pyramid->table = table;
    Level base;
    base.width = image.width;
    base.height = image.height;
    base.channels = c;
    base.codes = pyramid->codes->data();
    base.table = pyramid->table.get();
    levels.push_back(std::move(base));
  } else {
    std::vector<float> rgb(count * 3);
    std::vector<V4f> texels(count);
    for (size_t i = 0; i < count; ++i) {
      const size_t t = i * static_cast<size_t>(c);
      // Grey and grey-alpha images broadcast their grey value; alpha defaults to opaque.
      rgb[i * 3 + 0] = image.value(t);
      rgb[i * 3 + 1] = c >= 3 ? image.value(t + 1) : image.value(t);
      rgb[i * 3 + 2] = c >= 3 ? image.value(t + 2) : image.value(t);
      texels[i].w = c == 4 ? image.value(t + 3) : (c == 2 ? image.value(t + 1) : 1.0f);
    }
    if (image.encoding == TextureEncoding::srgb)
      colour.srgb_texture_to_working(rgb.data(), count, 3);
    for (size_t i = 0; i < count; ++i) {
      texels[i].x = rgb[i * 3 + 0];
      texels[i].y = rgb[i * 3 + 1];
      texels[i].z = rgb[i * 3 + 2];
    }
    levels.push_back(exact_level(image.width, image.height, texels));
  }
  // Filtered in linear values (after linearisation), as a texture's mean radiance should be.
  while (levels.back().width > 1 || levels.back().height > 1) {
    const Level& fine = levels.back();
    const int width = std::max(1, fine.width / 2), height = std::max(1, fine.height / 2);
    const std::vector<BoxTap> tx = box_taps(fine.width, width);
    const std::vector<BoxTap> ty = box_taps(fine.height, height);
    // Across, then down, one fine row at a time: a whole level filtered across would be
    // the largest allocation of a texture's load (16 bytes a texel). A fine row shared by
    // two coarse rows (odd sides) is filtered again, to the same values.
    std::vector<V4f> row(static_cast<size_t>(width));
    std::vector<V4f> coarse(static_cast<size_t>(width) * height, V4f(0.0f));
    for (int y = 0; y < height; ++y) {
      const BoxTap& tap_y = ty[static_cast<size_t>(y)];
      for (size_t k = 0; k < tap_y.weights.size(); ++k) {
        const int fine_y = tap_y.first + static_cast<int>(k);
        for (int x = 0; x < width; ++x) {
          V4f sum(0.0f);
          const BoxTap& tap = tx[static_cast<size_t>(x)];
          for (size_t j = 0; j < tap.weights.size(); ++j)
            sum += fine.texel(tap.first + static_cast<int>(j), fine_y) * tap.weights[j];
          row[static_cast<size_t>(x)] = sum;
        }
        for (int x = 0; x < width; ++x)
          coarse[static_cast<size_t>(y) * width + x] +=
              row[static_cast<size_t>(x)] * tap_y.weights[k];
      }
    }
    levels.push_back(exact_level(width, height, coarse));
  }
  return pyramid;
}

Texture::Texture(std::shared_ptr<const Pyramid> pyramid, const TextureImage& sampler)
    : pyramid_(std::move(pyramid)),
      wrap_s_(sampler.wrap_s),
      wrap_t_(sampler.wrap_t),
      mag_filter_(sampler.mag_filter),
      min_filter_(sampler.min_filter),
      mip_mode_(sampler.mip_mode) {}

Texture::Texture(const TextureImage& image, const ColourPipeline& colour)
    : Texture(build_pyramid(image, colour, code_tables(colour)), image) {}

size_t Texture::bytes() const {
  size_t bytes = 0;
  for (const Level& level : pyramid_->levels) bytes += level.values.capacity() * sizeof(float);
  return bytes;
}

V4f Texture::lookup(const Level& level, const V2f& uv, TextureFilter filter) const {
  const float w = static_cast<float>(level.width), h = static_cast<float>(level.height);
  // Beyond 2^40 texels a float UV has no fractional texel left; clamping there keeps the
  // integer conversion defined without changing any representable lookup.
  constexpr float kLimit = 1099511627776.0f;
  if (!(std::fabs(uv.x * w) < kLimit) || !(std::fabs(uv.y * h) < kLimit)) return level.texel(0, 0);
  if (filter == TextureFilter::nearest) {
    const auto ix = static_cast<long long>(std::floor(uv.x * w));
    const auto iy = static_cast<long long>(std::floor(uv.y * h));
    return level.texel(wrap_index(ix, level.width, wrap_s_), wrap_index(iy, level.height, wrap_t_));
  }
  // Texel centres sit at half-integer coordinates.
  const float x = uv.x * w - 0.5f, y = uv.y * h - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float wx = x - fx, wy = y - fy;
  const auto ix = static_cast<long long>(fx), iy = static_cast<long long>(fy);
  const int x0 = wrap_index(ix, level.width, wrap_s_),
            x1 = wrap_index(ix + 1, level.width, wrap_s_);
  const int y0 = wrap_index(iy, level.height, wrap_t_),
            y1 = wrap_index(iy + 1, level.height, wrap_t_);
  return (level.texel(x0, y0) * (1.0f - wx) + level.texel(x1, y0) * wx) * (1.0f - wy) +
         (level.texel(x0, y1) * (1.0f - wx) + level.texel(x1, y1) * wx) * wy;
}

V4f Texture::sample(const V2f& uv, float footprint) const {
  const std::vector<Level>& levels = pyramid_->levels;
  const Level& base = levels.front();
  // The footprint in texels of the full image; its log2 is the mip level whose texels are
  // as wide as the footprint. A zero, negative or NaN footprint (unknown) magnifies.
  const float texels = footprint * std::sqrt(static_cast<float>(base.width) * base.height);
  const float lod = texels > 1.0f ? std::log2(texels) : 0.0f;
  if (!(lod > 0.0f)) return lookup(base, uv, mag_filter_);
  if (mip_mode_ == MipMode::none) return lookup(base, uv, min_filter_);
  const float last = static_cast<float>(levels.size() - 1);
  const float level = std::min(lod, last);
  if (mip_mode_ == MipMode::nearest)
    return lookup(levels[static_cast<size_t>(std::lround(level))], uv, min_filter_);
  const float lower = std::floor(level);
  const float blend = level - lower;
  const V4f a = lookup(levels[static_cast<size_t>(lower)], uv, min_filter_);
  if (blend == 0.0f) return a;
  const V4f b = lookup(levels[static_cast<size_t>(lower) + 1], uv, min_filter_);
  return a * (1.0f - blend) + b * blend;
}

std::vector<Texture> make_textures(const std::vector<TextureImage>& images,
                                   const ColourPipeline& colour) {
  // Which description first holds each distinct (decoded image, encoding): that one's
  // pyramid is built, the others share it. Descriptions without an image index (made in
  // code rather than loaded) are each their own.
  std::map<std::pair<int, TextureEncoding>, size_t> first;
  std::vector<size_t> owner(images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    owner[i] =
        images[i].image < 0
            ? i
            : first.emplace(std::make_pair(images[i].image, images[i].encoding), i).first->second;
  }
  const Texture::CodeTables tables =
      images.empty() ? Texture::CodeTables{} : Texture::code_tables(colour);
  std::vector<std::shared_ptr<const Texture::Pyramid>> pyramids(images.size());
  tbb::parallel_for(size_t{0}, images.size(), [&](size_t i) {
    if (owner[i] == i) pyramids[i] = Texture::build_pyramid(images[i], colour, tables);
  });
  std::vector<Texture> textures;
  textures.reserve(images.size());
  for (size_t i = 0; i < images.size(); ++i)
    textures.push_back(Texture(pyramids[owner[i]], images[i]));
  return textures;
}

}  // namespace prism
