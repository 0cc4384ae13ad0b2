// Ensembles: many variants (members) of one case, for probabilistic run-out, sensitivity
// studies and calibration.
//
// A case with a system/ensembleDict is an ensemble. Its dictionary names entries of the
// case's dictionaries (any file, any plugin's parameter) and how each varies:
//
//   seed        12345;          // the random draws (member k's draw depends only on the
//                               // seed, the parameter's name and k: adding members keeps
//                               // the earlier ones)
//   samples     64;             // draws of the distributions (default 1)
//   membersAtOnce 2;            // members run at the same time (default: 1 on a GPU; on
//                               // the CPU one per thread, the threads shared out among
//                               // them); together they must fit in the free memory
//   writers     no;             // the members without the case's writers (VTK frames);
//                               // their function objects' CSVs stay (default yes)
//   parameters
//   {
//       friction                                  // the name in members.csv and summaries
//       {
//           file   constant/materialProperties;   // relative to the case
//           entry  sand/phi_c;                    // the key path in that file
//           distribution { type normal; mean 30; standardDeviation 2; lower 25; upper 35; }
//       }
//       voidRatio { file constant/bodies; entry column/e0; values (0.80 0.85 0.90); }
//       cells     { file system/gridDict; entry cellSize; range { from 0.005; to 0.01; count 2; } }
//   }
//   summary                                       // quantities read from each member's CSVs
//   {
//       runOut { file postProcessing/massFront/runOut.csv; column front; at end; }   // end|max|min|<time>
//   }
//
// Members: every combination of the listed parameters (`values`, `range`) times `samples`
// draws of the distributed ones (uniform {lower upper}; normal and lognormal {mean
// standardDeviation} of the quantity itself, each optionally truncated to [lower, upper]).
//
// Each member is a case directory of its own, ensemble/member_NNNN/: the base case's
// system/ and constant/ with every dictionary written out whole (its #include files and
// macros expanded, so the member runs anywhere alone) and the member's values set; other
// files there are copied. An entry used as a $macro elsewhere cannot be a parameter (its
// uses are expanded where they stand): vary the entries that use it. Its
// results are those of that case run alone (scree runs it as a process of its own: a
// member that goes wrong stops alone, with its diagnosis in its log.scree, and the others
// go on). ensemble/members.csv lists each member's values, status and run time;
// ensemble/summary.csv the statistics of each summary quantity over the members that
// finished (mean, standard deviation, percentiles); ensemble/exceedance.csv the fraction
// of them above each value (the empirical exceedance curve).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/plugin/loader.hpp"

namespace scree {

/// How one parameter of an ensemble varies.
struct EnsembleParameter {
  enum class Kind { values, distribution };
  enum class Law { uniform, normal, lognormal };
  std::string name;
  std::filesystem::path file;         ///< relative to the case directory
  std::vector<std::string> entry;     ///< key path in that file
  SourceLocation where;               ///< its dictionary in ensembleDict
  Kind kind = Kind::values;
  std::vector<std::string> values;    ///< kind values: the values as written
  Law law = Law::uniform;             ///< kind distribution
  double mean = 0, sd = 0;            ///< normal, lognormal: of the quantity itself
  double lower = -1e300, upper = 1e300;  ///< uniform's range; the others' truncation

  /// The value of draw `u` in (0, 1) (the inverse of the distribution function, truncated).
  SCREE_API double quantile(double u) const;
};

/// A quantity read from each member's results for the summary.
struct EnsembleQuantity {
  enum class At { end, max, min, time };
  std::string name;
  std::filesystem::path file;  ///< a CSV, relative to the member's case
  std::string column;
  At at = At::end;
  double time = 0;
  SourceLocation where;
};

struct EnsembleSpec {
  static constexpr const char* kFile = "system/ensembleDict";
  std::uint64_t seed = 0;
  std::int64_t samples = 1;
  std::int64_t members_at_once = 0;  ///< 0: the backend's default
  bool writers = true;               ///< false: the members' cases without the writers {} of controlDict
  std::vector<EnsembleParameter> parameters;
  std::vector<EnsembleQuantity> summary;

  /// Whether `case_dir` is an ensemble (it has a system/ensembleDict).
  SCREE_API static bool present(const std::filesystem::path& case_dir);
  /// Read and check system/ensembleDict, and every parameter against the case's files (the
  /// file exists and is a dictionary, the entry's parent dictionary exists). Throws
  /// InputErrors listing every problem, each at its line.
  SCREE_API static EnsembleSpec read(const std::filesystem::path& case_dir);

  /// The number of members.
  SCREE_API std::int64_t members() const;
  /// Member k's value of every parameter, as written into its case (in parameters' order).
  SCREE_API std::vector<std::string> member_values(std::int64_t k) const;
};

/// The directory of member k: <case>/ensemble/member_NNNN.
SCREE_API std::filesystem::path member_dir(const std::filesystem::path& case_dir, std::int64_t k);

/// Write member k's case into `dest` (created, emptied first): every dictionary of the
/// case written out whole with the member's values set, other files copied, the base's
/// results, ensemble/ and ensembleDict left out. Throws InputError at the parameter's line
/// when its entry cannot be set.
SCREE_API void write_member_case(const std::filesystem::path& case_dir, const EnsembleSpec& spec, std::int64_t k,
                                 const std::filesystem::path& dest);

/// A summary quantity of one member's results, or nullopt when its file, column or time is
/// missing (`why` then says which).
SCREE_API std::optional<double> read_quantity(const std::filesystem::path& member, const EnsembleQuantity& q,
                                              std::string& why);

/// The statistics of a sample, as summary.csv gives them.
struct SampleStats {
  std::size_t n = 0;
  double mean = 0, sd = 0, min = 0, p05 = 0, p25 = 0, p50 = 0, p75 = 0, p95 = 0, max = 0;
};
/// Percentiles by linear interpolation between order statistics (type 7 of Hyndman & Fan
/// 1996, numpy's default); sd with n - 1.
SCREE_API SampleStats sample_stats(std::vector<double> x);

/// How an ensemble runs.
struct EnsembleRunOptions {
  std::filesystem::path scree;  ///< the scree executable that runs each member
  std::string device;           ///< "cpu", "cuda" or "" (scree's default)
  int threads = 1;              ///< CPU threads in all
  bool overwrite = false, restart = false, check = false;
};

/// Run (or, with check, validate) the ensemble of `case_dir`; returns scree's exit status
/// (0 every member finished; 1 errors in the ensemble or a member's case, among them
/// members that together do not fit in the free memory; 4 earlier results; 5 a member went
/// wrong, the others finished; 128 + N stopped by signal N). `rt` reads the members' cases
/// for their memory estimates.
SCREE_API int run_ensemble(const std::filesystem::path& case_dir, const EnsembleRunOptions& opt, PluginRuntime& rt);

}  // namespace scree
