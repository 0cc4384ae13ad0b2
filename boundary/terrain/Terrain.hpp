// terrain: the ground under a flow, a rigid surface read from an STL file (3D) or a
// polyline (2D), with Coulomb friction, slip or no slip.
//
//   ground { type terrain; file "constant/triSurface/valley.stl"; coefficient 0.47; }
//   ground { type terrain; file "constant/triSurface/valley.stl"; condition noSlip; }
//   ground { type terrain; points ((0 0.7) (0.5 0.41) (1.2 0)); coefficient 0.3; }   // 2D
//
// The file is a closed solid whose top is the ground: a digital elevation model's surface
// closed by side walls and a base, as terrain tools export it (and as an stl region of
// constant/bodies reads it). Seen from above, along `up` (by default the axis gravity
// points against), the solid's top over each column of grid nodes is the ground level
// z_g(x, y) there, and the triangle crossed there gives the ground's unit normal n
// (pointing up, into the flow). Every node at or below the ground level of its column is
// a ground node. On each ground node that carries mass, after every grid update, the
// velocity the update produced is held by the ground's `condition`: friction (the
// default), Coulomb contact with a surface at rest of normal n (mpm/wall_law.hpp,
// coulomb_contact): its approach along n is stopped and its tangential part reduced by
// mu |v.n|, and the flow may lift off (separable, by default); slip, the same with mu = 0;
// noSlip, the velocity set to zero (the flow sticks to the ground).
// Nodes at or below the ground act alike whatever their depth, so a point that comes
// within a cell of the ground is stopped by the nodes it maps to.
//
// In 2D the ground is the polyline `points`, seen from above alike: over each column of
// nodes, its highest crossing and the unit normal of the segment crossed there (a
// vertical segment, which no column crosses, is a step of the height field).
//
// The ground is a height field of the grid's node columns: an overhang of the solid is
// filled below its top, and the ground is resolved to a cell, as every wall on grid nodes
// is. With `shape solid` the same file (or, in 2D, `points` as a closed polygon) is a rigid
// solid of any shape instead, a retaining wall, a pier, an overhang, a check dam: every
// node inside it or on its surface is held, with the unit normal of the surface nearest to
// it, pointing out of the solid (from the node to that nearest point, or the nearest
// face's normal for a node on the surface).
//
//   wall { type terrain; shape solid; file "constant/triSurface/wall.stl"; condition slip; }
//   pier { type terrain; shape solid; points ((0.5 0) (0.6 0) (0.6 0.3) (0.5 0.3)); coefficient 0.4; }
// It is a node law (boundary/node_law.hpp) on the ground nodes of the grid a rank
// holds, so a decomposed run applies it on each rank's part.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/boundary/node_law.hpp"
#include "scree/core/constants.hpp"
#include "scree/exec/memory.hpp"
#include "scree/geometry/tri_surface.hpp"
#include "scree/plugin/context.hpp"

namespace scree::boundary {

/// The ground's law on the listed ground nodes: node i of the list is grid node nodes[i],
/// its ground normal normals[D i .. D i + D - 1].
template <int D>
struct TerrainKernel {
  const Index* nodes;
  const Real* normals;
  Real mu;
  int separable;
  int stick;  ///< noSlip: the velocity is set to zero
  GridNodes<D> g;
  SCREE_HD void operator()(Index i) const {
    const Index I = nodes[i];
    if (!(g.fields.mass[I] > 0)) return;  // no material at the node: no velocity
    const Real* n = normals + D * i;
    Real v[D];
    if (g.velocity) {
      for (int d = 0; d < D; ++d) v[d] = stick ? Real(0) : g.fields.velocity[d][I];
      if (!stick) coulomb_contact<D>(v, n, mu, separable != 0);
      for (int d = 0; d < D; ++d) g.fields.velocity[d][I] = v[d];
    }
    if (g.velocity_new) {
      for (int d = 0; d < D; ++d) v[d] = stick ? Real(0) : g.fields.velocity_new[d][I];
      if (!stick) coulomb_contact<D>(v, n, mu, separable != 0);
      for (int d = 0; d < D; ++d) g.fields.velocity_new[d][I] = v[d];
    }
  }
};

class Terrain final : public BoundaryCondition {
 public:
  static constexpr const char* type_name = "terrain";
  static ParamSpec spec() {
    ParamSpec s(type_name, "the ground under a flow, read from an STL solid (3D) or a polyline (2D): friction, slip or "
                           "no slip on the nodes at or below it");
    s.word("file", "3D: STL file relative to the case, a closed solid whose top is the ground, e.g. "
                   "\"constant/triSurface/valley.stl\"")
        .optional();
    s.list("points", "2D: the ground's profile ((x0 y0) (x1 y1) ...), a polyline seen from above").optional();
    s.word("condition", "friction: Coulomb friction (coefficient); slip: frictionless; noSlip: the flow sticks")
        .choices({"friction", "slip", "noSlip"})
        .default_value("friction");
    s.scalar("coefficient", "-", "Coulomb friction coefficient mu = tan(basal friction angle) (condition friction)")
        .non_negative()
        .optional();
    s.word("up", "the vertical axis the ground is seen along (default: the axis gravity points against)")
        .choices({"x", "y", "z"})
        .optional();
    s.boolean("separable", "the flow may lift off the ground").default_value("yes");
    s.word("shape", "heightField: the ground is the solid's top over each column of nodes (terrain); solid: every "
                    "node inside the solid or on its surface, with the normal of the surface nearest to it (walls "
                    "and obstacles of any shape; in 2D points is then a closed polygon)")
        .choices({"heightField", "solid"})
        .default_value("heightField");
    return s;
  }

  Terrain(const ParamReader& r, const SolverContext& ctx) {
    const std::string condition = r.word("condition");
    if (condition == "friction" && !r.has("coefficient"))
      throw InputError(r.dict().where(), "'" + ctx.name + "': coefficient: missing; condition friction (the default) "
                                         "needs the Coulomb coefficient mu >= 0 (or condition slip or noSlip)");
    if (condition != "friction" && r.has("coefficient"))
      throw InputError(r.entry("coefficient").where(), "coefficient: condition " + condition +
                                                           " takes no coefficient; expected it only with condition friction");
    mu_ = condition == "friction" ? static_cast<Real>(r.scalar("coefficient")) : Real(0);
    stick_ = condition == "noSlip" ? 1 : 0;
    separable_ = r.boolean("separable") ? 1 : 0;
    dimension_ = ctx.dimension;
    const bool three = dimension_ == 3;
    if (three ? !r.has("file") : !r.has("points"))
      throw InputError(r.dict().where(), "'" + ctx.name + "': " + (three ? "file" : "points") + ": missing; a " +
                                             (three ? "3D ground is read from an STL solid (file)"
                                                    : "2D ground is a polyline (points ((x0 y0) (x1 y1) ...))"));
    if (three ? r.has("points") : r.has("file")) {
      const char* key = three ? "points" : "file";
      throw InputError(r.entry(key).where(), std::string(key) + ": a " + (three ? "3D" : "2D") + " ground takes " +
                                                 (three ? "file (an STL solid), not points" : "points (a polyline), not file"));
    }
    const NodeLattice lattice = NodeLattice::of(ctx);
    if (r.word("shape") == "solid") {
      if (r.has("up"))
        throw InputError(r.entry("up").where(), "up: a solid is not seen from above; expected up only with shape "
                                                "heightField");
      solid(r, lattice, ctx.case_dir);
      return;
    }
    const int up = up_axis(r, ctx);
    // The ground over each column of nodes (the axes across `up`): its level and normal.
    const int u = three ? (up + 1) % 3 : 1 - up, w = three ? (up + 2) % 3 : 2;
    const int nu = lattice.nodes[u], nw = three ? lattice.nodes[w] : 1;
    std::vector<Real> level(static_cast<std::size_t>(nu) * nw, -kUnbounded);
    std::vector<Real> normal(static_cast<std::size_t>(dimension_) * level.size(), 0);
    if (three) {
      const Entry& file = r.entry("file");
      const std::string name = file.as_word();
      const auto surface = geometry::TriSurface::load(ctx.case_dir / name, name, file.where());
      for (int j = 0; j < nw; ++j)
        for (int i = 0; i < nu; ++i) {
          geometry::Point3 x = geometry::Point3::zero();
          x[u] = lattice.origin[u] + i * lattice.h;
          x[w] = lattice.origin[w] + j * lattice.h;
          geometry::TriSurface::Crossing c;
          if (!surface->top(x, up, c)) continue;  // the ground does not reach this column
          const std::size_t k = static_cast<std::size_t>(j) * nu + i;
          level[k] = static_cast<Real>(c.height);
          for (int d = 0; d < 3; ++d) normal[3 * k + d] = static_cast<Real>(c.normal[d]);
        }
    } else {
      const auto line = polyline(r.entry("points"));
      for (int i = 0; i < nu; ++i) {
        const Real x = lattice.origin[u] + i * lattice.h;
        for (std::size_t s = 0; s + 1 < line.size(); ++s) {  // the highest crossing
          const auto &a = line[s], &b = line[s + 1];
          if (a[0] == b[0] || x < std::min(a[0], b[0]) || x > std::max(a[0], b[0])) continue;
          const Real y = a[1] + (x - a[0]) * (b[1] - a[1]) / (b[0] - a[0]);
          if (!(y > level[static_cast<std::size_t>(i)])) continue;
          level[static_cast<std::size_t>(i)] = y;
          Real n[2];  // the segment's normal, pointing up
          n[u] = -(b[1] - a[1]);
          n[up] = b[0] - a[0];
          const Real scale = (n[up] < 0 ? -1 : 1) / std::sqrt(n[0] * n[0] + n[1] * n[1]);
          for (int d = 0; d < 2; ++d) normal[2 * static_cast<std::size_t>(i) + d] = n[d] * scale;
        }
      }
    }
    auto column = [&](const Real* x) {
      const long i = std::lround((x[u] - lattice.origin[u]) / lattice.h);
      const long j = three ? std::lround((x[w] - lattice.origin[w]) / lattice.h) : 0;
      return static_cast<std::size_t>(j) * nu + static_cast<std::size_t>(i);
    };
    nodes_.host() = select_nodes(lattice, [&](const Real* x) { return x[up] <= level[column(x)]; });
    // Each ground node's normal, in the order of the list (select_nodes' flat node order).
    std::vector<Real>& normals = normals_.host();
    normals.reserve(static_cast<std::size_t>(dimension_) * nodes_.host().size());
    for (Index I : nodes_.host()) {
      Index rest = I;
      Real x[3] = {0, 0, 0};
      for (int d = 0; d < dimension_; ++d) {
        x[d] = lattice.origin[d] + static_cast<Real>(rest % lattice.nodes[d]) * lattice.h;
        rest /= lattice.nodes[d];
      }
      const std::size_t k = column(x);
      for (int d = 0; d < dimension_; ++d) normals.push_back(normal[static_cast<std::size_t>(dimension_) * k + d]);
    }
  }

  bool has_node_law() const override { return true; }
  void apply(const Exec& ex, const GridNodes<2>& g) const override { run(ex, g); }
  void apply(const Exec& ex, const GridNodes<3>& g) const override { run(ex, g); }

 private:
  template <int D>
  void run(const Exec& ex, const GridNodes<D>& g) const {
    const Index n = static_cast<Index>(nodes_.host().size());
    if (n == 0 || !(g.velocity || g.velocity_new)) return;
    parallel_for(ex, n, TerrainKernel<D>{nodes_.on(ex), normals_.on(ex), mu_, separable_, stick_, g});
  }

  /// shape solid: the nodes inside the solid or on its surface (within 1e-6 h of it), each
  /// with the outward unit normal of the surface nearest to it.
  void solid(const ParamReader& r, const NodeLattice& lattice, const std::filesystem::path& case_dir) {
    const Real touch = Real(1e-6) * lattice.h;
    std::vector<Index>& nodes = nodes_.host();
    std::vector<Real>& normals = normals_.host();
    auto visit = [&](const Real* lo, const Real* hi, auto&& held) {
      int first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
      for (int d = 0; d < dimension_; ++d) {
        first[d] = std::max(0, static_cast<int>(std::floor((lo[d] - touch - lattice.origin[d]) / lattice.h)));
        last[d] = std::min(lattice.nodes[d] - 1,
                           static_cast<int>(std::ceil((hi[d] + touch - lattice.origin[d]) / lattice.h)));
        if (last[d] < first[d]) return;
      }
      // The flat node order of select_nodes: x fastest.
      for (int k = first[2]; k <= last[2]; ++k)
        for (int j = first[1]; j <= last[1]; ++j)
          for (int i = first[0]; i <= last[0]; ++i) {
            const int idx[3] = {i, j, k};
            Real x[3] = {0, 0, 0}, n[3] = {0, 0, 0};
            for (int d = 0; d < dimension_; ++d) x[d] = lattice.origin[d] + idx[d] * lattice.h;
            if (!held(x, n)) continue;
            nodes.push_back(static_cast<Index>(i) +
                            static_cast<Index>(lattice.nodes[0]) * (j + static_cast<Index>(lattice.nodes[1]) * k));
            for (int d = 0; d < dimension_; ++d) normals.push_back(n[d]);
          }
    };
    if (dimension_ == 3) {
      const Entry& file = r.entry("file");
      const std::string name = file.as_word();
      const auto surface = geometry::TriSurface::load(case_dir / name, name, file.where());
      const geometry::Box3& b = surface->bounds();
      Real lo[3], hi[3];
      for (int d = 0; d < 3; ++d) {
        lo[d] = static_cast<Real>(b.lo[d]);
        hi[d] = static_cast<Real>(b.hi[d]);
      }
      visit(lo, hi, [&](const Real* x, Real* n) {
        const geometry::Point3 p{{x[0], x[1], x[2]}};
        const auto near = surface->nearest(p, touch);
        if (!(near.distance <= touch || surface->contains(p))) return false;
        for (int d = 0; d < 3; ++d) n[d] = static_cast<Real>(near.normal[d]);
        return true;
      });
      return;
    }
    // 2D: a closed polygon (the last vertex joins the first).
    const auto poly = polyline(r.entry("points"));
    if (poly.size() < 3)
      throw InputError(r.entry("points").where(), "points: a solid needs a closed polygon of at least 3 vertices, found " +
                                                      std::to_string(poly.size()));
    Real lo[2] = {kUnbounded, kUnbounded}, hi[2] = {-kUnbounded, -kUnbounded};
    for (const auto& v : poly)
      for (int d = 0; d < 2; ++d) {
        lo[d] = std::min(lo[d], v[d]);
        hi[d] = std::max(hi[d], v[d]);
      }
    auto inside = [&](Real x, Real y) {  // even-odd rule
      bool in = false;
      for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const auto &a = poly[i], &c = poly[j];
        if ((a[1] > y) != (c[1] > y) && x < (c[0] - a[0]) * (y - a[1]) / (c[1] - a[1]) + a[0]) in = !in;
      }
      return in;
    };
    visit(lo, hi, [&](const Real* x, Real* n) {
      Real best = kUnbounded, px = 0, py = 0;
      std::size_t which = 0;
      for (std::size_t i = 0; i < poly.size(); ++i) {  // the nearest point of each edge
        const auto &a = poly[i], &c = poly[(i + 1) % poly.size()];
        const Real ex = c[0] - a[0], ey = c[1] - a[1], len2 = ex * ex + ey * ey;
        Real t = len2 > 0 ? ((x[0] - a[0]) * ex + (x[1] - a[1]) * ey) / len2 : Real(0);
        t = std::min(Real(1), std::max(Real(0), t));
        const Real qx = a[0] + t * ex, qy = a[1] + t * ey;
        const Real d2 = (qx - x[0]) * (qx - x[0]) + (qy - x[1]) * (qy - x[1]);
        if (d2 < best) {
          best = d2;
          px = qx;
          py = qy;
          which = i;
        }
      }
      const Real dist = std::sqrt(best);
      const bool in = inside(x[0], x[1]);
      if (!(dist <= touch || in)) return false;
      if (dist > touch) {  // from inside to the nearest point: outwards
        n[0] = (px - x[0]) / dist;
        n[1] = (py - x[1]) / dist;
        return true;
      }
      // On the boundary: the nearest edge's normal, turned out of the polygon.
      const auto &a = poly[which], &c = poly[(which + 1) % poly.size()];
      const Real ex = c[0] - a[0], ey = c[1] - a[1], len = std::sqrt(ex * ex + ey * ey);
      n[0] = ey / len;
      n[1] = -ex / len;
      const Real mx = Real(0.5) * (a[0] + c[0]), my = Real(0.5) * (a[1] + c[1]);
      if (inside(mx + Real(1e-6) * len * n[0], my + Real(1e-6) * len * n[1])) {
        n[0] = -n[0];
        n[1] = -n[1];
      }
      return true;
    });
  }

  /// The 2D ground's vertices: at least two (x y) pairs.
  static std::vector<std::array<Real, 2>> polyline(const Entry& e) {
    std::vector<std::array<Real, 2>> line;
    for (const Item& p : e.single_item().list()) {
      if (p.kind() != Item::Kind::list || p.list().size() != 2 || p.list()[0].kind() != Item::Kind::number ||
          p.list()[1].kind() != Item::Kind::number)
        throw InputError(p.where(), "points: each vertex must be (x y), found " + p.to_string());
      line.push_back({static_cast<Real>(p.list()[0].number()), static_cast<Real>(p.list()[1].number())});
    }
    if (line.size() < 2)
      throw InputError(e.where(), "points: a ground profile needs at least 2 vertices, found " + std::to_string(line.size()));
    return line;
  }

  /// `up`, or the axis of gravity's largest component (gravity points down it).
  static int up_axis(const ParamReader& r, const SolverContext& ctx) {
    if (r.has("up")) {
      const int axis = r.word("up")[0] - 'x';
      if (axis >= ctx.dimension)
        throw InputError(r.entry("up").where(), "up: a 2D case has the axes x and y; expected up x or up y");
      return axis;
    }
    int axis = ctx.dimension - 1;
    Real largest = 0;
    for (int d = 0; d < static_cast<int>(ctx.gravity.size()) && d < 3; ++d)
      if (std::fabs(ctx.gravity[static_cast<std::size_t>(d)]) > largest) {
        largest = std::fabs(ctx.gravity[static_cast<std::size_t>(d)]);
        axis = d;
      }
    if (largest > 0 && ctx.gravity[static_cast<std::size_t>(axis)] > 0)
      throw InputError(r.dict().where(), "'" + ctx.name + "': gravity points up axis " + std::string(1, char('x' + axis)) +
                                             ", so the ground would be seen from below; give `up` for a ground under "
                                             "gravity along -" + std::string(1, char('x' + axis)));
    return axis;
  }

  Real mu_ = 0;
  int separable_ = 1;
  int stick_ = 0;
  int dimension_ = 3;
  HostedList<Index> nodes_;  // the ground nodes (flat indices of the grid)
  HostedList<Real> normals_;  // D per ground node
};

}  // namespace scree::boundary
