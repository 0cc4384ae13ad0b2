// Comm (comm/comm.hpp): one rank, and MPI where this build has it.
#include "scree/comm/comm.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#if defined(SCREE_HAVE_MPI)
#include <mpi.h>
#if __has_include(<mpi-ext.h>)
#include <mpi-ext.h>
#endif
#endif

namespace scree {

namespace {

/// One rank: reductions are the identity, a gather a copy.
class SelfComm final : public Comm {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::string describe() const override { return "one rank"; }
  void max(double*, int) override {}
  void sum(double*, int) override {}
  void sum(std::uint64_t*, int) override {}
  void max(std::uint64_t*, int) override {}
  void broadcast(void*, std::size_t, int) override {}
  using Comm::exchange;
  void exchange(const Exchange* with, int n) override {
    if (n > 0)
      throw std::logic_error("Comm::exchange: rank " + std::to_string(with[0].peer) +
                             " does not exist in a one-rank run");
  }
  std::vector<std::size_t> all_to_all(const std::vector<char>& send, const std::vector<std::size_t>& counts,
                                      std::vector<char>& recv) override {
    recv = send;
    return {counts.empty() ? send.size() : counts[0]};
  }
  std::vector<std::size_t> gather(const void* send, std::size_t bytes, std::vector<char>& recv, int) override {
    recv.resize(bytes);
    if (bytes) std::memcpy(recv.data(), send, bytes);
    return {bytes};
  }
  void barrier() override {}
  [[noreturn]] void abort(int code) override { std::exit(code); }
};

#if defined(SCREE_HAVE_MPI)
bool g_started = false;  // comm_init started MPI (and comm_finalize ends it)

void check(int err, const char* what) {
  if (err == MPI_SUCCESS) return;
  char msg[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(err, msg, &len);
  throw std::runtime_error(std::string("MPI error in ") + what + ": " + std::string(msg, len));
}

/// Messages larger than an int's count go in pieces of kPiece bytes.
constexpr std::size_t kPiece = std::size_t(1) << 30;

class MpiComm final : public Comm {
 public:
  explicit MpiComm(MPI_Comm c) : comm_(c) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::string describe() const override {
    char version[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    MPI_Get_library_version(version, &len);
    std::string v(version, static_cast<std::size_t>(len));
    if (const auto nl = v.find_first_of(",\n"); nl != std::string::npos) v.resize(nl);
    std::string cuda = "built without CUDA support";
#if defined(MPIX_CUDA_AWARE_SUPPORT) && MPIX_CUDA_AWARE_SUPPORT
    cuda = MPIX_Query_cuda_support() ? "CUDA-aware" : "CUDA-aware build, not at run time";
#endif
    return "MPI: " + v + "; " + cuda;
  }
  bool device_aware() const override {
#if defined(MPIX_CUDA_AWARE_SUPPORT) && MPIX_CUDA_AWARE_SUPPORT
    return MPIX_Query_cuda_support() != 0;
#else
    return false;
#endif
  }
  void max(double* v, int n) override { check(MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_MAX, comm_), "max"); }
  void sum(double* v, int n) override { check(MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_SUM, comm_), "sum"); }
  void sum(std::uint64_t* v, int n) override {
    check(MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_UINT64_T, MPI_SUM, comm_), "sum");
  }
  void max(std::uint64_t* v, int n) override {
    check(MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_UINT64_T, MPI_MAX, comm_), "max");
  }
  void broadcast(void* data, std::size_t bytes, int root) override {
    char* p = static_cast<char*>(data);
    for (std::size_t off = 0; off < bytes || off == 0; off += kPiece) {
      const int n = static_cast<int>(std::min(kPiece, bytes - off));
      check(MPI_Bcast(p + off, n, MPI_BYTE, root, comm_), "broadcast");
      if (bytes == 0) break;
    }
  }
  using Comm::exchange;
  void exchange(const Exchange* with, int n) override {
    // Receives posted first, then the sends, each in pieces whose count fits an int.
    std::vector<MPI_Request> req;
    for (int i = 0; i < n; ++i)
      for (std::size_t o = 0; o < with[i].recv_bytes; o += kPiece) {
        req.emplace_back();
        check(MPI_Irecv(static_cast<char*>(with[i].recv) + o,
                        static_cast<int>(std::min(kPiece, with[i].recv_bytes - o)), MPI_BYTE, with[i].peer, 17, comm_,
                        &req.back()),
              "exchange receive");
      }
    for (int i = 0; i < n; ++i)
      for (std::size_t o = 0; o < with[i].send_bytes; o += kPiece) {
        req.emplace_back();
        check(MPI_Isend(static_cast<const char*>(with[i].send) + o,
                        static_cast<int>(std::min(kPiece, with[i].send_bytes - o)), MPI_BYTE, with[i].peer, 17, comm_,
                        &req.back()),
              "exchange send");
      }
    check(MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE), "exchange");
  }
  std::vector<std::size_t> all_to_all(const std::vector<char>& send, const std::vector<std::size_t>& counts,
                                      std::vector<char>& recv) override {
    std::vector<std::uint64_t> sc(counts.begin(), counts.end()), rc(static_cast<std::size_t>(size_));
    check(MPI_Alltoall(sc.data(), 1, MPI_UINT64_T, rc.data(), 1, MPI_UINT64_T, comm_), "all_to_all counts");
    std::size_t total = 0;
    for (auto c : rc) total += c;
    recv.resize(total);
    // Point-to-point, so that no count has to fit an int: receives posted first.
    std::vector<MPI_Request> req;
    std::size_t off = 0;
    for (int r = 0; r < size_; ++r) {
      for (std::size_t o = 0; o < rc[r]; o += kPiece) {
        req.emplace_back();
        check(MPI_Irecv(recv.data() + off + o, static_cast<int>(std::min<std::size_t>(kPiece, rc[r] - o)), MPI_BYTE, r,
                        23, comm_, &req.back()),
              "all_to_all receive");
      }
      off += rc[r];
    }
    off = 0;
    for (int r = 0; r < size_; ++r) {
      for (std::size_t o = 0; o < sc[r]; o += kPiece) {
        req.emplace_back();
        check(MPI_Isend(send.data() + off + o, static_cast<int>(std::min<std::size_t>(kPiece, sc[r] - o)), MPI_BYTE,
                        r, 23, comm_, &req.back()),
              "all_to_all send");
      }
      off += sc[r];
    }
    check(MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE), "all_to_all");
    return {rc.begin(), rc.end()};
  }
  std::vector<std::size_t> gather(const void* send, std::size_t bytes, std::vector<char>& recv, int root) override {
    std::vector<char> s(static_cast<const char*>(send), static_cast<const char*>(send) + bytes);
    std::vector<std::size_t> to(static_cast<std::size_t>(size_), 0);
    to[static_cast<std::size_t>(root)] = bytes;
    std::vector<char> r;
    auto got = all_to_all(s, to, r);
    if (rank_ == root) {
      recv = std::move(r);
      return got;
    }
    recv.clear();
    return {};
  }
  void barrier() override { check(MPI_Barrier(comm_), "barrier"); }
  [[noreturn]] void abort(int code) override {
    MPI_Abort(comm_, code);
    std::exit(code);
  }

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};
#endif

}  // namespace

void comm_init(int* argc, char*** argv) {
#if defined(SCREE_HAVE_MPI)
  // Only under a launcher (mpirun, srun): a process started alone is one rank, and an MPI
  // singleton would cost every plain run the start of a runtime daemon.
  bool launched = false;
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK", "MPI_LOCALNRANKS"})
    launched = launched || std::getenv(v) != nullptr;
  if (!launched) return;
  int ready = 0;
  MPI_Initialized(&ready);
  if (ready) return;
  int provided = 0;
  check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  g_started = true;
#else
  (void)argc;
  (void)argv;
#endif
}

void comm_finalize() {
#if defined(SCREE_HAVE_MPI)
  int done = 0;
  MPI_Finalized(&done);
  if (g_started && !done) MPI_Finalize();
  g_started = false;
#endif
}

std::shared_ptr<Comm> self() { return std::make_shared<SelfComm>(); }

std::shared_ptr<Comm> world() {
#if defined(SCREE_HAVE_MPI)
  int ready = 0, done = 0;
  MPI_Initialized(&ready);
  MPI_Finalized(&done);
  if (ready && !done) {
    int n = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    if (n > 1) return std::make_shared<MpiComm>(MPI_COMM_WORLD);
  }
#endif
  return self();
}

bool mpi_compiled() {
#if defined(SCREE_HAVE_MPI)
  return true;
#else
  return false;
#endif
}

int local_rank() {
  for (const char* v : {"OMPI_COMM_WORLD_LOCAL_RANK", "MPI_LOCALRANKID", "SLURM_LOCALID", "PMI_LOCAL_RANK"})
    if (const char* s = std::getenv(v)) return std::atoi(s);
  return 0;
}

}  // namespace scree
