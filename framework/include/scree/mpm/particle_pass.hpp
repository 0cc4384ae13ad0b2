// The particle kernel of the explicit MPM (Feng et al. 2025, section 2.2, eqs. 5-11), written once
// for both backends and templated on dimension, shape function and material.
//
// One pass over a body's particles does any combination of these phases (flags), so that
// each update scheme is a short sequence of passes and grid updates (Solver::step, solver/solver.cpp):
//
//   gather (from grid set G, weights at the particle's current position x_p):
//     kStressFromNew / kStressFromVelocity: velocity gradient L_p = sum_I v_I (x) grad N_Ip
//        (eq. 7) from G.velocity_new or G.velocity; F_p <- (I + L_p dt) F_p (eq. 8);
//        V_p = det(F_p) V0_p; stress update through the material with the strain
//        increment sym(L_p) dt and the spin skew(L_p) dt: objective, where the paper's eq. 9
//        (the small-strain measure of F) is not under the large rotations of a flow
//     kGatherVelocity: particle velocity from the grid: FLIP (eq. 10)
//        v_p <- v_p + sum N (v_I^{k+1} - p_I/m_I), blended with PIC v_p <- sum N v_I^{k+1}
//        by pic_fraction; or APIC (Jiang et al. 2015): v_p <- sum N v^{k+1}, C_p affine.
//        (p_I/m_I is v_I^k before the boundary conditions: see the gather loop.)
//     kGatherPosition: x_p <- x_p + dt sum N v_I^{k+1} (eq. 11)
//   scatter (into grid set S, weights at the updated position):
//     kScatterMassMomentum: m_I += N m_p (eq. 5), p_I += N m_p (v_p + C_p (x_I - x_p)) (eq. 6)
//     kScatterForce: f_I += -V_p sigma_p grad N_Ip + N_Ip m_p g (internal + gravity)
//     kScatterMomentum: S.force_I += N m_p v_p (MUSL's re-mapping of the updated
//        velocities, accumulated in the force array, which is free after the integration,
//        so that the momentum p_I stays available to the FLIP increment)
//
// Sign convention: stress tension positive. Units: SI.
#pragma once

#include <limits>

#include "scree/core/config.hpp"
#include "scree/core/report_cycles.hpp"
#include "scree/core/tensor.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/material/material.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/schemes.hpp"
#include "scree/mpm/shape_functions.hpp"
#include "scree/mpm/stencil.hpp"

namespace scree {

enum PassFlags : unsigned {
  kGatherVelocity = 1u << 0,
  kGatherPosition = 1u << 1,
  kStressFromNew = 1u << 2,
  kStressFromVelocity = 1u << 3,
  kScatterMassMomentum = 1u << 4,
  kScatterForce = 1u << 5,
  kScatterMomentum = 1u << 6,
};
inline constexpr unsigned kAnyGather = kGatherVelocity | kGatherPosition | kStressFromNew | kStressFromVelocity;
inline constexpr unsigned kAnyScatter = kScatterMassMomentum | kScatterForce | kScatterMomentum;
inline constexpr unsigned kStressPhases = kStressFromNew | kStressFromVelocity;
inline constexpr unsigned kAllPhases = kAnyGather | kAnyScatter;
/// The phases of the light kernel: transfers only, no stress update and no force (a
/// kernel compiled without the material's update needs a fraction of its registers).
inline constexpr unsigned kTransferPhases = kGatherVelocity | kGatherPosition | kScatterMassMomentum | kScatterMomentum;

/// Number of stored stress components: 2D plane strain keeps xx, yy, zz, xy; 3D all six.
template <int D>
inline constexpr int kStressComponents = D == 2 ? 4 : 6;

/// Device pointers to one body's particle arrays (structure of arrays).
template <int D>
struct ParticleArrays {
  Index n = 0;
  Real* x[D];              ///< position [m]
  Real* v[D];              ///< velocity [m/s]
  Real* F[D * D];          ///< deformation gradient, row-major [-], kept as diag(J, 1[, 1]): F[0] = J = det F
                           ///< (ParticlePass::stress_update says why)
  Real* sigma[kStressComponents<D>];  ///< Cauchy stress (xx yy zz xy [yz zx]) [Pa]
  Real* mass;              ///< [kg] (per unit thickness in 2D)
  Real* volume0;           ///< initial volume [m^3] (area in 2D)
  Real* C[D * D];          ///< APIC affine velocity matrix [1/s] (null for FLIP)
  Real* state;             ///< material state, component k of particle i at state[k n + i]
};

/// The physics of the case that every particle pass shares: built once, at setup
/// (Solver::setup_passes), from the case's mpmSchemes and gravity.
template <int D>
struct PassPhysics {
  Vec<D> gravity;
  Real pic_fraction = 0;  ///< FLIP/PIC blend per step: 0 = pure FLIP (the paper's eq. 10), 1 = PIC
  Real pic_rate = 0;      ///< FLIP/PIC blend per unit time [1/s] (mpmSchemes picRate); 0: pic_fraction
  /// Largest det F (mpmSchemes maxVolumeRatio); infinite: no limit (one comparison per point)
  Real max_volume_ratio = kNoVolumeLimit;
  Transfer transfer = Transfer::flip;
  Real mass_eps = 0;  ///< nodes lighter than this are not accelerated (the grid update's)
  Real damping = 0, damping_start = 0, damping_end = 0;  ///< the grid update's local damping
};

/// How the particle kernels run (exec/kernel_policy.hpp and what the case needs of them):
/// built once, at setup, except split_elastic, which each launch takes from the split
/// tuner's current choice (solver/split_tuner.hpp).
/// None of it changes what a pass computes beyond the order of its additions.
struct PassPolicy {
  bool serial = false;    ///< CPU loop on one thread: plain adds instead of atomics
  bool need_speed = true;  ///< compute the largest signal speed (the adaptive step, the stopCo check)
  /// With need_speed: 0, every step; else only on steps whose index & speed_mask is 0. The
  /// health check of a fixed step (stopCo) samples the speed (KernelPolicy::speed_every):
  /// computed on every step it is a large share of a cheap material's pass, and an
  /// unstable step is caught a few steps later all the same.
  unsigned speed_mask = 0;
  bool reference = false;  ///< the straightforward kernel (see the top of this file)
  /// CUDA, 2D: run the stress kernel with a register cap (launch bounds of 64 threads and
  /// this many blocks per SM, 6: 170 registers, 12 warps per SM; the solver's default)
  /// instead of the compiler's choice (0; 254 registers for phaseTransition, 8 warps).
  int stress_blocks_per_sm = 0;
  /// CUDA, 2D: the elastic-only kernel's register cap (10 blocks of 64 per SM: 96
  /// registers, 20 warps per SM; the solver's default) or 0 (the compiler's choice).
  int elastic_blocks_per_sm = 0;
  /// Elastic first (fast kernels; materials with update_elastic, material.hpp): the stress
  /// pass updates the points whose increment is elastic, in a kernel compiled without the
  /// plastic integration (a fraction of its registers: more warps per SM), and appends the
  /// others to PassParams::deferred, counted in deferred_count[parity]; further launches run
  /// those (MaterialBody::launch_elastic_first: `refill` below). One stress pass per step, so
  /// the counters of the two parities alternate. False (the default; the solver decides,
  /// KernelPolicy::split): one kernel with the whole update.
  bool split_elastic = false;
  /// With split_elastic, for a material whose update runs in turns (material_has_turns): the
  /// deferred points' updates in DeferredStress (lanes refilled as their points finish),
  /// then their scatter; false: the whole pass over them, one point per lane.
  bool refill = true;
  int refill_lanes = 16;  ///< KernelPolicy::refill_lanes
  /// Keep the energy ledger (StepControl::energy): the stress work, the collisional
  /// dissipation and what the PIC blend removes, summed per warp and added once per warp.
  /// On, MaterialBody::launch runs every pass in the ledger's own kernels (ParticlePass's
  /// Ledger: the transfer pass alone, the stress pass split elastic-first as the fast one's
  /// where split_elastic says so, else whole); off (the default) the kernels carry none of it.
  bool energy = false;
  /// With `energy`: the transfer pass in the ledger's light kernel (KernelPolicy::
  /// ledger_light_transfer), not its whole-pass one.
  bool ledger_light_transfer = true;
  /// With `energy`: the walls' share measured on the points (USF, USL; the grid update then
  /// leaves it out): the work of the velocity change the walls made at the point's nodes,
  /// m sum N (v^{k+1} - v^{k+1} without walls) . (v_old + v_new)/2. The grid's own measure
  /// misses what the FLIP update takes from the points beyond it (sum m_p N_Ip^2 < m_I), which
  /// the budget's residual would then carry. MUSL re-maps momentum into the force array
  /// before its gather: measured on the grid.
  bool wall_ledger = false;
};

/// One launch of a particle pass (passed by value to the kernel): the case's physics and
/// the kernel policy, both built once, and what this pass of this step does: its phases,
/// the grid sets it reads and writes, the clock slots and the body it runs over.
template <int D>
struct PassParams {
  PassPhysics<D> physics;
  PassPolicy policy;

  unsigned flags = 0;
  int parity = 0;         ///< parity of the current step (its StepControl slot)
  int gather_parity = 0;  ///< parity of the step whose grid set G is gathered from: its dt
                          ///< drives the gather phases; dt = 0 makes them a no-op
  GridGeometry<D> grid;   ///< the (sub-)grid the sets cover
  GridFields<D> gather;   ///< the set G read by gather phases
  GridFields<D> scatter;  ///< the set S written by scatter phases (zeroed beforehand)
  StepControl* control = nullptr;
  std::uint32_t* tile_stamps = nullptr;  ///< tiles of S (Tiles<D>) to stamp; null: none
  Index* deferred = nullptr;             ///< PassPolicy::split_elastic's list (MaterialBody's)
  unsigned* deferred_count = nullptr;
  /// With the deferred updates in turns (PassPolicy::refill): what the elastic-only kernel
  /// hands a deferred point's update over with (Handoff); null: the update gathers again.
  Real* handoff = nullptr;
  /// The body's count of stress updates that reached their material's bound on the work
  /// (material_reports_bound; MaterialBody's); null for other materials.
  unsigned long long* bounded = nullptr;
  /// Body::body_id of the body the pass runs over (MaterialBody::launch sets it): a point
  /// with a non-finite field records it in StepControl::bad.
  int body = 0;
};

/// The PIC share a of a step of length dt in the FLIP/PIC blend v <- a v_PIC + (1 - a) v_FLIP.
/// picFraction fixes a per step: the velocity fluctuations it removes (v_FLIP - v_PIC) then
/// decay at a rate a/dt, which doubles when dt is halved. picRate fixes the rate instead:
/// a = 1 - exp(-picRate dt), so that n steps covering a time t remove exactly
/// 1 - exp(-picRate t) of them whatever the step.
template <int D>
SCREE_INLINE Real pic_share(const PassPhysics<D>& ph, Real dt) {
  return ph.pic_rate > 0 ? -expm1(-ph.pic_rate * dt) : ph.pic_fraction;
}

/// Whether M declares the collisional dissipation of a step (material.hpp, optional).
template <class M>
inline constexpr bool material_has_collisional_dissipation() {
  return requires(const typename M::Params& p, const typename M::State& s, const StrainIncrement& inc) {
    { M::collisional_dissipation(p, s, inc) } -> std::convertible_to<Real>;
  };
}

/// Whether this step computes the largest signal speed (PassPolicy::speed_mask).
template <int D>
SCREE_INLINE bool speed_wanted(const PassParams<D>& pp) {
  return pp.policy.need_speed && (pp.policy.speed_mask == 0 || (pp.control->step[pp.parity] & pp.policy.speed_mask) == 0);
}

namespace detail {

template <int D>
SCREE_INLINE Sym3 load_stress(Real* const* s, Index p) {
  if constexpr (D == 2) return Sym3{{s[0][p], s[1][p], s[2][p], s[3][p], 0, 0}};
  else return Sym3{{s[0][p], s[1][p], s[2][p], s[3][p], s[4][p], s[5][p]}};
}
template <int D>
SCREE_INLINE void store_stress(Real* const* s, Index p, const Sym3& v) {
  for (int c = 0; c < kStressComponents<D>; ++c) s[c][p] = v[c];
}

/// Shape-function weights of a particle at x over its stencil.
template <int D, class Shape>
struct Stencil {
  static constexpr int S = Shape::kStencil;
  static constexpr int kNodes = D == 2 ? S * S : S * S * S;
  int base[D];
  Real w[D][S], dw[D][S];
  bool inside;

  SCREE_INLINE Stencil(const Shape& sh, const GridGeometry<D>& g, const Vec<D>& x) {
    inside = true;
    for (int d = 0; d < D; ++d) {
      const Real xi = (x[d] - g.origin[d]) / g.h;
      // Tested in floating point first: a non-finite or huge coordinate (a blown-up
      // particle) converts to an arbitrary int, which may pass the integer test below.
      if (!(xi > Real(-2) && xi < Real(g.n[d] + 2))) {
        inside = false;
        base[d] = 0;
        for (int a = 0; a < S; ++a) w[d][a] = dw[d][a] = 0;
        continue;
      }
      sh.eval(xi, base[d], w[d], dw[d]);
      if (base[d] < 0 || base[d] + S > g.n[d]) inside = false;
    }
  }
  /// Node k of the stencil: flat index, weight N, gradient grad N, offset x_I - x_p.
  SCREE_INLINE void node(int k, const GridGeometry<D>& g, const Vec<D>& x, Index& I, Real& N, Vec<D>& gradN,
                         Vec<D>& dx) const {
    int a[D];
    int r = k;
    for (int d = 0; d < D; ++d) {
      a[d] = r % S;
      r /= S;
    }
    int idx[D];
    N = 1;
    for (int d = 0; d < D; ++d) {
      idx[d] = base[d] + a[d];
      N *= w[d][a[d]];
      dx[d] = g.origin[d] + g.h * idx[d] - x[d];
    }
    for (int d = 0; d < D; ++d) {
      Real gdx = dw[d][a[d]];
      for (int e = 0; e < D; ++e)
        if (e != d) gdx *= w[e][a[e]];
      gradN[d] = gdx;
    }
    I = g.flat(idx);
  }
  /// Stamp the tiles that hold the stencil's nodes (at most 2 per axis).
  SCREE_INLINE void stamp_tiles(const GridGeometry<D>& g, std::uint32_t* stamps, std::uint32_t stamp) const {
    for (int c = 0; c < (1 << D); ++c) {
      int idx[D];
      for (int d = 0; d < D; ++d) idx[d] = base[d] + (((c >> d) & 1) ? S - 1 : 0);
      store_if_changed(stamps + Tiles<D>::of(g, idx), stamp);
    }
  }
};

/// APIC's inverse inertia factor D_p^{-1} = (4 / h^2) I for the quadratic B-spline; for
/// the other shapes C_p is taken as sum v_I (x) grad N_I, which also reproduces affine
/// velocity fields exactly.
template <class Shape>
inline constexpr bool kApicFromInertia = Shape::kStencil == 3 && sizeof(Shape) == sizeof(Real);

}  // namespace detail

/// Whether M::update reads the stress it is given. A model that rebuilds sigma from its
/// state (phaseTransition: sigma_f + sigma_col) declares `static constexpr bool
/// reads_stress = false;`, and the kernel then neither loads nor co-rotates it.
template <class M>
inline constexpr bool material_reads_stress() {
  if constexpr (requires { M::reads_stress; }) return M::reads_stress;
  else return true;
}

/// What a pass's stress update stored (sigma and the current volume V0 det F), handed to the
/// same pass's scatter of the internal force: the values themselves, so that the scatter
/// does not load back from global memory what the thread has just written.
struct FreshStress {
  Sym3 sigma = Sym3::zero();
  Real volume = 0;
  bool valid = false;
  /// The energy ledger's share of the point (PassPolicy::energy): the stress work V (sigma^n
  /// + sigma^{n+1})/2 : deps of the step and the collisional dissipation V Gamma dt [J, J/m
  /// in 2D].
  Real work = 0, dissipated = 0;
};

/// What the elastic-only kernel of the split hands a deferred point's update over with, when
/// the update runs in turns (PassPolicy::refill): the point's gather and strain increment are
/// made once, in that kernel, which stores the point's new motion and these, and
/// DeferredStress starts the update from them. Per point p (n points), column k at
/// h[k n + p]: the increment's strain (the components plane strain does not hold at zero) and
/// spin, J, |v| at the step's start (or -1), and the energy ledger's PIC and wall shares.
template <int D>
struct Handoff {
  static constexpr int kDeps = D == 2 ? 3 : 6;   // 2D: xx, yy, xy
  static constexpr int kSpin = D == 2 ? 1 : 3;   // 2D: xy
  static constexpr int kJ = kDeps + kSpin, kSpeed = kJ + 1, kPic = kSpeed + 1, kWall = kPic + 1;
  static constexpr int kColumns = kWall + 1;

  SCREE_INLINE static constexpr int deps_slot(int k) { return D == 2 && k == 2 ? 3 : k; }

  SCREE_INLINE static void store(Real* h, Index n, Index p, const StrainIncrement& inc, Real v_start) {
    for (int k = 0; k < kDeps; ++k) h[k * n + p] = inc.deps[deps_slot(k)];
    h[kDeps * n + p] = inc.spin.xy;
    if constexpr (D == 3) {
      h[(kDeps + 1) * n + p] = inc.spin.yz;
      h[(kDeps + 2) * n + p] = inc.spin.zx;
    }
    h[kJ * n + p] = inc.J;
    h[kSpeed * n + p] = v_start;
  }
  /// The energy ledger's shares (a pass without the ledger has none to hand over).
  SCREE_INLINE static void store_ledger(Real* h, Index n, Index p, Real pic, Real wall) {
    h[kPic * n + p] = pic;
    h[kWall * n + p] = wall;
  }
  SCREE_INLINE static StrainIncrement load(const Real* h, Index n, Index p, Real dt, Real& v_start) {
    StrainIncrement inc;
    inc.deps = Sym3::zero();
    for (int k = 0; k < kDeps; ++k) inc.deps[deps_slot(k)] = h[k * n + p];
    inc.spin = Spin3::zero();
    inc.spin.xy = h[kDeps * n + p];
    if constexpr (D == 3) {
      inc.spin.yz = h[(kDeps + 1) * n + p];
      inc.spin.zx = h[(kDeps + 2) * n + p];
    }
    inc.J = h[kJ * n + p];
    inc.dt = dt;
    v_start = h[kSpeed * n + p];
    return inc;
  }
  SCREE_INLINE static void load_ledger(const Real* h, Index n, Index p, Real& pic, Real& wall) {
    pic = h[kPic * n + p];
    wall = h[kWall * n + p];
  }
};

/// The particle pass. ElasticFirst: the first kernel of the elastic-first split
/// (PassPolicy::split_elastic): a point whose stress update is not elastic is appended to
/// pp.deferred and left untouched (no state, position or velocity written, nothing
/// scattered); the ordinary pass then runs over the deferred points alone. With
/// pp.handoff (the updates in turns), its motion is stored and its gather handed over
/// instead (Handoff), for DeferredStress. Ledger: the
/// kernel that keeps the energy ledger (PassPolicy::energy), compiled apart so that the
/// others carry none of its code: held through the stress update, its values make the
/// register-capped elastic kernel spill.
template <int D, class Shape, class M, unsigned May = kAllPhases, bool ElasticFirst = false, bool Ledger = false>
struct ParticlePass {
  PassParams<D> pp;
  ParticleArrays<D> pa;
  Shape shape;
  typename M::Params mp;

  SCREE_INLINE void operator()(Index p) const { run(p, true); }
  /// Warp-collective form (parallel_for_warps): every lane of a warp calls it.
  SCREE_INLINE void operator()(Index p, bool valid) const { run(p, valid); }

  SCREE_INLINE void run(Index p, bool valid) const {
#if defined(SCREE_REPORT_CYCLES) && defined(__CUDA_ARCH__)
    // Diagnostic builds (CMake option SCREE_REPORT_CYCLES = C): a warp whose pass takes more
    // than C clock cycles prints one line (scree/core/report_cycles.hpp).
    diag::report_clear();
    const long long pass_in = clock64();
#endif
    StepControl* ctl = pp.control;
    const Real dt = ctl->dt[pp.gather_parity];
    // A zero step (the run reached its target time) changes no particle.
    const unsigned flags = (dt > 0 ? pp.flags : (pp.flags & ~kAnyGather)) & May;
    // Inactive lanes (past the end, frozen, or lost in this pass) still take part in the
    // warp-collective scatter with nothing to add, so nothing below returns early.
    bool active = valid && pa.volume0[p] >= 0;  // frozen: it left the grid earlier
    const Real mass = active ? pa.mass[p] : Real(0);

    Vec<D> x = Vec<D>::zero(), v = Vec<D>::zero();
    Mat<D> C = Mat<D>::zero();
    if (active) load_motion(p, x, v, C);

    // ---------------- gather phases (weights at the current position) ----------------
    Real speed = 0;  // signal speed c + |v| after the stress update
    FreshStress fresh;  // the stress and volume the update wrote, for the scatter's force
    Real pic_loss = 0;   // the energy ledger: kinetic energy the PIC blend removed (PassPolicy::energy)
    Real wall_loss = 0;  // ... and the walls (PassPolicy::wall_ledger)
    bool defer = false;  // ElasticFirst: the update is not elastic, left to the second kernel
    bool bounded = false;  // the update reached its material's bound on the work
    if ((flags & kAnyGather) && active) {
      Mat<D> L;
      Real v_start;
      if (!gather(p, flags, dt, mass, x, v, C, L, v_start, pic_loss, wall_loss)) {
        active = false;
      } else if constexpr ((May & kStressPhases) != 0) {
        if (flags & kStressPhases) defer = !stress_update<ElasticFirst>(p, L, dt, v_start, mass, speed, fresh, bounded);
      }
    }
    if constexpr (ElasticFirst) {
      push_index(pp.deferred, pp.deferred_count + pp.parity, p, defer, pp.policy.serial);
      if (defer) {
        if (pp.handoff) {  // the update in turns starts from this gather (Handoff)
          store_motion(p, x, v, C);
          if constexpr (Ledger) Handoff<D>::store_ledger(pp.handoff, pa.n, p, pic_loss, wall_loss);
        }
        active = false;  // nothing more of it is written, nor scattered here
        pic_loss = wall_loss = 0;  // counted by the second kernel
      }
    }
    if constexpr (Ledger && (May & kAnyGather) != 0) ledger(pic_loss, wall_loss, fresh);
    if constexpr (!ElasticFirst && (May & kStressPhases) != 0 && material_reports_bound<M>())
      if (flags & kStressPhases) {  // the count of bounded updates: one atomic per warp that has any
        if (pp.policy.reference) {
          if (bounded) atomic_increment(pp.bounded, pp.policy.serial);
        } else {
          warp_count(pp.bounded, bounded, pp.policy.serial);
        }
      }
    if constexpr ((May & kStressPhases) != 0)
      if ((flags & kStressPhases) && speed_wanted(pp)) {
        // The step's largest signal speed, for the adaptive time step: one atomic per warp.
        if (pp.policy.reference) {
          if (speed > 0) atomic_max_nonneg(&ctl->max_speed[pp.parity], speed, pp.policy.serial);
        } else {
          speed = warp_max(speed);
          if (first_lane_of_warp() && speed > 0) atomic_max_nonneg(&ctl->max_speed[pp.parity], speed, pp.policy.serial);
        }
      }

    // ---------------- scatter phases (weights at the updated position) ----------------
    if (flags & kAnyScatter) scatter(p, flags, active, x, v, C, mass, fresh);

    if constexpr ((May & kAnyGather) != 0)  // a pass that only scatters moves no point
      if (active) store_motion(p, x, v, C);
#if defined(SCREE_REPORT_CYCLES) && defined(__CUDA_ARCH__)
    {
      const long long pass_cycles = clock64() - pass_in;
      const unsigned n = diag::report_substeps[diag::report_slot()], paths = diag::report_paths[diag::report_slot()];
      const unsigned all = __activemask();
      const unsigned sum = __reduce_add_sync(all, n), top = __reduce_max_sync(all, n);
      const int busy = __popc(__ballot_sync(all, n > 0));
      const int p1 = __popc(__ballot_sync(all, paths & 1u)), p2 = __popc(__ballot_sync(all, paths & 2u)),
                p4 = __popc(__ballot_sync(all, paths & 4u));
      const long long slowest = warp_max(Real(pass_cycles));
      if (first_lane_of_warp() && slowest > SCREE_REPORT_CYCLES)
        printf("pass-cycles %lld step %llu elastic-first %d block %u lanes %d substeps-sum %u substeps-max %u "
               "paths %d %d %d\n",
               slowest, ctl->step[pp.gather_parity], ElasticFirst ? 1 : 0, blockIdx.x, busy, sum, top, p1, p2, p4);
    }
#endif
  }

  /// The point's position, velocity and (APIC) affine matrix.
  SCREE_INLINE void load_motion(Index p, Vec<D>& x, Vec<D>& v, Mat<D>& C) const {
    for (int d = 0; d < D; ++d) {
      x[d] = pa.x[d][p];
      v[d] = pa.v[d][p];
    }
    if (pp.physics.transfer == Transfer::apic)
      for (int i = 0; i < D * D; ++i) C.a[i / D][i % D] = pa.C[i][p];
  }
  SCREE_INLINE void store_motion(Index p, const Vec<D>& x, const Vec<D>& v, const Mat<D>& C) const {
    for (int d = 0; d < D; ++d) {
      pa.x[d][p] = x[d];
      pa.v[d][p] = v[d];
    }
    if (pp.physics.transfer == Transfer::apic)
      for (int i = 0; i < D * D; ++i) pa.C[i][p] = C.a[i / D][i % D];
  }

  /// The gather phases (weights at the current position x, from the set G): the velocity
  /// gradient L (eq. 7) for the stress phases, the new velocity (FLIP/PIC, eq. 10, or APIC:
  /// v and C) and position (eq. 11). v_start: |v| at the start of the step when the step
  /// takes the signal speed, else -1. The energy ledger's shares of the PIC blend and the
  /// walls (PassPolicy::energy). Returns false when the stencil left the grid (the point is
  /// then frozen: lost()).
  SCREE_INLINE bool gather(Index p, unsigned flags, Real dt, Real mass, Vec<D>& x, Vec<D>& v, Mat<D>& C, Mat<D>& L,
                           Real& v_start, Real& pic_loss, Real& wall_loss) const {
    StepControl* ctl = pp.control;
    const GridGeometry<D>& g = pp.grid;
    const bool apic = pp.physics.transfer == Transfer::apic;
    const detail::Stencil<D, Shape> st(shape, g, x);
    if (!st.inside) {
      lost(p);  // the stencil left the grid: freeze the particle (the solver warns)
      return false;
    }
    Vec<D> v_pic = Vec<D>::zero(), dv = Vec<D>::zero();
    Vec<D> dw = Vec<D>::zero();  // Ledger, wall_ledger: sum N (v^{k+1} - v^{k+1} without the walls)
    L = Mat<D>::zero();
    Mat<D> B = Mat<D>::zero(), Lnew = Mat<D>::zero();
    const bool from_new = flags & kStressFromNew;
    const bool want_L = flags & kStressPhases;
    const bool flip_increment = (flags & kGatherVelocity) && !apic && (pp.physics.pic_fraction < 1 || pp.physics.pic_rate > 0);
    // Unrolled: the stencil's weights stay in registers (a loop index would put the
    // Stencil in local memory, read back at every node).
SCREE_UNROLL
    for (int k = 0; k < detail::Stencil<D, Shape>::kNodes; ++k) {
      Index I;
      Real N;
      Vec<D> gradN, dx;
      st.node(k, g, x, I, N, gradN, dx);
      Vec<D> vi, vn;
      for (int d = 0; d < D; ++d) {
        vi[d] = pp.gather.velocity[d][I];
        vn[d] = pp.gather.velocity_new[d][I];
      }
      v_pic += N * vn;
      if (flip_increment) {
        // FLIP's increment against the velocity the particles mapped, momentum/mass,
        // before the boundary conditions: the correction a constraint makes at a node
        // then reaches the particles too. Against the constrained v^k, a particle next
        // to a no-slip wall would keep a velocity the grid discarded, for ever.
        // One reciprocal per node, not a division per component (a double division is a
        // chain of about ten dependent instructions on a GPU).
        const Real m = pp.gather.mass[I];
        const Real rm = m > 0 ? 1 / m : Real(0);
        Vec<D> v_mapped;
        for (int d = 0; d < D; ++d) v_mapped[d] = m > 0 ? pp.gather.momentum[d][I] * rm : vi[d];
        dv += N * (vn - v_mapped);
        if constexpr (Ledger)
          if (pp.policy.wall_ledger) {
            // The node's v^{k+1} without the walls: the mapped velocity accelerated by
            // the force (and the local damping) the grid update applied.
            const Real t = ctl->t[pp.gather_parity];
            const bool damp = damping_active(pp.physics.damping, t, pp.physics.damping_start, pp.physics.damping_end);
            for (int d = 0; d < D; ++d) {
              Real f = pp.gather.force[d][I];
              if (damp) f = damped_force(f, vi[d], pp.physics.damping);
              const Real free = m > pp.physics.mass_eps ? v_mapped[d] + dt * f * rm : v_mapped[d];
              dw[d] += N * (vn[d] - free);
            }
          }
      }
      if (want_L)  // eq. (7); the velocity chosen per component (a reference to one of
        for (int d = 0; d < D; ++d)  // two vectors would put both in local memory)
          for (int e = 0; e < D; ++e) L.a[d][e] += (from_new ? vn[d] : vi[d]) * gradN[e];
      if (apic) {
        if constexpr (detail::kApicFromInertia<Shape>) B += outer(vn, dx) * N;
        else Lnew += outer(vn, gradN);
      }
    }
    // The new velocity and position (eqs. 10-11) need the gather alone: made before the
    // stress update, so that the gather's sums are dead while the update needs registers.
    // The signal speed takes |v| of the velocity the step started from; -1 when this
    // step takes no speed. (The flag itself, held through the stress update, would make
    // the register-capped elastic kernel spill.)
    v_start = speed_wanted(pp) ? norm(v) : Real(-1);
    if (flags & kGatherVelocity) {
      if (apic) {
        v = v_pic;
        if constexpr (detail::kApicFromInertia<Shape>) C = B * (4 / (g.h * g.h));
        else C = Lnew;
      } else {
        // FLIP (eq. 10) blended with PIC.
        const Real a = pic_share(pp.physics, dt);
        Vec<D> v_old = Vec<D>::zero();  // Ledger: the walls' work takes the step's mean velocity
        if constexpr (Ledger) v_old = v;
        Real flip2 = 0, new2 = 0;
        for (int d = 0; d < D; ++d) {
          const Real vf = v[d] + dv[d];
          v[d] = a * v_pic[d] + (1 - a) * vf;
          flip2 += vf * vf;
          new2 += v[d] * v[d];
        }
        if constexpr (Ledger)
          if (flip_increment) {
            pic_loss = Real(0.5) * mass * (flip2 - new2);
            if (pp.policy.wall_ledger) {
              // The walls moved both the FLIP and the PIC part by sum N dw: their work on
              // the point is that impulse times the step's mean velocity (v_old +
              // v_new)/2, so that it adds up with the forces' to the point's kinetic
              // energy change, and is zero at rest (the kinetic energy against the velocity
              // without walls would count the unbalanced acceleration the floor's reaction
              // cancels, 1/2 m (dt g)^2 at every step, under a resting body).
              Real w = 0;
              for (int d = 0; d < D; ++d) w += dw[d] * (v_old[d] + v[d]);
              wall_loss = -Real(0.5) * mass * w;
            }
          }
      }
    }
    if (flags & kGatherPosition) x += dt * v_pic;  // eq. (11)
    return true;
  }

  /// The energy ledger (PassPolicy::energy): the warp's sums, added by its first lane.
  /// Warp-collective: every lane calls it (inactive ones with zeros).
  SCREE_INLINE void ledger(Real pic_loss, Real wall_loss, const FreshStress& fresh) const {
    Real* e = pp.control->energy.at(warp_index());
    const Real pic = warp_sum(pic_loss), work = warp_sum(fresh.work), diss = warp_sum(fresh.dissipated);
    const Real wall = warp_sum(wall_loss);
    if (first_lane_of_warp()) {
      if (pic != 0) atomic_add(e + kEnergyPic, pic, pp.policy.serial);
      if (wall != 0) atomic_add(e + kEnergyWalls, wall, pp.policy.serial);
      if (work != 0) atomic_add(e + kEnergyStressWork, work, pp.policy.serial);
      if (diss != 0) atomic_add(e + kEnergyCollisional, diss, pp.policy.serial);
    }
  }

  /// P2G: mass, momentum and force into the set S. `active` becomes false when the
  /// stencil leaves the grid.
  SCREE_INLINE void scatter(Index p, unsigned flags, bool& active, const Vec<D>& x, const Vec<D>& v,
                            const Mat<D>& C, Real mass, const FreshStress& fresh) const {
    const GridGeometry<D>& g = pp.grid;
    const detail::Stencil<D, Shape> st(shape, g, x);
    if (active && !st.inside) {
      lost(p);
      active = false;
    }
    Sym3 sig = Sym3::zero();
    Real vol = 0;
    if ((flags & kScatterForce) && active) {
      if (fresh.valid) {  // this pass's stress update: the values it stored, not a re-read
        sig = fresh.sigma;
        vol = fresh.volume;
      } else {
        sig = detail::load_stress<D>(pa.sigma, p);
        vol = pa.volume0[p] * pa.F[0][p];  // J: F is kept as diag(J, 1[, 1]) (stress_update)
      }
    }
    const bool apic = pp.physics.transfer == Transfer::apic;
    // Lanes with the same first stencil node share every node: they add per warp first.
    const bool per_lane = pp.policy.reference;
#if defined(__CUDA_ARCH__)
    const long long key = active ? static_cast<long long>(g.flat(st.base)) : -1 - static_cast<long long>(threadIdx.x);
    const WarpSegment seg(per_lane ? -1 - static_cast<long long>(threadIdx.x) : key);
#else
    const WarpSegment seg(0);
#endif
    if (pp.tile_stamps && active && seg.head)
      st.stamp_tiles(g, pp.tile_stamps, tile_stamp(pp.control->step[pp.parity]));
    const bool serial = pp.policy.serial;
    auto add = [&](Real* field, Real value) {
#if defined(__CUDA_ARCH__)
      const Real s = per_lane ? value : seg.sum(value);
      if (active && seg.head && (per_lane || s != 0)) atomic_add(field, s, serial);
#else
      atomic_add(field, value, serial);
#endif
    };
    for_each_stencil_node(st, g, x, active, [&](Index I, Real N, const Vec<D>& gradN, const Vec<D>& dx) {
#if !defined(__CUDA_ARCH__)
      if (N == 0 && (flags & kScatterForce) == 0) return;
#endif
      if (flags & kScatterMassMomentum) {
        add(&pp.scatter.mass[I], N * mass);  // eq. (5)
        Vec<D> vI = v;
        if (apic) vI += C * dx;
        for (int d = 0; d < D; ++d) add(&pp.scatter.momentum[d][I], N * mass * vI[d]);  // eq. (6)
      }
      if (flags & kScatterMomentum)
        for (int d = 0; d < D; ++d) add(&pp.scatter.force[d][I], N * mass * v[d]);
      if (flags & kScatterForce) {
        for (int d = 0; d < D; ++d) {
          Real s = 0;
          for (int e = 0; e < D; ++e) s += sig(d, e) * gradN[e];
          add(&pp.scatter.force[d][I], -vol * s + N * mass * pp.physics.gravity[d]);
        }
      }
    });
  }

  /// eqs. (8)-(9) with an objective stress update. Sets `speed` to the signal speed c +
  /// v_start (|v| at the start of the step) when the step takes it (v_start >= 0), else 0.
  /// ElasticOnly: the material's update_elastic; when that declines, nothing is written and
  /// the result is false. `bounded`: the update reached its material's bound on the work
  /// (material_reports_bound).
  template <bool ElasticOnly>
  SCREE_INLINE bool stress_update(Index p, const Mat<D>& L, Real dt, Real v_start, Real mass, Real& speed,
                                  FreshStress& fresh, bool& bounded) const {
    const StrainIncrement inc = increment(p, L, dt);
    Sym3 sigma_start;
    Sym3 sigma = start_stress(p, inc, sigma_start);
    typename M::State s = material_state(p);
    if constexpr (ElasticOnly) {
      if (!M::update_elastic(mp, s, sigma, inc)) {
        if (pp.handoff) Handoff<D>::store(pp.handoff, pa.n, p, inc, v_start);
        return false;
      }
    } else if constexpr (material_reports_bound<M>()) {
      bounded = M::update(mp, s, sigma, inc);
    } else {
      M::update(mp, s, sigma, inc);
    }
    commit(p, s, sigma, inc, sigma_start, v_start, mass, speed, fresh);
    return true;
  }

  /// The step's strain increment from the velocity gradient L: eq. (8) as the volume ratio
  /// J = det F (inc.J), the increment sym(L) dt and the spin skew(L) dt.
  SCREE_INLINE StrainIncrement increment(Index p, const Mat<D>& L, Real dt) const {
    // eq. (8), F <- (I + L dt) F, kept as its determinant alone: the point's volume ratio
    // J = det F, the one part of F that anything uses (the volume V0 J; the materials get
    // the increment, its spin and J). F is stored as diag(J, 1[, 1]), so the update is
    // J <- det(I + L dt) J: a product of numbers near 1 keeps its precision, where the
    // determinant of an accumulated F (stretches of up to 1e9 in a long granular flow, its
    // determinant a difference of products near 1e17) is lost to cancellation, down to a
    // negative volume (cases/flume/README.md, "Why the runs blew up").
    Real J = det(Mat<D>::identity() + L * dt) * pa.F[0][p];
    StrainIncrement inc;
    inc.deps = sym3_from(L) * dt;
    if (J > pp.physics.max_volume_ratio) [[unlikely]] {
      // The point's volume V0 J is capped at V0 max_volume_ratio: its density, and so the
      // signal speeds of the time step, stay bounded. The strain increment loses the same
      // volume, ln r spread over the D normal components, r = max_volume_ratio/J: the
      // material's void ratio (1 + e follows exp(tr deps)) then stays that of the capped
      // volume, instead of growing without bound at the cap.
      const Real r = pp.physics.max_volume_ratio / J;
      J = pp.physics.max_volume_ratio;
      const Real lr = log(r) / D;
      for (int d = 0; d < D; ++d) inc.deps[d] += lr;
    }
    inc.spin = spin_from(L);
    inc.spin.xy *= dt;
    inc.spin.yz *= dt;
    inc.spin.zx *= dt;
    if constexpr (D == 2) {
      // Plane strain: the out-of-plane parts are 0 dt = 0 for any finite step. Written as
      // constants, the compiler holds them in no register through the update.
      inc.deps[2] = inc.deps[4] = inc.deps[5] = 0;
      inc.spin.yz = inc.spin.zx = 0;
    }
    inc.dt = dt;
    inc.J = J;
    return inc;
  }

  /// The stress the material's update receives: the stored one co-rotated with the step's
  /// spin (zero for a model that does not read it, material_reads_stress). sigma_start: the
  /// energy ledger's stress at the step's start (co-rotated).
  SCREE_INLINE Sym3 start_stress(Index p, const StrainIncrement& inc, Sym3& sigma_start) const {
    Sym3 sigma = Sym3::zero();
    if constexpr (material_reads_stress<M>()) sigma = corotate(detail::load_stress<D>(pa.sigma, p), inc.spin);
    // Ledger: the stress at the step's start (co-rotated), for the work of the step (commit).
    sigma_start = Sym3::zero();
    if constexpr (Ledger) {
      if constexpr (material_reads_stress<M>()) sigma_start = sigma;
      else sigma_start = corotate(detail::load_stress<D>(pa.sigma, p), inc.spin);
    }
    return sigma;
  }

  /// The point's material state (the 2D kernels skip the Reals that are zero in plane strain).
  SCREE_INLINE typename M::State material_state(Index p) const {
    typename M::State s;
    constexpr unsigned plane = D == 2 ? plane_zero_slots<M>() : 0u;
    load_state<typename M::State, plane>(s, pa.state, pa.n, p);
    return s;
  }

  /// After the material's update (s, sigma): the signal speed, the stores, and what the
  /// scatter's force takes (fresh; with the energy ledger, the work of the step).
  SCREE_INLINE void commit(Index p, const typename M::State& s, const Sym3& sigma, const StrainIncrement& inc,
                           [[maybe_unused]] const Sym3& sigma_start, Real v_start, Real mass, Real& speed,
                           FreshStress& fresh) const {
    const Real vol = pa.volume0[p] * inc.J;
    // The speed before the stores: with no memory access between them, the compiler shares
    // what the update and wave_speed() both compute (phaseTransition: the collisional
    // coefficients at the new void ratio).
    speed = 0;
    if (v_start >= 0) {
      // An inverted point (V <= 0) has no density and so no wave speed: its |v| alone (a
      // density of 0 would give most models c = inf, a zero adaptive step and an infinite
      // Courant number in the health check).
      speed = vol > 0 ? M::wave_speed(mp, s, sigma, mass / vol, pp.grid.h) + v_start : v_start;
    }
    pa.F[0][p] = inc.J;  // F = diag(J, 1[, 1]): its other entries stay those of the identity
    constexpr unsigned plane = D == 2 ? plane_zero_slots<M>() : 0u;  // zero in plane strain
    store_state<typename M::State, plane>(s, pa.state, pa.n, p);
    detail::store_stress<D>(pa.sigma, p, sigma);
    fresh = FreshStress{sigma, vol, true};
    if constexpr (Ledger) {
      // The work of the step, V (sigma^n + sigma^{n+1})/2 : deps: the trapezoidal rule, exact
      // for a linear elastic increment, where V sigma^{n+1} : deps counts 1/2 deps : C : deps
      // too much at every step, always > 0, and books a vibration's elastic energy as
      // dissipation (cases/flume/README.md).
      fresh.work = vol * ddot((sigma_start + sigma) * Real(0.5), inc.deps);
      if constexpr (material_has_collisional_dissipation<M>()) fresh.dissipated = vol * M::collisional_dissipation(mp, s, inc);
    }
  }

  /// Freeze a particle whose stencil left the grid (negative volume0 marks it) and
  /// count it once; the first one records itself (StepControl::first_lost), and the solver
  /// reports the count. A point blown up (a non-finite position) comes from a non-finite
  /// nodal velocity, which the grid update's probe has already reported in this step
  /// (report_nonfinite_node); the host then finds the point in the frozen state.
  SCREE_INLINE void lost(Index p) const {
    pa.volume0[p] = -fabs(pa.volume0[p]);
    if (atomic_fetch_increment(&pp.control->lost, pp.policy.serial) == 0) {
      pp.control->first_lost.body = pp.body;
      pp.control->first_lost.index = p;
      pp.control->first_lost.step = pp.control->step[pp.parity];
    }
  }
};

/// The stress updates of the points the elastic-first split deferred (PassPolicy::
/// split_elastic, PassPolicy::refill), for a material whose update runs in turns
/// (material_has_turns): each point's strain increment and update, from the gather the
/// elastic-only kernel made and handed over (Handoff), its state and stress stored. Their
/// scatter is a pass of its own afterwards (ParticlePass with the scatter phases alone, over
/// the same list), so that the update can run apart from it: on CUDA the warps take points
/// from the list as a queue, and a lane whose point is done holds until refill_lanes of its
/// warp are (PassPolicy), then those lanes store their results and take the next points
/// together. A warp then runs its lanes' substep chains side by side instead
/// of all as long as its longest. Each point's arithmetic is the whole pass's (ParticlePass's
/// gather, increment and commit, the material's update_in_turns): only the order of the
/// sums into the grid and the step's totals changes, as between any two CUDA launches.
template <int D, class Shape, class M, bool Ledger>
struct DeferredStress {
  ParticlePass<D, Shape, M, kAnyGather, false, Ledger> pass;
  const Index* list;       ///< the deferred points (MaterialBody's)
  const unsigned* count;   ///< their number
  unsigned* head;          ///< the queue's next entry (CUDA)
  unsigned* reset_count;   ///< the other parity's counters, zeroed for the next step's kernels
  unsigned* reset_head;

  /// A point in flight: what its update's end and the commit need.
  struct Point {
    Index p = 0;
    StrainIncrement inc;
    Real v_start = -1, mass = 0;
    Sym3 sigma_start;  ///< the energy ledger's start stress (Ledger)
  };
  /// A lane's totals over its points: the largest signal speed, the updates that reached the
  /// material's bound, the energy ledger's shares.
  struct Sums {
    Real speed = 0, pic = 0, wall = 0, work = 0, dissipated = 0;
    unsigned bounded = 0;
  };

  Index size() const { return *count; }
  SCREE_HD void reset() const {
    *reset_count = 0;
    *reset_head = 0;
  }

  /// The start of point p's update, from what the elastic-only kernel handed over
  /// (Handoff: the gather's increment; the point's motion is stored already): the start
  /// stress and the material's update_begin. Returns whether turns remain.
  SCREE_INLINE bool begin(Index p, Point& pt, typename M::Work& w, Sums& sums) const {
    const PassParams<D>& pp = pass.pp;
    const Real dt = pp.control->dt[pp.gather_parity];
    pt.p = p;
    pt.mass = pass.pa.mass[p];
    pt.inc = Handoff<D>::load(pp.handoff, pass.pa.n, p, dt, pt.v_start);
    if constexpr (Ledger) {
      Real pic, wall;
      Handoff<D>::load_ledger(pp.handoff, pass.pa.n, p, pic, wall);
      sums.pic += pic;
      sums.wall += wall;
    }
    const Sym3 sigma = pass.start_stress(p, pt.inc, pt.sigma_start);
    const typename M::State s = pass.material_state(p);
    return M::update_begin(pass.mp, s, sigma, pt.inc, w);
  }

  /// The end of the point's update and its commit (the speed, the stores).
  SCREE_INLINE void end(const Point& pt, typename M::Work& w, Sums& sums) const {
    typename M::State s = pass.material_state(pt.p);
    Sym3 sigma = Sym3::zero();
    if constexpr (material_reports_bound<M>()) sums.bounded += M::update_end(pass.mp, s, sigma, pt.inc, w) ? 1u : 0u;
    else M::update_end(pass.mp, s, sigma, pt.inc, w);
    Real speed = 0;
    FreshStress fresh;
    pass.commit(pt.p, s, sigma, pt.inc, pt.sigma_start, pt.v_start, pt.mass, speed, fresh);
    sums.speed = fmax(sums.speed, speed);
    sums.work += fresh.work;
    sums.dissipated += fresh.dissipated;
  }

  /// Add a lane's totals to the step's (warp-collective on CUDA: every lane calls it).
  SCREE_INLINE void book(const Sums& s) const {
    const PassParams<D>& pp = pass.pp;
    const bool serial = pp.policy.serial;
    if (speed_wanted(pp)) {
      const Real speed = warp_max(s.speed);
      if (first_lane_of_warp() && speed > 0) atomic_max_nonneg(&pp.control->max_speed[pp.parity], speed, serial);
    }
    if constexpr (material_reports_bound<M>()) warp_add(pp.bounded, s.bounded, serial);
    if constexpr (Ledger) {
      FreshStress f;
      f.work = s.work;
      f.dissipated = s.dissipated;
      pass.ledger(s.pic, s.wall, f);
    }
  }

  /// CPU: the list's entry j, whole.
  void item(Index j) const {
    Point pt;
    typename M::Work w;
    Sums sums;
    if (begin(list[j], pt, w, sums))
      while (M::update_turn(pass.mp, w)) {
      }
    end(pt, w, sums);
    book(sums);
  }

#if defined(__CUDACC__)
  /// CUDA: the warp's lanes take points from the queue until it is empty (see the top).
  __device__ void drain() const {
    const unsigned n = *count;
    const int lanes = pass.pp.policy.refill_lanes;
    Point pt;
    typename M::Work w;
    Sums sums;
    bool busy = false;  // turns to run
    bool done = false;  // a finished update to end and commit
    bool more = true;   // the queue may hold points (alike in every lane)
    for (;;) {
      const unsigned idle = __ballot_sync(0xffffffffu, !busy);
      if (__popc(idle) >= lanes || idle == 0xffffffffu) {
        if (done) end(pt, w, sums);
        done = false;
        if (more) {
          unsigned taken;
          const unsigned j = warp_take(head, idle, taken);
          more = taken < n;
          if (!busy && j < n) {
            busy = begin(list[j], pt, w, sums);
            done = !busy;
          }
        }
        if (!more && !__any_sync(0xffffffffu, busy || done)) break;
      }
      if (busy) {
        busy = M::update_turn(pass.mp, w);
        done = !busy;
      }
    }
    book(sums);
  }
#endif
};

}  // namespace scree
