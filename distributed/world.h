// The processes an MPI launcher started together, and the few collective operations Prism
// needs of them: a counter every rank draws from, a gather of byte buffers and a sum of
// counters at rank 0. Nothing here exposes MPI's headers, so the session and the apps use it
// whether or not Prism was built with MPI (PRISM_HAVE_MPI); without it, or when no launcher
// started the process, the world is this process alone and no MPI call is made.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace prism::distributed {

class World {
 public:
  // The process's world, made on first use: MPI is initialised only when an MPI launcher
  // started the process (OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_RANK set), because an
  // OpenMPI singleton init forks a daemon and a plain `prism render` must not pay for it.
  // Throws std::runtime_error when a launcher started several ranks but Prism was built
  // without MPI: each would render the whole frame and write the same files.
  static World& process();
  // The world if process() has made it, else null; asks nothing of MPI.
  static World* existing();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  bool uses_mpi() const { return uses_mpi_; }
  // How the ranks talk, for --verbose: "shared memory (...)" when Prism chose OpenMPI's
  // shared-memory transport because every rank is on one node, else "MPI's default".
  const char* transport() const {
    return chose_shared_memory_ ? "shared memory (OpenMPI pml ob1, btl self,vader: every rank "
                                  "on one node)"
                                : "MPI's default or the launcher's choice";
  }
  // Collective: returns once every rank has called it.
  void barrier() const;

  // Prints "prism: error: rank R: MESSAGE" and ends every rank (MPI_Abort): after a failure
  // on one rank the others would otherwise wait for it forever in the next collective. A
  // world of one just prints and exits.
  [[noreturn]] void abort(const std::string& message) const;

  // Runs `f`; if it throws on this rank of a world of several, aborts every rank with its
  // message instead of returning to a caller whose peers wait in a collective.
  template <typename F>
  decltype(auto) all_or_abort(F&& f) const {
    if (size_ == 1) return f();
    try {
      return f();
    } catch (const std::exception& e) {
      abort(e.what());
    }
  }

  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

 private:
  World();
  int rank_ = 0, size_ = 1;
  bool uses_mpi_ = false;
  bool chose_shared_memory_ = false;
};

// A counter shared by every rank: next() returns 0, 1, 2, ... across all of them together,
// each value once, so ranks claim work items (tiles, jobs) as they become free. Collective:
// every rank constructs and destroys it at the same point. Thread-safe.
class SharedCounter {
 public:
  explicit SharedCounter(const World& world);
  ~SharedCounter();
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;

  uint64_t next();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Collective: rank 0 receives every rank's `bytes`, indexed by rank (its own included);
// the other ranks receive an empty vector.
std::vector<std::vector<std::byte>> gather_at_root(const World& world,
                                                   std::span<const std::byte> bytes);

// Collective: rank 0's `values` become the element-wise sums over every rank; the other
// ranks' are left as they were.
void sum_at_root(const World& world, std::span<uint64_t> values);

}  // namespace prism::distributed
