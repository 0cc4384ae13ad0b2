// Filling a body's region with particles (constant/bodies).
//
// The region is filled with n points per cell along each axis, at the centres of the n^D
// sub-cells of each background cell, keeping the points inside the region; each point
// carries the volume (h/n)^D of its sub-cell. Regions: rectangle and polygon in 2D; box,
// cylinder, sphere, extrudedPolygon and stl in 3D (geometry/shapes.hpp, tri_surface.hpp;
// their keys are documented by the body spec, case/case.cpp, and `scree --list-plugins`).
// A body's `clip { lower (..); upper (..); }` keeps the points inside that box as well
// (a quarter cylinder beside two symmetry planes). The mass of a body is rho times the
// volume of its sub-cells whose centres are inside: within the volume of the shell of
// half-width sqrt(D)/2 h/n about the region's surface of the exact rho V.
// Initial velocity: uniform `velocity`, plus a rigid rotation `angularVelocity` about
// the region's centroid (or `rotationCentre`): v = v0 + omega x (x - c).
// Geostatic initial stress (initialStress { type geostatic; K0; overburden; surface; }):
//   sigma_v = -|g| int_z^inf rho dz (the material above),  sigma_h = K0 sigma_v  (tension positive)
// with z the elevation along -g. `overburden all` (the default): the material above the
// point in its own column, of every body the caller adds to the Overburden
// (case/overburden.hpp; without one, the body's own columns), so a slope drawn as one
// polygon loads its toe with the soil above the toe, and layers of bodies with their own
// densities. A body standing alone with a level top gets sigma_v = -rho |g| (s - z) with s
// its top particle plus half a spacing, as `overburden body` gives, to the bit.
// `overburden body`, or a given `surface`: one level s for the whole body (the highest
// point plus half a spacing, or `surface`), sigma_v = -rho |g| (s - z), in any direction of g.
// With g along -y in 3D: sigma_yy = -rho g (H - y), sigma_xx = sigma_zz = K0 sigma_yy.
// A two-phase body's density varies with z (its mixture's, `profile`); its stress here is
// the total stress, which porous/porous_media.cpp makes effective (Bishop).
// Bodies may not overlap unless one of them says `allowOverlap yes` (check_bodies).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "scree/core/tensor.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/mpm/grid.hpp"

namespace scree {

template <int D>
class Overburden;

template <int D>
struct GeneratedParticles {
  std::vector<Vec<D>> x, v;
  std::vector<Real> volume;
  std::vector<Sym3> sigma;
  Mat<D> velocity_gradient = Mat<D>::zero();  ///< of the initial velocity field
  /// With a filter: each kept point's place in the whole body's order (from 0); empty
  /// without one (every point kept, in order).
  std::vector<std::int64_t> index;
  std::uint64_t total = 0;  ///< the points of the whole body, kept or not
  Real point_volume = 0;    ///< (h/n)^D, every point's volume
};

/// Which of a body's points a run keeps: a rank of a decomposed run generates only the
/// points of its own box (Solver, case/decomposition.hpp).
template <int D>
using PointFilter = std::function<bool(const Vec<D>&)>;

/// "" if region type `type` fits a case of `dimension` (rectangle, polygon: 2D; box,
/// cylinder, sphere, extrudedPolygon, stl: 3D), else the message "type: region type ...
/// does not fit a 3D case; expected ..." (an unknown type: "", the spec reports it).
SCREE_API std::string region_dimension_mismatch(const std::string& type, int dimension);

/// Whether a body's initial stress is geostatic from the material above it (`overburden
/// all`, the default, without a `surface`): its stress then needs every body's columns.
SCREE_API bool takes_overburden(const Dictionary& body);

/// Generate the particles of one body dictionary (validated against CoreSpecs::body).
/// `density` is the material's initial mass density (for the geostatic stress). Throws
/// InputError, at the region's file:line, for a region that does not fit the case or
/// the grid (see check_bodies). `case_dir`: what an stl region's file is relative to.
/// With `keep`, only the points it accepts are made; what depends on the whole body (the
/// geostatic surface, the centroid of a rotation, the checks against the domain) is still
/// taken over every point, so a kept point is made exactly as without the filter.
/// `overburden`: the columns of every body of the case (`overburden all`), the same on
/// every rank; null: the body's own. `profile`: the body's density [kg/m^3] against the
/// elevation along -g where it is not `density` (a two-phase body's mixture); the
/// geostatic stress is then the total stress. Throws InputError for `overburden all` with
/// gravity that does not act along one axis.
template <int D>
SCREE_API GeneratedParticles<D> generate_particles(const Dictionary& body, const GridGeometry<D>& grid,
                                                   Real density, const Vec<D>& gravity,
                                                   const std::filesystem::path& case_dir = {},
                                                   const PointFilter<D>& keep = {},
                                                   const Overburden<D>* overburden = nullptr,
                                                   const std::function<Real(Real)>& profile = {});

/// Calls f(x) for every particle position of `body`, in generate_particles' order, without
/// keeping them (a decomposed run cuts its boxes from their histogram before any rank
/// makes its points). Throws InputError as generate_particles for a region that does not
/// fit the case.
template <int D>
SCREE_API void for_each_particle_position(const Dictionary& body, const GridGeometry<D>& grid,
                                          const std::function<void(const Vec<D>&)>& f,
                                          const std::filesystem::path& case_dir = {});

/// The number of particles generate_particles makes for `body` with `particles_per_cell`
/// points per cell along each axis on cells of size `cell_size`, estimated without making
/// them: the region's area (volume in 3D) times (particles_per_cell / cell_size)^D, the
/// points' density (the cut cells along the region's edge aside). The volume is exact for
/// every shape (an STL's by the divergence theorem); a clipped region's is its clipped
/// bounds' times the share of 32^D midpoints inside. 0 for a region that does not fit the
/// case (check_bodies reports it). A double: a case may ask for more points than any
/// integer type holds.
template <int D>
SCREE_API double estimate_particle_count(const Dictionary& body, Real cell_size, int particles_per_cell,
                                         const std::filesystem::path& case_dir = {});

/// The checks of every body of constant/bodies against the grid, without keeping any
/// particle (scree --check runs them, and every run before it allocates anything):
///   - each region fits the case (rectangle or polygon in 2D, box, cylinder, sphere,
///     extrudedPolygon or stl in 3D; a polygon of 3 or more vertices; an STL file that
///     reads and is closed; a clip box that meets the region) and holds at least one
///     particle position;
///   - no particle lies outside the domain of system/gridDict;
///   - no body has particles inside another body's region (both ways): two bodies in
///     one place double the mass there. A body with `allowOverlap yes` may overlap.
/// Each problem is appended to `errors` at the region's file:line; an overlap names the
/// other body's region and its file:line.
template <int D>
SCREE_API void check_bodies(const Dictionary& bodies, const GridGeometry<D>& grid, std::vector<InputError>& errors,
                            const std::filesystem::path& case_dir = {});

}  // namespace scree
