// The material interface: what a constitutive model provides to the MPM kernels.
//
// A material is a plain struct M (no virtual functions, nothing allocated) with:
//
//   static constexpr const char* type_name = "linearElastic";   // name in dictionaries
//   struct Params { ... };      // trivially copyable; copied to the GPU once
//   struct State  { ... };      // trivially copyable, only Real / Sym3 members, or empty;
//                               // stored structure-of-arrays, one array per Real
//   static ParamSpec spec();                          // declared parameters (host)
//   static Params read(const ParamReader& r);         // validated input -> Params (host)
//   static Real density(const Params& p);             // initial mass density [kg/m^3]
//   static State initial_state(const Params& p, Sym3& sigma);
//       // host: the state that goes with the initial stress sigma (tension positive);
//       // the model may adjust sigma (e.g. cap tension) and must return a defined state
//   SCREE_HD static void update(const Params& p, State& s, Sym3& sigma,
//                               const StrainIncrement& inc);
//       // the stress update of one step. sigma arrives already rotated objectively
//       // (the framework applies corotate(sigma, inc.spin)); tensor-valued state must be
//       // rotated by the model itself with corotate(x, inc.spin).
//   SCREE_HD static bool update_elastic(const Params& p, State& s, Sym3& sigma,
//                                       const StrainIncrement& inc);          // optional
//       // the model's cheap common case alone (an elastic step of an elastoplastic model):
//       // when it applies, the same result as update() and true; otherwise false with s
//       // and sigma untouched. The GPU kernels then run it over all points in a kernel
//       // without the expensive branch, and update() over the others (PassPolicy::
//       // split_elastic), so the common case runs at a higher occupancy.
//   SCREE_HD static Real wave_speed(const Params& p, const State& s, const Sym3& sigma,
//                                   Real density, Real cell_size);
//       // the largest signal speed c [m/s] for the CFL time step dt = CFL h / c: the
//       // elastic P-wave speed, and for viscous models also the explicit-diffusion limit
//       // dt < rho h^2 / (2 mu_eff) written as a speed, c_visc = 2 mu_eff / (rho h)
//   static void describe(OutputFields<M>& out);       // output fields (host)
//   static constexpr unsigned plane_zero_slots = plane_tensor_slots(offsetof(State, x) / sizeof(Real));
//       // optional: the State's Reals that are zero in 2D (plane strain), here the yz and
//       // xz components of a Sym3 member x; the 2D kernels neither load nor store them
//       // (the framework's own 2D stress keeps 4 components for the same reason)
//   SCREE_HD static Real collisional_dissipation(const Params& p, const State& s,
//                                                const StrainIncrement& inc);  // optional
//       // the energy a rate-dependent (collisional) mechanism dissipated over the step, per
//       // volume [J/m^3], from the state after the update; the energy budget (function object
//       // energies, `budget yes`) sums it as its collisional term. A model whose stored energy
//       // is not all elastic also names an output field elasticEnergy [J/m^3] (describe()).
//   static constexpr bool reads_stress = false;       // optional (default true): update()
//       // builds sigma from the state and never reads the stress it is given; the kernels
//       // then skip loading and co-rotating it
//   static std::string work_bound(const Params& p);   // optional, with update() returning
//       // bool: a model whose update is iterative and bounded (substeps, Newton iterations)
//       // returns true from update() when the update reached that bound, and names the
//       // bound here (e.g. "maxSubsteps 8"); the framework counts those updates per body
//       // and reports them in the run's log (Body::bounded_updates)
//   struct Work { ... };                              // optional, with the three below:
//   SCREE_HD static bool update_begin(const Params& p, const State& s, const Sym3& sigma,
//                                     const StrainIncrement& inc, Work& w);
//   SCREE_HD static bool update_turn(const Params& p, Work& w);
//   SCREE_HD static bool update_end(const Params& p, State& s, Sym3& sigma,
//                                   const StrainIncrement& inc, Work& w);
//       // update() in turns, for a model whose work varies from point to point (substeps):
//       // begin returns whether turns remain, turn does one and returns whether more
//       // remain, end writes the result and returns what update() returns (s is the state
//       // update() was given, unchanged; sigma arrives co-rotated as update()'s). In
//       // sequence they must give update()'s result to the bit (update_in_turns below is
//       // that sequence; test it against update()). The GPU kernel of the points the
//       // elastic-first split defers then gives a lane whose point is done the next one
//       // while the other lanes of its warp still turn (PassPolicy::refill)
//
// The concept Material<M> below states the required part; Registry::add_material<M>()
// checks it with one message per missing piece.
//
// Rules for the device code (update, update_elastic, wave_speed and everything they call,
// which runs inside CUDA kernels as well as on the CPU):
//   * SCREE_HD on every function they call (free functions of the model included); only
//     <cmath> functions (sqrt, exp, pow, fmax, ...), no std:: containers, strings or
//     algorithms, no virtual calls, no function pointers or std::function;
//   * no allocation (new, malloc), no exceptions (throw/try), no recursion, no static or
//     global mutable state, no I/O (printf only in diagnostic builds);
//   * always return a defined state: finite values for any input a kernel may hand over
//     (a zero or NaN strain increment, dt = 0, a stress-free point);
//   * rotation: sigma arrives co-rotated (Hughes-Winget) with inc.spin, but tensor-valued
//     State members do not: rotate them with corotate(x, inc.spin) inside update();
//   * wave_speed() must include every limit of the explicit step: the viscous one
//     c_visc = 2 mu_eff/(rho h) of a rate-dependent model as well as the elastic one.
// Host parts (spec, read, density, initial_state, describe) may use anything; read()
// should derive in advance every parameter-only factor the device code needs (kernels
// get Params only from read()).
//
// Output field names: the tools (scree-element, utilities/plot, utilities/render) look for
// the conventional names, so a material should use them for these quantities:
//   voidRatio, granularTemperature, plasticStrain (equivalent plastic strain),
//   deviatoricStrainRate, frictionalStress (tensor), shearViscosity, collisionalPressure,
//   collisionalDeviatoricStress, collisionalFraction.
//
// Register it in a plugin with `SCREE_PLUGIN(r) { r.add_material<M>(); }`
// (scree/plugin/plugin_api.hpp); that instantiates the particle kernels for M on both
// backends and in 2D and 3D.
//
// Units: SI (Pa, m, s, kg). Sign convention: tension positive (continuum mechanics);
// geomechanics outputs (p, q) are compression positive and say so in their docs.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"
#include "scree/params/spec.hpp"

namespace scree {

/// What a stress update receives for one step at one material point.
struct StrainIncrement {
  Sym3 deps;   ///< strain increment sym(L) dt (tension positive), [-]
  Spin3 spin;  ///< spin increment skew(L) dt, [-]
  Real dt;     ///< time step [s]
  Real J;      ///< volume ratio V/V0 = det F after this increment, [-]
};

/// Whether M's update() reports reaching a bound on its work (see the top of this file).
template <class M>
inline constexpr bool material_reports_bound() {
  return requires(const typename M::Params& p, typename M::State& s, Sym3& sigma, const StrainIncrement& inc) {
    { M::update(p, s, sigma, inc) } -> std::same_as<bool>;
    { M::work_bound(p) } -> std::convertible_to<std::string>;
  };
}

/// Whether M has the optional update_elastic (see the top of this file).
template <class M>
inline constexpr bool material_has_elastic_path() {
  return requires(const typename M::Params& p, typename M::State& s, Sym3& sigma, const StrainIncrement& inc) {
    { M::update_elastic(p, s, sigma, inc) } -> std::same_as<bool>;
  };
}

/// Whether M has the optional update in turns (see the top of this file).
template <class M>
inline constexpr bool material_has_turns() {
  return requires(const typename M::Params& p, typename M::State& s, Sym3& sigma, const StrainIncrement& inc,
                  typename M::Work& w) {
    { M::update_begin(p, s, sigma, inc, w) } -> std::same_as<bool>;
    { M::update_turn(p, w) } -> std::same_as<bool>;
    M::update_end(p, s, sigma, inc, w);
  };
}

/// Whether the elastic-first split's deferred points of M run their updates in turns (M has
/// update_elastic and the update in turns): the points the split's Handoff is for.
template <class M>
inline constexpr bool material_defers_in_turns() {
  return material_has_elastic_path<M>() && material_has_turns<M>();
}

/// A model's update in turns, in sequence: what its update() must equal, bit for bit.
template <class M>
SCREE_HD inline auto update_in_turns(const typename M::Params& p, typename M::State& s, Sym3& sigma,
                                     const StrainIncrement& inc) {
  typename M::Work w;
  if (M::update_begin(p, s, sigma, inc, w))
    while (M::update_turn(p, w)) {
    }
  return M::update_end(p, s, sigma, inc, w);
}

/// Number of Reals in a material's State (0 for an empty State).
template <class S>
inline constexpr int state_size() {
  if constexpr (std::is_empty_v<S>) {
    return 0;
  } else {
    static_assert(sizeof(S) % sizeof(Real) == 0, "State must hold only Real (or Sym3) members");
    static_assert(std::is_trivially_copyable_v<S>, "State must be trivially copyable");
    return static_cast<int>(sizeof(S) / sizeof(Real));
  }
}

/// The bits of the yz and xz components (Voigt 4 and 5) of a Sym3 that starts at Real slot
/// `first` of a State: for a material's plane_zero_slots.
inline constexpr unsigned plane_tensor_slots(std::size_t first) {
  return (1u << (first + 4)) | (1u << (first + 5));
}

/// M::plane_zero_slots when M declares it, else none.
template <class M>
inline constexpr unsigned plane_zero_slots() {
  if constexpr (requires { M::plane_zero_slots; }) return M::plane_zero_slots;
  else return 0u;
}

/// Whether Skip holds slot k (slots past 32 never: plane_zero_slots is 32 bits).
template <unsigned Skip>
SCREE_INLINE constexpr bool skips_slot(int k) {
  return k < 32 && ((Skip >> k) & 1u) != 0;
}

/// Load/store a State from/to structure-of-arrays storage: component k of particle i
/// lives at soa[k * stride + i]. The slots set in Skip are neither read (they load as 0)
/// nor written: the 2D kernels pass the material's plane_zero_slots, so that the
/// components plane strain keeps at zero cost no memory traffic and no registers.
template <class S, unsigned Skip = 0u>
SCREE_INLINE void load_state(S& s, const Real* soa, Index stride, Index i) {
  constexpr int n = state_size<S>();
  static_assert(n <= 32 || Skip == 0u, "plane_zero_slots covers the first 32 Reals of a State");
  if constexpr (n > 0) {
    Real tmp[n];
    for (int k = 0; k < n; ++k) tmp[k] = skips_slot<Skip>(k) ? Real(0) : soa[k * stride + i];
    memcpy(&s, tmp, sizeof(S));
  }
}
template <class S, unsigned Skip = 0u>
SCREE_INLINE void store_state(const S& s, Real* soa, Index stride, Index i) {
  constexpr int n = state_size<S>();
  if constexpr (n > 0) {
    Real tmp[n];
    memcpy(tmp, &s, sizeof(S));
    for (int k = 0; k < n; ++k)
      if (!skips_slot<Skip>(k)) soa[k * stride + i] = tmp[k];
  }
}

/// One output field of a material: a scalar (1 component) or a symmetric tensor
/// (6 components, Voigt order), evaluated on the host from a particle's state and stress.
struct OutputField {
  std::string name;  ///< e.g. "voidRatio", "granularTemperature", "frictionalStress"
  int components;    ///< 1 or 6
  std::string unit;
  std::string doc;
  /// Writes `components` values to out, from (params, state as Reals, total stress).
  std::function<void(const void* params, const Real* state, const Sym3& sigma, Real* out)> eval;
};

/// Names, units and docs of a material's outputs. Conventional names shared by all
/// materials (the element-test driver and plotting scripts look for them):
///   voidRatio, granularTemperature, frictionalStress (tensor), plasticStrain
///   (equivalent plastic strain), shearViscosity, collisionalPressure, ...
template <class M>
class OutputFields {
 public:
  using Params = typename M::Params;
  using State = typename M::State;

  /// A scalar member of State, e.g. out.state("voidRatio", &State::e, "-", "void ratio e").
  void state(std::string name, Real State::*member, std::string unit, std::string doc) {
    const int k = offset_of(member);
    fields_.push_back({std::move(name), 1, std::move(unit), std::move(doc),
                       [k](const void*, const Real* s, const Sym3&, Real* out) { out[0] = s[k]; }});
  }
  /// A symmetric-tensor member of State.
  void state(std::string name, Sym3 State::*member, std::string unit, std::string doc) {
    const int k = offset_of(member);
    fields_.push_back({std::move(name), 6, std::move(unit), std::move(doc),
                       [k](const void*, const Real* s, const Sym3&, Real* out) {
                         for (int c = 0; c < 6; ++c) out[c] = s[k + c];
                       }});
  }
  /// A scalar computed from params, state and total stress.
  void derived(std::string name, std::string unit, std::string doc,
               std::function<Real(const Params&, const State&, const Sym3&)> f) {
    fields_.push_back({std::move(name), 1, std::move(unit), std::move(doc),
                       [f](const void* p, const Real* s, const Sym3& sig, Real* out) {
                         State st{};
                         if constexpr (state_size<State>() > 0) memcpy(&st, s, sizeof(State));
                         out[0] = f(*static_cast<const Params*>(p), st, sig);
                       }});
  }
  /// A symmetric tensor computed from params, state and total stress.
  void derived_tensor(std::string name, std::string unit, std::string doc,
                      std::function<Sym3(const Params&, const State&, const Sym3&)> f) {
    fields_.push_back({std::move(name), 6, std::move(unit), std::move(doc),
                       [f](const void* p, const Real* s, const Sym3& sig, Real* out) {
                         State st{};
                         if constexpr (state_size<State>() > 0) memcpy(&st, s, sizeof(State));
                         const Sym3 t = f(*static_cast<const Params*>(p), st, sig);
                         for (int c = 0; c < 6; ++c) out[c] = t[c];
                       }});
  }
  const std::vector<OutputField>& fields() const { return fields_; }

 private:
  template <class T>
  static int offset_of(T State::*member) {
    State probe{};
    const auto off = reinterpret_cast<const char*>(&(probe.*member)) - reinterpret_cast<const char*>(&probe);
    return static_cast<int>(off / static_cast<std::ptrdiff_t>(sizeof(Real)));
  }
  std::vector<OutputField> fields_;
};

/// The material contract (the top of this file), piece by piece: each concept names one
/// requirement, so that check_material<M>() can say which one M misses. What a concept
/// cannot see is checked by the compiler where the kernels are instantiated: that update()
/// and wave_speed() are SCREE_HD and follow the device-code rules.
namespace material_contract {

template <class M>
concept has_type_name = requires {
  { M::type_name } -> std::convertible_to<const char*>;
};
template <class M>
concept has_params = requires { typename M::Params; } && std::is_trivially_copyable_v<typename M::Params>;
/// Whether S{r_0, ..., r_{n-1}} compiles for n Reals that are not constants: every member
/// takes Reals without narrowing (an int, float or bool member does not), brace elision
/// filling Sym3 members.
template <class S, std::size_t... I>
constexpr bool from_reals(std::index_sequence<I...>) {
  return requires { S{(static_cast<void>(I), std::declval<Real>())...}; };
}
/// State: empty, or trivially copyable, standard layout and made of Reals only (Real and Sym3
/// members: a whole number of Reals, aligned as a Real, each member initialisable from Reals).
template <class S>
constexpr bool state_layout_ok() {
  if constexpr (!std::is_trivially_copyable_v<S> || !std::is_standard_layout_v<S>) return false;
  else if constexpr (std::is_empty_v<S>) return true;
  else if constexpr (sizeof(S) % sizeof(Real) != 0 || alignof(S) != alignof(Real)) return false;
  else return from_reals<S>(std::make_index_sequence<sizeof(S) / sizeof(Real)>{});
}
template <class M>
concept has_state = requires { typename M::State; } && state_layout_ok<typename M::State>();
template <class M>
concept has_spec = requires {
  { M::spec() } -> std::same_as<ParamSpec>;
};
template <class M>
concept has_read = requires(const ParamReader& r) {
  { M::read(r) } -> std::same_as<typename M::Params>;
};
template <class M>
concept has_density = requires(const typename M::Params& p) {
  { M::density(p) } -> std::convertible_to<Real>;
};
template <class M>
concept has_initial_state = requires(const typename M::Params& p, Sym3& sigma) {
  { M::initial_state(p, sigma) } -> std::same_as<typename M::State>;
};
template <class M>
concept has_update =
    requires(const typename M::Params& p, typename M::State& s, Sym3& sigma, const StrainIncrement& inc) {
      M::update(p, s, sigma, inc);  // void, or bool with work_bound (material_reports_bound)
    } && (std::is_void_v<decltype(M::update(std::declval<const typename M::Params&>(),
                                            std::declval<typename M::State&>(), std::declval<Sym3&>(),
                                            std::declval<const StrainIncrement&>()))> ||
          material_reports_bound<M>());
template <class M>
concept has_wave_speed = requires(const typename M::Params& p, const typename M::State& s, const Sym3& sigma, Real x) {
  { M::wave_speed(p, s, sigma, x, x) } -> std::convertible_to<Real>;
};
template <class M>
concept has_describe = requires(OutputFields<M>& out) { M::describe(out); };

}  // namespace material_contract

/// A material: everything the top of this file requires of M (the optional parts aside).
template <class M>
concept Material = material_contract::has_type_name<M> && material_contract::has_params<M> &&
                   material_contract::has_state<M> && material_contract::has_spec<M> &&
                   material_contract::has_read<M> && material_contract::has_density<M> &&
                   material_contract::has_initial_state<M> && material_contract::has_update<M> &&
                   material_contract::has_wave_speed<M> && material_contract::has_describe<M>;

/// Material<M>, with one readable compile-time message per missing piece (the compiler
/// names M in the instantiation context). Registry::add_material<M>() calls it.
template <class M>
constexpr bool check_material() {
  using namespace material_contract;
  static_assert(has_type_name<M>, "material M needs `static constexpr const char* type_name = \"name\";`");
  static_assert(has_params<M>, "material M needs a trivially copyable `struct Params`");
  static_assert(has_state<M>,
                "material M needs `struct State`, empty or trivially copyable with only Real / Sym3 members");
  static_assert(has_spec<M>, "material M needs `static ParamSpec spec()`");
  static_assert(has_read<M>, "material M needs `static Params read(const ParamReader&)`");
  static_assert(has_density<M>, "material M needs `static Real density(const Params&)`");
  static_assert(has_initial_state<M>, "material M needs `static State initial_state(const Params&, Sym3& sigma)`");
  static_assert(has_update<M>, "material M needs `SCREE_HD static void update(const Params&, State&, Sym3& sigma, "
                               "const StrainIncrement&)` (or returning bool, with `static std::string "
                               "work_bound(const Params&)`)");
  static_assert(has_wave_speed<M>, "material M needs `SCREE_HD static Real wave_speed(const Params&, const State&, "
                                   "const Sym3& sigma, Real density, Real cell_size)`");
  static_assert(has_describe<M>, "material M needs `static void describe(OutputFields<M>&)`");
  return Material<M>;
}

/// A material at one point, type-erased, for host-side drivers (the element-test
/// driver, tests). Made by the registry from any registered material.
class SCREE_API PointMaterial {
 public:
  virtual ~PointMaterial();
  virtual const std::string& type_name() const = 0;
  /// Start from the initial stress sigma (tension positive); the model may adjust it.
  virtual void initialise(Sym3& sigma) = 0;
  /// One stress update (sigma is co-rotated with inc.spin first, as in the MPM kernels).
  virtual void update(Sym3& sigma, const StrainIncrement& inc) = 0;
  virtual Real density() const = 0;
  virtual Real wave_speed(const Sym3& sigma, Real cell_size) const = 0;
  /// The material's output fields and their current values.
  virtual const std::vector<OutputField>& output_fields() const = 0;
  virtual void evaluate(const OutputField& f, const Sym3& sigma, Real* out) const = 0;
  /// Raw state (state_size Reals), for tests and checkpointing.
  virtual std::vector<Real> state() const = 0;
  /// Whether the split's deferred points of this model run their updates in turns
  /// (material_defers_in_turns).
  virtual bool updates_in_turns() const = 0;
};

/// The adapter behind PointMaterial for a material struct M.
template <class M>
class PointMaterialOf final : public PointMaterial {
 public:
  explicit PointMaterialOf(const typename M::Params& p) : p_(p) {
    OutputFields<M> out;
    M::describe(out);
    fields_ = out.fields();
  }
  const std::string& type_name() const override { return name_; }
  void initialise(Sym3& sigma) override { s_ = M::initial_state(p_, sigma); }
  void update(Sym3& sigma, const StrainIncrement& inc) override {
    sigma = corotate(sigma, inc.spin);
    M::update(p_, s_, sigma, inc);
  }
  Real density() const override { return M::density(p_); }
  Real wave_speed(const Sym3& sigma, Real cell_size) const override {
    return M::wave_speed(p_, s_, sigma, M::density(p_), cell_size);
  }
  const std::vector<OutputField>& output_fields() const override { return fields_; }
  void evaluate(const OutputField& f, const Sym3& sigma, Real* out) const override {
    const auto raw = state();
    f.eval(&p_, raw.data(), sigma, out);
  }
  std::vector<Real> state() const override {
    std::vector<Real> raw(state_size<typename M::State>());
    if constexpr (state_size<typename M::State>() > 0) memcpy(raw.data(), &s_, sizeof(s_));
    return raw;
  }
  bool updates_in_turns() const override { return material_defers_in_turns<M>(); }
  const typename M::State& raw_state() const { return s_; }
  const typename M::Params& params() const { return p_; }

 private:
  typename M::Params p_;
  typename M::State s_{};
  std::vector<OutputField> fields_;
  std::string name_ = M::type_name;
};

}  // namespace scree
