#include "scene_io/gltf_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool has_uri_scheme(const std::string& uri) {
  // RFC 3986: scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":"
  if (uri.empty() || !std::isalpha(static_cast<unsigned char>(uri[0]))) return false;
  for (std::size_t i = 1; i < uri.size(); ++i) {
    const char c = uri[i];
    if (c == ':') return i > 1;  // one letter could be a Windows drive, refused anyway as absolute
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '-' && c != '.')
      return false;
  }
  return false;
}

// Closes the descriptor on every path out of read_regular_file.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string percent_decode(const std::string& uri, const std::string& element,
                           const std::string& file) {
  std::string out;
  out.reserve(uri.size());
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      if (uri[i] == '\0') fail(file, element, "the URI contains a NUL character");
      out += uri[i];
      continue;
    }
    const int high = i + 1 < uri.size() ? hex_value(uri[i + 1]) : -1;
    const int low = i + 2 < uri.size() ? hex_value(uri[i + 2]) : -1;
    if (high < 0 || low < 0) {
      fail(file, element,
           shown(uri) + " has an invalid percent-escape at character " + std::to_string(i) +
               " (RFC 3986 needs % and two hexadecimal digits)");
    }
    const char c = static_cast<char>(high * 16 + low);
    if (c == '\0') fail(file, element, shown(uri) + " decodes to a NUL character (%00)");
    out += c;
    i += 2;
  }
  return out;
}

std::vector<unsigned char> read_regular_file(const std::filesystem::path& path,
                                             std::size_t max_bytes,
                                             std::optional<std::size_t> exact,
                                             const std::string& element, const std::string& file,
                                             bool follow_symlink) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; the fstat below refuses it anyway.
  const int flags = O_RDONLY | O_CLOEXEC | O_NONBLOCK | (follow_symlink ? 0 : O_NOFOLLOW);
  const Descriptor d{::open(path.c_str(), flags)};
  if (d.fd < 0) fail(file, element, std::string("cannot be opened: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(d.fd, &st) != 0) fail(file, element, std::string("fstat: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) fail(file, element, "is not a regular file");
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size > max_bytes) {
    fail(file, element,
         "file of " + std::to_string(size) + " bytes exceeds the limit of " +
             std::to_string(max_bytes));
  }
  if (exact && size != *exact) {
    fail(file, element,
         "file holds " + std::to_string(size) + " bytes but byteLength is " +
             std::to_string(*exact));
  }
  charge(size, 1, element);
  std::vector<unsigned char> bytes(size);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(d.fd, bytes.data() + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(file, element, "read error (the file shrank or cannot be read)");
    done += static_cast<std::size_t>(n);
  }
  return bytes;
}

FileGate::FileGate(const std::filesystem::path& folder, bool allow_external,
                   const std::string& file)
    : allow_external_(allow_external), file_(file) {
  std::error_code ec;
  folder_ = std::filesystem::canonical(folder, ec);
  if (ec) fail(file, "file", "cannot resolve the asset's folder: " + ec.message());
}

std::string FileGate::admit(const std::string& uri, const std::string& element,
                            std::optional<std::size_t> exact, std::size_t max_bytes) {
  const std::string decoded = percent_decode(uri, element, file_);
  const std::filesystem::path relative(decoded);
  if (has_uri_scheme(uri) || relative.is_absolute() || decoded.empty()) {
    fail(file_, element,
         shown(uri) + " is " +
             (decoded.empty()       ? "empty"
              : has_uri_scheme(uri) ? "not a relative path"
                                    : "absolute") +
             (allow_external_
                  ? "; only paths relative to the asset are resolved"
                  : "; only files in the asset's folder are read (see --allow-external-paths)"));
  }
  std::error_code ec;
  // Canonical (symlinks resolved, "." and ".." gone): what is checked is what is opened.
  const std::filesystem::path resolved = std::filesystem::canonical(folder_ / relative, ec);
  if (ec) fail(file_, element, "file " + shown(uri) + " not found");
  if (!allow_external_) {
    const std::filesystem::path inside = resolved.lexically_relative(folder_);
    if (inside.empty() || *inside.begin() == ".." || inside == ".") {
      fail(file_, element,
           shown(uri) + " points outside the asset's folder (see --allow-external-paths)");
    }
  }
  if (!std::filesystem::is_regular_file(resolved, ec)) {
    fail(file_, element, shown(uri) + " is not a regular file");
  }
  const std::string token = "prism-file-" + std::to_string(admitted_.size());
  admitted_[token] = Admitted{uri, resolved, element, exact, max_bytes};
  return token;
}

std::vector<std::string> FileGate::admitted_paths() const {
  std::vector<std::string> paths;
  for (const auto& [token, a] : admitted_) paths.push_back(a.path.string());
  std::sort(paths.begin(), paths.end());
  paths.erase(std::unique(paths.begin(), paths.end()), paths.end());
  return paths;
}

std::string FileGate::original_uri(const std::string& token) const {
  const auto it = admitted_.find(token);
  return it == admitted_.end() ? token : it->second.uri;
}

bool FileGate::exists(const std::string& name, void* self) {
  return static_cast<FileGate*>(self)->admitted_.count(name) != 0;
}

std::string FileGate::expand(const std::string& name, void*) {
  return name;
}

bool FileGate::read(std::vector<unsigned char>* out, std::string* err, const std::string& name,
                    void* self) {
  auto& gate = *static_cast<FileGate*>(self);
  const auto it = gate.admitted_.find(name);
  if (it == gate.admitted_.end()) {
    if (err) *err += "not a file the loader admitted";
    return false;
  }
  const Admitted& a = it->second;
  try {
    // Canonical, so no component is a symlink; a swap to one after the check is refused.
    *out = read_regular_file(a.path, a.max_bytes, a.exact, a.element, gate.file_);
    return true;
  } catch (const LoadError& e) {
    if (gate.failed_element_.empty()) {
      gate.failed_element_ = a.element;
      gate.failure_ = e.what();
    }
    if (err) *err += "cannot read " + a.element;
    return false;
  }
}

bool FileGate::write(std::string* err, const std::string&, const std::vector<unsigned char>&,
                     void*) {
  if (err) *err += "the loader writes no files";
  return false;
}

tinygltf::FsCallbacks FileGate::callbacks() {
  tinygltf::FsCallbacks fs;
  fs.FileExists = &FileGate::exists;
  fs.ExpandFilePath = &FileGate::expand;
  fs.ReadWholeFile = &FileGate::read;
  fs.WriteWholeFile = &FileGate::write;
  fs.user_data = this;
  return fs;
}

}  // namespace prism::gltf_detail
