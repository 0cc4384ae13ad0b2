// Solid shapes for the regions of constant/bodies in 3D: their inside tests, bounding
// boxes and volumes (case/particle_generation.cpp fills them with particles; the memory
// estimate counts their points from the volumes).
//
//   cylinder         points x with 0 <= t <= 1 and |x - p1 - t a| <= r, where a = p2 - p1 and
//                    t = (x - p1).a / |a|^2 (OpenFOAM's cylinderToCell: the axis runs from p1
//                    to p2). Volume pi r^2 |a|.
//   sphere           |x - c| <= r. Volume 4/3 pi r^3.
//   extrudedPolygon  a polygon in the plane of the two axes that follow `axis` in cyclic
//                    order (axis z: (x y); x: (y z); y: (z x)), extruded along `axis` over
//                    min <= x_axis <= max. Inside the polygon by the even-odd rule (the 2D
//                    polygon's own test). Volume: the shoelace area times (max - min).
//   stl              a closed triangulated surface (geometry/tri_surface.hpp).
// Every test includes the boundary; particles sit at sub-cell centres, which a surface
// aligned with the lattice never passes through.
#pragma once

#include <array>
#include <vector>

#include "scree/core/tensor.hpp"

namespace scree::geometry {

/// A point of space: the particles' own vector type (core/tensor.hpp: dot, cross, +, -).
using Point3 = Vec<3>;

/// An axis-aligned box lo..hi (empty when some hi < lo).
struct SCREE_API Box3 {
  Point3 lo = Point3::zero(), hi = Point3::zero();
  bool empty() const { return hi[0] < lo[0] || hi[1] < lo[1] || hi[2] < lo[2]; }
  bool contains(const Point3& x) const {
    for (int d = 0; d < 3; ++d)
      if (x[d] < lo[d] || x[d] > hi[d]) return false;
    return true;
  }
  Box3 intersect(const Box3& o) const;
  double volume() const;  ///< 0 when empty
};

struct SCREE_API Cylinder {
  Point3 p1 = Point3::zero(), p2 = Point3::zero();
  double radius = 0;
  bool contains(const Point3& x) const;
  /// The tight box: along axis d each end disc reaches r sqrt(1 - a_d^2 / |a|^2) from its centre.
  Box3 bounds() const;
  double volume() const;  ///< pi r^2 |p2 - p1|
};

struct SCREE_API Sphere {
  Point3 centre = Point3::zero();
  double radius = 0;
  bool contains(const Point3& x) const;
  Box3 bounds() const;
  double volume() const;  ///< 4/3 pi r^3
};

/// Even-odd rule (crossing number) point-in-polygon test: a horizontal ray from (u, v)
/// crosses the polygon's edges an odd number of times iff the point is inside.
SCREE_API bool inside_polygon(const std::vector<std::array<double, 2>>& poly, double u, double v);
/// |shoelace formula|: the area of a simple polygon.
SCREE_API double polygon_area(const std::vector<std::array<double, 2>>& poly);

struct SCREE_API ExtrudedPolygon {
  std::vector<std::array<double, 2>> points;  ///< in the (axis+1, axis+2) plane, cyclic
  int axis = 2;                               ///< 0 x, 1 y, 2 z
  double min = 0, max = 0;                    ///< extent along axis
  bool contains(const Point3& x) const;
  Box3 bounds() const;
  double volume() const;  ///< polygon area (max - min)
};

}  // namespace scree::geometry
