// Checkpoints: the whole state of a run at one of its write times, from which `scree
// --restart` (or `startFrom latestTime;` in system/controlDict) continues it.
//
// A checkpoint holds everything a step reads that the case's dictionaries do not give
// again: every body's particle block (positions, velocities, F, stress, mass, volume, ids,
// the material's state variables and a formulation's extra columns: particle_storage.hpp),
// the pore liquid's cumulative inflows, the clock on the device (time, step, the last
// signal speed the next step is derived from, the lost-point count: step_control.hpp),
// the step counters that decide when particles are sorted, and when each writer and
// function object is due next. The grid is not in it: a checkpoint is taken after the
// step's gather (Solver::flush), when the set the next step scatters into is all zeros,
// as it is in a fresh grid. A restarted CPU run on one thread equals the uninterrupted run
// bit for bit (tests/verification/restart).
//
// Where: <case>/checkpoints/<time>.ckpt, <time> as %.12g ("0.25.ckpt"); a decomposed run's
// pieces in <case>/checkpoints/<time>.ranks/ (Checkpoint::pieces). Written at every
// checkpointInterval-th write time, at endTime and when a run is stopped by a signal
// (not after a failure: the newest checkpoint is then the last healthy write, the one to
// restart from with a smaller step); the newest checkpointKeep are kept.
//
// The file (little-endian, Reals as IEEE doubles): the magic "SCREE-CHECKPOINT", a format
// version, sizeof(Real) and sizeof(StepControl), the sections below, and an FNV-1a 64-bit
// checksum of everything before it. It is written to a temporary, flushed to disk (fsync)
// and renamed into place, so that a killed run leaves the old checkpoint or the complete
// new one, never half of one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"

namespace scree {

struct SCREE_API Checkpoint {
  /// 2: the decomposition's slabs; 3: the case's physics; 4: the pieces of a decomposed run;
  /// 5: the decomposition's bisection tree (earlier versions are read too).
  static constexpr std::uint32_t kVersion = 5;

  int dimension = 0;
  double time = 0;              ///< the clock [s]
  std::int64_t step = 0;        ///< every step taken (also those with dt = 0)
  std::int64_t sorted_at = 0;   ///< steps that advanced the clock at the last particle sort
  std::int64_t writes = 0;      ///< write times so far (the checkpoint interval counts them)
  std::vector<unsigned char> clock;  ///< the StepControl, as its bytes
  std::vector<double> schedule;      ///< OutputSchedule::state()
  struct Body {
    std::string name;           ///< as in constant/bodies
    std::string material_type;  ///< the material's type (a check against the case)
    std::uint64_t particles = 0;
    std::uint64_t columns = 0;  ///< Reals per particle
    std::vector<Real> data;     ///< columns x particles (the body's storage block)
  };
  std::vector<Body> bodies;
  std::vector<Real> liquid;     ///< the pore liquid's state (PorousMedia::save_state; empty: none)
  /// A decomposed run's boxes (case/decomposition.hpp): its bisection tree
  /// (Decomposition::tree_code), which a restart on as many ranks takes up; empty: one rank.
  /// The slabs of versions 2 to 4 (an axis and the cells of the ranks + 1 cuts) are read as
  /// the tree that cuts one slab off after another.
  std::vector<std::int32_t> decomposition;
  /// The case's physics when it was written (case_physics): a restart refuses a case whose
  /// physics changed since (physics_changes). Empty in a checkpoint of version 1 or 2.
  std::vector<std::pair<std::string, std::string>> physics;

  /// A decomposed run's checkpoint is a manifest and one piece per rank. Each rank writes
  /// the points it holds to <time>.ranks/<rank>.ckpt (a checkpoint of its own, with the
  /// same header); once every piece is on disk the root writes <time>.ckpt, the manifest:
  /// the header, each body's total count and no points, and `pieces`, the pieces' paths
  /// relative to its folder. A run killed before the manifest leaves the previous
  /// checkpoint the newest; the pieces without a manifest are removed by the next purge.
  std::vector<std::string> pieces;

  /// Write atomically (temporary, fsync, rename). Throws std::runtime_error naming the file
  /// on an I/O failure (disk full, not writable).
  void write(const std::filesystem::path& file) const;
  /// Read and verify (magic, version, sizes, checksum). Throws std::runtime_error naming the
  /// file and what is wrong with it. A manifest's pieces are read too, and each body's
  /// points concatenated in rank order: all of them, or, when the manifest has `ranks`
  /// pieces (a restart on as many ranks), only piece `rank`'s (Body::particles stays the
  /// body's total; its data hold data.size() / columns points).
  static Checkpoint read(const std::filesystem::path& file, int rank = 0, int ranks = 1);
};

class Case;

/// The physics of a case as a checkpoint records it: every entry, at any depth, of the
/// dictionaries that define what is computed (system/gridDict, system/mpmSchemes,
/// constant/g, materialProperties, bodies and boundaryConditions), as "<file>/<dotted key>"
/// ("constant/materialProperties/soil.E") and its value written back in dictionary syntax (so comments, layout, macros and includes do not
/// count, values do). system/controlDict is not among them: a restart may change the time
/// control (endTime, deltaT, maxCo), the output and the health limits.
SCREE_API std::vector<std::pair<std::string, std::string>> case_physics(const Case& c);

/// Where the physics of `now` differs from a checkpoint's (`then`): one error per entry
/// changed, added or removed, at the entry (a removed one at its file), saying so; empty when
/// none differs or when the checkpoint records no physics (versions 1 and 2).
SCREE_API std::vector<InputError> physics_changes(const std::vector<std::pair<std::string, std::string>>& then,
                                                  const Case& now);

/// <case>/checkpoints
SCREE_API std::filesystem::path checkpoint_dir(const std::filesystem::path& case_dir);
/// The piece of rank `rank` of the checkpoint `file` (<time>.ckpt): <time>.ranks/<rank>.ckpt
/// beside it, and its path relative to the manifest's folder (Checkpoint::pieces).
SCREE_API std::filesystem::path checkpoint_piece(const std::filesystem::path& file, int rank);
SCREE_API std::string checkpoint_piece_relative(const std::filesystem::path& file, int rank);
/// The file of a checkpoint at time t: <case>/checkpoints/<t as %.12g>.ckpt
SCREE_API std::filesystem::path checkpoint_file(const std::filesystem::path& case_dir, double t);
/// The time of a checkpoint file from its name (<time>.ckpt), or false when it is not one.
SCREE_API bool checkpoint_time(const std::filesystem::path& file, double& t);
/// The checkpoints of a case (files named <time>.ckpt), oldest first by their time.
SCREE_API std::vector<std::filesystem::path> list_checkpoints(const std::filesystem::path& case_dir);
/// Remove all but the newest `keep` checkpoints of a case (keep 0: every one; a run from
/// startTime clears those of an earlier run), with their pieces, and the temporaries a
/// killed run left, with the pieces of a checkpoint whose manifest it never wrote (those
/// older than the newest manifest: later ones may be being written).
SCREE_API void purge_checkpoints(const std::filesystem::path& case_dir, std::size_t keep);

}  // namespace scree
