#include "distributed/world.h"

#include <atomic>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

#ifdef PRISM_HAVE_MPI
#include <mpi.h>
#endif

namespace prism::distributed {
namespace {

World* g_world = nullptr;

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

#ifndef PRISM_HAVE_MPI
// What the launcher says of the world's size, for a build that cannot ask MPI.
int launcher_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 1;
}
#endif

}  // namespace

World& World::process() {
  static World world;
  return world;
}

World* World::existing() {
  return g_world;
}

World::World() {
  if (!launched_by_mpi()) {
    g_world = this;
    return;
  }
#ifdef PRISM_HAVE_MPI
  // Serialised, not MPI_THREAD_MULTIPLE: the only MPI calls made from TBB's worker threads
  // are SharedCounter's claims, which take a mutex; OpenMPI 4.1's pt2pt one-sided component
  // refuses MPI_THREAD_MULTIPLE (which component runs depends on the transport), and one
  // locked claim per tile of several milliseconds costs nothing measurable.
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
  uses_mpi_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  g_world = this;
  if (provided < MPI_THREAD_SERIALIZED)
    abort("MPI provides thread level " + std::to_string(provided) +
          ", below MPI_THREAD_SERIALIZED, which tile claims from worker threads need");
#else
  if (launcher_size() > 1)
    throw std::runtime_error("an MPI launcher started " + std::to_string(launcher_size()) +
                             " ranks, but this prism was built without MPI (each rank would "
                             "render the whole frame and write the same files)");
  g_world = this;
#endif
}

World::~World() {
#ifdef PRISM_HAVE_MPI
  int finalized = 0;
  if (uses_mpi_ && MPI_Finalized(&finalized) == MPI_SUCCESS && !finalized) MPI_Finalize();
#endif
  g_world = nullptr;
}

void World::abort(const std::string& message) const {
  std::fprintf(stderr, "prism: error: rank %d: %s\n", rank_, message.c_str());
  std::fflush(stderr);
#ifdef PRISM_HAVE_MPI
  if (uses_mpi_) MPI_Abort(MPI_COMM_WORLD, 1);
#endif
  std::_Exit(1);
}

void World::barrier() const {
#ifdef PRISM_HAVE_MPI
  if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

struct SharedCounter::State {
  std::atomic<uint64_t> local{0};  // a world of one
#ifdef PRISM_HAVE_MPI
  MPI_Win window = MPI_WIN_NULL;
  uint64_t* value = nullptr;  // rank 0's, inside the window
  std::mutex mutex;           // MPI_THREAD_SERIALIZED: one claim in MPI at a time
#endif
};

SharedCounter::SharedCounter(const World& world) : state_(std::make_unique<State>()) {
#ifdef PRISM_HAVE_MPI
  if (world.size() == 1) return;
  // Passive target on rank 0: ranks fetch-and-add without rank 0 taking part, so no thread
  // has to serve requests. "same_op" lets the one-sided component use hardware atomics.
  MPI_Info info;
  MPI_Info_create(&info);
  MPI_Info_set(info, "accumulate_ops", "same_op");
  MPI_Win_allocate(world.root() ? sizeof(uint64_t) : 0, sizeof(uint64_t), info, MPI_COMM_WORLD,
                   &state_->value, &state_->window);
  MPI_Info_free(&info);
  if (world.root()) {
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, state_->window);
    *state_->value = 0;
    MPI_Win_unlock(0, state_->window);
  }
  // Nobody draws before rank 0 has set the start.
  MPI_Barrier(MPI_COMM_WORLD);
#else
  (void)world;
#endif
}

SharedCounter::~SharedCounter() {
#ifdef PRISM_HAVE_MPI
  if (state_->window != MPI_WIN_NULL) MPI_Win_free(&state_->window);
#endif
}

uint64_t SharedCounter::next() {
#ifdef PRISM_HAVE_MPI
  if (state_->window != MPI_WIN_NULL) {
    const std::lock_guard<std::mutex> lock(state_->mutex);
    const uint64_t one = 1;
    uint64_t got = 0;
    MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, state_->window);
    MPI_Fetch_and_op(&one, &got, MPI_UINT64_T, 0, 0, MPI_SUM, state_->window);
    MPI_Win_unlock(0, state_->window);
    return got;
  }
#endif
  return state_->local++;
}

std::vector<std::vector<std::byte>> gather_at_root(const World& world,
                                                   std::span<const std::byte> bytes) {
  std::vector<std::vector<std::byte>> out;
  if (world.size() == 1) {
    out.emplace_back(bytes.begin(), bytes.end());
    return out;
  }
#ifdef PRISM_HAVE_MPI
  // MPI's counts are int: past 2 GiB in all, a gather in pieces would be needed.
  if (bytes.size() > static_cast<size_t>(INT_MAX))
    world.abort("gather: " + std::to_string(bytes.size()) + " bytes, more than MPI's int counts");
  const int count = static_cast<int>(bytes.size());
  std::vector<int> counts(world.root() ? static_cast<size_t>(world.size()) : 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> displacements(counts.size());
  std::vector<std::byte> all;
  if (world.root()) {
    long long total = 0;
    for (size_t r = 0; r < counts.size(); ++r) {
      displacements[r] = static_cast<int>(total);
      total += counts[r];
      if (total > INT_MAX)
        world.abort("gather: more than 2 GiB in all, more than MPI's int displacements");
    }
    all.resize(static_cast<size_t>(total));
  }
  MPI_Gatherv(bytes.data(), count, MPI_BYTE, all.data(), counts.data(), displacements.data(),
              MPI_BYTE, 0, MPI_COMM_WORLD);
  for (size_t r = 0; r < counts.size(); ++r)
    out.emplace_back(all.begin() + displacements[r], all.begin() + displacements[r] + counts[r]);
#endif
  return out;
}

void sum_at_root(const World& world, std::span<uint64_t> values) {
  if (world.size() == 1) return;
#ifdef PRISM_HAVE_MPI
  const int n = static_cast<int>(values.size());
  if (world.root())
    MPI_Reduce(MPI_IN_PLACE, values.data(), n, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  else
    MPI_Reduce(values.data(), nullptr, n, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
#else
  (void)values;  // a world of one returned above
#endif
}

}  // namespace prism::distributed
