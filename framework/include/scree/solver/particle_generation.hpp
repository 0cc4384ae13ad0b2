// Filling a body's region with particles (constant/bodies).
//
// The region (rectangle/box, or polygon in 2D) is filled with n points per cell along
// each axis, at the centres of the n^D sub-cells of each background cell, keeping the
// points inside the region; each point carries the volume (h/n)^D of its sub-cell.
// Initial velocity: uniform `velocity`, plus a rigid rotation `angularVelocity` about
// the region's centroid (or `rotationCentre`): v = v0 + omega x (x - c).
// Geostatic initial stress:
//   sigma_v = -rho |g| (s - z),  sigma_h = K0 sigma_v  (tension positive)
// with z the elevation along -g and s the free-surface elevation (default: the top of
// the body), so a column of height H starts with sigma_v = -rho g H at its base.
// Bodies may not overlap unless one of them says `allowOverlap yes` (check_bodies).
#pragma once

#include <vector>

#include "scree/core/tensor.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/mpm/grid.hpp"

namespace scree {

template <int D>
struct GeneratedParticles {
  std::vector<Vec<D>> x, v;
  std::vector<Real> volume;
  std::vector<Sym3> sigma;
  Mat<D> velocity_gradient = Mat<D>::zero();  ///< of the initial velocity field
};

/// Generate the particles of one body dictionary (validated against CoreSpecs::body).
/// `density` is the material's initial mass density (for the geostatic stress). Throws
/// InputError, at the region's file:line, for a region that does not fit the case or
/// the grid (see check_bodies).
template <int D>
SCREE_API GeneratedParticles<D> generate_particles(const Dictionary& body, const GridGeometry<D>& grid,
                                                   Real density, const Vec<D>& gravity);

/// The number of particles generate_particles makes for `body` with `particles_per_cell`
/// points per cell along each axis on cells of size `cell_size`, estimated without making
/// them: the region's area (volume in 3D) times (particles_per_cell / cell_size)^D, the
/// points' density (the cut cells along the region's edge aside). 0 for a region that
/// does not fit the case (check_bodies reports it). A double: a case may ask for more
/// points than any integer type holds.
template <int D>
SCREE_API double estimate_particle_count(const Dictionary& body, Real cell_size, int particles_per_cell);

/// The checks of every body of constant/bodies against the grid, without keeping any
/// particle (scree --check runs them, and every run before it allocates anything):
///   - each region fits the case (rectangle in 2D, box in 3D, a polygon of 3 or more
///     vertices in 2D) and holds at least one particle position;
///   - no particle lies outside the domain of system/gridDict;
///   - no body has particles inside another body's region (both ways): two bodies in
///     one place double the mass there. A body with `allowOverlap yes` may overlap.
/// Each problem is appended to `errors` at the region's file:line; an overlap names the
/// other body's region and its file:line.
template <int D>
SCREE_API void check_bodies(const Dictionary& bodies, const GridGeometry<D>& grid, std::vector<InputError>& errors);

}  // namespace scree
