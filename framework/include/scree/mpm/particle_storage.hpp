// ParticleStorage<D>: one body's particle data, structure of arrays in one allocation.
//
// Columns of n Reals each:
//   x[D] v[D] x0[D] F[D*D] sigma[kStressComponents] mass volume0 id C[D*D] state[K] extra[E]
// (C only with APIC; extra: columns a formulation adds to every point, e.g. the pore
// fluid's of a two-phase body, porous/two_phase.hpp). Every column is permuted together when particles are sorted
// (particle_sort.hpp); a snapshot copies the whole block (snapshot_copy.hpp). The material
// decides only K, the number of Reals of its State.
#pragma once

#include <cstring>
#include <vector>

#include "scree/exec/memory.hpp"
#include "scree/mpm/body.hpp"
#include "scree/mpm/particle_pass.hpp"

namespace scree {

template <int D>
class ParticleStorage {
 public:
  static constexpr int kSig = kStressComponents<D>;
  /// The columns every block starts with, whatever its material: x, v, x0, F, sigma, mass,
  /// volume0 (negative: a point that left the grid), id.
  static constexpr int kColX = 0, kColV = D, kColX0 = 2 * D, kColF = 3 * D, kColSigma = 3 * D + D * D,
                       kColMass = kColSigma + kSig, kColVolume0 = kColMass + 1, kColId = kColMass + 2;

  /// Lay out the columns for n particles with K state Reals (and C with APIC).
  ParticleStorage(Index n, int K, Transfer transfer, int extra = 0)
      : n_(n), K_(K), E_(extra), transfer_(transfer) {
    layout();
  }

  Index size() const { return n_; }
  int columns() const { return columns_; }
  int state_reals() const { return K_; }
  std::size_t bytes_per_particle() const { return static_cast<std::size_t>(columns_) * sizeof(Real); }

  /// Column c of a host copy of the block (columns() * n Reals).
  const Real* col(const Real* block, int c) const { return block + static_cast<std::size_t>(c) * n_; }
  Real* col(Real* block, int c) const { return block + static_cast<std::size_t>(c) * n_; }
  /// Column indices.
  int c_x() const { return c_x_; }
  int c_v() const { return c_v_; }
  int c_x0() const { return c_x0_; }
  int c_F() const { return c_F_; }
  int c_sig() const { return c_sig_; }
  int c_mass() const { return c_mass_; }
  int c_vol0() const { return c_vol0_; }
  int c_id() const { return c_id_; }
  int c_C() const { return c_C_; }
  int c_state() const { return c_state_; }
  int c_extra() const { return c_extra_; }
  int extra_columns() const { return E_; }
  /// The first extra column on the backend (column j at extra() + j n); null without any.
  Real* extra() const { return E_ > 0 ? const_cast<Real*>(data_.data()) + static_cast<std::size_t>(c_extra_) * n_ : nullptr; }

  /// Upload a host block to `device` and point the arrays at it.
  void upload(const std::vector<Real>& host, Device device) {
    data_.resize(host.size(), device);
    data_.copy_from_host(host);
    bind();
  }
  /// Hold the n particles of a host block instead (another count allowed), on `device`.
  void replace(const std::vector<Real>& host, Index n, Device device) {
    n_ = n;
    upload(host, device);
  }
  /// A host copy of the block.
  std::vector<Real> to_host() const { return data_.to_host(); }
  Buffer<Real>& data() { return data_; }
  const Buffer<Real>& data() const { return data_; }
  const ParticleArrays<D>& arrays() const { return arrays_; }

 private:
  void layout() {
    c_x_ = kColX;
    c_v_ = kColV;
    c_x0_ = kColX0;
    c_F_ = kColF;
    c_sig_ = kColSigma;
    c_mass_ = kColMass;
    c_vol0_ = kColVolume0;
    c_id_ = kColId;
    int c = kColId + 1;
    c_C_ = c;
    if (transfer_ == Transfer::apic) c += D * D;
    c_state_ = c;
    c += K_;
    c_extra_ = c;
    c += E_;
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

  Index n_;
  int K_;
  int E_;
  Transfer transfer_;
  int columns_ = 0, c_x_ = 0, c_v_ = 0, c_x0_ = 0, c_F_ = 0, c_sig_ = 0, c_mass_ = 0, c_vol0_ = 0, c_id_ = 0,
      c_C_ = 0, c_state_ = 0, c_extra_ = 0;
  Buffer<Real> data_;
  ParticleArrays<D> arrays_{};
};

}  // namespace scree
