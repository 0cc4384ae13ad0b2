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
//       // without the expensive branch, and update() over the others (PassParams::
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

/// Whether M has the optional update_elastic (see the top of this file).
template <class M>
inline constexpr bool material_has_elastic_path() {
  return requires(const typename M::Params& p, typename M::State& s, Sym3& sigma, const StrainIncrement& inc) {
    { M::update_elastic(p, s, sigma, inc) } -> std::same_as<bool>;
  };
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
  const typename M::State& raw_state() const { return s_; }
  const typename M::Params& params() const { return p_; }

 private:
  typename M::Params p_;
  typename M::State s_{};
  std::vector<OutputField> fields_;
  std::string name_ = M::type_name;
};

}  // namespace scree
