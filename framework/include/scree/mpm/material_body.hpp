// MaterialBody<D, M>: a body of particles with material M, implementing Body<D>.
//
// Instantiated inside the material's plugin by Registry::add_material<M>() (compiled as
// CUDA when the CUDA backend is on), so each plugin carries its own kernels: the
// ParticlePass for each shape function, for the CPU (OpenMP) and the CUDA backend. It
// puts together the particle storage (particle_storage.hpp), the sort by cell
// (particle_sort.hpp), the snapshot copy (snapshot_copy.hpp) and the launches of the
// particle kernels; what is specific to M is the initial state, the signal speed, the
// output fields and the kernels' instantiation.
//
// Kernels (particle_pass.hpp): a pass without stress update runs the light instantiation
// (kTransferPhases: no material code, a fraction of the registers) in blocks of 256; a
// pass with it the full one in blocks of 64 (its occupancy is set by the material's
// registers, and small blocks let the SMs fill in behind warps that take longer, e.g. a
// point that needs many substeps). PassPolicy::reference runs the full one everywhere.
#pragma once

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "scree/exec/kernel_policy.hpp"
#include "scree/material/material.hpp"
#include "scree/mpm/body.hpp"
#include "scree/mpm/particle_sort.hpp"
#include "scree/mpm/particle_storage.hpp"
#include "scree/mpm/snapshot_copy.hpp"

namespace scree {

namespace detail {
/// Sets c[0..n) to zero, as a kernel on the body's stream (stream-ordered with its passes).
struct ZeroCounters {
  unsigned* c;
  SCREE_HD void operator()(Index i) const { c[i] = 0; }
};
}  // namespace detail

template <int D, class M>
class MaterialBody final : public Body<D> {
 public:
  using Params = typename M::Params;
  using State = typename M::State;
  static constexpr int K = state_size<State>();
  static constexpr int kSig = kStressComponents<D>;

  MaterialBody(const Params& params, const BodySetup<D>& s)
      : params_(params),
        name_(s.name),
        body_id_(s.body_id),
        type_(M::type_name),
        exec_(s.exec),
        shape_(s.shape),
        lp_(s.gimp_half_length),
        store_(static_cast<Index>(s.x.size()), K, s.transfer, extra_column_count(s.extra)),
        extra_(s.extra) {
    for (auto& e : extra_) e.values.clear();  // uploaded below from s.extra; not kept on the host
    const Index n = store_.size();
    std::vector<Real> host(static_cast<std::size_t>(store_.columns() * n), 0.0);
    auto col = [&](int c) { return store_.col(host.data(), c); };
    const Real rho = M::density(params_);
    for (Index p = 0; p < n; ++p) {
      for (int d = 0; d < D; ++d) {
        col(store_.c_x() + d)[p] = s.x[p][d];
        col(store_.c_v() + d)[p] = s.v.empty() ? 0 : s.v[p][d];
        col(store_.c_x0() + d)[p] = s.x[p][d];
      }
      for (int i = 0; i < D; ++i) col(store_.c_F() + i * D + i)[p] = 1;
      if (s.transfer == Transfer::apic)
        for (int i = 0; i < D * D; ++i) col(store_.c_C() + i)[p] = s.velocity_gradient.a[i / D][i % D];
      Sym3 sigma = s.sigma.empty() ? Sym3::zero() : s.sigma[p];
      const State st = M::initial_state(params_, sigma);
      for (int c = 0; c < kSig; ++c) col(store_.c_sig() + c)[p] = sigma[c];
      col(store_.c_mass())[p] = s.mass_factor == 1 ? rho * s.volume[p] : s.mass_factor * rho * s.volume[p];
      col(store_.c_vol0())[p] = s.volume[p];
      col(store_.c_id())[p] = static_cast<Real>(s.ids.empty() ? s.first_id + p : s.ids[static_cast<std::size_t>(p)]);
      if constexpr (K > 0) {
        Real tmp[K > 0 ? K : 1];
        std::memcpy(tmp, &st, sizeof(State));
        for (int k = 0; k < K; ++k) col(store_.c_state())[static_cast<std::size_t>(k) * n + p] = tmp[k];
      }
    }
    for (int c = 0, j = 0; j < static_cast<int>(extra_.size()); c += extra_[j].components, ++j)
      for (int k = 0; k < extra_[j].components; ++k) {
        Real* dst = col(store_.c_extra() + c + k);
        const auto& v = s.extra[j].values;
        for (Index p = 0; p < n; ++p)
          dst[p] = v.empty() ? extra_[j].initial : v[static_cast<std::size_t>(p) * extra_[j].components + k];
      }
    store_.upload(host, exec_.device);
    if constexpr (material_has_elastic_path<M>()) {  // the elastic-first split's list (zeroed)
      deferred_.resize(static_cast<std::size_t>(n), exec_.device);
      deferred_count_.resize(4, exec_.device);
      resize_handoff(n);
    }
    if constexpr (material_reports_bound<M>()) bounded_.resize(1, exec_.device);  // zeroed
    OutputFields<M> out;
    M::describe(out);
    fields_ = out.fields();
  }

  const std::string& name() const override { return name_; }
  bool can_split_stress() const override { return material_has_elastic_path<M>(); }
  bool updates_in_turns() const override { return material_defers_in_turns<M>(); }
  void reset_split() override {
    if constexpr (material_has_elastic_path<M>()) parallel_for(exec_, 4, detail::ZeroCounters{deferred_count_.data()});
  }
  const std::string& material_type() const override { return type_; }
  std::string work_bound() const override {
    if constexpr (material_reports_bound<M>()) return M::work_bound(params_);
    else return {};
  }
  std::uint64_t bounded_updates() const override {
    if constexpr (material_reports_bound<M>()) {
      mem::synchronize(exec_.device);
      return bounded_.to_host()[0];
    } else {
      return 0;
    }
  }
  Index size() const override { return store_.size(); }
  const ParticleArrays<D>& arrays() const override { return store_.arrays(); }
  std::size_t bytes_per_particle() const override { return store_.bytes_per_particle(); }
  Real* extra_columns() const override { return store_.extra(); }

  void pass(const PassParams<D>& params) override {
    if (store_.size() == 0) return;  // a rank of a decomposed run may hold none of the body's points
    PassParams<D> pp = params;
    pp.body = body_id_;  // named by a point with a non-finite field (StepControl::bad)
    if constexpr (material_reports_bound<M>()) pp.bounded = bounded_.data();
    const Real inv_h = 1 / pp.grid.h;
    switch (shape_) {
      case ShapeKind::linear: launch(pp, ShapeLinear{inv_h}); break;
      case ShapeKind::gimp: launch(pp, ShapeGimp{inv_h, lp_}); break;
      case ShapeKind::bspline2: launch(pp, ShapeBspline2{inv_h}); break;
    }
  }

  Real max_signal_speed(Real h) const override {
    const auto host = store_.to_host();
    auto col = [&](int c) { return store_.col(host.data(), c); };
    Real cmax = 0;
    for (Index p = 0; p < store_.size(); ++p) {
      State st{};
      load_state(st, col(store_.c_state()), store_.size(), p);
      Sym3 sig = Sym3::zero();
      for (int c = 0; c < kSig; ++c) sig[c] = col(store_.c_sig() + c)[p];
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = col(store_.c_F() + i)[p];
      const Real vol = std::fabs(col(store_.c_vol0())[p]) * det(F);
      const Real rho = vol > 0 ? col(store_.c_mass())[p] / vol : M::density(params_);
      Real v2 = 0;
      for (int d = 0; d < D; ++d) v2 += col(store_.c_v() + d)[p] * col(store_.c_v() + d)[p];
      cmax = std::max(cmax, M::wave_speed(params_, st, sig, rho, h) + std::sqrt(v2));
    }
    return cmax;
  }

  void snapshot(BodySnapshot& out) const override {
    const auto host = store_.to_host();
    build_snapshot(host.data(), out);
  }

  std::function<void(BodySnapshot&)> snapshot_async(void* copy_stream) override {
#if defined(__CUDACC__)
    if (exec_.device == Device::cuda) {
      auto wait = copy_.start(store_.data(), exec_.stream, copy_stream, exec_.device);
      return [this, wait](BodySnapshot& out) { wait([&](const Real* host) { build_snapshot(host, out); }); };
    }
#endif
    return Body<D>::snapshot_async(copy_stream);
  }

  /// The snapshot from a host copy of the particle block (columns * n Reals).
  void build_snapshot(const Real* host, BodySnapshot& out) const {
    const Index n = store_.size();
    auto col = [&](int c) { return store_.col(host, c); };
    out.name = name_;
    out.body_id = body_id_;
    out.material_type = type_;
    out.n = n;
    out.position.assign(static_cast<std::size_t>(3 * n), 0.0);
    out.id.resize(n);
    out.lost.assign(static_cast<std::size_t>(n), 0);
    auto add = [&](std::string nm, int comps, std::string unit, std::string doc) -> Real* {
      out.fields.push_back({std::move(nm), comps, std::move(unit), std::move(doc),
                            std::vector<Real>(static_cast<std::size_t>(comps * n), 0.0)});
      return out.fields.back().values.data();
    };
    out.fields.clear();
    out.fields.reserve(10 + fields_.size() + extra_.size());
    auto standard = [&](const char* nm) {  // output/field_info.hpp: one table of their units and meaning
      const FieldInfo& f = standard_particle_field(nm);
      return add(f.name, f.components, f.unit, f.doc);
    };
    Real* vel = standard("velocity");
    Real* disp = standard("displacement");
    Real* stress = standard("stress");
    Real* pres = standard("pressure");
    Real* qdev = standard("deviatoricStress");
    Real* vol = standard("volume");
    Real* pmass = standard("mass");
    Real* dens = standard("density");
    Real* bid = standard("bodyId");
    std::vector<Real*> mat;
    for (const auto& f : fields_) mat.push_back(add(f.name, f.components, f.unit, f.doc));
    for (int c = 0, j = 0; j < static_cast<int>(extra_.size()); c += extra_[j].components, ++j) {
      const auto& e = extra_[j];
      if (!e.output) continue;
      const int comps = e.components == 1 ? 1 : 3;
      Real* dst = add(e.name, comps, e.unit, e.doc);
      for (int k = 0; k < e.components; ++k) {
        const Real* src = col(store_.c_extra() + c + k);
        for (Index p = 0; p < n; ++p) dst[static_cast<std::size_t>(comps) * p + k] = src[p];
      }
    }
    std::vector<Real> st(K > 0 ? K : 1);
    for (Index p = 0; p < n; ++p) {
      Sym3 sig = Sym3::zero();
      for (int c = 0; c < kSig; ++c) sig[c] = col(store_.c_sig() + c)[p];
      for (int d = 0; d < D; ++d) {
        out.position[3 * p + d] = col(store_.c_x() + d)[p];
        vel[3 * p + d] = col(store_.c_v() + d)[p];
        disp[3 * p + d] = col(store_.c_x() + d)[p] - col(store_.c_x0() + d)[p];
      }
      for (int c = 0; c < 6; ++c) stress[6 * p + c] = sig[c];
      pres[p] = pressure(sig);
      qdev[p] = deviatoric_stress(sig);
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = col(store_.c_F() + i)[p];
      vol[p] = std::fabs(col(store_.c_vol0())[p]) * det(F);
      out.lost[p] = col(store_.c_vol0())[p] < 0;  // ParticlePass::lost marks a point that left the grid
      pmass[p] = col(store_.c_mass())[p];
      dens[p] = vol[p] > 0 ? col(store_.c_mass())[p] / vol[p] : 0;
      bid[p] = out.body_id;
      out.id[p] = static_cast<std::int64_t>(col(store_.c_id())[p]);
      for (int k = 0; k < K; ++k) st[k] = col(store_.c_state())[static_cast<std::size_t>(k) * n + p];
      for (std::size_t f = 0; f < fields_.size(); ++f)
        fields_[f].eval(&params_, st.data(), sig, mat[f] + p * fields_[f].components);
    }
  }

  void set_velocities(const std::vector<Real>& v) override {
    const Index n = store_.size();
    if (v.size() != static_cast<std::size_t>(D * n))
      throw std::invalid_argument("set_velocities: expected " + std::to_string(D * n) + " values");
    std::vector<Real> col(static_cast<std::size_t>(n));
    for (int d = 0; d < D; ++d) {
      for (Index p = 0; p < n; ++p) col[p] = v[static_cast<std::size_t>(D * p + d)];
      mem::copy(store_.arrays().v[d], exec_.device, col.data(), Device::cpu, col.size() * sizeof(Real));
    }
  }

  std::vector<Real> save_state() const override { return store_.to_host(); }
  void restore_state(const std::vector<Real>& block) override {
    if (block.size() != store_.data().size())
      throw std::invalid_argument("body '" + name_ + "': a state of " + std::to_string(block.size()) +
                                  " values, not " + std::to_string(store_.data().size()));
    // F as the kernels keep it, diag(det F, 1[, 1]) (ParticlePass::stress_update): a state
    // written with the whole F (before that change) continues with its determinant.
    std::vector<Real> s = block;
    const Index n = store_.size();
    const std::size_t cF = static_cast<std::size_t>(store_.c_F());
    for (Index p = 0; p < n; ++p) {
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = s[(cF + i) * n + p];
      const Real J = det(F);
      for (int i = 0; i < D * D; ++i) s[(cF + i) * n + p] = i == 0 ? J : (i % (D + 1) == 0 ? Real(1) : Real(0));
    }
    store_.data().copy_from_host(s);  // same size: the arrays stay bound
    reset_split();
  }

  void replace_state(const std::vector<Real>& block, Index n) override {
    if (block.size() != static_cast<std::size_t>(store_.columns()) * static_cast<std::size_t>(n))
      throw std::invalid_argument("body '" + name_ + "': a block of " + std::to_string(block.size()) +
                                  " values for " + std::to_string(n) + " points of " +
                                  std::to_string(store_.columns()) + " values");
    store_.replace(block, n, exec_.device);
    if constexpr (material_has_elastic_path<M>()) {
      deferred_.resize(static_cast<std::size_t>(n), exec_.device);
      resize_handoff(n);
      reset_split();
    }
  }

  void sort_by_cell(const GridGeometry<D>& g) override { sorter_.sort(store_, exec_, g); }

 private:
  static int extra_column_count(const std::vector<typename BodySetup<D>::ExtraColumn>& e) {
    int c = 0;
    for (const auto& x : e) c += x.components;
    return c;
  }

  /// The deferred points' Handoff, for a material whose update runs in turns.
  void resize_handoff(Index n) {
    if constexpr (material_defers_in_turns<M>())
      handoff_.resize(static_cast<std::size_t>(n) * Handoff<D>::kColumns, exec_.device);
  }

  static constexpr int kTransferBlock = 256;
  static constexpr int kStressBlock = 64;

  template <class Shape>
  void launch(const PassParams<D>& pp, const Shape& shape) {
    // The energy ledger (PassPolicy::energy) runs kernels of its own (ParticlePass's Ledger),
    // dispatched as the fast ones are
    if (pp.policy.energy) launch_pass<true>(pp, shape);
    else launch_pass<false>(pp, shape);
  }

  template <bool Ledger, class Shape>
  void launch_pass(const PassParams<D>& pp, const Shape& shape) {
    // The transfer pass alone: compiled without the stress update (for the ledger, which books
    // the PIC blend's and the walls' shares there, its whole pass needs every register and a
    // stack frame, the light one a fraction and none: ledger_light_transfer)
    if (!pp.policy.reference && (!Ledger || pp.policy.ledger_light_transfer) && (pp.flags & ~kTransferPhases) == 0) {
      ParticlePass<D, Shape, M, kTransferPhases, false, Ledger> k{pp, store_.arrays(), shape, params_};
      parallel_for_warps(exec_, store_.size(), k, kTransferBlock);
      return;
    }
    if constexpr (material_has_elastic_path<M>())
      if (!pp.policy.reference && pp.policy.split_elastic && (pp.flags & kStressPhases)) {
        launch_elastic_first<Ledger>(pp, shape);
        return;
      }
    ParticlePass<D, Shape, M, kAllPhases, false, Ledger> k{pp, store_.arrays(), shape, params_};
    if constexpr (D == 2 && !Ledger)  // the ledger's whole pass runs uncapped
      if (!pp.policy.reference && pp.policy.stress_blocks_per_sm == KernelPolicy::kStressCap) {
        parallel_for_warps_bounded<kStressBlock, KernelPolicy::kStressCap>(exec_, store_.size(), k);
        return;
      }
    parallel_for_warps(exec_, store_.size(), k, pp.policy.reference ? kCudaBlockSize : kStressBlock);
  }

  /// The elastic-first split (PassPolicy::split_elastic): every point through the
  /// elastic-only kernel, then the points it deferred, read from the device-side list (no
  /// host round trip; CUDA-graph safe): for a material whose update runs in turns
  /// (PassPolicy::refill), their updates drawn from the list as a queue (DeferredStress) and
  /// then their scatter; otherwise the whole pass over them. The kernel after the elastic-only
  /// one clears the other parity's counters, which the next step's kernels fill.
  /// Ledger: the kernels keep the energy ledger (PassPolicy::energy).
  template <bool Ledger, class Shape>
  void launch_elastic_first(const PassParams<D>& pp, const Shape& shape) {
    PassParams<D> first = pp;
    first.deferred = deferred_.data();
    first.deferred_count = deferred_count_.data();
    if constexpr (material_has_turns<M>())
      if (pp.policy.refill) first.handoff = handoff_.data();
    ParticlePass<D, Shape, M, kAllPhases, true, Ledger> elastic{first, store_.arrays(), shape, params_};
    bool capped = false;
    if constexpr (D == 2)  // the capped kernel exists only in 2D (no unused 3D instance to compile)
      if (pp.policy.elastic_blocks_per_sm == KernelPolicy::kElasticCap) {
        parallel_for_warps_bounded<kStressBlock, KernelPolicy::kElasticCap>(exec_, store_.size(), elastic);
        capped = true;
      }
    if (!capped) parallel_for_warps(exec_, store_.size(), elastic, kStressBlock);
    // counters: the list's length per parity, then the queue's head per parity
    unsigned* count = deferred_count_.data();
    unsigned* head = count + 2;
    constexpr int kMinBlocks = D == 2 ? KernelPolicy::kStressCap : 1;  // the whole update's register cap
    if constexpr (material_has_turns<M>())
      if (pp.policy.refill) {
        const DeferredStress<D, Shape, M, Ledger> update{{first, store_.arrays(), shape, params_},
                                                         deferred_.data(),
                                                         count + pp.parity,
                                                         head + pp.parity,
                                                         count + (1 - pp.parity),
                                                         head + (1 - pp.parity)};
        parallel_for_queue<kStressBlock, kMinBlocks>(exec_, store_.size(), update);
        if (pp.flags & kAnyScatter) {
          ParticlePass<D, Shape, M, kAnyScatter, false, Ledger> scatter{pp, store_.arrays(), shape, params_};
          parallel_for_listed_warps<kTransferBlock, 1>(exec_, deferred_.data(), count + pp.parity, nullptr,
                                                       store_.size(), kDeferredBlocks, scatter);
        }
        return;
      }
    ParticlePass<D, Shape, M, kAllPhases, false, Ledger> full{pp, store_.arrays(), shape, params_};
    parallel_for_listed_warps<kStressBlock, kMinBlocks>(exec_, deferred_.data(), count + pp.parity,
                                                        count + (1 - pp.parity), store_.size(), kDeferredBlocks, full);
  }
  /// Blocks of the deferred points' kernel (grid-stride): 0 asks parallel_for_listed_warps
  /// for one wave of the device (a fixed count is a fraction of a wave too many or too few
  /// on some device, and the last, partial wave runs alone).
  static constexpr int kDeferredBlocks = 0;

  Params params_;
  std::string name_;
  int body_id_;
  std::string type_;
  Exec exec_;
  ShapeKind shape_;
  Real lp_;
  ParticleStorage<D> store_;
  std::vector<typename BodySetup<D>::ExtraColumn> extra_;
  ParticleSorter<D> sorter_;
  mutable SnapshotCopy copy_;
  Buffer<Index> deferred_;            // the elastic-first split's deferred points
  Buffer<unsigned> deferred_count_;   // their number per step parity, then the queue's head per parity
  Buffer<Real> handoff_;              // what the elastic-only kernel hands their updates over with
  Buffer<unsigned long long> bounded_;  // updates that reached the bound (material_reports_bound)
  std::vector<OutputField> fields_;
};

template <int D, class M>
std::unique_ptr<Body<D>> make_material_body(const typename M::Params& params, const BodySetup<D>& setup) {
  return std::make_unique<MaterialBody<D, M>>(params, setup);
}

}  // namespace scree
