#include "scene_io/gltf_budget.h"

#include <cstdio>
#include <limits>

#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {
thread_local MemoryBudget* current = nullptr;
}  // namespace

std::string byte_size(std::size_t bytes) {
  char text[64];
  if (bytes >= (std::size_t{1} << 30)) {
    std::snprintf(text, sizeof text, "%.2f GiB", double(bytes) / double(std::size_t{1} << 30));
  } else if (bytes >= (std::size_t{1} << 20)) {
    std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(std::size_t{1} << 20));
  } else {
    std::snprintf(text, sizeof text, "%zu bytes", bytes);
  }
  return text;
}

void MemoryBudget::charge(std::size_t count, std::size_t size, const std::string& element) {
  last_element_ = element;
  const bool overflow = size != 0 && count > std::numeric_limits<std::size_t>::max() / size;
  const std::size_t bytes = overflow ? std::numeric_limits<std::size_t>::max() : count * size;
  if (overflow || bytes > limit_ - used_) {
    fail(file_, element,
         "needs " + (overflow ? std::string("more than 16 EiB") : byte_size(bytes)) +
             ", which takes the load past its memory budget of " + byte_size(limit_) + " (" +
             byte_size(used_) + " already used; see --memory-limit)");
  }
  used_ += bytes;
}

BudgetScope::BudgetScope(MemoryBudget& budget) : previous_(current) {
  current = &budget;
}

BudgetScope::~BudgetScope() {
  current = previous_;
}

void charge(std::size_t count, std::size_t size, const std::string& element) {
  if (current) current->charge(count, size, element);
}

}  // namespace prism::gltf_detail
