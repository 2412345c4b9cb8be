// MPI's few calls that world.cpp makes, behind a module of their own (libprism_mpi.so,
// built from mpi/mpi_module.cpp when CMake finds MPI) that the world opens only when an MPI
// launcher started the process: linking libmpi into prism would cost every command its
// start-up (OpenMPI's library and its dependencies, about 3 ms), and only `mpirun` needs it.
//
// The interface is MPI's, one call each, with MPI's int counts; the checks and messages
// (sizes past INT_MAX, thread levels) stay in world.cpp, which knows what each call is for.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

namespace prism::distributed {

// A uint64 in rank 0's memory that every rank fetch-and-adds one to. Thread-safe.
class MpiCounter {
 public:
  virtual ~MpiCounter() = default;
  virtual uint64_t next() = 0;
};

class MpiModule {
 public:
  struct Started {
    int rank = 0, size = 1;
    int provided = 0;         // the thread level MPI granted
    bool serialized = false;  // provided >= MPI_THREAD_SERIALIZED
  };
  // MPI_Init_thread asking for MPI_THREAD_SERIALIZED, then the world's rank and size.
  virtual Started init() const = 0;
  // MPI_Finalize unless MPI already is finalized.
  virtual void finalize() const = 0;
  [[noreturn]] virtual void abort() const = 0;
  virtual void barrier() const = 0;
  // Collective: a counter starting at 0, ready on every rank once this returns.
  virtual std::unique_ptr<MpiCounter> make_counter(bool root) const = 0;
  // MPI_Gather of one int per rank; `counts` (one per rank) is written at rank 0 only.
  virtual void gather_count(int count, int* counts) const = 0;
  // MPI_Gatherv of bytes; `all`, `counts` and `displacements` are read at rank 0 only.
  virtual void gather_bytes(const std::byte* bytes, int count, std::byte* all, const int* counts,
                            const int* displacements) const = 0;
  // MPI_Reduce with MPI_SUM into rank 0's `values`, in place.
  virtual void sum_at_root(uint64_t* values, int count, bool root) const = 0;

  virtual ~MpiModule() = default;
};

// The module's exported symbols: the entry returns the module's one MpiModule, the build
// symbol its "<version> <commit>" (renderer/loadable_module.h refuses another build's).
inline constexpr const char* kMpiModuleEntry = "prism_mpi_module";
inline constexpr const char* kMpiModuleBuild = "prism_mpi_module_build";

}  // namespace prism::distributed
