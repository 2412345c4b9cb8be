// The one memory budget of a glTF load: every byte of geometry, texels, buffers and copies
// the loader allocates on behalf of the file is charged to it before the allocation, so that
// a small file cannot multiply per-object limits into gigabytes (five zero-filled accessors,
// primitives sharing one accessor, a mesh copied per morph-weight set, one .bin referenced by
// hundreds of buffers). Crossing it is a LoadError naming the element being allocated.
#pragma once

#include <cstddef>
#include <string>

namespace prism::gltf_detail {

class MemoryBudget {
 public:
  MemoryBudget(std::size_t limit, const std::string& file) : limit_(limit), file_(file) {}

  // Charges count x size bytes for `element`; throws LoadError, before anything is allocated,
  // when the load's total would exceed the limit (or the product overflows).
  void charge(std::size_t count, std::size_t size, const std::string& element);

  std::size_t used() const { return used_; }
  // The element of the last charge: what was being allocated when memory ran out regardless
  // (std::bad_alloc under a budget larger than the machine's free memory).
  const std::string& last_element() const { return last_element_; }
  std::size_t limit() const { return limit_; }

 private:
  std::size_t limit_;
  std::size_t used_ = 0;
  const std::string& file_;
  std::string last_element_;
};

// The loader's parts run deep below load_gltf and on its thread; rather than thread a budget
// through every reader's signature, the load installs its budget for its own thread.
class BudgetScope {
 public:
  explicit BudgetScope(MemoryBudget& budget);
  ~BudgetScope();
  BudgetScope(const BudgetScope&) = delete;
  BudgetScope& operator=(const BudgetScope&) = delete;

 private:
  MemoryBudget* previous_;
};

// Charges the budget of the load running on this thread (none: nothing is charged, for parts
// used outside a load such as unit tests of a reader).
void charge(std::size_t count, std::size_t size, const std::string& element);

// "1.5 GiB", "12 MiB", "300 bytes".
std::string byte_size(std::size_t bytes);

}  // namespace prism::gltf_detail
