// The only way a URI of a glTF file becomes a file that is read. tinygltf 2.7 decodes URIs its
// own way (`+` as a space, an invalid `%zz` as a NUL that cuts the path short), treats a data:
// URI of an unknown media type as a path, and retries a missing file relative to the current
// directory; so it is never given a real URI. Each buffer and image URI is checked here, and
// tinygltf sees a token in its place that only these file callbacks resolve, to exactly the
// file that was checked.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace prism::gltf_detail {

// RFC 3986 percent-decoding of a URI reference's path, once: "%XX" becomes the byte XX, `+`
// stays `+`. An invalid escape or an escaped NUL throws LoadError naming `element`.
std::string percent_decode(const std::string& uri, const std::string& element,
                           const std::string& file);

// Reads the regular file at `path` (opened without following a final symlink, and without
// blocking on a FIFO or device), refusing it when it is larger than max_bytes or, with
// `exact`, of another size; the bytes are charged to the load's budget before they are read.
std::vector<unsigned char> read_regular_file(const std::filesystem::path& path,
                                             std::size_t max_bytes,
                                             std::optional<std::size_t> exact,
                                             const std::string& element, const std::string& file,
                                             bool follow_symlink = false);

class FileGate {
 public:
  // `folder` is the asset's folder; with allow_external, relative paths may leave it.
  FileGate(const std::filesystem::path& folder, bool allow_external, const std::string& file);

  // Checks the URI `uri` of `element` (not a data: URI): decoded, resolved against the folder,
  // canonicalised, inside the folder, a regular file. Returns the token tinygltf is given in
  // its place. `exact`: the size the file must have (a buffer's byteLength).
  std::string admit(const std::string& uri, const std::string& element,
                    std::optional<std::size_t> exact, std::size_t max_bytes);

  std::size_t admitted() const { return admitted_.size(); }
  // The canonical paths of the admitted files, sorted: what a load read besides the file.
  std::vector<std::string> admitted_paths() const;
  // The URI a token stands for; any other text unchanged.
  std::string original_uri(const std::string& token) const;

  // Callbacks for tinygltf::TinyGLTF::SetFsCallbacks; they open admitted files only.
  tinygltf::FsCallbacks callbacks();

  // Set when a callback failed to read an admitted file: tinygltf's own message would name the
  // token, not the element.
  const std::string& failed_element() const { return failed_element_; }
  const std::string& failure() const { return failure_; }

 private:
  struct Admitted {
    std::string uri;
    std::filesystem::path path;  // canonical
    std::string element;
    std::optional<std::size_t> exact;
    std::size_t max_bytes = 0;
  };
  static bool exists(const std::string& name, void* self);
  static std::string expand(const std::string& name, void* self);
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& name,
                   void* self);
  static bool write(std::string* err, const std::string& name,
                    const std::vector<unsigned char>& bytes, void* self);

  std::filesystem::path folder_;  // canonical
  bool allow_external_;
  const std::string& file_;
  std::map<std::string, Admitted> admitted_;
  std::string failed_element_, failure_;
};

}  // namespace prism::gltf_detail
