// The 3D stress update of a plane-strain increment equals the 2D (plane-strain) update.
//
// A plane-strain history is a 3D history whose velocity gradient has no z row or column. The
// kernels update a point in 2D and in 3D through the same material code (a material works on
// Sym3 whatever the dimension), but the paths around it differ: the 2D kernel builds the strain
// increment and spin from a 2x2 L, writes zz, yz, zx of the increment as constants 0, loads and
// stores only 4 stress components (xx yy zz xy) and skips the material's plane_zero_slots of the
// state (yz and zx of phaseTransition's sigma_f); the 3D kernel keeps everything. This test runs
// the kernels' own stress update (ParticlePass<D>::stress_update, particle_pass.hpp) for D = 2
// and D = 3 on one point, through the same sequence of plane-strain increments, and asserts:
//   * every stored stress component (sigma_zz included: it is integrated, not derived) and every
//     state variable agree to 1e-12 relative to the stress or state scale, and the wave speed
//     too (the CFL step must not depend on the embedding);
//   * in 3D sigma_yz = sigma_zx = 0 and the yz, zx components of tensor-valued state are 0
//     exactly (the plane-strain solution has none: a model producing them would lose them in
//     2D, where they are not stored).
// Tolerance: the two paths are the same operations on the same numbers (det(I + L dt) of the
// 3x3 embedding reduces to the 2x2 one exactly, the spin's yz and zx are exact zeros), so the
// results are expected to be bit-identical on the CPU; 1e-12 relative leaves room for a
// compiler contracting a multiply-add differently in the two instantiations (nvcc does), i.e.
// a few ulps per step over histories of ~1e3 steps, and is still 8 orders below the
// integrator's own tolerance (STOL = 1e-4), so that any modelling difference between the
// embeddings (a 2D-only Lode angle, a derived sigma_zz, a 2x2 spin) would fail it. The
// measured largest difference is printed (0 when bit-identical).
//
// The histories: compression, shearing (with spin) to the critical state, reversal, unloading
// into the stress-free apex, isochoric shear at the apex, recompression from it; for the
// kinetic theory and phaseTransition a rising (fast shear) and decaying (rest) granular
// temperature, and a volumetric pulse. Each material is run both as one full update per step
// (ParticlePass's reference) and as the elastic-first split of the fast kernels
// (update_elastic first, the full update where it declines).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "linearElastic/LinearElastic.hpp"
#include "material_test_util.hpp"
#include "scree/mpm/particle_pass.hpp"

using namespace scree;
using namespace scree::materials;
using namespace scree::materials::mtest;

namespace {

/// One plane-strain step: the in-plane velocity gradient [1/s] and the time step [s].
struct PlaneStep {
  double l00, l01, l10, l11, dt;
};

/// A history: `count` steps of the same velocity gradient, appended.
void add(std::vector<PlaneStep>& h, int count, double l00, double l01, double l10, double l11, double dt) {
  for (int i = 0; i < count; ++i) h.push_back({l00, l01, l10, l11, dt});
}

/// One point's storage for a D-dimensional kernel, with the stress update of that kernel.
template <int D, class M>
struct KernelPoint {
  using Pass = ParticlePass<D, ShapeLinear, M>;
  static constexpr int kState = state_size<typename M::State>();
  static constexpr unsigned kPlane = D == 2 ? plane_zero_slots<M>() : 0u;
  Real F[D * D] = {};
  Real sig[kStressComponents<D>] = {};
  Real vol0 = 1e-3;
  Real mass = 1;
  Real state[kState > 0 ? kState : 1] = {};
  Pass pass{};

  KernelPoint(const typename M::Params& mp, Sym3 sigma0) {
    pass.mp = mp;
    pass.pp.grid.h = 0.05;  // wave_speed's cell size (viscous limit)
    pass.pa.n = 1;
    for (int k = 0; k < D * D; ++k) pass.pa.F[k] = &F[k];
    F[0] = 1;  // J
    for (int c = 0; c < kStressComponents<D>; ++c) pass.pa.sigma[c] = &sig[c];
    pass.pa.volume0 = &vol0;
    pass.pa.mass = &mass;
    pass.pa.state = state;
    const typename M::State s = M::initial_state(mp, sigma0);
    store_state<typename M::State, kPlane>(s, state, 1, 0);
    detail::store_stress<D>(pass.pa.sigma, 0, sigma0);
  }
  /// The kernels' update of one step; returns the signal speed it computed (v_start = 0).
  Real step(const PlaneStep& st, bool elastic_first) {
    Mat<D> L = Mat<D>::zero();
    L(0, 0) = st.l00;
    L(0, 1) = st.l01;
    L(1, 0) = st.l10;
    L(1, 1) = st.l11;
    Real speed = 0;
    FreshStress fresh;
    bool bounded = false;
    if constexpr (material_has_elastic_path<M>()) {
      if (elastic_first && pass.template stress_update<true>(0, L, st.dt, 0, mass, speed, fresh, bounded))
        return speed;
    }
    pass.template stress_update<false>(0, L, st.dt, 0, mass, speed, fresh, bounded);
    return speed;
  }
  Sym3 stress() const { return detail::load_stress<D>(pass.pa.sigma, 0); }
  typename M::State raw_state() const {
    typename M::State s{};
    load_state<typename M::State, kPlane>(s, state, 1, 0);
    return s;
  }
};

template <class M>
std::vector<Real> as_reals(const typename M::State& s) {
  std::vector<Real> r(state_size<typename M::State>());
  if (!r.empty()) std::memcpy(r.data(), &s, sizeof(s));
  return r;
}

struct Agreement {
  double stress = 0, state = 0, speed = 0;  ///< largest relative differences over the history
  double out_of_plane = 0;                  ///< largest |sigma_yz|, |sigma_zx| in 3D [Pa]
  double p_max = 0, q_max = 0, p_min = 1e300;  ///< range covered (to show the path is what it says)
  int steps = 0;
};

/// Run the history in 2D and 3D; compare after every step.
template <class M>
Agreement compare(const typename M::Params& mp, const Sym3& sigma0, const std::vector<PlaneStep>& h,
                  bool elastic_first, unsigned tensor_state_slots = 0) {
  KernelPoint<2, M> p2(mp, sigma0);
  KernelPoint<3, M> p3(mp, sigma0);
  Agreement a;
  for (const PlaneStep& st : h) {
    const Real c2 = p2.step(st, elastic_first), c3 = p3.step(st, elastic_first);
    const Sym3 s2 = p2.stress(), s3 = p3.stress();
    const double scale = std::max({norm(s3), 1e-300});
    for (int c = 0; c < 4; ++c) a.stress = std::max(a.stress, std::fabs(s2[c] - s3[c]) / scale);
    a.out_of_plane = std::max({a.out_of_plane, std::fabs(s3[4]), std::fabs(s3[5])});
    const std::vector<Real> x2 = as_reals<M>(p2.raw_state()), x3 = as_reals<M>(p3.raw_state());
    double xs = 0;
    for (Real v : x3) xs = std::max(xs, std::fabs(v));
    for (std::size_t k = 0; k < x3.size(); ++k) {
      if (k < 32 && ((tensor_state_slots >> k) & 1u)) {  // yz, zx of a tensor state: 0 in 3D too
        a.out_of_plane = std::max(a.out_of_plane, std::fabs(x3[k]));
        continue;
      }
      a.state = std::max(a.state, std::fabs(x2[k] - x3[k]) / std::max(xs, 1e-300));
    }
    a.speed = std::max(a.speed, std::fabs(c2 - c3) / std::max(std::fabs(c3), 1e-300));
    a.p_max = std::max(a.p_max, pressure(s3));
    a.p_min = std::min(a.p_min, pressure(s3));
    a.q_max = std::max(a.q_max, deviatoric_stress(s3));
    ++a.steps;
    if (!finite(s3)) break;
  }
  return a;
}

constexpr double kTol = 1e-12;

void expect_agree(const Agreement& a, const char* what) {
  EXPECT_LE(a.stress, kTol) << what << ": 2D and 3D stresses differ";
  EXPECT_LE(a.state, kTol) << what << ": 2D and 3D states differ";
  EXPECT_LE(a.speed, kTol) << what << ": 2D and 3D wave speeds differ";
  EXPECT_EQ(a.out_of_plane, 0.0) << what << ": out-of-plane shear from a plane-strain history";
  std::printf("%-34s %5d steps: max rel. diff stress %.1e state %.1e speed %.1e; p in [%.3g, %.3g] Pa, q max %.3g Pa\n",
              what, a.steps, a.stress, a.state, a.speed, a.p_min, a.p_max, a.q_max);
}

/// The frictional history (dt = 1e-3 s): compression, shear to the critical state (gamma = 1),
/// reversal, unloading into the apex, shear at the apex, recompression and shear from it.
std::vector<PlaneStep> frictional_history() {
  std::vector<PlaneStep> h;
  const double dt = 1e-3;
  add(h, 50, -0.1, 0, 0, -0.1, dt);       // compression, 1e-4 per step in x and y
  add(h, 1000, 0, 1, 0, 0, dt);           // simple shear (spin included) to gamma = 1: critical state
  add(h, 200, 0, -1, 0, 0, dt);           // reversal: elastic unloading, then plastic in reverse
  add(h, 600, 0.1, 0, 0.05, 0.1, dt);     // volumetric unloading (with a little spin) into the apex
  add(h, 50, 0, 1, 0, 0, dt);             // isochoric shear at the apex: stays stress-free
  add(h, 100, -0.2, 0, 0, -0.2, dt);      // recompression from the apex
  add(h, 300, -0.02, 0.5, -0.3, 0.0, dt); // shear with compression, rotating, a general L
  return h;
}

}  // namespace

TEST(PlaneEmbedding, LinearElasticSameIn2DAnd3D) {
  const double E = 1e7, nu = 0.3;
  const LinearElastic::Params P{E, nu, 1000, E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))};
  std::vector<PlaneStep> h;
  add(h, 100, -0.1, 0, 0, -0.05, 1e-3);
  add(h, 300, 0, 1, 0, 0, 1e-3);        // a finite rotation (spin): Hughes-Winget in both
  add(h, 200, 0.05, -0.3, 0.7, 0.1, 1e-3);
  const Agreement a = compare<LinearElastic>(P, Sym3{{-1e4, -2e4, -1.5e4, 3e3, 0, 0}}, h, false);
  expect_agree(a, "linearElastic");
}

TEST(PlaneEmbedding, SimsandSameIn2DAnd3D) {
  for (const double e0 : {0.70, 0.90}) {  // dense (dilates, peak) and loose (contracts)
    const Simsand::Params P{table1(), 2650, e0};
    for (const bool split : {false, true}) {
      const Agreement a = compare<Simsand>(P, k0_stress(100e3, 0.5), frictional_history(), split);
      const std::string what = std::string("simsand e0 ") + (e0 < 0.8 ? "0.70" : "0.90") + (split ? " split" : " full");
      expect_agree(a, what.c_str());
      EXPECT_EQ(a.p_min, 0.0) << what << ": the history reaches the apex";
      EXPECT_GT(a.q_max, 50e3) << what << ": the history shears";
    }
  }
}

TEST(PlaneEmbedding, KineticTheorySameIn2DAnd3D) {
  const KineticTheory::Params P{table2(), 1 / 0.55 - 1, 1e-6};
  std::vector<PlaneStep> h;
  const double dt = 1e-4;
  add(h, 2000, 0, 20, 0, 0, dt);          // fast simple shear: T rises to its steady value
  add(h, 2000, 0, 0, 0, 0, dt);           // at rest: T decays (Haff)
  add(h, 200, -0.5, 5, -2, 0.3, dt);      // a general L with compression
  add(h, 200, 0.5, 0, 0, 0.5, dt);        // expansion
  add(h, 500, 0, 0, 0, 0, dt);
  const Agreement a = compare<KineticTheory>(P, Sym3::zero(), h, false);
  expect_agree(a, "kineticTheory");
  EXPECT_GT(a.p_max, 100 * a.p_min) << "the shear raised T and the collisional pressure, rest let them decay";
}

TEST(PlaneEmbedding, PhaseTransitionSameIn2DAnd3D) {
  const PhaseTransition::Params P{table3_collapse_f(), table3_collapse_c(), 0.80, 1e-6};
  const unsigned sigf_planes = plane_tensor_slots(offsetof(PhaseTransition::State, sigf) / sizeof(Real));
  std::vector<PlaneStep> h = frictional_history();
  // then a fast shear (T rises, the collisional stress with it) and rest (T decays)
  add(h, 1000, -0.05, 50, 0, 0, 1e-4);
  add(h, 1000, 0, 0, 0, 0, 1e-4);
  add(h, 200, 0.05, 0, 0, 0.05, 1e-3);  // unload again towards the apex
  for (const bool split : {false, true}) {
    const Agreement a = compare<PhaseTransition>(P, k0_stress(20e3, 0.5), h, split, sigf_planes);
    expect_agree(a, split ? "phaseTransition split" : "phaseTransition full");
    EXPECT_LT(a.p_min, 1e-2) << "the history reaches the frictional apex (a few mPa of collisional pressure left)";
  }
}
