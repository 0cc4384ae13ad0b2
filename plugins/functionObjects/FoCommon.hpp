// Shared pieces of the function objects in this folder: lost points, body selection,
// directions, and field lookup in snapshots. Their CSV files are the SDK's
// (scree/output/csv_file.hpp, whose conventions every file written here follows).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "scree/output/csv_file.hpp"
#include "scree/output/ranks.hpp"
#include "scree/output/snapshot.hpp"
#include "scree/params/spec.hpp"
#include "scree/plugin/context.hpp"

namespace scree::fo {

/// The names joined as "a, b, c" (for messages).
std::string join(const std::vector<std::string>& v);


using Vec3 = std::array<double, 3>;

/// Points that have left the grid (BodySnapshot::lost) count in no function object's
/// statistics: each leaves them out and says how many there were in
/// postProcessing/<name>/lostPoints.csv ("time [s],lost points [-]", over its selected
/// bodies), one row per execution from the first at which there is one. A run that loses
/// no point writes no such file, and its other files are as before. A fresh run removes
/// the file an earlier run left; a restart keeps its rows before the restart's time.
class LostPoints {
 public:
  LostPoints() = default;
  LostPoints(const SolverContext& ctx, std::string who);
  /// The selected bodies' lost points at s, over every rank's points (collective); the
  /// root writes the row once there are any.
  std::int64_t record(const Snapshot& s, const std::vector<std::string>& bodies);

 private:
  Ranks ranks_;
  std::filesystem::path path_;
  double start_time_ = 0;
  std::string who_;
  bool started_ = false;
  CsvFile csv_;
};

/// At the first execution of a function object writing one file per time: create `dir`
/// (ensure_writable_dir) and, for a fresh run (start_time <= 0), remove the files of an
/// earlier run there: those named <number>.csv and `also` (if given).
void prepare_time_files(const std::filesystem::path& dir, const std::string& who, double start_time,
                        const std::string& also = "");

/// Location of `key` in a plugin dictionary (the dictionary itself when defaulted).
SourceLocation where_of(const ParamReader& r, const char* key);

/// The `bodies` entry (optional word list; empty result: all bodies), each name checked
/// against the case's bodies (InputError with "did you mean").
std::vector<std::string> read_bodies(const ParamReader& r, const SolverContext& ctx);
/// Whether body `b` is in `selection` (empty selection: every body).
bool selected(const std::vector<std::string>& selection, const BodySnapshot& b);

/// A unit vector from the optional vector entry `key` (dimension components), or `def`.
/// InputError when the entry is the zero vector.
Vec3 read_direction(const ParamReader& r, const char* key, const SolverContext& ctx, Vec3 def);
/// The message for a zero direction `key` (`found`: the entry as written).
std::string zero_direction(const std::string& key, const std::string& found);
/// Whether the vector entry `key` of `d` is present and all zeros (for the specs'
/// whole-dictionary checks).
bool zero_vector(const Dictionary& d, const char* key);
/// The number of components of the first present vector entry among `keys` (validated
/// to one per dimension), 0 when none is present: the case's dimension as a spec's
/// check can know it.
int given_dimension(const Dictionary& d, std::initializer_list<const char*> keys);
/// A point from the optional vector entry `key`, or the origin.
Vec3 read_point(const ParamReader& r, const char* key, const SolverContext& ctx);
/// "Up": -gravity normalised, or +y (2D) / +z (3D) without gravity.
Vec3 default_up(const SolverContext& ctx);

/// The field `name` of a body, or a std::runtime_error naming `who`, the body and the
/// fields it has.
const FieldData& require_field(const BodySnapshot& b, const std::string& name, const std::string& who);

/// Component suffixes of a field when expanded into CSV columns: scalars none; vectors
/// (3) _x _y [_z in 3D]; symmetric tensors (6) _xx _yy _zz _xy [_yz _zx in 3D]; other
/// counts _0 _1 .... The second member gives the component index of each suffix.
std::vector<std::pair<std::string, int>> component_suffixes(int components, int dimension);

inline double dot(const Vec3& a, const double* x) { return a[0] * x[0] + a[1] * x[1] + a[2] * x[2]; }

}  // namespace scree::fo
