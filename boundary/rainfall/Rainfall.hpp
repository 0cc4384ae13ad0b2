// rainfall: rain of a given intensity on the surface of two-phase bodies, by the correction
// of both phases' nodal velocities (and so accelerations) after the grid update; the
// supplementary material of the rainfall-infiltration MPM we implement, its eqs. (A)-(E):
//
//   (A) outward unit normal at node I, the direction of its share of the surface
//         a_I = sum_p V_p grad N_I(x_p),  n_I = a_I / |a_I|
//       (grad N_I(x_p) points from the points towards the node: outwards at a surface node;
//       at a node that slip or friction walls hold, in the walls' planes: project_on_walls).
//       The seed's eq. (A) weights the sum with the mixture's density rho_mix (m_s + n S_l
//       rho_l V per point); where the saturation varies along the surface that tilts n_I off
//       the surface of the points, and the flux the correction sets along n_I is not the flux
//       through a_I, which is what the surface takes (SurfaceInflow counts it so): on
//       cases/rainfallSlope the surface took up to 0.3% more than the rain in its first
//       seconds. Along a_I the surface takes exactly the rain where (B) holds;
//   (B) if [n S_l (v~_l - v~_s) - w] . n_I <= 0, the surface would take at least the rain
//       (w: the rain's velocity, intensity x its unit direction; w . n < 0 into the soil):
//       correct, else the soil cannot take the rain, the surface keeps the natural
//       condition of the weak form (zero liquid traction, p_w = 0: ponding);
//   (C) n S_l [(v~_l + dv_l n) - (v~_s + dv_s n)] . n = w . n,
//   (D) M_lm dv_l + M_s dv_s = 0 (the mixture's momentum is unchanged), hence
//         r = (w . n) / (n S_l) - (v~_l - v~_s) . n,
//         dv_l = r M_s / (M_s + M_lm),  dv_s = -r M_lm / (M_s + M_lm);
//   (E) v_l = v~_l + dv_l n, v_s = v~_s + dv_s n (the accelerations (v - v^k) / dt follow).
// n S_l at the node is M_lm / M_l (both mapped from the points, eq. 9 of the paper). The
// velocities v~ are those of the grid update with every force (the paper's temporary
// accelerations leave the external forces out; gravity's share of the normal flux is then
// part of what the correction replaces, the same at convergence of the flux).
//
// The rain offered to the surface nodes and what they do not take of it (the surface ponds,
// or the water runs off) are counted in the case's liquid totals (TwoPhaseNodes::totals):
// the snapshot's liquidRainOffered and liquidRainNotTaken, waterBalance's rain columns.
// Where the surface ponds is seen on the points: a surface node that does not take all the
// rain holds the rate it leaves (LiquidFields::not_taken), and the points in its reach carry
// it as rainNotTaken, with pondingDuration, how long it has lasted (PoreRate).
//
// What the surface does not take stands on it up to `pondingDepth` (as the surface storage
// of a Richards solver, HYDRUS's largest surface pressure head), and the rest runs off
// (liquidRunOff). The pond P_I of a surface node is offered to the soil with the next step's
// rain, w' = w - P_I / (dt rho_l a_I . up) up in (B)-(E), until it has drained, also after
// the rain has stopped (the grid update keeps such a node's surface open); its weight loads
// the surface, p_b = rho_l g d on both phases, d = P_I / (rho_l a_I . up) its depth. Between
// steps the points near the surface carry it (the grid is cleared every step): SurfaceScatter
// returns it to the surface nodes that face up, PoreRate gathers it back, both keeping it
// whole. The points show it as pondDepth, and carry it as pond, whose sum is the water
// standing on the surface: liquidRainNotTaken - liquidRunOff.
//
// Surface nodes are found at every step: nodes with mass that touch an empty cell and a cell
// holding points, or only empty cells (their mass then comes from the GIMP domains of points
// beyond: porous/free_surface.hpp, surface_node), inside the condition's region and time window.
// There the surface is open while it rains (a two-phase body's surface is closed elsewhere,
// porous/grid_update.hpp): p_w = 0, the natural condition, takes in what the soil can take.
//
// The intensity is a function of time (time/function_of_time.hpp): a constant, or a
// hyetograph as a table or a CSV file, evaluated at every step's time on the device.
//
//   rain { type rainfall; box { min (0 1.0); max (0.1 1.2); } intensity 1800; unit mm/h; }
//   rain { type rainfall; face yMax; pondingDepth 0.01;
//          intensity { type csvFile; file "constant/hyetograph.csv"; timeUnit h; unit mm/h;
//                      interpolation step; outOfBounds zero; } }
#pragma once

#include <cmath>
#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/core/constants.hpp"
#include "scree/exec/memory.hpp"
#include "scree/plugin/context.hpp"
#include "scree/porous/free_surface.hpp"
#include "scree/porous/hydraulic_condition.hpp"
#include "scree/porous/liquid_fields.hpp"
#include "scree/time/function_of_time.hpp"

namespace scree::boundary {

/// The correction (A)-(E) at one node (seepage_correction, porous/free_surface.hpp), applied
/// only where (B) holds; returns whether it was applied.
template <int D>
SCREE_HD inline bool rainfall_correction(const Real* grad, Real ms, Real ml, Real mlm, const Real* w, Real* vs,
                                         Real* vl) {
  return seepage_correction<D>(grad, ms, ml, mlm, w, vs, vl, true);
}

namespace detail {
template <int D>
struct RainfallKernel {
  const Index* nodes;
  TimeTable intensity;  // I(t) [m/s]
  Real dir[3];          // the rain's direction, of length len
  Real len;
  Real t_start, t_end;
  Real pond_depth;  // the most water the surface holds [m]; 0: all the surface leaves runs off
  TwoPhaseNodes<D> g;
  SCREE_HD void operator()(Index i) const {
    const Index I = nodes[i];
    const Real t = g.control->t[g.parity];
    const bool raining = t >= t_start && t < t_end;
    const Real P = pond_depth > 0 ? g.liquid.pond[I] : Real(0);  // the pond on the node [kg]
    if (!raining && !(P > 0)) return;
    const Real ms = g.solid.mass[I];
    if (!(ms > g.mass_eps)) return;
    if (!surface_node<D>(g.grid, g.cells, I, g.walls, g.masks ? g.masks[I] : 0u, t, true)) return;
    const Real rate = raining ? intensity(t) : Real(0);
    const Real level = level_share<D>(g.liquid, I, g.up);  // the node's share of the surface seen from above
    Real w[D];
    for (int d = 0; d < D; ++d) w[d] = rate * dir[d] / len;
    // The pond is offered with the rain: P over the step, falling onto the node's level share,
    // w' = w - P / (dt rho_l a_I . up) up, so that rho_l |w' . a_I| dt is the rain's offer
    // plus P. (B)-(E) then hold with w' as with the rain alone: the surface takes all of it
    // where the soil can, else it keeps the natural condition and the pond what it leaves.
    const Real dt = g.control->dt[g.parity];
    Real runoff = 0;
    const Real pond_in = P > 0 && level > 0 ? P : Real(0);
    if (P > 0 && !(level > 0)) runoff = P;  // a surface turned away holds no water
    Real wp[D];
    for (int d = 0; d < D; ++d) wp[d] = w[d] - (pond_in > 0 && dt > 0 ? pond_in / (dt * g.rho_l * level) : Real(0)) * g.up[d];
    Real grad[D], vs[D], vl[D];
    for (int d = 0; d < D; ++d) {
      grad[d] = g.liquid.area[d][I];
      vs[d] = g.solid.velocity_new[d][I];
      vl[d] = g.liquid.velocity_new[d][I];
    }
    if (g.masks && g.masks[I]) project_on_walls<D>(g.walls, g.masks[I], t, grad);  // the walls' planes
    const bool takes_it_all = rainfall_correction<D>(grad, ms, g.liquid.mass[I], g.liquid.mass_mix[I], wp, vs, vl);
    if (takes_it_all) {
      for (int d = 0; d < D; ++d) {
        g.solid.velocity_new[d][I] = vs[d];
        g.liquid.velocity_new[d][I] = vl[d];
      }
    }
    const Share s = share(I, w, vs, vl, pond_in > 0);
    // Where (B) fails the surface ponds: the rain it does not take, per unit horizontal area,
    // is the intensity times the share of what was offered that did not enter (more than the
    // intensity where liquid seeps out). Every node of the rank's grid gets it (the points
    // near a cut read their ghosts' too).
    if (!takes_it_all && s.offered > 0) g.liquid.not_taken[I] = rate * fmax(Real(0), 1 - s.taken / s.offered);
    // What the surface leaves stands on it, up to pond_depth (rho_l pond_depth a_I . up), and
    // the rest runs off; where it takes all, nothing stands (the round-off of taken = P +
    // offered runs off, so that the pond is always [3] - [4] of the totals). A step of no
    // time (on a target time) moves no water: the pond stays.
    const Real left = pond_in + s.offered - s.taken;
    const Real kept = !(dt > 0) ? pond_in
                      : takes_it_all || !(level > 0) ? Real(0)
                                                     : fmin(fmax(left, Real(0)), g.rho_l * pond_depth * level);
    runoff += left - kept;
    if (pond_depth > 0) g.liquid.pond[I] = kept;
    if (g.totals && (s.offered > 0 || P > 0) && g.owned.holds(g.grid, I)) {
      atomic_add(g.totals + 2, s.offered, g.serial);
      atomic_add(g.totals + 3, s.offered - s.taken, g.serial);
      atomic_add(g.totals + 4, runoff, g.serial);
    }
  }

  /// The rain offered to node I in the step [kg] (per metre in 2D), rho_l |w . a_I| dt
  /// (a_I = sum V grad N_I, the node's share of the surface, outwards: w . a_I < 0 where the
  /// rain falls onto it; 0 elsewhere), and what the node takes of it, its inflow
  /// -dt (M_l / V_I) n S_l (v_l - v_s) . a_I: SurfaceInflow's count (porous/grid_update.hpp)
  /// with this step's corrected velocities.
  struct Share {
    Real offered = 0, taken = 0;
  };
  /// With `pond`, what the node takes is counted also where no rain falls onto it.
  SCREE_HD Share share(Index I, const Real* w, const Real* vs, const Real* vl, bool pond) const {
    Real wa = 0, qa = 0;
    const Real ml = g.liquid.mass[I], nS = ml > 0 ? g.liquid.mass_mix[I] / ml : Real(0);
    for (int d = 0; d < D; ++d) {
      wa += w[d] * g.liquid.area[d][I];
      qa += nS * (vl[d] - vs[d]) * g.liquid.area[d][I];
    }
    if (!(wa < 0) && !pond) return {};
    const Real dt = g.control->dt[g.parity], vol = nodal_volume<D>(g.liquid, I, g.drag_per_mass, g.rho_l);
    return {wa < 0 ? -dt * g.rho_l * wa : Real(0), vol > 0 ? -dt * (ml / vol) * qa : Real(0)};
  }
};
}  // namespace detail

class Rainfall final : public BoundaryCondition, public HydraulicCondition {
 public:
  static constexpr const char* type_name = "rainfall";
  static ParamSpec spec() {
    ParamSpec s(type_name,
                "rain on the surface nodes of two-phase bodies inside a region: the seepage into the soil is the "
                "rain's intensity while the soil can take it, else the surface ponds");
    Region::declare(s);
    s.function("intensity", "m/s", "rain intensity, per unit horizontal area (a constant or a hyetograph)")
        .non_negative();
    std::vector<std::string> units;
    for (const auto& [name, factor] : units_of("m/s")) units.push_back(name);
    s.word("unit", "the intensity's unit (a table or file may name its own)").choices(units).default_value("m/s");
    s.vector("direction", "-", "direction in which the rain falls (default: along gravity)").size(-1).optional();
    s.scalar("startTime", "s", "the rain starts").default_value(-kUnbounded);
    s.scalar("endTime", "s", "the rain stops").default_value(kUnbounded);
    s.scalar("pondingDepth", "m",
             "the most water that stands on the surface where it cannot take the rain (a pond, which drains into "
             "the soil as the soil takes it, also after the rain, and loads the surface with its weight); what "
             "exceeds it runs off. 0: all of it runs off")
        .default_value(0.0)
        .non_negative();
    return s;
  }
  Rainfall(const ParamReader& r, const SolverContext& ctx)
      : region_(Region::read(r, ctx)), intensity_(r.function("intensity", 1, ctx.case_dir, {r.word("unit")})) {
    std::vector<Real> dir = r.has("direction") ? r.scalars("direction") : ctx.gravity;
    Real len = 0;
    for (Real c : dir) len += c * c;
    len = std::sqrt(len);
    if (!(len > 0)) {
      if (r.has("direction"))
        throw InputError(r.entry("direction").where(),
                         "direction: the zero vector gives the rain no direction; expected the direction in which "
                         "it falls, e.g. (0 -1) (or leave it out: along gravity)");
      throw InputError(r.dict().where(), "direction: the rain needs a direction (gravity is zero and no direction is given)");
    }
    for (int d = 0; d < ctx.dimension; ++d) dir_[d] = dir[d];
    len_ = len;
    t_start_ = r.scalar("startTime");
    t_end_ = r.scalar("endTime");
    pond_depth_ = r.scalar("pondingDepth");
    hosted_ = select_nodes(NodeLattice::of(ctx), [this](const Real* x) { return region_.contains(x); });
  }
  bool has_hydraulic_law() const override { return true; }
  bool keeps_a_pond() const override { return pond_depth_ > 0; }
  /// Under the rain the surface is open (p_w = 0, the weak form's natural condition): the
  /// soil takes what it can, and (B) clips it to the rain.
  void open_surfaces(std::vector<OpenSurface>& out) const override {
    out.push_back({[this](const Real* x) { return region_.contains(x); }, t_start_, t_end_});
  }
  void apply_hydraulic(const Exec& ex, const TwoPhaseNodes<2>& g) const override { run(ex, g); }
  void apply_hydraulic(const Exec& ex, const TwoPhaseNodes<3>& g) const override { run(ex, g); }

 private:
  template <int D>
  void run(const Exec& ex, const TwoPhaseNodes<D>& g) const {
    if (hosted_.empty()) return;
    if (nodes_.size() != hosted_.size()) {
      nodes_.resize(hosted_.size(), ex.device);
      nodes_.copy_from_host(hosted_);
    }
    detail::RainfallKernel<D> k{nodes_.data(), intensity_.on(ex), {dir_[0], dir_[1], dir_[2]}, len_, t_start_, t_end_,
                                pond_depth_, g};
    parallel_for(ex, static_cast<Index>(hosted_.size()), k);
  }

  Region region_;
  FunctionOfTime intensity_;
  Real dir_[3] = {0, 0, 0}, len_ = 1;
  Real t_start_ = -kUnbounded, t_end_ = kUnbounded;
  Real pond_depth_ = 0;
  std::vector<Index> hosted_;
  mutable Buffer<Index> nodes_;
};

}  // namespace scree::boundary
