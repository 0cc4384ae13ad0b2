// Solid shapes (see geometry/shapes.hpp).
#include "scree/geometry/shapes.hpp"

#include <algorithm>
#include <cmath>

#include "scree/core/constants.hpp"

namespace scree::geometry {

Box3 Box3::intersect(const Box3& o) const {
  Box3 r;
  for (int d = 0; d < 3; ++d) {
    r.lo[d] = std::max(lo[d], o.lo[d]);
    r.hi[d] = std::min(hi[d], o.hi[d]);
  }
  return r;
}

double Box3::volume() const {
  if (empty()) return 0;
  return (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
}

bool Cylinder::contains(const Point3& x) const {
  const Point3 a = p2 - p1, r = x - p1;
  const double aa = dot(a, a), t = dot(r, a) / aa;
  if (t < 0 || t > 1) return false;
  const Point3 radial = r - t * a;
  return dot(radial, radial) <= radius * radius;
}

Box3 Cylinder::bounds() const {
  const Point3 a = p2 - p1;
  const double aa = dot(a, a);
  Box3 b;
  for (int d = 0; d < 3; ++d) {
    const double e = radius * std::sqrt(std::max(0.0, 1 - a[d] * a[d] / aa));
    b.lo[d] = std::min(p1[d], p2[d]) - e;
    b.hi[d] = std::max(p1[d], p2[d]) + e;
  }
  return b;
}

double Cylinder::volume() const { return kPi * radius * radius * norm(p2 - p1); }

bool Sphere::contains(const Point3& x) const {
  const Point3 r = x - centre;
  return dot(r, r) <= radius * radius;
}

Box3 Sphere::bounds() const {
  Box3 b;
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = centre[d] - radius;
    b.hi[d] = centre[d] + radius;
  }
  return b;
}

double Sphere::volume() const { return 4.0 / 3.0 * kPi * radius * radius * radius; }

bool inside_polygon(const std::vector<std::array<double, 2>>& poly, double x, double y) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]) in = !in;
  }
  return in;
}

double polygon_area(const std::vector<std::array<double, 2>>& poly) {
  double twice = 0;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    twice += poly[j][0] * poly[i][1] - poly[i][0] * poly[j][1];
  return std::fabs(twice) / 2;
}

bool ExtrudedPolygon::contains(const Point3& x) const {
  if (x[axis] < min || x[axis] > max) return false;
  return inside_polygon(points, x[(axis + 1) % 3], x[(axis + 2) % 3]);
}

Box3 ExtrudedPolygon::bounds() const {
  Box3 b;
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  b.lo[axis] = min;
  b.hi[axis] = max;
  b.lo[u] = b.lo[v] = kUnbounded;
  b.hi[u] = b.hi[v] = -kUnbounded;
  for (const auto& p : points) {
    b.lo[u] = std::min(b.lo[u], p[0]);
    b.hi[u] = std::max(b.hi[u], p[0]);
    b.lo[v] = std::min(b.lo[v], p[1]);
    b.hi[v] = std::max(b.hi[v], p[1]);
  }
  return b;
}

double ExtrudedPolygon::volume() const { return polygon_area(points) * (max - min); }

}  // namespace scree::geometry
