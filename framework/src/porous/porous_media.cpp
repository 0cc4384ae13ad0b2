// PorousMedia<D> (porous_media.hpp): compiled as CUDA when the CUDA backend is on, for the
// pore liquid's kernels (porous/two_phase.hpp).
#include "porous_media.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "scree/core/constants.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/params/spec.hpp"

namespace scree {

std::shared_ptr<ParamSpec> two_phase_spec() {
  static const std::shared_ptr<ParamSpec> spec = [] {
    auto s = std::make_shared<ParamSpec>(
        "twoPhase", "the body is a porous solid with a pore liquid (two-phase formulation; its material is the "
                    "skeleton, its density the grains' rho_s, its stress the effective stress)");
    s->scalar("porosity", "-", "initial porosity n0").range(0, 1).open_min().open_max();
    s->scalar("liquidDensity", "kg/m^3", "density of the pore liquid rho_l").default_value(1000.0).positive();
    s->scalar("liquidBulkModulus", "Pa", "bulk modulus of the pore liquid K_l (water: 2.2e9; a smaller value "
                                         "allows a larger time step, the pore pressure's wave is then slower)")
        .default_value(2.2e9)
        .positive();
    s->scalar("viscosity", "Pa s", "dynamic viscosity of the pore liquid mu_l (water at 20 C: 1.0e-3)")
        .default_value(1.0e-3)
        .positive();
    s->scalar("intrinsicPermeability", "m^2", "intrinsic permeability kappa (give this or hydraulicConductivity)")
        .positive()
        .optional();
    s->scalar("hydraulicConductivity", "m/s",
              "saturated hydraulic conductivity K_sat = kappa rho_l |g| / mu_l (give this or intrinsicPermeability)")
        .positive()
        .optional();
    s->dict("retention", "retention curve { type vanGenuchten; ... } (default: saturated, S_l = 1)").optional();
    s->dict("permeability", "relative permeability { type mualemVanGenuchten; ... } (default: k_rel = 1)")
        .optional();
    auto init = std::make_shared<ParamSpec>("initialPorePressure", "initial pore pressure");
    init->word("type", "uniform: `value`; hydrostatic: p_w = rho_l |g| (waterTable - z), suction above it")
        .choices({"uniform", "hydrostatic"});
    init->scalar("value", "Pa", "uniform pore pressure (compression positive)").default_value(0.0);
    init->scalar("waterTable", "m", "elevation of the water table along -g (hydrostatic)").default_value(0.0);
    s->dict("initialPorePressure", "initial pore pressure (default: uniform 0)").sub_spec(init).optional();
    s->check([](const Dictionary& d, std::vector<InputError>& errors) {
      const bool k = d.has("intrinsicPermeability"), K = d.has("hydraulicConductivity");
      if (k == K)
        errors.emplace_back(d.where(), std::string("twoPhase: give exactly one of intrinsicPermeability [m^2] and "
                                                   "hydraulicConductivity [m/s]") +
                                           (k ? " (both are given)" : " (neither is given)"));
    });
    return s;
  }();
  return spec;
}

const std::vector<FieldInfo>& two_phase_fields() {
  static const std::vector<FieldInfo> fields{
      {"porePressure", 1, "Pa", "pore-liquid pressure p_w, compression positive (negative: suction)"},
      {"saturation", 1, "-", "degree of liquid saturation S_l"},
      {"porosity", 1, "-", "porosity n = 1 - (1 - n0) / det F"},
      {"suction", 1, "Pa", "suction s = -p_w where p_w < 0, else 0"},
      {"liquidVelocity", 3, "m/s", "velocity of the pore liquid v_l"},
      {"seepageVelocity", 3, "m/s", "Darcy flux, the seepage velocity w = n S_l (v_l - v_s)"},
      {"rainNotTaken", 1, "m/s",
       "rain the surface does not take (it ponds or runs off), with any liquid seeping out there, per unit "
       "horizontal area: the most at the surface nodes in the point's reach; 0 where the surface takes all the rain "
       "or none falls"},
      {"pondingDuration", 1, "s",
       "how long the surface in the point's reach has not taken all the rain, without a break (0: it takes it all); "
       "the ponding began at the time less this"},
      {"pond", 1, "kg",
       "ponded water the point carries for the surface nodes in its reach between steps (per metre in 2D): its sum "
       "over the points is the water standing on the surface (rainfall's pondingDepth)"},
      {"pondDepth", 1, "m",
       "depth of the water standing on the surface, the most at the surface nodes in the point's reach (0: no pond)"}};
  return fields;
}

namespace {

/// A two-phase body's initial pore liquid against the elevation z [m] along -g (the
/// coordinate along the vertical axis): the pore pressure p_w(z) [Pa, compression positive]
/// of `initialPorePressure`, uniform or hydrostatic p_w = rho_l |g| (waterTable - z), and
/// its saturation S_l(p_w) from the retention curve's table, as the kernels take it (the
/// first step re-evaluates every point's S_l, and with the retention curve itself here,
/// 1e-5 from the table, that re-evaluation changed the stored liquid without any flow).
struct InitialLiquid {
  Real n0 = 0, rho_l = 0, g = 0;
  bool hydrostatic = false;
  Real table = 0, value = 0;
  BodyHydraulics models;
  std::unique_ptr<HydraulicTableStorage> curve;  // on the host

  InitialLiquid(const Dictionary& tp, const HydraulicModelFactory& factory, Real gravity) : g(gravity) {
    const ParamReader r(*two_phase_spec(), tp);
    n0 = r.scalar("porosity");
    rho_l = r.scalar("liquidDensity");
    if (tp.has("initialPorePressure")) {
      const ParamReader ir(*two_phase_spec()->find("initialPorePressure")->sub(), tp.at("initialPorePressure").dict());
      hydrostatic = ir.word("type") == "hydrostatic";
      table = ir.scalar("waterTable");
      value = ir.scalar("value");
    }
    models = read_hydraulics(tp, factory);
    curve = std::make_unique<HydraulicTableStorage>(models.retention.get(), models.permeability.get(), Device::cpu);
  }
  Real pressure(Real z) const { return hydrostatic ? rho_l * g * (table - z) : value; }
  Real saturation(Real p) const { return curve->table().saturation(p); }
  /// The mixture's density rho_mix = (1 - n0) rho_s + n0 S_l rho_l [kg/m^3] at z.
  Real mixture(Real rho_s, Real z) const { return (1 - n0) * rho_s + n0 * saturation(pressure(z)) * rho_l; }
};

}  // namespace

template <int D>
PorousMedia<D>::PorousMedia(HydraulicModelFactory models, const GridGeometry<D>& grid, const Exec& exec,
                            const Vec<D>& gravity, ShapeKind shape, Real gimp_half_length)
    : models_(std::move(models)), grid_(grid), exec_(exec), gravity_(gravity), shape_(shape), gimp_half_length_(gimp_half_length) {
  Real gmax = -1;
  for (int d = 0; d < D; ++d)
    if (std::fabs(gravity[d]) > gmax) {
      gmax = std::fabs(gravity[d]);
      vertical_ = d;
    }
  const Real g = norm(gravity);
  for (int d = 0; d < D; ++d) up_[d] = g > 0 ? -gravity[d] / g : Real(0);
  set_grid(grid);
  // Inflow through the surfaces, added by prescribed pore pressures, rain offered, rain not
  // taken, the ponded water that ran off.
  totals_.resize(kTotals, exec_.device);
  totals_.copy_from_host(std::vector<Real>(kTotals, Real(0)));
}

template <int D>
PorousMedia<D>::~PorousMedia() = default;

template <int D>
void PorousMedia<D>::set_grid(const GridGeometry<D>& grid) {
  grid_ = grid;
  const Index nn = grid_.num_nodes();
  n_cells_ = nn;  // cell (i, j) indexed as node (i, j): the last row of cells is unused
  for (int s = 0; s < 2; ++s) {  // resize: zeroed
    liquid_data_[s].resize(static_cast<std::size_t>(nn) * kLiquidFieldCount<D>, exec_.device);
    Real* b = liquid_data_[s].data();
    int k = 0;
    auto next = [&] { return b + static_cast<std::size_t>(k++) * nn; };
    LiquidFields<D>& f = sets_[s];
    f.mass = next();
    f.mass_mix = next();
    f.drag = next();
    f.conductance = next();
    for (int d = 0; d < D; ++d) f.momentum[d] = next();
    for (int d = 0; d < D; ++d) f.force[d] = next();
    for (int d = 0; d < D; ++d) f.velocity_new[d] = next();
    for (int d = 0; d < D; ++d) f.area[d] = next();
    f.pressure = next();
    f.volume = next();
    f.not_taken = next();
    f.pond = next();
    cells_[s].resize(static_cast<std::size_t>(nn), exec_.device);
  }
  surface_.resize(static_cast<std::size_t>(nn), exec_.device);
  // Per cell: inflow, capacity, and the moments sum V C p, sum V C x_d (PoreRate).
  balance_.resize(static_cast<std::size_t>((3 + D) * nn), exec_.device);
  // Per cell: the reconstructed pressure P_c, x_c and g_c per axis (CellPressure).
  cell_pressure_.resize(static_cast<std::size_t>((1 + 2 * D) * nn), exec_.device);
}

template <int D>
void PorousMedia<D>::clear_conditions() {
  laws_.clear();
  node_laws_.clear();
  open_windows_.clear();
  host_open_.clear();
  open_masks_.resize(0, exec_.device);
  pond_bits_ = 0;
}

template <int D>
std::vector<Real> PorousMedia<D>::totals() const {
  mem::synchronize(exec_.device);
  return totals_.to_host();
}


template <int D>
std::function<Real(Real)> PorousMedia<D>::mixture_density(const Dictionary& body, Real grain_density) const {
  const Entry* e = body.find("twoPhase");
  if (!e) return {};
  const Real g = norm(gravity_);
  auto liquid = std::make_shared<const InitialLiquid>(e->dict(), models_, g);
  // The profile takes the elevation along -g; the pore pressure, the coordinate along the
  // vertical axis (as prepare() evaluates it at the points): the same up to the axis' sign.
  const Real up = g > 0 ? -gravity_[vertical_] / g : Real(1);
  return [liquid, grain_density, up](Real elevation) { return liquid->mixture(grain_density, elevation * up); };
}

template <int D>
bool PorousMedia<D>::prepare(const Dictionary& body, BodySetup<D>& s, Real grain_density) {
  const Entry* e = body.find("twoPhase");
  if (!e) return false;
  const Dictionary& tp = e->dict();
  const ParamReader r(*two_phase_spec(), tp);
  PorousBody b;
  b.grain_density = grain_density;
  PoreParams& P = b.params;
  P.n0 = r.scalar("porosity");
  P.rho_l = r.scalar("liquidDensity");
  P.bulk_l = r.scalar("liquidBulkModulus");
  P.viscosity = r.scalar("viscosity");
  const Real g = norm(gravity_);
  if (r.has("intrinsicPermeability")) {
    P.kappa = r.scalar("intrinsicPermeability");
  } else {
    if (!(g > 0))
      throw InputError(tp.at("hydraulicConductivity").where(),
                       "hydraulicConductivity: needs gravity (constant/g) to convert to an intrinsic permeability; "
                       "give intrinsicPermeability instead");
    P.kappa = r.scalar("hydraulicConductivity") * P.viscosity / (P.rho_l * g);
  }
  BodyHydraulics h = read_hydraulics(tp, models_);
  b.retention = std::move(h.retention);
  b.permeability = std::move(h.permeability);
  b.table = std::make_unique<HydraulicTableStorage>(b.retention.get(), b.permeability.get(), exec_.device);
  P.table = b.table->table();

  // The initial pore pressure per point, and its saturation.
  const std::size_t n = s.x.size();
  std::vector<Real> pw(n, 0), sat(n), por(n, P.n0), suction(n);
  const InitialLiquid liquid(tp, models_, g);
  for (std::size_t p = 0; p < n; ++p) {
    pw[p] = liquid.pressure(s.x[p][vertical_]);
    sat[p] = liquid.saturation(pw[p]);
    suction[p] = pw[p] < 0 ? -pw[p] : 0;
  }

  // The effective initial stress. A geostatic body's stress is the total stress of its
  // overburden (case/overburden.hpp), which integrates the mixture's density of every
  // two-phase body above (mixture_density) and the density of every single-phase one. The
  // effective stress is sigma' = sigma + S_l p_w I (Bishop, chi = S_l; tension positive,
  // p_w compression positive), with K0 acting on the effective stresses:
  //   sigma'_v = sigma_v + S_l p_w,  sigma'_h = K0 sigma'_v.
  if (const Entry* is = body.find("initialStress"); is && is->dict().get_word("type") == "geostatic" && g > 0) {
    const Real K0 = is->dict().has("K0") ? is->dict().get_scalar("K0") : Real(0.5);
    for (std::size_t p = 0; p < n; ++p) {
      const Real sv_eff = s.sigma[p][vertical_] + sat[p] * pw[p], sh_eff = K0 * sv_eff;
      Sym3 sig{{sh_eff, sh_eff, sh_eff, 0, 0, 0}};
      sig[vertical_] = sv_eff;
      s.sigma[p] = sig;
    }
  } else {
    // Any other initial stress is the effective stress as given.
  }
  s.mass_factor = 1 - P.n0;
  using Col = typename BodySetup<D>::ExtraColumn;
  s.extra.clear();
  // The columns in the order of two_phase_fields(), whose names, units and meaning they take.
  // The liquid moves with the skeleton at t = 0 (a body thrown with a `velocity` carries its
  // water): no seepage. A liquid at rest in a moving skeleton would be a Darcy flux n |v|.
  std::vector<Real> vl(n * D);
  for (std::size_t p = 0; p < n; ++p)
    for (int d = 0; d < D; ++d) vl[p * D + static_cast<std::size_t>(d)] = p < s.v.size() ? s.v[p][d] : Real(0);
  const std::vector<Real>* initial[] = {&pw, &sat, &por, &suction, &vl, nullptr, nullptr, nullptr, nullptr, nullptr};
  static_assert(sizeof(initial) / sizeof(initial[0]) == kPoreColumns<D> - 2 * (D - 1),
                "one initial column (or none) per field of two_phase_fields()");
  for (std::size_t k = 0; k < two_phase_fields().size(); ++k) {
    const FieldInfo& f = two_phase_fields()[k];
    s.extra.push_back(Col{f.name, f.unit, f.doc, f.components == 1 ? 1 : D, 0,
                          initial[k] ? *initial[k] : std::vector<Real>{}, true});
  }
  pending_.push_back(std::move(b));
  return true;
}

template <int D>
void PorousMedia<D>::attach(Body<D>* body) {
  if (pending_.empty()) throw std::logic_error("PorousMedia::attach without prepare");
  PorousBody b = std::move(pending_.front());
  pending_.erase(pending_.begin());
  b.body = body;
  bodies_.push_back(std::move(b));
  // PorePassParams::drag_per_mass: mu_l / (kappa rho_l) when every body has the same rho_l
  // and mu_l / kappa (compared exactly), else 0.
  const PoreParams& p0 = bodies_.front().params;
  drag_per_mass_ = p0.viscosity / (p0.kappa * p0.rho_l);
  for (const PorousBody& o : bodies_)
    if (o.params.rho_l != p0.rho_l || o.params.viscosity / o.params.kappa != p0.viscosity / p0.kappa)
      drag_per_mass_ = 0;
}

template <int D>
void PorousMedia<D>::finish_columns(int gather_set, int scatter_set) {
  for (const PorousBody& b : bodies_)
    parallel_for(exec_, b.body->arrays().n, PoreColumns<D>{pass_params(b, gather_set, scatter_set), b.body->arrays()});
}

template <int D>
bool PorousMedia<D>::holds(const Body<D>* body) const {
  for (const PorousBody& b : bodies_)
    if (b.body == body) return true;
  return false;
}

template <int D>
void PorousMedia<D>::add_condition(const HydraulicCondition* hc) {
  std::vector<PorePressureLaw> laws;
  hc->constrain_pores(laws);
  for (const PorePressureLaw& l : laws) laws_.push_back(l);
  if (static_cast<int>(laws_.size()) > kMaxPorePressureLaws)
    throw std::runtime_error("too many pore-pressure conditions (at most " + std::to_string(kMaxPorePressureLaws) +
                             " per case)");
  if (hc->has_hydraulic_law()) node_laws_.push_back(hc);
  std::vector<OpenSurface> open;
  hc->open_surfaces(open);
  for (const OpenSurface& o : open) {
    const int bit = static_cast<int>(open_windows_.size());
    if (bit >= kMaxOpenSurfaces)
      throw std::runtime_error("too many open surfaces (ponding, rainfall: at most " +
                               std::to_string(kMaxOpenSurfaces) + " per case)");
    open_windows_.push_back(OpenSurfaceWindow{o.t_start, o.t_end, o.outflow_only ? 1 : 0});
    if (hc->keeps_a_pond()) pond_bits_ |= std::uint32_t(1) << bit;
    if (host_open_.empty()) host_open_.assign(static_cast<std::size_t>(grid_.num_nodes()), 0u);
    for (Index I = 0; I < grid_.num_nodes(); ++I) {
      const Vec<D> x = grid_.node_position(I);
      Real xs[3] = {0, 0, 0};
      for (int d = 0; d < D; ++d) xs[d] = x[d];
      if (o.select(xs)) host_open_[static_cast<std::size_t>(I)] |= std::uint32_t(1) << bit;
    }
    open_masks_.resize(host_open_.size(), exec_.device);
    open_masks_.copy_from_host(host_open_);
  }
}

template <int D>
void PorousMedia<D>::set_walls(const Wall* walls, const WallMask* masks, const std::vector<Wall>& table,
                               const std::vector<WallMask>& host_masks) {
  walls_ = walls;
  masks_ = masks;
  if (!walls) return;
  WallMask drained = 0;
  for (std::size_t i = 0; i < table.size(); ++i)
    if (table[i].drained) drained |= WallMask(1) << i;
  std::vector<WallMask> lm(host_masks.size());
  for (std::size_t i = 0; i < lm.size(); ++i) lm[i] = host_masks[i] & ~drained;
  liquid_masks_.resize(lm.size(), exec_.device);
  liquid_masks_.copy_from_host(lm);
  has_liquid_walls_ = true;
}

template <int D>
PorePassParams<D> PorousMedia<D>::pass_params(const PorousBody& b, int gather_set, int scatter_set) const {
  PorePassParams<D> lp;
  lp.pore = b.params;
  lp.gather = sets_[gather_set];
  lp.scatter = sets_[scatter_set];
  lp.cells = const_cast<Real*>(cells_[scatter_set].data());
  lp.surface = const_cast<std::uint8_t*>(surface_.data());
  lp.extra = b.body->extra_columns();
  lp.n_laws = static_cast<int>(laws_.size());
  for (int i = 0; i < lp.n_laws; ++i) lp.laws[i] = laws_[i];
  lp.vertical = vertical_;
  lp.g = norm(gravity_);
  const Index nn = grid_.num_nodes();
  lp.inflow = const_cast<Real*>(balance_.data());
  lp.capacity = lp.inflow + nn;
  lp.moments = lp.inflow + 2 * nn;
  lp.cell_pressure = const_cast<Real*>(cell_pressure_.data());
  lp.drag_per_mass = drag_per_mass_;
  lp.n_cells = nn;
  lp.totals = const_cast<Real*>(totals_.data());
  lp.ponds = pond_bits_ != 0;
  lp.open_masks = open_masks_.size() ? open_masks_.data() : nullptr;
  lp.pond_bits = pond_bits_;
  for (int d = 0; d < D; ++d) lp.up[d] = up_[d];
  return lp;
}

template <int D>
void PorousMedia<D>::gather(const PassParams<D>& pp, int gather_set, int scatter_set) {
  // Every body's rates into the cells first (PoreRate), the cells' pressures (CellPressure),
  // then every body's points' pressures (PorePressure).
  const Real inv_h = 1 / grid_.h;
  auto go = [&](const auto& sh) {
    using Shape = std::decay_t<decltype(sh)>;
    for (const PorousBody& b : bodies_)
      parallel_for(exec_, b.body->arrays().n, PoreRate<D, Shape>{{pp, pass_params(b, gather_set, scatter_set),
                                                                 b.body->arrays(), sh}});
    if (halo_.sum) {  // the cells' sums from the points of every rank (CellPressure reads a cell's neighbours)
      HaloFields f;
      for (int k = 0; k < 3 + D; ++k) f.add(balance_.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(n_cells_));
      halo_.sum(f);
    }
    if (!bodies_.empty()) {
      const PorePassParams<D> lp = pass_params(bodies_.front(), gather_set, scatter_set);
      parallel_for(exec_, n_cells_,
                   CellPressure<D>{grid_, lp.inflow, lp.capacity, lp.moments, lp.cell_pressure, n_cells_, pp.control,
                                   pp.gather_parity});
    }
    for (const PorousBody& b : bodies_)
      parallel_for(exec_, b.body->arrays().n, PorePressure<D, Shape>{{pp, pass_params(b, gather_set, scatter_set),
                                                                     b.body->arrays(), sh}});
  };
  switch (shape_) {
    case ShapeKind::linear: go(ShapeLinear{inv_h}); break;
    case ShapeKind::gimp: go(ShapeGimp{inv_h, gimp_half_length_}); break;
    case ShapeKind::bspline2: go(ShapeBspline2{inv_h}); break;
  }
}

template <int D>
HaloFields PorousMedia<D>::mixture_fields(const GridFields<D>& solid, int set) const {
  // What MixtureScatter adds (and the solid passes of single-phase bodies before it).
  HaloFields f;
  const LiquidFields<D>& l = sets_[set];
  f.add(solid.mass);
  for (int d = 0; d < D; ++d) f.add(solid.momentum[d]);
  for (int d = 0; d < D; ++d) f.add(solid.force[d]);
  f.add(l.mass);
  f.add(l.mass_mix);
  f.add(l.conductance);
  if (!(drag_per_mass_ > 0)) {
    f.add(l.drag);
    f.add(l.volume);
  }
  for (int d = 0; d < D; ++d) f.add(l.momentum[d]);
  for (int d = 0; d < D; ++d) f.add(l.force[d]);
  for (int d = 0; d < D; ++d) f.add(l.area[d]);
  f.add(const_cast<Real*>(cells_[set].data()));
  return f;
}

template <int D>
HaloFields PorousMedia<D>::surface_fields(int set) const {
  // What SurfaceScatter adds at the surface nodes.
  HaloFields f;
  const LiquidFields<D>& l = sets_[set];
  f.add(l.pressure);
  return f;
}

template <int D>
void PorousMedia<D>::scatter(const PassParams<D>& pp, int gather_set, int scatter_set) {
  // Every body's P2G of both phases and points per cell first (MixtureScatter), then the
  // surface nodes they make, then every body's surface-only fields (SurfaceScatter).
  const Real inv_h = 1 / grid_.h;
  auto go = [&](const auto& sh) {
    using Shape = std::decay_t<decltype(sh)>;
    for (const PorousBody& b : bodies_)
      parallel_for_warps(exec_, b.body->arrays().n,
                         MixtureScatter<D, Shape>{{pp, pass_params(b, gather_set, scatter_set), b.body->arrays(), sh}});
    if (halo_.sum) halo_.sum(mixture_fields(pp.scatter, scatter_set));
    parallel_for(exec_, grid_.num_nodes(),
                 SurfaceMask<D>{grid_, cells_[scatter_set].data(), pp.scatter.mass, sets_[scatter_set].mass,
                                surface_.data()});
    for (const PorousBody& b : bodies_)
      parallel_for_warps(exec_, b.body->arrays().n, SurfaceScatter<D, Shape>{{pp, pass_params(b, gather_set, scatter_set),
                                                                             b.body->arrays(), sh}});
    if (halo_.sum) halo_.sum(surface_fields(scatter_set));
    if (halo_.sum && pond_bits_) {  // the pond's nodal sums (cleared by the grid update, after PoreRate read them)
      HaloFields f;
      f.add(sets_[scatter_set].pond);
      halo_.sum(f);
    }
  };
  switch (shape_) {
    case ShapeKind::linear: go(ShapeLinear{inv_h}); break;
    case ShapeKind::gimp: go(ShapeGimp{inv_h, gimp_half_length_}); break;
    case ShapeKind::bspline2: go(ShapeBspline2{inv_h}); break;
  }
}

template <int D>
void PorousMedia<D>::grid_update(int set, StepControl* control, int parity, Real mass_eps, Real damping,
                                 Real damping_start, Real damping_end, const GridFields<D>* solid_sets) {
  TwoPhaseGridUpdate<D> u;
  u.grid = grid_;
  u.solid = solid_sets[set];
  u.solid_other = solid_sets[1 - set];
  u.liquid = sets_[set];
  u.liquid_other = sets_[1 - set];
  u.cells_other = cells_[1 - set].data();
  u.inflow = balance_.data();
  u.capacity = balance_.data() + grid_.num_nodes();
  u.moments = balance_.data() + 2 * grid_.num_nodes();
  u.n_cells = n_cells_;
  u.control = control;
  u.parity = parity;
  u.walls = walls_;
  u.masks = masks_;
  u.liquid_masks = has_liquid_walls_ ? liquid_masks_.data() : nullptr;
  u.cells = cells_[set].data();
  u.surface = surface_.data();
  u.open_masks = open_masks_.size() ? open_masks_.data() : nullptr;
  for (std::size_t i = 0; i < open_windows_.size(); ++i) u.open[i] = open_windows_[i];
  u.mass_eps = mass_eps;
  u.damping = damping;
  u.damping_start = damping_start;
  u.damping_end = damping_end;
  u.drag_per_mass = drag_per_mass_;
  u.rho_l = bodies_.empty() ? Real(0) : bodies_.front().params.rho_l;
  u.ponds = pond_bits_ != 0;
  u.g = norm(gravity_);
  for (int d = 0; d < D; ++d) u.up[d] = up_[d];
  parallel_for(exec_, grid_.num_nodes(), u);
  TwoPhaseNodes<D> g;
  g.grid = grid_;
  g.solid = solid_sets[set];
  g.liquid = sets_[set];
  g.cells = cells_[set].data();
  g.walls = walls_;
  g.masks = masks_;
  g.control = control;
  g.parity = parity;
  g.mass_eps = mass_eps;
  g.totals = totals_.data();
  g.owned = halo_.owned;
  g.serial = exec_.device == Device::cpu && exec_.threads == 1;
  g.drag_per_mass = u.drag_per_mass;
  g.rho_l = u.rho_l;
  for (int d = 0; d < D; ++d) g.up[d] = up_[d];
  for (const HydraulicCondition* hc : node_laws_) hc->apply_hydraulic(exec_, g);
  SurfaceInflow<D> f;
  f.grid = grid_;
  f.solid = solid_sets[set];
  f.liquid = sets_[set];
  f.surface = surface_.data();
  f.control = control;
  f.parity = parity;
  f.totals = totals_.data();
  f.owned = halo_.owned;
  f.serial = exec_.device == Device::cpu && exec_.threads == 1;
  f.drag_per_mass = u.drag_per_mass;
  f.rho_l = u.rho_l;
  parallel_for(exec_, grid_.num_nodes(), f);
  // SurfaceInflow cleared the surface's sums where this rank's SurfaceMask selected a node;
  // on a shared node next to the edge of this rank's grid (where the cells beyond are
  // missing) a neighbour's mask may have selected it when this rank's did not.
  if (halo_.clear) halo_.clear(surface_fields(set));
}

template <int D>
void PorousMedia<D>::scalars(const Body<D>* body, const std::vector<Real>& t,
                             std::vector<BodySnapshot::Scalar>& out) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].body != body) continue;
    const PoreParams& P = bodies_[i].params;
    out.push_back({"liquidDensity", "kg/m^3", "the pore liquid's density rho_l", P.rho_l});
    out.push_back({"liquidBulkModulus", "Pa", "the pore liquid's bulk modulus K_l", P.bulk_l});
    if (i != 0) return;  // the case's liquid totals go with its first two-phase body
    const char* per = D == 2 ? " (per metre of thickness), all two-phase bodies of the case" : ", all two-phase bodies";
    out.push_back({"liquidInflowSurface", "kg",
                   std::string("the pore liquid's net mass that entered through the surfaces since t = 0") + per, t[0]});
    out.push_back({"liquidInflowPrescribed", "kg",
                   std::string("the pore liquid's net mass that prescribed pore pressures added since t = 0") + per,
                   t[1]});
    out.push_back({"liquidRainOffered", "kg",
                   std::string("the rain that fell onto the surface under rainfall conditions since t = 0") + per,
                   t[2]});
    out.push_back({"liquidRainNotTaken", "kg",
                   std::string("of the rain offered, what the surface did not take (ponded or run off) since t = 0, "
                               "less what it took of the pond") +
                       per,
                   t[3]});
    out.push_back({"liquidRunOff", "kg",
                   std::string("of the water left on the surface, what ran off since t = 0 (beyond the pond's depth, "
                               "or where the surface it stood on went away): liquidRainNotTaken less the pond") +
                       per,
                   t[4]});
    return;
  }
}

template <int D>
Real PorousMedia<D>::max_signal_speed() const {
  Real c = 0;
  for (const PorousBody& b : bodies_) {
    // Saturated and undrained, at the initial porosity: c^2 = K_l / (n0 rho_mix).
    const Real rho_mix = (1 - b.params.n0) * b.grain_density + b.params.n0 * b.params.rho_l;
    c = std::max(c, std::sqrt(b.params.bulk_l / (b.params.n0 * rho_mix)));
  }
  return c;
}

template <int D>
void PorousMedia<D>::restore_state(const std::vector<Real>& s) {
  // A checkpoint of fewer totals (the two inflows alone, or without the run-off) restores with
  // the others at zero.
  if (s.size() > totals_.size() || s.size() < 2)
    throw std::invalid_argument("the pore liquid's state has " + std::to_string(s.size()) + " values, not " +
                                std::to_string(totals_.size()));
  std::vector<Real> t(totals_.size(), Real(0));
  std::copy(s.begin(), s.end(), t.begin());
  totals_.copy_from_host(t);
}

template class PorousMedia<2>;
template class PorousMedia<3>;

}  // namespace scree
