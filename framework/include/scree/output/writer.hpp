// Output-writer plugins: write particle (and grid) data at the case's write times.
//
// Writers run on the host from a Snapshot (a copy taken off the device), on a writer
// thread, so a slow disk does not stall the run. A writer must never leave a
// half-written file in the output directory: write to a temporary name and rename
// (write_file_atomically below).
//
// Where: a writer that writes files declares a word parameter `directory` (relative to
// the case directory) and names its files after itself, <name>.* and <name>_* (the vtk
// writer: VTK/particles.pvd, VTK/particles_3.vtp). The core relies on both: it checks
// before a run that the directory can be created, and `scree` refuses to run over the
// files of an earlier run there unless given --overwrite (case/setup_check.hpp).
//
//   struct MyWriter : Writer {
//     static constexpr const char* type_name = "myWriter";
//     static ParamSpec spec();
//     MyWriter(const ParamReader& r, const SolverContext& ctx);
//     void write(const Snapshot& s) override;
//   };
//   SCREE_PLUGIN(r) { r.add_writer<MyWriter>(); }
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "scree/output/snapshot.hpp"
#include "scree/params/spec.hpp"

namespace scree {

struct SolverContext;  // what plugins learn about the case (scree/plugin/context.hpp)

class SCREE_API Writer {
 public:
  virtual ~Writer();
  /// Write one time. Called in time order, never concurrently with itself.
  virtual void write(const Snapshot& s) = 0;
  /// After the last write (close series files and the like).
  virtual void finish() {}
  /// Whether the writer wants grid fields in its snapshots.
  virtual bool wants_grid() const { return false; }

  // A run decomposed over several ranks (docs/multi-gpu.md). A writer whose
  // writes_pieces() is true writes each rank's points as a piece of its own and a file
  // that lists the pieces (ParaView's parallel formats), so that no rank holds the whole
  // case; every rank has one. Any other writer gets the whole case gathered on the root
  // and is called through write(). The solver drives a writer of pieces at a write time:
  //
  //   root:        frame = begin_frame(header)        "" skips the time (already written)
  //   every rank:  write_piece(local, frame, rank)    the points the rank holds
  //   root, once every rank's piece is in place:  end_frame(header, frame, ranks)
  //
  // `header` has the time, the step, the root's own points and, when wants_grid(), the
  // whole grid. begin_frame and end_frame run on the root only; write_piece may throw
  // (the run then stops on every rank with the message). None of them talks to the other
  // ranks: the solver carries the frame's name and waits for the pieces.
  virtual bool writes_pieces() const { return false; }
  virtual std::string begin_frame(const Snapshot& header) {
    (void)header;
    return {};
  }
  virtual void write_piece(const Snapshot& local, const std::string& frame, int rank) {
    (void)local, (void)frame, (void)rank;
  }
  virtual void end_frame(const Snapshot& header, const std::string& frame, int ranks) {
    (void)header, (void)frame, (void)ranks;
  }
};

/// Write a file through `fill(temporary_path)` then rename it into place, so that the
/// target is either the old file or the complete new one.
SCREE_API void write_file_atomically(const std::filesystem::path& target,
                                     const std::function<void(const std::filesystem::path&)>& fill);

/// The file name a temporary of write_file_atomically stands for ("<target>" of
/// ".<target>.tmp<pid>_<n>"), or "" for any other name: what a killed run left, for the
/// clean-ups of the output places, the VTK writer and the checkpoints.
SCREE_API std::string atomic_temporary_target(const std::string& filename);

}  // namespace scree
