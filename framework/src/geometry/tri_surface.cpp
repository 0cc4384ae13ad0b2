// Closed triangulated surfaces from STL files (see geometry/tri_surface.hpp).
#include "scree/geometry/tri_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "scree/core/constants.hpp"

namespace fs = std::filesystem;

namespace scree::geometry {
namespace {

/// Points ordered by their coordinates (the welding map of the closedness check).
struct PointLess {
  bool operator()(const Point3& a, const Point3& b) const {
    return std::lexicographical_compare(a.v, a.v + 3, b.v, b.v + 3);
  }
};

std::string point_text(const Point3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%g %g %g)", p[0], p[1], p[2]);
  return buf;
}

SourceLocation at_line(const std::string& display, int line) {
  return SourceLocation{std::make_shared<std::string>(display), line, line > 0 ? 1 : 0};
}

std::string named_at(const SourceLocation& key) {
  return " (the surface of the stl region whose file is named at " + key.str() + ")";
}

/// The ASCII STL grammar, line by line:
///   solid [name] / facet normal nx ny nz / outer loop / vertex x y z (3 times) / endloop /
///   endfacet / ... / endsolid [name]; several solids may follow one another.
std::vector<TriSurface::Triangle> parse_ascii(const std::string& text, const std::string& display,
                                              const SourceLocation& key) {
  std::vector<TriSurface::Triangle> tris;
  std::istringstream in(text);
  std::string line;
  int n = 0;
  enum class State { outside, solid, facet, loop, endloop, endfacet } state = State::outside;
  TriSurface::Triangle t;
  int vertices = 0;
  auto fail = [&](const std::string& expected, const std::string& found) {
    std::string f = found;
    const auto b = f.find_first_not_of(" \t\r");
    f = b == std::string::npos ? "" : f.substr(b);
    while (!f.empty() && (f.back() == '\r' || f.back() == ' ')) f.pop_back();
    return InputError(at_line(display, n), "malformed ASCII STL: expected " + expected + ", found " +
                                               (f.empty() ? std::string("the end of the file") : "'" + f + "'") +
                                               named_at(key));
  };
  auto numbers = [&](std::istringstream& ls, double* out, int count) {
    for (int i = 0; i < count; ++i) {
      std::string w;
      if (!(ls >> w)) return false;
      char* end = nullptr;
      out[i] = std::strtod(w.c_str(), &end);
      if (end == w.c_str() || *end != '\0') return false;
      if (!std::isfinite(out[i]))  // "inf", "nan", or beyond the range of a double (1e400)
        throw InputError(at_line(display, n), "ASCII STL: '" + w + "' is not a finite number; expected " +
                                                  "coordinates in metres" + named_at(key));
    }
    std::string extra;
    return !(ls >> extra);
  };
  while (std::getline(in, line)) {
    ++n;
    std::istringstream ls(line);
    std::string w;
    if (!(ls >> w)) continue;  // a blank line
    switch (state) {
      case State::outside:
        if (w != "solid") throw fail("'solid name' (the start of a solid)", line);
        state = State::solid;
        break;
      case State::solid: {
        if (w == "endsolid") {
          state = State::outside;
          break;
        }
        std::string normal;
        double nv[3];
        if (w != "facet" || !(ls >> normal) || normal != "normal" || !numbers(ls, nv, 3))
          throw fail("'facet normal nx ny nz' or 'endsolid'", line);
        t = TriSurface::Triangle{};
        t.line = n;
        state = State::facet;
        break;
      }
      case State::facet: {
        std::string loop;
        if (w != "outer" || !(ls >> loop) || loop != "loop" || (ls >> w)) throw fail("'outer loop'", line);
        vertices = 0;
        state = State::loop;
        break;
      }
      case State::loop:
        if (w != "vertex" || !numbers(ls, t.v[vertices].v, 3))
          throw fail("'vertex x y z' (vertex " + std::to_string(vertices + 1) + " of the facet at line " +
                         std::to_string(t.line) + ")",
                     line);
        if (++vertices == 3) state = State::endloop;
        break;
      case State::endloop:
        if (w != "endloop" || (ls >> w)) throw fail("'endloop' (a facet has 3 vertices)", line);
        state = State::endfacet;
        break;
      case State::endfacet:
        if (w != "endfacet" || (ls >> w)) throw fail("'endfacet'", line);
        tris.push_back(t);
        state = State::solid;
        break;
    }
  }
  if (state != State::outside)
    throw fail(state == State::solid ? "'endsolid'" : "the rest of the facet begun at line " + std::to_string(t.line),
               "");
  return tris;
}

/// Binary STL: an 80-byte header, a little-endian uint32 triangle count n, then n records
/// of 50 bytes (normal, 3 vertices: 12 float32; a uint16 attribute).
std::vector<TriSurface::Triangle> parse_binary(const std::string& bytes, const std::string& display,
                                               const SourceLocation& key) {
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  std::vector<TriSurface::Triangle> tris(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const char* rec = bytes.data() + 84 + 50 * static_cast<std::size_t>(i);
    float f[12];
    std::memcpy(f, rec, sizeof f);
    tris[i].line = static_cast<int>(i + 1);
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) {
        tris[i].v[k][d] = f[3 + 3 * k + d];
        if (!std::isfinite(tris[i].v[k][d]))
          throw InputError(at_line(display, 0), "malformed binary STL: triangle " + std::to_string(i + 1) +
                                                    " has a coordinate that is not a finite number" + named_at(key));
      }
  }
  return tris;
}

std::string where_triangle(const TriSurface::Triangle& t, bool binary, const std::string& display) {
  return binary ? "triangle " + std::to_string(t.line) + " of " + display
                : "the facet at " + display + ":" + std::to_string(t.line);
}

/// (b - a) x (c - a) . (d - a): > 0 when d lies on the side of the plane abc that its
/// normal points to, 0 on the plane.
double orient(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  return dot(cross(b - a, c - a), d - a);
}

/// Whether the segment pq crosses the triangle t: p and q strictly on either side of its
/// plane, and the line through them within the closed triangle, an edge or a vertex
/// included (two shells may cross exactly through the diagonal of a face). A segment that
/// only touches the plane (shells sharing a face, an edge or a vertex) does not cross. Each
/// edge's side is computed from its vertices in one order (PointLess), so that the two
/// triangles sharing an edge see exactly opposite sides of it and a line through the edge
/// is within one of them whatever the rounding.
bool crosses(const Point3& p, const Point3& q, const TriSurface::Triangle& t) {
  const double dp = orient(t.v[0], t.v[1], t.v[2], p), dq = orient(t.v[0], t.v[1], t.v[2], q);
  if (!((dp > 0 && dq < 0) || (dp < 0 && dq > 0))) return false;
  double side[3];
  for (int k = 0; k < 3; ++k) {
    const Point3& a = t.v[k];
    const Point3& b = t.v[(k + 1) % 3];
    side[k] = PointLess{}(a, b) ? orient(p, q, a, b) : -orient(p, q, b, a);
  }
  return (side[0] >= 0 && side[1] >= 0 && side[2] >= 0) || (side[0] <= 0 && side[1] <= 0 && side[2] <= 0);
}

/// The first pair of triangles (in file order) that cross each other without sharing a
/// vertex, or {-1, -1}: a surface that crosses itself, or closed shells that overlap, whose
/// inside the parity rule gets wrong (where two shells overlap it counts as outside).
/// Candidates are the pairs whose bounding boxes share a cell of a uniform grid.
std::pair<int, int> first_crossing(const std::vector<TriSurface::Triangle>& tris,
                                   const std::vector<std::array<int, 3>>& vertex_ids, const Box3& bounds) {
  const int n = static_cast<int>(tris.size());
  const int cells = static_cast<int>(std::clamp(std::ceil(std::cbrt(n / 2.0)), 1.0, 64.0));
  double size[3];
  for (int d = 0; d < 3; ++d) size[d] = bounds.hi[d] > bounds.lo[d] ? (bounds.hi[d] - bounds.lo[d]) / cells : 1;
  auto cell = [&](double x, int d) {
    return std::clamp(static_cast<int>(std::floor((x - bounds.lo[d]) / size[d])), 0, cells - 1);
  };
  std::vector<std::array<int, 6>> range(tris.size());
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(cells) * cells * cells);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      const auto [lo, hi] = std::minmax({tris[i].v[0][d], tris[i].v[1][d], tris[i].v[2][d]});
      range[i][d] = cell(lo, d);
      range[i][3 + d] = cell(hi, d);
    }
    for (int z = range[i][2]; z <= range[i][5]; ++z)
      for (int y = range[i][1]; y <= range[i][4]; ++y)
        for (int x = range[i][0]; x <= range[i][3]; ++x)
          grid[(static_cast<std::size_t>(z) * cells + y) * cells + x].push_back(i);
  }
  std::vector<int> seen(tris.size(), -1);  // the triangle i for which j was last tested
  for (int i = 0; i < n; ++i)
    for (int z = range[i][2]; z <= range[i][5]; ++z)
      for (int y = range[i][1]; y <= range[i][4]; ++y)
        for (int x = range[i][0]; x <= range[i][3]; ++x)
          for (int j : grid[(static_cast<std::size_t>(z) * cells + y) * cells + x]) {
            if (j <= i || seen[j] == i) continue;
            seen[j] = i;
            bool shared = false;
            for (int a : vertex_ids[i])
              for (int b : vertex_ids[j]) shared = shared || a == b;
            if (shared) continue;
            const auto& s = tris[i];
            const auto& t = tris[j];
            for (int k = 0; k < 3; ++k)
              if (crosses(s.v[k], s.v[(k + 1) % 3], t) || crosses(t.v[k], t.v[(k + 1) % 3], s)) return {i, j};
          }
  return {-1, -1};
}

}  // namespace

std::shared_ptr<const TriSurface> TriSurface::load(const fs::path& path, const std::string& display,
                                                   const SourceLocation& key) {
  std::error_code ec;
  const std::string expect = "; expected a closed triangulated surface in ASCII or binary STL";
  if (!fs::exists(path, ec))
    throw InputError(key, "file: " + display + " does not exist (looked for " + path.string() + ")" + expect);
  if (!fs::is_regular_file(path, ec))
    throw InputError(key, "file: " + display + " is not a regular file (" + path.string() + ")" + expect);
  const auto size = fs::file_size(path, ec);
  const auto mtime = fs::last_write_time(path, ec);

  // Each file once per process (a run reads a body's region when it checks the case, for
  // the memory estimate and when it makes the particles).
  struct Cached {
    std::uintmax_t size;
    fs::file_time_type mtime;
    std::shared_ptr<const TriSurface> surface;
  };
  static std::mutex mutex;
  static std::map<std::string, Cached> cache;
  const std::string id = fs::weakly_canonical(path, ec).string();
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cache.find(id);
    if (it != cache.end() && it->second.size == size && it->second.mtime == mtime) return it->second.surface;
  }

  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(key, "file: " + display + " cannot be read (" + path.string() + ": " +
                              std::strerror(errno) + ")" + expect);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw InputError(key, "file: reading " + display + " failed (" + path.string() + ")" + expect);

  std::shared_ptr<const TriSurface> s;
  std::uint32_t n = 0;
  if (bytes.size() >= 84) std::memcpy(&n, bytes.data() + 80, 4);
  const auto first = bytes.find_first_not_of(" \t\r\n");
  if (bytes.size() >= 84 && bytes.size() == 84 + 50 * static_cast<std::uintmax_t>(n)) {
    s = from_triangles(parse_binary(bytes, display, key), display, key, true);
  } else if (first != std::string::npos && bytes.compare(first, 5, "solid") == 0) {
    s = from_triangles(parse_ascii(bytes, display, key), display, key, false);
  } else {
    throw InputError(key, "file: " + display + " is neither an ASCII STL (text beginning with 'solid') nor a " +
                              "binary STL (an 80-byte header, a triangle count n and 50 bytes per triangle: " +
                              "84 + 50 n bytes; this file has " + std::to_string(bytes.size()) + " bytes)" + expect);
  }
  std::lock_guard<std::mutex> lock(mutex);
  cache[id] = Cached{size, mtime, s};
  return s;
}

std::shared_ptr<const TriSurface> TriSurface::from_triangles(std::vector<Triangle> tris, const std::string& display,
                                                             const SourceLocation& key, bool binary) {
  if (tris.empty())
    throw InputError(key, "file: " + display + " holds no triangle; expected a closed triangulated surface");

  // Coordinates so large that a triangle's squared area (the fourth power of its size, in
  // the test below) overflows: no test on such a surface means anything, and it must not be
  // reported as zero-area triangles (inf <= inf). Typically a surface in other units.
  for (const Triangle& t : tris) {
    const Point3 e1 = t.v[1] - t.v[0], e2 = t.v[2] - t.v[0], e3 = t.v[2] - t.v[1];
    const double longest = std::max({dot(e1, e1), dot(e2, e2), dot(e3, e3)});
    const Point3 c = cross(e1, e2);
    if (!std::isfinite(longest * longest) || !std::isfinite(dot(c, c))) {
      double largest = 0;
      for (const Point3& p : t.v)
        for (int d = 0; d < 3; ++d) largest = std::max(largest, std::fabs(p[d]));
      char buf[32];
      std::snprintf(buf, sizeof buf, "%g", largest);
      throw InputError(key, "file: " + display + " has coordinates too large to compute with (the first: " +
                                where_triangle(t, binary, display) + ", a coordinate of magnitude " + buf +
                                ": its squared area overflows a double); expected coordinates in metres " +
                                "(scale the surface)");
    }
  }

  // Zero-area triangles: a sliver's edges are shared by three triangles, and it has no inside.
  int degenerate = 0;
  const Triangle* first_degenerate = nullptr;
  for (const Triangle& t : tris) {
    const Point3 e1 = t.v[1] - t.v[0], e2 = t.v[2] - t.v[0], e3 = t.v[2] - t.v[1];
    const double longest = std::max({dot(e1, e1), dot(e2, e2), dot(e3, e3)});
    const Point3 c = cross(e1, e2);
    if (dot(c, c) <= 1e-24 * longest * longest) {
      if (!degenerate++) first_degenerate = &t;
    }
  }
  if (degenerate)
    throw InputError(key, "file: " + display + " has " + std::to_string(degenerate) +
                              " zero-area triangle(s) (the first: " + where_triangle(*first_degenerate, binary, display) +
                              "); expected a closed surface of triangles with non-zero area (remove or merge them)");

  // Closed: every edge (between vertices welded where their coordinates are equal) shared by
  // exactly two triangles.
  std::map<Point3, int, PointLess> ids;
  auto id = [&](const Point3& p) { return ids.emplace(p, static_cast<int>(ids.size())).first->second; };
  struct EdgeUse {
    int count = 0;
    int forward = 0;  ///< uses from the lower vertex id to the higher
    const Triangle* first = nullptr;
    Point3 a, b;
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  std::vector<std::array<int, 3>> vertex_ids;
  vertex_ids.reserve(tris.size());
  for (const Triangle& t : tris) {
    const int v[3] = {id(t.v[0]), id(t.v[1]), id(t.v[2])};
    vertex_ids.push_back({v[0], v[1], v[2]});
    for (int k = 0; k < 3; ++k) {
      const int a = v[k], b = v[(k + 1) % 3];
      const std::uint64_t e = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
      EdgeUse& u = edges[e];
      u.forward += a < b;
      if (!u.count++) {
        u.first = &t;
        u.a = t.v[k];
        u.b = t.v[(k + 1) % 3];
      }
    }
  }
  long long open = 0;
  bool oriented = true;  // every edge run once each way: the normals all point out (or all in)
  const EdgeUse* example = nullptr;
  for (const auto& [e, u] : edges) {
    oriented = oriented && u.forward == 1;
    if (u.count != 2) {
      ++open;
      if (!example || u.first->line < example->first->line) example = &u;
    }
  }
  if (open)
    throw InputError(key, "file: the surface of " + display + " is not closed: " + std::to_string(open) + " of its " +
                              std::to_string(edges.size()) +
                              " edges are not shared by exactly two triangles (e.g. the edge " + point_text(example->a) +
                              " - " + point_text(example->b) + " of " + where_triangle(*example->first, binary, display) +
                              ", used by " + std::to_string(example->count) +
                              "); expected a closed surface, whose inside is defined (close the holes, or join "
                              "vertices that should coincide exactly)");

  auto s = std::make_shared<TriSurface>();
  s->tris_ = std::move(tris);
  Box3& b = s->bounds_;
  b.lo = {kUnbounded, kUnbounded, kUnbounded};
  b.hi = {-kUnbounded, -kUnbounded, -kUnbounded};
  double six_v = 0;
  for (const Triangle& t : s->tris_) {
    for (const Point3& p : t.v)
      for (int d = 0; d < 3; ++d) {
        b.lo[d] = std::min(b.lo[d], p[d]);
        b.hi[d] = std::max(b.hi[d], p[d]);
      }
    six_v += dot(t.v[0], cross(t.v[1], t.v[2]));
  }
  s->volume_ = std::fabs(six_v) / 6;

  // Crossing triangles: closed shells that overlap, or a surface through itself.
  if (const auto [i, j] = first_crossing(s->tris_, vertex_ids, b); i >= 0) {
    // Shells: the triangles joined by shared vertices (union-find over vertex ids).
    std::vector<int> parent(ids.size());
    for (std::size_t k = 0; k < parent.size(); ++k) parent[k] = static_cast<int>(k);
    auto root = [&](int x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (const auto& v : vertex_ids)
      for (int k = 1; k < 3; ++k) parent[root(v[k])] = root(v[0]);
    int shells = 0;
    for (std::size_t k = 0; k < parent.size(); ++k) shells += root(static_cast<int>(k)) == static_cast<int>(k);
    const bool two_shells = root(vertex_ids[i][0]) != root(vertex_ids[j][0]);
    throw InputError(key, "file: the surface of " + display + " crosses itself: " +
                              where_triangle(s->tris_[i], binary, display) + " crosses " +
                              where_triangle(s->tris_[j], binary, display) +
                              (two_shells ? ", of two of its " + std::to_string(shells) + " closed shells, which overlap"
                                          : ", of one closed shell") +
                              "; the inside of such a surface is not defined (where shells overlap, the points would "
                              "count as outside); expected closed shells that neither cross themselves nor overlap "
                              "(join overlapping solids into one surface, their union)");
  }

  // Bucket grids of the projections across x, y and z.
  for (int k = 0; k < 3; ++k) {
    RayGrid& g = s->rays_[k];
    g.axis = k;
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    const int n = static_cast<int>(std::clamp(std::ceil(std::sqrt(s->tris_.size() / 2.0)), 1.0, 256.0));
    g.nu = g.nv = n;
    g.u0 = b.lo[u];
    g.v0 = b.lo[v];
    g.du = b.hi[u] > b.lo[u] ? (b.hi[u] - b.lo[u]) / n : 1;
    g.dv = b.hi[v] > b.lo[v] ? (b.hi[v] - b.lo[v]) / n : 1;
    g.buckets.assign(static_cast<std::size_t>(n) * n, {});
    auto cell = [](double x, double x0, double dx, int nx) {
      return std::clamp(static_cast<int>(std::floor((x - x0) / dx)), 0, nx - 1);
    };
    for (std::size_t i = 0; i < s->tris_.size(); ++i) {
      const Triangle& t = s->tris_[i];
      const double area2 = (t.v[1][u] - t.v[0][u]) * (t.v[2][v] - t.v[0][v]) -
                           (t.v[1][v] - t.v[0][v]) * (t.v[2][u] - t.v[0][u]);
      if (area2 == 0) continue;  // edge-on to the ray: never crossed
      double ulo = kUnbounded, uhi = -kUnbounded, vlo = kUnbounded, vhi = -kUnbounded;
      for (const Point3& p : t.v) {
        ulo = std::min(ulo, p[u]);
        uhi = std::max(uhi, p[u]);
        vlo = std::min(vlo, p[v]);
        vhi = std::max(vhi, p[v]);
      }
      for (int j = cell(vlo, g.v0, g.dv, n); j <= cell(vhi, g.v0, g.dv, n); ++j)
        for (int i2 = cell(ulo, g.u0, g.du, n); i2 <= cell(uhi, g.u0, g.du, n); ++i2)
          g.buckets[static_cast<std::size_t>(j) * n + i2].push_back(static_cast<int>(i));
    }
  }
  // Triangles not oriented alike (STL writers do not all keep the rule): the divergence
  // theorem's sum means nothing; the volume is the bounds' times the share of 48^3
  // midpoints inside (for the memory estimate only: the particles do not use it).
  if (!oriented) {
    constexpr int n = 48;
    long long in = 0;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const int ijk[3] = {i, j, k};
          Point3 x;
          for (int d = 0; d < 3; ++d) x[d] = b.lo[d] + (ijk[d] + 0.5) * (b.hi[d] - b.lo[d]) / n;
          in += s->contains(x);
        }
    s->volume_ = b.volume() * static_cast<double>(in) / (static_cast<double>(n) * n * n);
  }
  return s;
}

template <class F>
void TriSurface::RayGrid::each_crossing(const std::vector<Triangle>& tris, const Point3& x, F&& f) const {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const double pu = x[u], pv = x[v];
  const int iu = static_cast<int>(std::floor((pu - u0) / du)), iv = static_cast<int>(std::floor((pv - v0) / dv));
  // Outside the projected bounds (the top bound belongs to the last bucket).
  if (pu < u0 || pv < v0 || iu > nu || iv > nv) return;
  const auto& bucket = buckets[static_cast<std::size_t>(std::min(iv, nv - 1)) * nu + std::min(iu, nu - 1)];
  // A point on an edge belongs to the triangle whose (counter-clockwise) edge points "up",
  // or exactly left: of two triangles sharing an edge, traversed both ways, exactly one.
  auto owns = [](double eu, double ev) { return ev > 0 || (ev == 0 && eu < 0); };
  for (int i : bucket) {
    const Triangle& t = tris[static_cast<std::size_t>(i)];
    const Point3* a = &t.v[0];
    const Point3* b = &t.v[1];
    const Point3* c = &t.v[2];
    double area2 = ((*b)[u] - (*a)[u]) * ((*c)[v] - (*a)[v]) - ((*b)[v] - (*a)[v]) * ((*c)[u] - (*a)[u]);
    if (area2 < 0) {
      std::swap(b, c);
      area2 = -area2;
    }
    // Edge functions: twice the area of (start, end, p); all >= 0 inside.
    double w[3];
    const Point3* p[3] = {a, b, c};
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      const Point3& s = *p[k];
      const Point3& e = *p[(k + 1) % 3];
      const double eu = e[u] - s[u], ev = e[v] - s[v];
      const double f = eu * (pv - s[v]) - ev * (pu - s[u]);
      w[(k + 2) % 3] = f;  // the barycentric weight of the vertex opposite the edge
      inside = f > 0 || (f == 0 && owns(eu, ev));
    }
    if (!inside) continue;
    const double height = (w[0] * (*a)[axis] + w[1] * (*b)[axis] + w[2] * (*c)[axis]) / area2;
    f(i, height);
  }
}

int TriSurface::RayGrid::crossings(const std::vector<Triangle>& tris, const Point3& x) const {
  int count = 0;
  each_crossing(tris, x, [&](int, double height) { count += height > x[axis]; });
  return count;
}

bool TriSurface::contains(const Point3& x) const {
  if (!bounds_.contains(x)) return false;
  int votes = 0;
  for (const RayGrid& g : rays_) votes += g.crossings(tris_, x) % 2;
  return votes >= 2;
}

bool TriSurface::top(const Point3& x, int axis, Crossing& out) const {
  int best = -1;
  double highest = -kUnbounded;
  rays_[axis].each_crossing(tris_, x, [&](int i, double height) {
    if (height > highest) {
      highest = height;
      best = i;
    }
  });
  if (best < 0) return false;
  const Triangle& t = tris_[static_cast<std::size_t>(best)];
  Point3 n = cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
  const double scale = (n[axis] < 0 ? -1 : 1) / std::sqrt(dot(n, n));
  for (int d = 0; d < 3; ++d) n[d] *= scale;
  out.height = highest;
  out.normal = n;
  return true;
}

namespace {

/// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection,
/// section 5.1.5: the Voronoi regions of the vertices, the edges and the face).
Point3 closest_on_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
  const Point3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Point3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Point3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

TriSurface::Nearest TriSurface::nearest(const Point3& x, double touch) const {
  Nearest out;
  double best = kUnbounded;
  std::size_t which = 0;
  for (std::size_t i = 0; i < tris_.size(); ++i) {
    const Triangle& t = tris_[i];
    const Point3 c = closest_on_triangle(x, t.v[0], t.v[1], t.v[2]);
    const Point3 r = c - x;
    const double d2 = dot(r, r);
    if (d2 < best) {
      best = d2;
      out.point = c;
      which = i;
    }
  }
  out.distance = std::sqrt(best);
  if (out.distance > touch && contains(x)) {
    out.normal = (out.point - x) * (1 / out.distance);  // from inside to the surface: outwards
    return out;
  }
  const Triangle& t = tris_[which];
  Point3 n = cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
  n = n * (1 / std::sqrt(dot(n, n)));
  // Outwards: the side of the triangle's centre that the solid does not hold.
  Point3 m = (t.v[0] + t.v[1] + t.v[2]) * (1.0 / 3);
  double size = std::sqrt(dot(t.v[1] - t.v[0], t.v[1] - t.v[0]));
  if (contains(m + n * (1e-6 * size))) n = n * -1.0;
  out.normal = n;
  return out;
}

}  // namespace scree::geometry
