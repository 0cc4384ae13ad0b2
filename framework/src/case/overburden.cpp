// The overburden of the geostatic initial stress (see overburden.hpp).
#include "scree/case/overburden.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scree/case/particle_generation.hpp"
#include "scree/case/settings.hpp"

namespace scree {

DensityIntegral::DensityIntegral(const DensityProfile& rho, Real lo, Real hi) : rho_(rho.rho), lo_(lo) {
  if (!rho.profile) return;
  // The midpoint rule in steps of at most 1 mm: the mixture's density changes with S_l over
  // the capillary fringe, metres to centimetres thick for the retention curves of soils.
  const Real span = std::max(hi - lo, Real(1e-3));
  const int steps = std::max(1, static_cast<int>(std::ceil(span / 1e-3)));
  dz_ = span / steps;
  table_.assign(static_cast<std::size_t>(steps) + 1, 0);
  for (int i = 0; i < steps; ++i) table_[i + 1] = table_[i] + dz_ * rho.profile(lo + (i + Real(0.5)) * dz_);
}

Real DensityIntegral::at(Real z) const {
  const int steps = static_cast<int>(table_.size()) - 1;
  const Real u = std::min(Real(steps), std::max(Real(0), (z - lo_) / dz_));
  const int i = std::min(steps - 1, static_cast<int>(u));
  return table_[i] + (u - i) * (table_[i + 1] - table_[i]);
}

Real DensityIntegral::between(Real a, Real b) const {
  if (!(b > a)) return 0;
  return table_.empty() ? rho_ * (b - a) : at(b) - at(a);
}

template <int D>
int gravity_axis(const Vec<D>& gravity) {
  int axis = -1;
  for (int d = 0; d < D; ++d)
    if (gravity[d] != 0) {
      if (axis >= 0) return -1;
      axis = d;
    }
  return axis;
}

template <int D>
Overburden<D>::Overburden(const Vec<D>& gravity) : axis_(gravity_axis(gravity)) {
  if (axis_ < 0)
    throw std::invalid_argument("the overburden's columns need gravity along one axis of the grid");
  g_ = norm(gravity);
  // As generate_particles takes it, so that a level body's stress is the same to the bit.
  up_ = gravity * (-1 / g_);
}

template <int D>
std::uint64_t Overburden<D>::column_key(const Body& b, const Vec<D>& x) const {
  // The horizontal lattice indices of x in b's lattice (points sit at origin + (j + 1/2) sub).
  std::uint64_t key = 0;
  for (int d = D - 1; d >= 0; --d) {
    if (d == axis_) continue;
    const auto j = static_cast<std::int64_t>(std::floor((x[d] - b.origin[d]) / b.sub));
    key = (key << 32) | static_cast<std::uint32_t>(j);
  }
  return key;
}

template <int D>
void Overburden<D>::begin_body(Real sub, const Vec<D>& origin, const DensityProfile& rho) {
  Body b;
  b.sub = sub;
  b.origin = origin;
  bodies_.push_back(std::move(b));
  pending_rho_ = rho;
  pending_.clear();
  last_run_.clear();
}

template <int D>
void Overburden<D>::add_point(const Vec<D>& x) {
  const Body& b = bodies_.back();
  const std::uint64_t column = column_key(b, x);
  const auto k = static_cast<std::int64_t>(std::floor((x[axis_] - b.origin[axis_]) / b.sub));
  const Real z = elevation(x);
  const auto [it, first] = last_run_.try_emplace(column, pending_.size());
  if (!first) {
    Pending& r = pending_[it->second];
    if (k == r.k_hi + 1) {
      r.k_hi = k;
      r.z_hi = z;
      return;
    }
    it->second = pending_.size();  // a gap in the column (an overhang): a new run
  }
  pending_.push_back({column, k, k, z, z});
}

template <int D>
void Overburden<D>::end_body() {
  Body& b = bodies_.back();
  std::sort(pending_.begin(), pending_.end(), [](const Pending& p, const Pending& q) {
    return p.column != q.column ? p.column < q.column : p.k_lo < q.k_lo;
  });
  Real lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const Pending& p = pending_[i];
    if (i == 0 || p.column != pending_[i - 1].column) {
      b.columns.push_back(p.column);
      b.first.push_back(static_cast<std::uint32_t>(b.runs.size()));
    }
    // Elevation falls along the axis where gravity points along it: the run's ends either way.
    const Run r{std::min(p.z_lo, p.z_hi), std::max(p.z_lo, p.z_hi)};
    b.runs.push_back(r);
    lo = std::min(lo, r.lo);
    hi = std::max(hi, r.hi);
  }
  b.first.push_back(static_cast<std::uint32_t>(b.runs.size()));
  b.rho = DensityIntegral(pending_rho_, lo - b.sub, hi + b.sub);
  pending_ = {};
  last_run_ = {};
  pending_rho_ = {};
}

template <int D>
void Overburden<D>::add_body(const Dictionary& body, const GridGeometry<D>& grid, const DensityProfile& rho,
                             const std::filesystem::path& case_dir) {
  begin_body(grid.h / BodySettings::read(body).particles_per_cell, grid.origin, rho);
  for_each_particle_position<D>(body, grid, [this](const Vec<D>& x) { add_point(x); }, case_dir);
  end_body();
}

template <int D>
Real Overburden<D>::vertical_stress(const Vec<D>& x) const {
  const Real z = elevation(x);
  Real sv = 0;
  for (const Body& b : bodies_) {
    const std::uint64_t key = column_key(b, x);
    const auto it = std::lower_bound(b.columns.begin(), b.columns.end(), key);
    if (it == b.columns.end() || *it != key) continue;
    const std::size_t c = static_cast<std::size_t>(it - b.columns.begin());
    // Each run is the interval [lo - sub/2, hi + sub/2] of the body's material; the part
    // above z counts (x's own sub-cell from z up).
    Real length = 0, mass = 0;
    for (std::uint32_t r = b.first[c]; r < b.first[c + 1]; ++r) {
      const Real top = b.runs[r].hi + Real(0.5) * b.sub;
      if (!(top > z)) continue;
      const Real bottom = std::max(b.runs[r].lo - Real(0.5) * b.sub, z);
      length += top - bottom;
      mass += b.rho.between(bottom, top);
    }
    sv += b.rho.constant() ? (-b.rho.density() * g_) * length : -g_ * mass;
  }
  return sv;
}

template SCREE_API int gravity_axis<2>(const Vec<2>&);
template SCREE_API int gravity_axis<3>(const Vec<3>&);
template class Overburden<2>;
template class Overburden<3>;

}  // namespace scree
