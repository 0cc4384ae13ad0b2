// A closed triangulated surface read from an STL file (ASCII or binary), and which points
// it encloses: the `stl` region of constant/bodies.
//
// The reader is the framework's own: the framework does not link VTK (only the vtk writer
// plugin does), and STL is simple enough to read here, with messages that name the line.
//
// Inside test: ray parity, three rays voting. From the point, a ray runs along +x, +y and
// +z; each counts the triangles it crosses, and the point is inside where the count is odd
// (Jordan's theorem for a closed surface). Each ray is tested against the triangles
// projected onto the plane across it, with the fill rule of rasterisers (the "top-left"
// rule: a point on an edge shared by two triangles whose projections lie on either side of
// it belongs to exactly one of them; on a silhouette edge to both or neither, which leaves
// the parity as it is), so a ray through an edge or a vertex, as rays from lattice points
// through the diagonals of a cube's faces are, is counted once. The three rays vote (two of
// three decide) against the rounding of a ray that grazes an edge of triangles whose
// coordinates are not exact. A bucket grid over each projection keeps a query to the
// triangles near the ray.
// (A generalized winding number, Jacobson, Kavan & Sorkine-Hornung 2013, would also bear
// surfaces with small holes; this reader refuses open surfaces instead, and says where.)
//
// Checked on reading, each an InputError: a file that cannot be opened; malformed content
// (ASCII: the line inside the STL; binary: the triangle); no triangle; zero-area triangles
// (they make edges shared by three triangles, and have no inside); an open surface (edges
// not shared by exactly two triangles: how many, and one of them).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scree/geometry/shapes.hpp"
#include "scree/io/dictionary.hpp"

namespace scree::geometry {

class SCREE_API TriSurface {
 public:
  struct Triangle {
    Point3 v[3];
    int line = 0;  ///< of its `facet` in an ASCII file; its index (from 1) in a binary one
  };

  /// Reads and checks `path`. `display` names the file in messages (relative to the case),
  /// `key` is where the file is named (constant/bodies:line of `file`). Throws InputError.
  /// The same file (path, size and modification time) is read once per process.
  static std::shared_ptr<const TriSurface> load(const std::filesystem::path& path, const std::string& display,
                                                const SourceLocation& key);
  /// From triangles (tests); runs the same checks, naming `display`.
  static std::shared_ptr<const TriSurface> from_triangles(std::vector<Triangle> tris, const std::string& display,
                                                          const SourceLocation& key, bool binary = false);

  bool contains(const Point3& x) const;
  /// Where the line through x along `axis` crosses the surface last (at the largest
  /// coordinate along axis): that coordinate, and the unit normal of the triangle crossed
  /// there, oriented along +axis. Seen from above, the top of a solid: a terrain's ground.
  struct Crossing {
    double height = 0;
    Point3 normal = Point3::zero();
  };
  /// False where the line misses the surface (and `out` is left as it was).
  bool top(const Point3& x, int axis, Crossing& out) const;
  /// The point of the surface nearest to x and the unit normal there pointing out of the
  /// solid (the side contains() is false on): from x to that point for an x inside farther
  /// than `touch` from it, else the nearest triangle's normal turned outwards. A scan of
  /// every triangle: for setup, not for loops over many points of a large surface.
  struct Nearest {
    Point3 point = Point3::zero();
    Point3 normal = Point3::zero();
    double distance = 0;
  };
  Nearest nearest(const Point3& x, double touch) const;
  const Box3& bounds() const { return bounds_; }
  /// |sum over triangles of v0 . (v1 x v2)| / 6 (the divergence theorem), where the
  /// triangles are oriented alike; else sampled on 48^3 midpoints of the bounds.
  double volume() const { return volume_; }
  std::size_t size() const { return tris_.size(); }

 private:
  struct RayGrid {  // the triangles projected across one axis, bucketed
    int axis = 2, nu = 1, nv = 1;
    double u0 = 0, v0 = 0, du = 1, dv = 1;
    std::vector<std::vector<int>> buckets;
    int crossings(const std::vector<Triangle>& tris, const Point3& x) const;
    /// f(triangle index, coordinate along axis) for every triangle the line through x crosses.
    template <class F>
    void each_crossing(const std::vector<Triangle>& tris, const Point3& x, F&& f) const;
  };
  std::vector<Triangle> tris_;
  Box3 bounds_;
  double volume_ = 0;
  RayGrid rays_[3];
};

}  // namespace scree::geometry
