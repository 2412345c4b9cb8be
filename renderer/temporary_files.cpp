#include "renderer/temporary_files.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <system_error>

namespace prism {
namespace {

namespace fs = std::filesystem;

// ".NAME.tmp-": the prefix of a target's temporaries, with NAME cut so that a temporary name
// (prefix, PID, counter, extension) stays within NAME_MAX when NAME itself does.
std::string temporary_prefix(const fs::path& target) {
  const std::string filename = target.filename().string();
  constexpr std::size_t kSuffix = 1 + 5 + 20 + 1 + 10 + 16;  // ".", ".tmp-", pid, "-", n, ext
  const std::size_t keep = std::min<std::size_t>(filename.size(), NAME_MAX - kSuffix);
  // Appended piece by piece: GCC 12 reports a false -Wrestrict for "." + std::string&&.
  std::string prefix(".");
  prefix += filename.substr(0, keep);
  prefix += ".tmp-";
  return prefix;
}

}  // namespace

std::string temporary_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name = temporary_prefix(target);
  name += std::to_string(::getpid()) + "-" + std::to_string(counter++);
  // The extension stays, in case anything downstream infers the format from it.
  const std::string ext = target.extension().string();
  if (ext.size() <= 16) name += ext;
  return name;
}

void remove_stale_temporaries(const fs::path& dir, const fs::path& target) {
  const std::string prefix = temporary_prefix(target);
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const char* digits = name.c_str() + prefix.size();
    char* after = nullptr;
    errno = 0;
    const long pid = std::strtol(digits, &after, 10);
    if (errno != 0 || after == digits || *after != '-' || pid <= 0) continue;
    if (pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours
    std::error_code remove_ec;
    fs::remove(it->path(), remove_ec);
  }
}

}  // namespace prism
