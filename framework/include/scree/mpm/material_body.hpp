// MaterialBody<D, M>: a body of particles with material M, implementing Body<D>.
//
// Instantiated inside the material's plugin by Registry::add_material<M>() (compiled as
// CUDA when the CUDA backend is on), so each plugin carries its own kernels: the
// ParticlePass for each shape function, for the CPU (OpenMP) and the CUDA backend.
//
// Storage: one allocation of `columns * n` Reals, structure of arrays. Columns:
//   x[D] v[D] x0[D] F[D*D] sigma[kStressComponents] mass volume0 id C[D*D] state[K]
// (C only with APIC). Every column is permuted together when particles are sorted.
//
// Kernels (particle_pass.hpp): a pass without stress update runs the light instantiation
// (kTransferPhases: no material code, a fraction of the registers) in blocks of 256; a
// pass with it the full one in blocks of 64 (its occupancy is set by the material's
// registers, and small blocks let the SMs fill in behind warps that take longer, e.g. a
// point that needs many substeps). PassParams::reference runs the full one everywhere.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "scree/material/material.hpp"
#include "scree/mpm/body.hpp"

#if defined(__CUDACC__)
#include <cub/device/device_radix_sort.cuh>
#endif

#include <functional>

namespace scree {

#if defined(__CUDACC__)
namespace detail {
inline void cuda_ok(cudaError_t e) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA error: ") + cudaGetErrorString(e));
}
}  // namespace detail
#endif

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
        transfer_(s.transfer),
        n_(static_cast<Index>(s.x.size())) {
    layout();
    const Index n = n_;
    std::vector<Real> host(static_cast<std::size_t>(columns_ * n), 0.0);
    auto col = [&](int c) { return host.data() + static_cast<std::size_t>(c) * n; };
    const Real rho = M::density(params_);
    for (Index p = 0; p < n; ++p) {
      for (int d = 0; d < D; ++d) {
        col(c_x_ + d)[p] = s.x[p][d];
        col(c_v_ + d)[p] = s.v.empty() ? 0 : s.v[p][d];
        col(c_x0_ + d)[p] = s.x[p][d];
      }
      for (int i = 0; i < D; ++i) col(c_F_ + i * D + i)[p] = 1;
      if (transfer_ == Transfer::apic)
        for (int i = 0; i < D * D; ++i) col(c_C_ + i)[p] = s.velocity_gradient.a[i / D][i % D];
      Sym3 sigma = s.sigma.empty() ? Sym3::zero() : s.sigma[p];
      const State st = M::initial_state(params_, sigma);
      for (int c = 0; c < kSig; ++c) col(c_sig_ + c)[p] = sigma[c];
      col(c_mass_)[p] = rho * s.volume[p];
      col(c_vol0_)[p] = s.volume[p];
      col(c_id_)[p] = static_cast<Real>(s.first_id + p);
      if constexpr (K > 0) {
        Real tmp[K > 0 ? K : 1];
        std::memcpy(tmp, &st, sizeof(State));
        for (int k = 0; k < K; ++k) col(c_state_)[static_cast<std::size_t>(k) * n + p] = tmp[k];
      }
    }
    data_.resize(host.size(), exec_.device);
    data_.copy_from_host(host);
    if constexpr (material_has_elastic_path<M>()) {  // the elastic-first split's list (zeroed)
      deferred_.resize(static_cast<std::size_t>(n), exec_.device);
      deferred_count_.resize(2, exec_.device);
    }
    bind();
    OutputFields<M> out;
    M::describe(out);
    fields_ = out.fields();
  }

  const std::string& name() const override { return name_; }
  bool can_split_stress() const override { return material_has_elastic_path<M>(); }
  void reset_split() override {
    if constexpr (material_has_elastic_path<M>()) parallel_for(exec_, 2, detail::ZeroCounters{deferred_count_.data()});
  }
  const std::string& material_type() const override { return type_; }
  Index size() const override { return n_; }
  const ParticleArrays<D>& arrays() const override { return arrays_; }
  std::size_t bytes_per_particle() const override { return static_cast<std::size_t>(columns_) * sizeof(Real); }

  void pass(const PassParams<D>& pp) override {
    const Real inv_h = 1 / pp.grid.h;
    switch (shape_) {
      case ShapeKind::linear: launch(pp, ShapeLinear{inv_h}); break;
      case ShapeKind::gimp: launch(pp, ShapeGimp{inv_h, lp_}); break;
      case ShapeKind::bspline2: launch(pp, ShapeBspline2{inv_h}); break;
    }
  }

  Real max_signal_speed(Real h) const override {
    const auto host = data_.to_host();
    const Index n = n_;
    auto col = [&](int c) { return host.data() + static_cast<std::size_t>(c) * n; };
    Real cmax = 0;
    for (Index p = 0; p < n; ++p) {
      State st{};
      load_state(st, col(c_state_), n, p);
      Sym3 sig = Sym3::zero();
      for (int c = 0; c < kSig; ++c) sig[c] = col(c_sig_ + c)[p];
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = col(c_F_ + i)[p];
      const Real vol = std::fabs(col(c_vol0_)[p]) * det(F);
      const Real rho = vol > 0 ? col(c_mass_)[p] / vol : M::density(params_);
      Real v2 = 0;
      for (int d = 0; d < D; ++d) v2 += col(c_v_ + d)[p] * col(c_v_ + d)[p];
      cmax = std::max(cmax, M::wave_speed(params_, st, sig, rho, h) + std::sqrt(v2));
    }
    return cmax;
  }

  void snapshot(BodySnapshot& out) const override {
    const auto host = data_.to_host();
    build_snapshot(host.data(), out);
  }

  std::function<void(BodySnapshot&)> snapshot_async(void* copy_stream) override {
#if defined(__CUDACC__)
    if (exec_.device == Device::cuda) {
      // The particle block is copied on the device first (microseconds, ordered after the
      // queued passes on the compute stream), so the next steps may overwrite it at once;
      // the copy to pinned host memory then runs on copy_stream beside them, and the
      // output thread waits for it alone.
      const std::size_t bytes = data_.size() * sizeof(Real);
      auto compute = static_cast<cudaStream_t>(exec_.stream), copy = static_cast<cudaStream_t>(copy_stream);
      if (stage_.size() != data_.size()) {
        stage_.resize(data_.size(), exec_.device);
        mem::synchronize(exec_.device);
      }
      if (stage_free_) detail::cuda_ok(cudaStreamWaitEvent(compute, static_cast<cudaEvent_t>(stage_free_), 0));
      else detail::cuda_ok(cudaEventCreateWithFlags(reinterpret_cast<cudaEvent_t*>(&stage_free_), cudaEventDisableTiming));
      detail::cuda_ok(cudaMemcpyAsync(stage_.data(), data_.data(), bytes, cudaMemcpyDeviceToDevice, compute));
      cudaEvent_t staged, copied;
      detail::cuda_ok(cudaEventCreateWithFlags(&staged, cudaEventDisableTiming));
      detail::cuda_ok(cudaEventCreateWithFlags(&copied, cudaEventDisableTiming));
      detail::cuda_ok(cudaEventRecord(staged, compute));
      detail::cuda_ok(cudaStreamWaitEvent(copy, staged, 0));
      Real* host = acquire_pinned(bytes);
      detail::cuda_ok(cudaMemcpyAsync(host, stage_.data(), bytes, cudaMemcpyDeviceToHost, copy));
      detail::cuda_ok(cudaEventRecord(copied, copy));
      detail::cuda_ok(cudaEventRecord(static_cast<cudaEvent_t>(stage_free_), copy));
      cudaEventDestroy(staged);  // released once it has completed
      return [this, host, copied](BodySnapshot& out) {
        cudaEventSynchronize(copied);
        cudaEventDestroy(copied);
        build_snapshot(host, out);
        release_pinned(host);
      };
    }
#endif
    return Body<D>::snapshot_async(copy_stream);
  }

  ~MaterialBody() override {
#if defined(__CUDACC__)
    if (stage_free_) cudaEventDestroy(static_cast<cudaEvent_t>(stage_free_));
#endif
    for (Real* p : pinned_free_) mem::deallocate_pinned(p);
  }

  /// Pinned host buffers for snapshot_async, reused (page-locking memory costs
  /// milliseconds, and would stop the run at every snapshot).
  Real* acquire_pinned(std::size_t bytes) {
    {
      std::lock_guard lock(pinned_mutex_);
      if (!pinned_free_.empty()) {
        Real* p = pinned_free_.back();
        pinned_free_.pop_back();
        return p;
      }
    }
    return static_cast<Real*>(mem::allocate_pinned(bytes));
  }
  void release_pinned(Real* p) {
    std::lock_guard lock(pinned_mutex_);
    pinned_free_.push_back(p);
  }

  /// The snapshot from a host copy of the particle block (columns * n Reals).
  void build_snapshot(const Real* host, BodySnapshot& out) const {
    const Index n = n_;
    auto col = [&](int c) { return host + static_cast<std::size_t>(c) * n; };
    out.name = name_;
    out.body_id = body_id_;
    out.material_type = type_;
    out.n = n;
    out.position.assign(static_cast<std::size_t>(3 * n), 0.0);
    out.id.resize(n);
    auto add = [&](std::string nm, int comps, std::string unit, std::string doc) -> Real* {
      out.fields.push_back({std::move(nm), comps, std::move(unit), std::move(doc),
                            std::vector<Real>(static_cast<std::size_t>(comps * n), 0.0)});
      return out.fields.back().values.data();
    };
    out.fields.clear();
    out.fields.reserve(10 + fields_.size());
    Real* vel = add("velocity", 3, "m/s", "particle velocity");
    Real* disp = add("displacement", 3, "m", "displacement from the initial position");
    Real* stress = add("stress", 6, "Pa", "Cauchy stress, tension positive (xx yy zz xy yz zx)");
    Real* pres = add("pressure", 1, "Pa", "mean stress p = -tr(sigma)/3, compression positive");
    Real* qdev = add("deviatoricStress", 1, "Pa", "von Mises stress q = sqrt(3/2 s:s)");
    Real* vol = add("volume", 1, "m^3", "current volume (area per unit thickness in 2D)");
    Real* pmass = add("mass", 1, "kg", "particle mass (per unit thickness in 2D)");
    Real* dens = add("density", 1, "kg/m^3", "mass / current volume");
    Real* bid = add("bodyId", 1, "-", "index of the body in constant/bodies");
    std::vector<Real*> mat;
    for (const auto& f : fields_) mat.push_back(add(f.name, f.components, f.unit, f.doc));
    std::vector<Real> st(K > 0 ? K : 1);
    for (Index p = 0; p < n; ++p) {
      Sym3 sig = Sym3::zero();
      for (int c = 0; c < kSig; ++c) sig[c] = col(c_sig_ + c)[p];
      for (int d = 0; d < D; ++d) {
        out.position[3 * p + d] = col(c_x_ + d)[p];
        vel[3 * p + d] = col(c_v_ + d)[p];
        disp[3 * p + d] = col(c_x_ + d)[p] - col(c_x0_ + d)[p];
      }
      for (int c = 0; c < 6; ++c) stress[6 * p + c] = sig[c];
      pres[p] = pressure(sig);
      qdev[p] = deviatoric_stress(sig);
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = col(c_F_ + i)[p];
      vol[p] = std::fabs(col(c_vol0_)[p]) * det(F);
      pmass[p] = col(c_mass_)[p];
      dens[p] = vol[p] > 0 ? col(c_mass_)[p] / vol[p] : 0;
      bid[p] = out.body_id;
      out.id[p] = static_cast<std::int64_t>(col(c_id_)[p]);
      for (int k = 0; k < K; ++k) st[k] = col(c_state_)[static_cast<std::size_t>(k) * n + p];
      for (std::size_t f = 0; f < fields_.size(); ++f)
        fields_[f].eval(&params_, st.data(), sig, mat[f] + p * fields_[f].components);
    }
  }

  void set_velocities(const std::vector<Real>& v) override {
    if (v.size() != static_cast<std::size_t>(D * n_))
      throw std::invalid_argument("set_velocities: expected " + std::to_string(D * n_) + " values");
    std::vector<Real> col(static_cast<std::size_t>(n_));
    for (int d = 0; d < D; ++d) {
      for (Index p = 0; p < n_; ++p) col[p] = v[static_cast<std::size_t>(D * p + d)];
      mem::copy(arrays_.v[d], exec_.device, col.data(), Device::cpu, col.size() * sizeof(Real));
    }
  }

  void sort_by_cell(const GridGeometry<D>& g) override {
    if (n_ < 2) return;
    // Key: the flat index of the cell holding the particle (x fastest), 32 bits; a stable
    // sort of the keys (CUB radix sort on the GPU) gives the permutation, through which
    // every column is gathered, a few columns at a time via a scratch block. All of it is
    // queued on the body's stream after the passes before it: no host round trip. The
    // buffers are kept for the next sort.
    const Index n = n_;
    const std::size_t un = static_cast<std::size_t>(n);
    if (sort_keys_.size() != 2 * un) {
      sort_keys_.resize(2 * un, exec_.device);
      sort_perm_.resize(2 * un, exec_.device);
      // Small bodies gather every column in one kernel; large ones 4 at a time (memory).
      sort_chunk_ = un * columns_ * sizeof(Real) <= (std::size_t(64) << 20) ? columns_ : std::min(columns_, 4);
      sort_scratch_.resize(static_cast<std::size_t>(sort_chunk_) * un, exec_.device);
#if defined(__CUDACC__)
      if (exec_.device == Device::cuda) {
        cub::DoubleBuffer<std::uint32_t> k(sort_keys_.data(), sort_keys_.data() + un),
            v(sort_perm_.data(), sort_perm_.data() + un);
        std::size_t bytes = 0;
        cub::DeviceRadixSort::SortPairs(nullptr, bytes, k, v, static_cast<int>(n), 0, 32);
        sort_temp_.resize(bytes, exec_.device);
      }
#endif
      mem::synchronize(exec_.device);  // the buffers' zero fill ran on the default stream
    }
    std::uint32_t* kp = sort_keys_.data();
    std::uint32_t* pp = sort_perm_.data();
    ParticleArrays<D> a = arrays_;
    const GridGeometry<D> geo = g;
    std::uint64_t cells = 1;
    for (int d = 0; d < D; ++d) cells *= static_cast<std::uint64_t>(g.n[d]);
    parallel_for(exec_, n, [=] SCREE_HD(Index p) {
      std::uint32_t key = 0, s = 1;
      for (int d = 0; d < D; ++d) {
        int c = static_cast<int>(floor((a.x[d][p] - geo.origin[d]) / geo.h));
        c = c < 0 ? 0 : (c >= geo.n[d] ? geo.n[d] - 1 : c);
        key += static_cast<std::uint32_t>(c) * s;
        s *= static_cast<std::uint32_t>(geo.n[d]);
      }
      kp[p] = key;
      pp[p] = static_cast<std::uint32_t>(p);
    });
    const std::uint32_t* order = pp;
    if (exec_.device == Device::cuda) {
#if defined(__CUDACC__)
      int bits = 1;
      while (bits < 32 && (std::uint64_t(1) << bits) < cells) ++bits;
      cub::DoubleBuffer<std::uint32_t> k(kp, kp + un), v(pp, pp + un);
      std::size_t bytes = sort_temp_.size();
      cub::DeviceRadixSort::SortPairs(sort_temp_.data(), bytes, k, v, static_cast<int>(n), 0, bits,
                                      static_cast<cudaStream_t>(exec_.stream));
      check_cuda_launch("sort_by_cell: radix sort");
      order = v.Current();
#else
      throw std::logic_error("sort_by_cell: CUDA bodies need their material compiled as CUDA");
#endif
    } else {
      std::stable_sort(pp, pp + n, [kp](std::uint32_t i, std::uint32_t j) { return kp[i] < kp[j]; });
    }
    // column[i] <- column[order[i]] for every column, sort_chunk_ columns per kernel.
    Real* base = data_.data();
    Real* tmp = sort_scratch_.data();
    for (int c0 = 0; c0 < columns_; c0 += sort_chunk_) {
      const int nc = std::min(sort_chunk_, columns_ - c0);
      Real* first = base + static_cast<std::size_t>(c0) * un;
      parallel_for(exec_, n * nc, [=] SCREE_HD(Index j) {
        const Index c = j / n, i = j - c * n;
        tmp[j] = first[c * n + order[i]];
      });
      mem::copy_async(first, exec_.device, tmp, exec_.device, static_cast<std::size_t>(n * nc) * sizeof(Real),
                      exec_.stream);
    }
  }

 private:
  void layout() {
    int c = 0;
    c_x_ = c;
    c += D;
    c_v_ = c;
    c += D;
    c_x0_ = c;
    c += D;
    c_F_ = c;
    c += D * D;
    c_sig_ = c;
    c += kSig;
    c_mass_ = c++;
    c_vol0_ = c++;
    c_id_ = c++;
    c_C_ = c;
    if (transfer_ == Transfer::apic) c += D * D;
    c_state_ = c;
    c += K;
    columns_ = c;
  }
  void bind() {
    Real* b = data_.data();
    const Index n = n_;
    auto col = [&](int c) { return b + static_cast<std::size_t>(c) * n; };
    arrays_.n = n;
    for (int d = 0; d < D; ++d) {
      arrays_.x[d] = col(c_x_ + d);
      arrays_.v[d] = col(c_v_ + d);
    }
    for (int i = 0; i < D * D; ++i) {
      arrays_.F[i] = col(c_F_ + i);
      arrays_.C[i] = transfer_ == Transfer::apic ? col(c_C_ + i) : nullptr;
    }
    for (int c = 0; c < kSig; ++c) arrays_.sigma[c] = col(c_sig_ + c);
    arrays_.mass = col(c_mass_);
    arrays_.volume0 = col(c_vol0_);
    arrays_.state = col(c_state_);
  }
  static constexpr int kTransferBlock = 256;
  static constexpr int kStressBlock = 64;

  template <class Shape>
  void launch(const PassParams<D>& pp, const Shape& shape) {
    if (!pp.reference && (pp.flags & ~kTransferPhases) == 0) {
      ParticlePass<D, Shape, M, kTransferPhases> k{pp, arrays_, shape, params_};
      parallel_for_warps(exec_, n_, k, kTransferBlock);
    } else {
      if constexpr (material_has_elastic_path<M>())
        if (!pp.reference && pp.split_elastic && (pp.flags & kStressPhases)) {
          launch_elastic_first(pp, shape);
          return;
        }
      ParticlePass<D, Shape, M, kAllPhases> k{pp, arrays_, shape, params_};
      if constexpr (D == 2)
        if (!pp.reference && pp.stress_blocks_per_sm == 6) {
          parallel_for_warps_bounded<kStressBlock, 6>(exec_, n_, k);
          return;
        }
      parallel_for_warps(exec_, n_, k, pp.reference ? kCudaBlockSize : kStressBlock);
    }
  }

  /// The elastic-first split (PassParams::split_elastic): every point through the
  /// elastic-only kernel, then the whole pass over the points it deferred, read from the
  /// device-side list (no host round trip; CUDA-graph safe). The second kernel clears the
  /// other parity's counter, which the next step's first kernel fills.
  template <class Shape>
  void launch_elastic_first(const PassParams<D>& pp, const Shape& shape) {
    PassParams<D> first = pp;
    first.deferred = deferred_.data();
    first.deferred_count = deferred_count_.data();
    ParticlePass<D, Shape, M, kAllPhases, true> elastic{first, arrays_, shape, params_};
    bool capped = false;
    if constexpr (D == 2)  // the capped kernel exists only in 2D (no unused 3D instance to compile)
      if (pp.elastic_blocks_per_sm == kElasticBlocks2D) {
        parallel_for_warps_bounded<kStressBlock, kElasticBlocks2D>(exec_, n_, elastic);
        capped = true;
      }
    if (!capped) parallel_for_warps(exec_, n_, elastic, kStressBlock);
    ParticlePass<D, Shape, M, kAllPhases> full{pp, arrays_, shape, params_};
    unsigned* count = deferred_count_.data();
    constexpr int kMinBlocks = D == 2 ? 6 : 1;  // the whole update's register cap, as launch()
    parallel_for_listed_warps<kStressBlock, kMinBlocks>(exec_, deferred_.data(), count + pp.parity,
                                                        count + (1 - pp.parity), n_, kDeferredBlocks, full);
  }
  /// The 2D elastic-only kernel's register cap (PassParams::elastic_blocks_per_sm) as
  /// blocks of 64 per SM: 10 is 96 registers and 20 warps per SM, with 300-600 bytes of
  /// spills (nvcc 13, phaseTransition); the compiler alone takes 146 (14 warps), and the
  /// whole update 254, capped to 168 (12 warps).
  static constexpr int kElasticBlocks2D = 10;
  /// Blocks of the deferred points' kernel (grid-stride): 0 asks parallel_for_listed_warps
  /// for one wave of the device (1,024 fixed was 1.3 waves on an H100 at 6 blocks per SM:
  /// a tail of 0.3 wave; performance log, entry 17).
  static constexpr int kDeferredBlocks = 0;

  Params params_;
  std::string name_;
  int body_id_;
  std::string type_;
  Exec exec_;
  ShapeKind shape_;
  Real lp_;
  Transfer transfer_;
  Index n_;
  int columns_ = 0, c_x_ = 0, c_v_ = 0, c_x0_ = 0, c_F_ = 0, c_sig_ = 0, c_mass_ = 0, c_vol0_ = 0, c_id_ = 0,
      c_C_ = 0, c_state_ = 0;
  Buffer<Real> data_;
  ParticleArrays<D> arrays_{};
  // sort_by_cell's buffers (kept between sorts): keys and permutation (double-buffered
  // for the radix sort), CUB's temporary storage, and a scratch block of sort_chunk_ columns
  Buffer<std::uint32_t> sort_keys_, sort_perm_;
  // snapshot_async's device copy of the particle block, and the event after which the
  // copy stream has read it (the next snapshot's device copy waits for it)
  Buffer<Real> stage_;
  void* stage_free_ = nullptr;
  std::mutex pinned_mutex_;
  std::vector<Real*> pinned_free_;
  Buffer<Index> deferred_;            // the elastic-first split's deferred points
  Buffer<unsigned> deferred_count_;   // their number, one counter per step parity
  Buffer<char> sort_temp_;
  Buffer<Real> sort_scratch_;
  int sort_chunk_ = 0;
  std::vector<OutputField> fields_;
};

template <int D, class M>
std::unique_ptr<Body<D>> make_material_body(const typename M::Params& params, const BodySetup<D>& setup) {
  return std::make_unique<MaterialBody<D, M>>(params, setup);
}

}  // namespace scree
