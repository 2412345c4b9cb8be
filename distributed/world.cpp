#include "distributed/world.h"

#include <atomic>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "distributed/mpi_module.h"
#include "renderer/loadable_module.h"

namespace prism::distributed {
namespace {

World* g_world = nullptr;
// Set while the process's world uses MPI: loaded by World() and never unloaded.
const MpiModule* g_mpi = nullptr;

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

// What the launcher says of the world's size, for when MPI cannot be asked.
int launcher_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 1;
}

// When OpenMPI's launcher put every rank on this node, shared memory is the only transport
// they need, but OpenMPI first probes UCX's (InfiniBand, TCP, ...): 0.2 of MPI_Init's 0.3 s
// here, the difference between 0.81x and 0.90x of one process's throughput on a 2 s frame.
// A choice of the user's (`mpirun --mca pml ...`, which reaches the ranks as OMPI_MCA_pml)
// is kept; a choice in an MCA parameter file is overridden on one node only.
bool prefer_shared_memory_on_one_node() {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (!size || !local || std::strcmp(size, local) != 0) return false;
  if (std::getenv("OMPI_MCA_pml") || std::getenv("OMPI_MCA_btl")) return false;
  ::setenv("OMPI_MCA_pml", "ob1", 0);
  ::setenv("OMPI_MCA_btl", "self,vader", 0);
  return true;
}

// The MPI module, or a reason why this process cannot use MPI.
const MpiModule* load_mpi(std::string& why_not) {
#ifdef PRISM_HAVE_MPI
  // Global: OpenMPI's components, opened by libmpi itself, look libmpi's symbols up in the
  // global namespace.
  const ModuleOnce<MpiModule>& loaded = load_module_once<MpiModule>(
      "libprism_mpi.so", "MPI", kMpiModuleBuild, kMpiModuleEntry, SymbolScope::global);
  if (loaded.module) return loaded.module;
  why_not = "prism " + loaded.error;
#else
  why_not = "this prism was built without MPI";
#endif
  return nullptr;
}

}  // namespace

World& World::process() {
  static World world;
  return world;
}

World* World::existing() {
  return g_world;
}

World::World() {
  if (launched_by_mpi()) {
    std::string why_not;
    g_mpi = load_mpi(why_not);
    if (!g_mpi && launcher_size() > 1)
      throw std::runtime_error("an MPI launcher started " + std::to_string(launcher_size()) +
                               " ranks, but " + why_not +
                               " (each rank would render the whole frame and write the same "
                               "files)");
  }
  if (g_mpi) {
    chose_shared_memory_ = prefer_shared_memory_on_one_node();
    const MpiModule::Started started = g_mpi->init();
    uses_mpi_ = true;
    rank_ = started.rank;
    size_ = started.size;
    g_world = this;
    if (!started.serialized)
      abort("MPI provides thread level " + std::to_string(started.provided) +
            ", below MPI_THREAD_SERIALIZED, which tile claims from worker threads need");
    return;
  }
  g_world = this;
}

World::~World() {
  if (uses_mpi_) g_mpi->finalize();
  g_world = nullptr;
}

void World::abort(const std::string& message) const {
  std::fprintf(stderr, "prism: error: rank %d: %s\n", rank_, message.c_str());
  std::fflush(stderr);
  if (uses_mpi_) g_mpi->abort();
  std::_Exit(1);
}

void World::barrier() const {
  if (size_ > 1) g_mpi->barrier();
}

struct SharedCounter::State {
  std::atomic<uint64_t> local{0};           // a world of one
  std::unique_ptr<MpiCounter> distributed;  // a world of several
};

SharedCounter::SharedCounter(const World& world) : state_(std::make_unique<State>()) {
  if (world.size() > 1) state_->distributed = g_mpi->make_counter(world.root());
}

SharedCounter::~SharedCounter() = default;

uint64_t SharedCounter::next() {
  if (state_->distributed) return state_->distributed->next();
  return state_->local++;
}

std::vector<std::vector<std::byte>> gather_at_root(const World& world,
                                                   std::span<const std::byte> bytes) {
  std::vector<std::vector<std::byte>> out;
  if (world.size() == 1) {
    out.emplace_back(bytes.begin(), bytes.end());
    return out;
  }
  // MPI's counts are int: past 2 GiB in all, a gather in pieces would be needed.
  if (bytes.size() > static_cast<size_t>(INT_MAX))
    world.abort("gather: " + std::to_string(bytes.size()) + " bytes, more than MPI's int counts");
  const int count = static_cast<int>(bytes.size());
  std::vector<int> counts(world.root() ? static_cast<size_t>(world.size()) : 0);
  g_mpi->gather_count(count, counts.data());
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
  g_mpi->gather_bytes(bytes.data(), count, all.data(), counts.data(), displacements.data());
  for (size_t r = 0; r < counts.size(); ++r)
    out.emplace_back(all.begin() + displacements[r], all.begin() + displacements[r] + counts[r]);
  return out;
}

void sum_at_root(const World& world, std::span<uint64_t> values) {
  if (world.size() == 1) return;
  if (values.size() > static_cast<size_t>(INT_MAX))
    world.abort("sum: " + std::to_string(values.size()) + " values, more than MPI's int counts");
  g_mpi->sum_at_root(values.data(), static_cast<int>(values.size()), world.root());
}

}  // namespace prism::distributed
