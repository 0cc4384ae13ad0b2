// Closed triangulated surfaces for the tests, written as ASCII or binary STL: a
// parallelepiped (a box under an affine map) and a tetrahedron, both with outward normals
// (counter-clockwise seen from outside).
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace scree::test {

using P3 = std::array<double, 3>;
using Tri = std::array<P3, 3>;

/// The 12 triangles of the hexahedron whose corner (i, j, k) in {0, 1}^3 is corner(i, j, k).
template <class F>
std::vector<Tri> hexahedron(F corner) {
  // Each face's corners counter-clockwise seen from outside (checked on the unit cube).
  static const int quads[6][4][3] = {{{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},   // x = 0
                                     {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},   // x = 1
                                     {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},   // y = 0
                                     {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},   // y = 1
                                     {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}},   // z = 0
                                     {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};  // z = 1
  std::vector<Tri> t;
  for (const auto& q : quads) {
    P3 p[4];
    for (int c = 0; c < 4; ++c) p[c] = corner(q[c][0], q[c][1], q[c][2]);
    t.push_back({p[0], p[1], p[2]});
    t.push_back({p[0], p[2], p[3]});
  }
  return t;
}

/// The axis-aligned box lo..hi.
inline std::vector<Tri> box(const P3& lo, const P3& hi) {
  return hexahedron([&](int i, int j, int k) {
    return P3{i ? hi[0] : lo[0], j ? hi[1] : lo[1], k ? hi[2] : lo[2]};
  });
}

/// The tetrahedron a b c d, with det(b - a, c - a, d - a) > 0.
inline std::vector<Tri> tetrahedron(const P3& a, const P3& b, const P3& c, const P3& d) {
  return {{a, c, b}, {a, b, d}, {a, d, c}, {b, c, d}};
}

inline void write_ascii_stl(const std::string& path, const std::vector<Tri>& tris) {
  std::ofstream f(path);
  f << "solid test\n";
  char buf[160];
  for (const Tri& t : tris) {
    f << "  facet normal 0 0 0\n    outer loop\n";
    for (const P3& p : t) {
      std::snprintf(buf, sizeof buf, "      vertex %.17g %.17g %.17g\n", p[0], p[1], p[2]);
      f << buf;
    }
    f << "    endloop\n  endfacet\n";
  }
  f << "endsolid test\n";
}

/// Binary STL (float32: the coordinates are rounded to float).
inline void write_binary_stl(const std::string& path, const std::vector<Tri>& tris) {
  std::ofstream f(path, std::ios::binary);
  char header[80] = "solid binary test: a header that begins like an ASCII file";
  f.write(header, 80);
  const std::uint32_t n = static_cast<std::uint32_t>(tris.size());
  f.write(reinterpret_cast<const char*>(&n), 4);
  for (const Tri& t : tris) {
    float r[12] = {0, 0, 0};
    for (int v = 0; v < 3; ++v)
      for (int d = 0; d < 3; ++d) r[3 + 3 * v + d] = static_cast<float>(t[v][d]);
    f.write(reinterpret_cast<const char*>(r), sizeof r);
    const std::uint16_t attr = 0;
    f.write(reinterpret_cast<const char*>(&attr), 2);
  }
}

}  // namespace scree::test
