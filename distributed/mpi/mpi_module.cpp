// libprism_mpi.so: the MPI calls of mpi_module.h, the only code that includes mpi.h.
#include <mpi.h>

#include <cstdlib>
#include <mutex>
#include <string>

#include "distributed/mpi_module.h"
#include "renderer/version.h"

namespace prism::distributed {
namespace {

// Passive target on rank 0: ranks fetch-and-add without rank 0 taking part, so no thread
// has to serve requests. "same_op" lets the one-sided component use hardware atomics.
class WindowCounter final : public MpiCounter {
 public:
  explicit WindowCounter(bool root) {
    MPI_Info info;
    MPI_Info_create(&info);
    MPI_Info_set(info, "accumulate_ops", "same_op");
    MPI_Win_allocate(root ? sizeof(uint64_t) : 0, sizeof(uint64_t), info, MPI_COMM_WORLD, &value_,
                     &window_);
    MPI_Info_free(&info);
    if (root) {
      MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, window_);
      *value_ = 0;
      MPI_Win_unlock(0, window_);
    }
    // Nobody draws before rank 0 has set the start.
    MPI_Barrier(MPI_COMM_WORLD);
  }
  ~WindowCounter() override { MPI_Win_free(&window_); }

  uint64_t next() override {
    // MPI_THREAD_SERIALIZED: one claim in MPI at a time.
    const std::lock_guard<std::mutex> lock(mutex_);
    const uint64_t one = 1;
    uint64_t got = 0;
    MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window_);
    MPI_Fetch_and_op(&one, &got, MPI_UINT64_T, 0, 0, MPI_SUM, window_);
    MPI_Win_unlock(0, window_);
    return got;
  }

 private:
  MPI_Win window_ = MPI_WIN_NULL;
  uint64_t* value_ = nullptr;  // rank 0's, inside the window
  std::mutex mutex_;
};

class Module final : public MpiModule {
 public:
  Started init() const override {
    // Serialised, not MPI_THREAD_MULTIPLE: the only MPI calls made from TBB's worker
    // threads are the counter's claims, which take a mutex; OpenMPI 4.1's pt2pt one-sided
    // component refuses MPI_THREAD_MULTIPLE (which component runs depends on the transport),
    // and one locked claim per tile of several milliseconds costs nothing measurable.
    Started started;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &started.provided);
    started.serialized = started.provided >= MPI_THREAD_SERIALIZED;
    MPI_Comm_rank(MPI_COMM_WORLD, &started.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &started.size);
    return started;
  }

  void finalize() const override {
    int finalized = 0;
    if (MPI_Finalized(&finalized) == MPI_SUCCESS && !finalized) MPI_Finalize();
  }

  [[noreturn]] void abort() const override {
    MPI_Abort(MPI_COMM_WORLD, 1);
    std::_Exit(1);  // MPI_Abort does not return, but is not declared so
  }

  void barrier() const override { MPI_Barrier(MPI_COMM_WORLD); }

  std::unique_ptr<MpiCounter> make_counter(bool root) const override {
    return std::make_unique<WindowCounter>(root);
  }

  void gather_count(int count, int* counts) const override {
    MPI_Gather(&count, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
  }

  void gather_bytes(const std::byte* bytes, int count, std::byte* all, const int* counts,
                    const int* displacements) const override {
    MPI_Gatherv(bytes, count, MPI_BYTE, all, counts, displacements, MPI_BYTE, 0, MPI_COMM_WORLD);
  }

  void sum_at_root(uint64_t* values, int count, bool root) const override {
    if (root)
      MPI_Reduce(MPI_IN_PLACE, values, count, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    else
      MPI_Reduce(values, nullptr, count, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  }
};

std::string g_build = std::string(kVersion) + " " + kBuildCommit;

}  // namespace
}  // namespace prism::distributed

extern "C" {
__attribute__((visibility("default"))) const prism::distributed::MpiModule* prism_mpi_module() {
  static const prism::distributed::Module module;
  return &module;
}
__attribute__((visibility("default"))) const char* prism_mpi_module_build() {
  return prism::distributed::g_build.c_str();
}
}
