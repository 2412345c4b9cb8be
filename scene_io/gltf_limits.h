// The limits that bound what an untrusted glTF file can make the loader allocate or do.
// docs/gltf.md lists them with the reasons for each value; a file over a limit is refused with
// a LoadError naming the element, before the allocation the limit guards against.
#pragma once

#include <cstddef>

namespace prism::gltf_limits {

// Nesting of JSON arrays and objects. tinygltf converts `extras` and extension values to its
// Value type recursively, so a deeply nested file would overflow the call stack; real glTF is
// about 10 levels deep.
inline constexpr int kMaxJsonDepth = 128;

// Objects in all top-level arrays (nodes, meshes, accessors, ...) plus mesh primitives together.
// tinygltf keeps a few hundred bytes per object, so a file of "{}," repeated would otherwise
// need far more memory than its size; a million is beyond the largest production scenes.
inline constexpr std::size_t kMaxObjects = 1'000'000;

// Decoded size of a data: URI, checked from the base64 length before decoding. tinygltf hands
// images to the decoder with an int length, so this also keeps that cast safe.
inline constexpr std::size_t kMaxDataUriBytes = std::size_t{1} << 30;  // 1 GiB

// External image files: the same int length as above.
inline constexpr std::size_t kMaxImageFileBytes = std::size_t{1} << 30;  // 1 GiB

// Images, checked from the PNG/JPEG/... header before the decoder allocates anything.
inline constexpr int kMaxImageSide = 16384;
inline constexpr std::size_t kMaxImageTexels = std::size_t{1} << 26;  // 64 Mi, e.g. 8192 x 8192
// All images of a file together (tinygltf decodes every image, used or not).
inline constexpr std::size_t kMaxTotalImageTexels = std::size_t{1} << 27;  // 128 Mi

// JPEG decoding time grows with the number of scans (progressive JPEGs), each a pass over the
// whole image: libjpeg accepts thousands, and 20 000 scans decode for more than ten minutes.
// Encoders write at most a few dozen.
inline constexpr long kMaxJpegScans = 128;
inline constexpr std::size_t kMaxJpegScanPixels = std::size_t{1} << 31;  // e.g. 8192 x 8192 x 32

// The most an image's raw pixels may exceed its file: deflate expands at most 1032:1, and a
// JPEG of flat 8 x 8 blocks costs a few bits per block (about 400:1 for RGB); a header claiming
// more is a decompression bomb.
inline constexpr std::size_t kMaxPngRatio = 1100;
inline constexpr std::size_t kMaxJpegRatio = 4096;

// Largest index of refraction (KHR_materials_ior): real materials stay below 5; far larger
// values overflow the float Fresnel terms.
inline constexpr double kMaxIor = 1000.0;

// A sparse accessor without a bufferView is zeros plus its substitutions; the loader allocates
// it whole (count x element size), so a tiny file must not be able to claim gigabytes. With a
// bufferView the file's own bytes already bound it.
inline constexpr std::size_t kMaxZeroFilledSparseBytes = std::size_t{1} << 28;  // 256 MiB

}  // namespace prism::gltf_limits
