// The core dictionaries of a case as typed settings, read once.
//
// system/controlDict, system/mpmSchemes, system/gridDict and constant/g are declared by
// the parameter specs of CoreSpecs (case.hpp): names, units, ranges and every default.
// CaseSettings::read turns the validated dictionaries into these structs through
// ParamReader, which applies the specs' defaults, so a default is written in one place
// only (the spec) and `scree --list-plugins case` prints the truth. Nothing else in the
// core reads a core dictionary's keys.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/mpm/schemes.hpp"
#include "scree/time/time_control.hpp"

namespace scree {

class Case;

/// controlDict writeControl: runTime and adjustableRunTime both write every writeInterval
/// seconds of simulated time (the step lands on the write times either way).
enum class WriteControl { timeStep, runTime };

/// system/controlDict
struct ControlSettings {
  TimeSettings time;            ///< startTime, endTime, deltaT, adjustTimeStep, maxCo, maxDeltaT
  WriteControl write_control = WriteControl::runTime;
  double write_interval = 0;    ///< writeInterval [s or steps]
  std::int64_t progress_interval = 0;  ///< progressInterval [steps] (0: automatic)
  double max_lost_fraction = 1;        ///< maxLostFraction: more points off the grid stop the run [-]
  bool start_from_latest = false;      ///< startFrom latestTime: continue from the newest checkpoint
  std::int64_t checkpoint_interval = 0;  ///< checkpointInterval: a checkpoint every this many writes (0: none)
  std::int64_t checkpoint_keep = 0;      ///< checkpointKeep: the newest checkpoints kept
};

/// mpmSchemes damping { type local; ... }: Cundall's local non-viscous damping.
struct DampingSettings {
  Real coefficient = 0;  ///< alpha [-] (0: none)
  Real start_time = 0, end_time = 0;  ///< the window in which it acts [s]
};

/// system/mpmSchemes
struct SchemeSettings {
  UpdateScheme update_scheme = UpdateScheme::USF;
  ShapeKind shape = ShapeKind::linear;
  Transfer transfer = Transfer::flip;
  Real pic_fraction = 0;  ///< PIC share of the FLIP/PIC blend per step [-]
  Real pic_rate = 0;      ///< PIC share of the blend per unit time [1/s] (0: pic_fraction)
  /// maxVolumeRatio: largest det F; absent: no limit (kNoVolumeLimit)
  Real max_volume_ratio = kNoVolumeLimit;
  DampingSettings damping;
  std::int64_t sort_interval = 0;  ///< sortInterval [steps] (0: never)
  Real mass_tolerance = 0;         ///< massTolerance [-]
};

/// system/gridDict
struct GridSettings {
  int dimension = 2;
  std::vector<Real> lower, upper;  ///< corners of the domain [m]
  Real cell_size = 0;              ///< h [m]
  int ghost_layers = 0;
};

/// A body of constant/bodies: what the solver reads of it (its region, velocity and
/// initial stress are read where the particles are made, particle_generation.hpp).
struct BodySettings {
  std::string material;        ///< the name of a material in constant/materialProperties
  int particles_per_cell = 0;  ///< particles per cell along each axis

  /// Read a validated body dictionary through CoreSpecs::body.
  SCREE_API static BodySettings read(const Dictionary& body);
};

struct CaseSettings {
  ControlSettings control;
  SchemeSettings schemes;
  GridSettings grid;
  std::vector<Real> gravity;  ///< constant/g value [m/s^2]

  /// Read the validated core dictionaries of `c` (Case::read calls this once).
  SCREE_API static CaseSettings read(const Case& c);
};

}  // namespace scree
