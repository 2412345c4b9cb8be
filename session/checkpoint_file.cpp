#include "session/checkpoint_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "renderer/temporary_files.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'P', 'R', 'I', 'S', 'M', 'C', 'K', 'P'};
constexpr uint32_t kFormatVersion = 1;
constexpr size_t kSumsBytes = 8 * 4;
// Magic, version, fingerprint length; film; progress; ray kinds; pixels.
constexpr size_t kFixedHeaderBytes =
    8 + 4 + 4 + (4 * 4 + 4 + 1) + (4 + 4 + 8) + 4 + 8 * (kRayKindCount + 1) + 8;
constexpr size_t kHashBytes = 16;

struct HashState {
  HashState() : state(XXH3_createState()) {
    if (!state) throw std::bad_alloc();
    XXH3_128bits_reset(state);
  }
  ~HashState() { XXH3_freeState(state); }
  HashState(const HashState&) = delete;
  HashState& operator=(const HashState&) = delete;
  void update(const void* data, size_t n) { XXH3_128bits_update(state, data, n); }
  // The digest's bytes in the file's order: low half first, each half little-endian.
  void digest(unsigned char out[kHashBytes]) const {
    const XXH128_hash_t h = XXH3_128bits_digest(state);
    for (int i = 0; i < 8; ++i) {
      out[i] = static_cast<unsigned char>(h.low64 >> (8 * i));
      out[8 + i] = static_cast<unsigned char>(h.high64 >> (8 * i));
    }
  }
  XXH3_state_t* state;
};

// Little-endian encoding into a buffer that is hashed and written out as it fills, so a
// state of any size is written with a small, fixed amount of memory.
class Encoder {
 public:
  Encoder(int fd, const std::string& path) : fd_(fd), path_(path) { buffer_.reserve(kChunk); }

  void u8(uint8_t v) { buffer_.push_back(v); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<uint8_t>(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) u8(static_cast<uint8_t>(v >> (8 * i)));
  }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void f32(float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u32(bits);
  }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void bytes(const std::string& s) {
    for (char c : s) u8(static_cast<uint8_t>(c));
  }
  void sums(const PixelSums& p) {
    for (int c = 0; c < 3; ++c) f32(p.radiance[c]);
    u32(p.hits);
    u32(p.kept);
    for (int c = 0; c < 3; ++c) f32(p.radiance_squared[c]);
  }
  // Call between items: flushes once the buffer is full.
  void maybe_flush() {
    if (buffer_.size() >= kChunk) flush();
  }
  void finish() {
    flush();
    unsigned char digest[kHashBytes];
    hash_.digest(digest);
    write_all(digest, kHashBytes);
  }

 private:
  static constexpr size_t kChunk = size_t{1} << 20;

  void flush() {
    hash_.update(buffer_.data(), buffer_.size());
    write_all(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
  void write_all(const unsigned char* data, size_t n) {
    while (n > 0) {
      const ssize_t written = ::write(fd_, data, n);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) throw std::runtime_error(path_ + ": cannot write: " + std::strerror(errno));
      data += written;
      n -= static_cast<size_t>(written);
    }
  }

  int fd_;
  const std::string& path_;
  std::vector<unsigned char> buffer_;
  HashState hash_;
};

// Reads and hashes; every read is checked, and a short read is the file's damage, not an
// exception.
class Decoder {
 public:
  explicit Decoder(std::FILE* file) : file_(file) {}

  bool bytes(void* out, size_t n) {
    if (std::fread(out, 1, n, file_) != n) return false;
    hash_.update(out, n);
    return true;
  }
  bool u8(uint8_t* v) { return bytes(v, 1); }
  bool u32(uint32_t* v) {
    unsigned char b[4];
    if (!bytes(b, 4)) return false;
    *v = load32(b);
    return true;
  }
  bool i32(int32_t* v) {
    uint32_t u;
    if (!u32(&u)) return false;
    *v = static_cast<int32_t>(u);
    return true;
  }
  bool u64(uint64_t* v) {
    unsigned char b[8];
    if (!bytes(b, 8)) return false;
    *v = load64(b);
    return true;
  }
  bool f32(float* v) {
    uint32_t bits;
    if (!u32(&bits)) return false;
    std::memcpy(v, &bits, sizeof bits);
    return true;
  }
  bool f64(double* v) {
    uint64_t bits;
    if (!u64(&bits)) return false;
    std::memcpy(v, &bits, sizeof bits);
    return true;
  }

  // `count` records of `record_bytes` each, read in blocks and handed to `decode`.
  template <typename DecodeFn>
  bool records(size_t count, size_t record_bytes, DecodeFn&& decode) {
    constexpr size_t kBlock = 8192;
    std::vector<unsigned char> block(kBlock * record_bytes);
    for (size_t i = 0; i < count; i += kBlock) {
      const size_t n = std::min(kBlock, count - i);
      if (!bytes(block.data(), n * record_bytes)) return false;
      for (size_t k = 0; k < n; ++k) decode(i + k, block.data() + k * record_bytes);
    }
    return true;
  }

  // The stored hash, read without hashing it, against the hash of everything before.
  bool hash_matches() {
    unsigned char stored[kHashBytes], computed[kHashBytes];
    if (std::fread(stored, 1, kHashBytes, file_) != kHashBytes) return false;
    hash_.digest(computed);
    return std::memcmp(stored, computed, kHashBytes) == 0;
  }

  static uint32_t load32(const unsigned char* b) {
    return uint32_t{b[0]} | uint32_t{b[1]} << 8 | uint32_t{b[2]} << 16 | uint32_t{b[3]} << 24;
  }
  static uint64_t load64(const unsigned char* b) {
    return uint64_t{load32(b)} | uint64_t{load32(b + 4)} << 32;
  }
  static float loadf(const unsigned char* b) {
    const uint32_t bits = load32(b);
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  static PixelSums load_sums(const unsigned char* b) {
    PixelSums p;
    for (int c = 0; c < 3; ++c) p.radiance[c] = loadf(b + 4 * c);
    p.hits = load32(b + 12);
    p.kept = load32(b + 16);
    for (int c = 0; c < 3; ++c) p.radiance_squared[c] = loadf(b + 20 + 4 * c);
    return p;
  }

 private:
  std::FILE* file_;
  HashState hash_;
};

size_t expected_file_bytes(size_t fingerprint_bytes, size_t pixels, bool adaptive) {
  const size_t per_pixel = kSumsBytes + (adaptive ? kSumsBytes + 1 + 4 + 4 : 0);
  return kFixedHeaderBytes + fingerprint_bytes + pixels * per_pixel + kHashBytes;
}

}  // namespace

void write_checkpoint(const std::string& path, const RenderState& state,
                      const std::string& fingerprint) {
  if (fingerprint.size() > kMaxCheckpointFingerprint)
    throw std::runtime_error(path + ": the fingerprint is too long");
  const fs::path target(path);
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  remove_stale_temporaries(dir, target);
  const std::string temp = (dir / temporary_name(target)).string();
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error(path + ": cannot create " + temp + ": " + std::strerror(errno));
  const auto fail = [&](const std::string& reason) {
    ::close(fd);
    ::unlink(temp.c_str());
    throw std::runtime_error(path + ": " + reason);
  };
  try {
    Encoder e(fd, path);
    for (char c : kMagic) e.u8(static_cast<uint8_t>(c));
    e.u32(kFormatVersion);
    e.u32(static_cast<uint32_t>(fingerprint.size()));
    e.bytes(fingerprint);
    e.i32(state.width);
    e.i32(state.height);
    e.i32(state.spp);
    e.i32(state.min_spp);
    e.f32(state.target_error);
    e.u8(state.adaptive ? 1 + static_cast<uint8_t>(state.error_goal) : 0);
    e.i32(state.samples_done);
    e.i32(state.rounds);
    e.f64(state.seconds);
    e.u32(static_cast<uint32_t>(kRayKindCount));
    for (uint64_t n : state.rays.rays) e.u64(n);
    e.u64(state.rays.discarded_samples);
    const size_t pixels = static_cast<size_t>(state.width) * state.height;
    e.u64(pixels);
    for (const PixelSums& p : state.sums) {
      e.sums(p);
      e.maybe_flush();
    }
    if (state.adaptive) {
      for (const PixelSums& p : state.first_half) {
        e.sums(p);
        e.maybe_flush();
      }
      for (uint8_t a : state.active) {
        e.u8(a);
        e.maybe_flush();
      }
      for (uint32_t n : state.samples_per_pixel) {
        e.u32(n);
        e.maybe_flush();
      }
      for (float v : state.error) {
        e.f32(v);
        e.maybe_flush();
      }
    }
    e.finish();
  } catch (const std::exception& error) {
    fail(error.what());
  }
  // On disk before the rename makes it the checkpoint: a crash after the rename must not
  // leave a file whose name is new and whose blocks are not.
  if (::fsync(fd) != 0) fail(std::string("cannot flush to disk: ") + std::strerror(errno));
  if (::close(fd) != 0) {
    ::unlink(temp.c_str());
    throw std::runtime_error(path + ": cannot close: " + std::strerror(errno));
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    throw std::runtime_error(path +
                             ": cannot move the checkpoint into place: " + std::strerror(error));
  }
  // The rename itself lives in the folder; without this a crash could forget it.
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

CheckpointRead read_checkpoint(const std::string& path, const RenderSettings& film,
                               const std::string& fingerprint) {
  CheckpointRead out;
  const auto refuse = [&](const std::string& reason) {
    out.reason = reason;
    return out;
  };
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return refuse("cannot read it: " + std::string(std::strerror(errno)));
  if (!S_ISREG(st.st_mode)) return refuse("not a regular file");
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) return refuse("cannot open it: " + std::string(std::strerror(errno)));
  Decoder d(file.get());
  const std::string truncated = "truncated";

  char magic[8];
  if (!d.bytes(magic, sizeof magic)) return refuse(truncated);
  if (std::memcmp(magic, kMagic, sizeof magic) != 0) return refuse("not a Prism checkpoint");
  uint32_t version = 0, fingerprint_bytes = 0;
  if (!d.u32(&version) || !d.u32(&fingerprint_bytes)) return refuse(truncated);
  if (version != kFormatVersion)
    return refuse("format version " + std::to_string(version) + ", this Prism reads " +
                  std::to_string(kFormatVersion));
  if (fingerprint_bytes > kMaxCheckpointFingerprint) return refuse("damaged (fingerprint length)");
  std::string stored(fingerprint_bytes, '\0');
  if (!d.bytes(stored.data(), stored.size())) return refuse(truncated);
  if (stored != fingerprint)
    return refuse("written for another job (the scene, its options or the Prism version changed)");

  RenderState s;
  uint8_t adaptive = 0;
  uint32_t ray_kinds = 0;
  uint64_t pixels = 0;
  if (!d.i32(&s.width) || !d.i32(&s.height) || !d.i32(&s.spp) || !d.i32(&s.min_spp) ||
      !d.f32(&s.target_error) || !d.u8(&adaptive) || !d.i32(&s.samples_done) || !d.i32(&s.rounds) ||
      !d.f64(&s.seconds) || !d.u32(&ray_kinds))
    return refuse(truncated);
  if (adaptive > 1 + static_cast<uint8_t>(ErrorGoal::image))
    return refuse("damaged (adaptive flag)");
  s.adaptive = adaptive != 0;
  if (s.adaptive) s.error_goal = static_cast<ErrorGoal>(adaptive - 1);
  if (ray_kinds != kRayKindCount)
    return refuse("it counts " + std::to_string(ray_kinds) + " kinds of ray, this Prism " +
                  std::to_string(kRayKindCount));
  for (uint64_t& n : s.rays.rays)
    if (!d.u64(&n)) return refuse(truncated);
  if (!d.u64(&s.rays.discarded_samples) || !d.u64(&pixels)) return refuse(truncated);

  // Everything that sizes an allocation is checked against the film first, then the file's
  // size against what that film needs: nothing is allocated for a count the file made up.
  if (s.width <= 0 || s.height <= 0 ||
      pixels != static_cast<uint64_t>(s.width) * static_cast<uint64_t>(s.height))
    return refuse("damaged (its pixel count does not match its size)");
  if (s.width != film.width || s.height != film.height || s.spp != std::max(1, film.spp) ||
      s.adaptive != film.adaptive())
    return refuse(s.mismatch(film));  // the film's fields are compared first
  const size_t expected = expected_file_bytes(fingerprint_bytes, pixels, s.adaptive);
  if (static_cast<uint64_t>(st.st_size) != expected)
    return refuse(static_cast<uint64_t>(st.st_size) < expected ? truncated
                                                               : "damaged (longer than its film)");

  s.sums.resize(pixels);
  if (!d.records(pixels, kSumsBytes,
                 [&](size_t i, const unsigned char* b) { s.sums[i] = Decoder::load_sums(b); }))
    return refuse(truncated);
  if (s.adaptive) {
    s.first_half.resize(pixels);
    s.active.resize(pixels);
    s.samples_per_pixel.resize(pixels);
    s.error.resize(pixels);
    if (!d.records(
            pixels, kSumsBytes,
            [&](size_t i, const unsigned char* b) { s.first_half[i] = Decoder::load_sums(b); }) ||
        !d.records(pixels, 1, [&](size_t i, const unsigned char* b) { s.active[i] = b[0]; }) ||
        !d.records(pixels, 4,
                   [&](size_t i, const unsigned char* b) {
                     s.samples_per_pixel[i] = Decoder::load32(b);
                   }) ||
        !d.records(pixels, 4,
                   [&](size_t i, const unsigned char* b) { s.error[i] = Decoder::loadf(b); }))
      return refuse(truncated);
  }
  if (!d.hash_matches()) return refuse("damaged (its checksum does not match)");
  const std::string mismatch = s.mismatch(film);
  if (!mismatch.empty()) return refuse(mismatch);
  out.state = std::move(s);
  return out;
}

}  // namespace prism
