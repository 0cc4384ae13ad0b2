// The overburden of the geostatic initial stress: the weight of the material above a point.
//
//   sigma_v(x) = -|g| sum_b int_{z(x)}^{inf} rho_b(z') chi_b(x_h, z') dz'        [Pa]
//
// (tension positive, so the weight is a compression, negative), with z the elevation along
// up = -g/|g|, x_h the point's horizontal place, chi_b the indicator of body b's material
// and rho_b its density [kg/m^3]: a constant, or for a two-phase body the mixture's
// (1 - n0) rho_s + n0 S_l(p_w(z)) rho_l, varying with the elevation (DensityProfile).
//
// The material is the bodies' generation lattice (case/particle_generation.hpp): a body's
// point stands for the sub-cell of side sub = h/n about it. The columns of a body are the
// lines of its lattice along the vertical axis, one per horizontal sub-cell; in a column the
// points form runs of consecutive sub-cells, each run the interval from its lowest point's
// elevation - sub/2 to its highest point's + sub/2. The integral over body b at x is taken
// in b's column that holds x_h (floor((x_h - origin) / sub_b)), over the parts of its runs
// above z(x). A point's own sub-cell counts from z(x) up: half of it, so the top point of a
// level body carries rho g sub/2, as `overburden body`'s surface (top point + sub/2) gives.
// A gap in a column (an overhang, a cave) does not relieve the points below it: they carry
// the roof as well (the column's weight; arching across the gap is not modelled).
// Against the continuous integral over the region at the column's centre the column sum errs
// only where a region's face crosses the column: the column's material there ends at the edge
// of the last sub-cell whose centre is inside, within sub/2 of the face's height over the
// centre, so by at most rho |g| sub/2 per crossing face (tests/unit/case/test_overburden.cpp).
//
// The columns need gravity along one axis of the grid (each column a lattice line); the
// whole lattice of every body is walked on every rank, so a decomposed run's ranks hold the
// same columns and the stress of a point does not depend on the decomposition. Memory: per
// column, not per point: one run per column of a body without overhangs (two elevations, a
// column key and an index, 28 bytes), and while a body is added its runs (40 bytes) and a
// hash map entry per column. A 3D body of 1e6 points 100 points high: 1e4 columns, under
// 1 MB; every rank of a decomposed run holds the whole case's columns, not its points.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <unordered_map>
#include <vector>

#include "scree/core/tensor.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/mpm/grid.hpp"

namespace scree {

/// A body's density [kg/m^3] against the elevation z [m] along -g: `rho` where `profile`
/// is empty, else profile(z) (a two-phase body's mixture, porous/porous_media.cpp).
struct DensityProfile {
  Real rho = 0;
  std::function<Real(Real)> profile;
};

/// int_a^b rho(z) dz [kg/m^2] over one body's elevations: rho (b - a) for a constant
/// density; for a profile, a table of its running integral by the midpoint rule in steps of
/// at most 1 mm over [lo, hi], interpolated linearly (b, a clamped to [lo, hi]).
class SCREE_API DensityIntegral {
 public:
  DensityIntegral() = default;
  DensityIntegral(const DensityProfile& rho, Real lo, Real hi);
  Real between(Real a, Real b) const;
  Real density() const { return rho_; }
  bool constant() const { return table_.empty(); }

 private:
  Real at(Real z) const;
  Real rho_ = 0, lo_ = 0, dz_ = 1;
  std::vector<Real> table_;  ///< int_lo^{lo + i dz} rho dz
};

/// The index of the one axis gravity acts along, or -1 if it has more than one non-zero
/// component (or none).
template <int D>
SCREE_API int gravity_axis(const Vec<D>& gravity);

template <int D>
class SCREE_API Overburden {
 public:
  /// Throws std::invalid_argument unless gravity acts along one axis (gravity_axis >= 0).
  explicit Overburden(const Vec<D>& gravity);

  /// Adds every point of `body` (validated against CoreSpecs::body), in any order of bodies.
  void add_body(const Dictionary& body, const GridGeometry<D>& grid, const DensityProfile& rho,
                const std::filesystem::path& case_dir = {});
  /// The same, point by point: begin_body, add_point for each point of the body's lattice
  /// (spacing `sub`, lattice origin `origin`) in generate_particles' order, end_body.
  void begin_body(Real sub, const Vec<D>& origin, const DensityProfile& rho);
  void add_point(const Vec<D>& x);
  void end_body();

  /// sigma_v at x [Pa], compression negative: -|g| times the mass per area above x in its
  /// column, over every body added. Bodies of constant density add (-rho |g|) times their
  /// length above x, so one level body gives -rho |g| ((top + sub/2) - z) to the bit.
  Real vertical_stress(const Vec<D>& x) const;
  /// The elevation of x along -g, as vertical_stress measures it.
  Real elevation(const Vec<D>& x) const { return dot(x, up_); }

 private:
  struct Run {
    Real lo, hi;  ///< elevations of the run's lowest and highest points (not their edges)
  };
  struct Body {
    Real sub = 0;
    Vec<D> origin;
    DensityIntegral rho;
    std::vector<std::uint64_t> columns;  ///< sorted column keys
    std::vector<std::uint32_t> first;    ///< runs of columns[c]: first[c] .. first[c + 1]
    std::vector<Run> runs;
  };
  std::uint64_t column_key(const Body& b, const Vec<D>& x) const;

  Vec<D> up_;
  Real g_ = 0;
  int axis_ = -1;
  std::vector<Body> bodies_;
  // While a body is added: its runs so far, and each column's last run (a point one sub-cell
  // above it extends it; the lattice order brings a column's points upwards along the axis).
  struct Pending {
    std::uint64_t column;
    std::int64_t k_lo, k_hi;  ///< vertical lattice indices of the run's ends
    Real z_lo, z_hi;          ///< their elevations
  };
  std::vector<Pending> pending_;
  std::unordered_map<std::uint64_t, std::size_t> last_run_;
  DensityProfile pending_rho_;
};

}  // namespace scree
