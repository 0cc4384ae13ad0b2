// PorousMedia<D>: the two-phase formulation's part of a case (porous/two_phase.hpp): the
// two-phase bodies' pore liquid, its grid fields, its passes and grid update, and the
// hydraulic conditions. The solver owns one when a body of the case has a `twoPhase`
// block; a single-phase case never creates it (private to the core).
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <vector>

#include "scree/exec/memory.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/mpm/body.hpp"
#include "scree/mpm/halo_box.hpp"
#include "scree/mpm/owned_nodes.hpp"
#include "scree/mpm/schemes.hpp"
#include "scree/output/snapshot.hpp"
#include "scree/params/spec.hpp"
#include "scree/porous/body_hydraulics.hpp"
#include "scree/porous/two_phase.hpp"

namespace scree {

/// The `twoPhase { ... }` block of a body (constant/bodies): its spec.
SCREE_API std::shared_ptr<ParamSpec> two_phase_spec();

template <int D>
class PorousMedia {
 public:
  PorousMedia(HydraulicModelFactory models, const GridGeometry<D>& grid, const Exec& exec, const Vec<D>& gravity,
              ShapeKind shape, Real gimp_half_length);
  ~PorousMedia();

  /// The grid of this rank, its liquid's nodal fields allocated anew, all zero (a
  /// decomposed run's rebalance: after a flush, when no step is pending). The hydraulic
  /// conditions are then added anew (clear_conditions).
  void set_grid(const GridGeometry<D>& grid);
  /// A run decomposed over ranks (case/decomposition.hpp): `sum` adds the partial sums of
  /// nodal fields on the nodes this rank's grid shares with its neighbours (Solver's halo
  /// sum), `clear` zeroes fields on those nodes, `owned` the nodes whose inflows this rank
  /// counts. The liquid's three exchanges: its mass balance per cell before CellPressure,
  /// both phases' P2G and the cells' filling before SurfaceMask, and the surface's sums
  /// before the grid update.
  struct Halo {
    std::function<void(const HaloFields&)> sum, clear;
    OwnedNodes<D> owned;
  };
  void set_halo(Halo halo) { halo_ = std::move(halo); }
  /// Forget the hydraulic conditions (add_condition), before they are added anew on a new grid.
  void clear_conditions();

  /// Before a body is made: if its dictionary has a twoPhase block, set the setup's extra
  /// columns (the pore liquid's initial state), its mass factor (1 - n0) and its
  /// effective initial stress, and return true (the body is then attach()ed).
  bool prepare(const Dictionary& body, BodySetup<D>& s, Real grain_density);
  /// The density [kg/m^3] of a two-phase body's mixture against the elevation z [m] along
  /// -g: (1 - n0) rho_s + n0 S_l rho_l with S_l of the initial pore pressure at z, for the
  /// overburden of the geostatic stress (case/overburden.hpp); empty for a body without a
  /// twoPhase block. prepare() takes that total stress to the effective stress.
  std::function<Real(Real)> mixture_density(const Dictionary& body, Real grain_density) const;
  void attach(Body<D>* body);
  /// A hydraulic condition of the case (its pore pressures, open surfaces and node law).
  void add_condition(const HydraulicCondition* hc);
  /// The walls of the case and which of them the liquid obeys (all but the drained).
  void set_walls(const Wall* walls, const WallMask* masks, const std::vector<Wall>& table,
                 const std::vector<WallMask>& host_masks);

  /// The liquid's gather (before the solid passes of a step; pp as the solid's pass) from
  /// the liquid set `gather_set`.
  void gather(const PassParams<D>& pp, int gather_set, int scatter_set);
  /// After a G2P that no P2G follows (Solver::flush): the points' porosity and seepage
  /// (PoreColumns), which the P2G writes otherwise.
  void finish_columns(int gather_set, int scatter_set);
  /// Whether `body` is a two-phase body (its P2G is scatter()'s, not its solid pass's).
  bool holds(const Body<D>* body) const;
  /// The two-phase bodies' P2G of both phases into the solid set of `pp` and the liquid set
  /// `scatter_set` (after the solid passes, which gathered and updated them).
  void scatter(const PassParams<D>& pp, int gather_set, int scatter_set);
  /// The two-phase grid update of set `set` (USL), then the hydraulic node laws.
  void grid_update(int set, StepControl* control, int parity, Real mass_eps, Real damping, Real damping_start,
                   Real damping_end, const GridFields<D>* solid_sets);

  /// Checkpoints (case/checkpoint.hpp): what the liquid carries from step to step beside
  /// the points' extra columns (which the bodies save): the cumulative inflows.
  std::vector<Real> save_state() const { return totals(); }
  /// This rank's share of the cumulative inflows (kTotals values; synchronises with the
  /// device): a decomposed run sums them over the ranks.
  std::vector<Real> totals() const;
  /// Throws std::invalid_argument when `s` is not a state of save_state's size.
  void restore_state(const std::vector<Real>& s);

  /// Largest signal speed of the pore liquid over the points (host; the first step).
  Real max_signal_speed() const;
  bool empty() const { return bodies_.empty(); }
  /// The scalars of a two-phase body's snapshot (BodySnapshot::scalars): its liquid's
  /// constants, and on the first two-phase body the case's cumulative liquid inflows
  /// `totals` (totals(), summed over the ranks of a decomposed run).
  void scalars(const Body<D>* body, const std::vector<Real>& totals, std::vector<BodySnapshot::Scalar>& out) const;

 private:
  struct PorousBody {
    Body<D>* body = nullptr;
    PoreParams params;
    Real grain_density = 0;
    std::unique_ptr<HydraulicTableStorage> table;
    std::unique_ptr<RetentionModel> retention;
    std::unique_ptr<PermeabilityModel> permeability;
  };
  PorePassParams<D> pass_params(const PorousBody& b, int gather_set, int scatter_set) const;
  /// The nodal sums of a two-phase scatter into set `set` (`solid`: the solid's fields of it)
  /// before SurfaceMask, and those of SurfaceScatter: a decomposed run's halo sums.
  HaloFields mixture_fields(const GridFields<D>& solid, int set) const;
  HaloFields surface_fields(int set) const;

  HydraulicModelFactory models_;
  GridGeometry<D> grid_;
  Exec exec_;
  Vec<D> gravity_;
  int vertical_ = D - 1;
  Real up_[D] = {};  // the unit vector against gravity (0 without gravity)
  ShapeKind shape_;
  Real gimp_half_length_;
  std::vector<PorousBody> bodies_;
  std::vector<PorousBody> pending_;  // prepared, not yet attached
  Buffer<Real> liquid_data_[2];
  LiquidFields<D> sets_[2]{};
  Buffer<Real> cells_[2];
  Buffer<std::uint8_t> surface_;  // per node: on a surface of the points (SurfaceMask)
  Buffer<Real> balance_;  // per node: the liquid mass balance's inflow, then its capacity
  Real drag_per_mass_ = 0;  // PorePassParams::drag_per_mass
  Buffer<Real> cell_pressure_;  // per cell: P_c, x_c, g_c (CellPressure)
  static constexpr std::size_t kTotals = 5;  // TwoPhaseNodes::totals
  Buffer<Real> totals_;   // the cumulative inflows (PorePassParams::totals) and the rain's (TwoPhaseNodes::totals)
  Index n_cells_ = 0;
  std::vector<PorePressureLaw> laws_;
  std::vector<const HydraulicCondition*> node_laws_;
  const Wall* walls_ = nullptr;
  const WallMask* masks_ = nullptr;
  Buffer<WallMask> liquid_masks_;
  std::vector<OpenSurfaceWindow> open_windows_;  // open surfaces (ponding, rain): windows
  std::vector<std::uint32_t> host_open_;         // ... and per node the ones selecting it
  Buffer<std::uint32_t> open_masks_;
  bool has_liquid_walls_ = false;
  std::uint32_t pond_bits_ = 0;  // the open surfaces of the conditions that keep a pond (bits of open_masks_)
  Halo halo_;
};

}  // namespace scree
