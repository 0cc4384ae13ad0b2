// Comm: the ranks of one run and the messages between them.
//
// A case runs on one rank, or decomposed over several (case/decomposition.hpp) that talk
// through MPI: the halo sums of the grid, the particles that migrate between boxes, the
// per-step reduction of the clock's inputs, the per-chunk agreement of the host's
// decisions, and the gathers of output and checkpoints. The solver speaks only to this
// interface; `world()` is MPI_COMM_WORLD when the process runs under MPI (comm_init), and
// otherwise a communicator of one rank, on which every operation is a copy.
//
// Every operation is collective over the communicator (or over the pair in `exchange`):
// each rank calls it in the same order with matching sizes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "scree/core/config.hpp"

namespace scree {

class SCREE_API Comm {
 public:
  virtual ~Comm() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// What carries the messages, for the log ("MPI: Open MPI v4.1.4; built without CUDA
  /// support", "one rank").
  virtual std::string describe() const = 0;
  /// Whether messages may be sent from and received into GPU memory (a CUDA-aware MPI, as
  /// it says at run time); otherwise GPU data goes through host buffers.
  virtual bool device_aware() const { return false; }

  /// Element-wise over the ranks, in place.
  virtual void max(double* v, int n) = 0;
  virtual void sum(double* v, int n) = 0;
  virtual void sum(std::uint64_t* v, int n) = 0;
  virtual void max(std::uint64_t* v, int n) = 0;
  /// `bytes` of `data` from `root` to every rank.
  virtual void broadcast(void* data, std::size_t bytes, int root) = 0;
  /// One message each way between this rank and `peer`.
  struct Exchange {
    int peer;
    const void* send;
    std::size_t send_bytes;
    void* recv;
    std::size_t recv_bytes;
  };
  /// Every message of `with` sent and received at once, each to and from its own peer (both
  /// sides of a pair call with their own sizes; the sizes must match pairwise). Returns when
  /// all have arrived: a rank with two neighbours waits for the slower, not for both in turn.
  virtual void exchange(const Exchange* with, int n) = 0;
  void exchange(int peer, const void* send, std::size_t send_bytes, void* recv, std::size_t recv_bytes) {
    const Exchange e{peer, send, send_bytes, recv, recv_bytes};
    exchange(&e, 1);
  }
  /// Every rank sends counts[r] bytes of `send` (in rank order) to rank r and receives
  /// into `recv` what every rank sent it, in rank order; returns the bytes from each rank.
  virtual std::vector<std::size_t> all_to_all(const std::vector<char>& send, const std::vector<std::size_t>& counts,
                                              std::vector<char>& recv) = 0;
  /// The concatenation of every rank's `send`, in rank order, on `root` (empty elsewhere);
  /// returns each rank's byte count on `root`.
  virtual std::vector<std::size_t> gather(const void* send, std::size_t bytes, std::vector<char>& recv, int root) = 0;
  virtual void barrier() = 0;
  /// End every rank of the run at once (a rank found an error the others cannot know of).
  [[noreturn]] virtual void abort(int code) = 0;

  // Typed helpers.
  double max(double v) {
    max(&v, 1);
    return v;
  }
  double sum(double v) {
    sum(&v, 1);
    return v;
  }
  std::uint64_t sum(std::uint64_t v) {
    sum(&v, 1);
    return v;
  }
  std::uint64_t max(std::uint64_t v) {
    max(&v, 1);
    return v;
  }
  template <class T>
  std::vector<T> gather_vector(const std::vector<T>& v, int root, std::vector<std::size_t>* counts = nullptr) {
    std::vector<char> raw;
    const auto bytes = gather(v.data(), v.size() * sizeof(T), raw, root);
    if (counts) {
      counts->clear();
      for (std::size_t b : bytes) counts->push_back(b / sizeof(T));
    }
    std::vector<T> out(raw.size() / sizeof(T));
    if (!raw.empty()) std::memcpy(out.data(), raw.data(), raw.size());
    return out;
  }
};

/// Start MPI when this build has it and the process was started by an MPI launcher
/// (mpirun, srun: MPI_Init_thread); a process started alone is one rank and starts no MPI.
/// Call once, before anything else, from an executable's main; harmless to skip (world()
/// is then one rank).
SCREE_API void comm_init(int* argc, char*** argv);
/// End MPI (MPI_Finalize) if comm_init started it.
SCREE_API void comm_finalize();
/// The ranks of this run: MPI_COMM_WORLD when MPI is running, else one rank.
SCREE_API std::shared_ptr<Comm> world();
/// A communicator of this process alone (a one-rank run beside a decomposed one: tests).
SCREE_API std::shared_ptr<Comm> self();
/// Whether this build has MPI.
SCREE_API bool mpi_compiled();
/// The local rank of this process among those on its node (GPU binding), from the MPI
/// launcher's environment (OMPI_COMM_WORLD_LOCAL_RANK, MPI_LOCALRANKID, SLURM_LOCALID), or 0.
SCREE_API int local_rank();

}  // namespace scree
