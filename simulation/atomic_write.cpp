#include "simulation/atomic_write.h"

#include <fstream>
#include <stdexcept>
#include <system_error>

#include "renderer/temporary_files.h"

namespace prism {

namespace fs = std::filesystem;

void write_atomically(const fs::path& target,
                      const std::function<std::string(const fs::path&)>& write) {
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  remove_stale_temporaries(dir, target.filename());
  const fs::path temporary = dir / temporary_name(target.filename());
  std::string why = write(temporary);
  std::error_code error;
  if (why.empty()) {
    fs::rename(temporary, target, error);
    if (error) why = error.message();
  }
  if (!why.empty()) {
    fs::remove(temporary, error);
    throw std::runtime_error(target.string() + ": cannot be written: " + why);
  }
}

void write_text_atomically(const fs::path& target, const std::string& text) {
  write_atomically(target, [&](const fs::path& temporary) -> std::string {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    return out ? "" : "write failed";
  });
}

}  // namespace prism
