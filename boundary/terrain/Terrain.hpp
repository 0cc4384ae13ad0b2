// terrain: the ground under a 3D flow, a rigid surface read from an STL file, with
// Coulomb friction.
//
//   ground { type terrain; file "constant/triSurface/valley.stl"; coefficient 0.47; }
//   ground { type terrain; file "constant/triSurface/valley.stl"; condition noSlip; }
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
// The ground is a height field of the grid's node columns: an overhang of the solid is
// filled below its top, and the ground is resolved to a cell, as every wall on grid nodes
// is. It is a node law (boundary/node_law.hpp) on the ground nodes of the grid a rank
// holds, so a decomposed run applies it on each rank's part. 3D only.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/core/constants.hpp"
#include "scree/exec/memory.hpp"
#include "scree/geometry/tri_surface.hpp"
#include "scree/plugin/context.hpp"

namespace scree::boundary {

/// Coulomb contact on the listed ground nodes: node i of the list is grid node nodes[i],
/// its ground normal normals[3 i .. 3 i + 2].
struct TerrainKernel {
  const Index* nodes;
  const Real* normals;
  Real mu;
  int separable;
  int stick;  ///< noSlip: the velocity is set to zero
  GridNodes<3> g;
  SCREE_HD void operator()(Index i) const {
    const Index I = nodes[i];
    if (!(g.fields.mass[I] > 0)) return;  // no material at the node: no velocity
    const Real* n = normals + 3 * i;
    Real v[3];
    if (g.velocity) {
      for (int d = 0; d < 3; ++d) v[d] = stick ? Real(0) : g.fields.velocity[d][I];
      if (!stick) coulomb_contact<3>(v, n, mu, separable != 0);
      for (int d = 0; d < 3; ++d) g.fields.velocity[d][I] = v[d];
    }
    if (g.velocity_new) {
      for (int d = 0; d < 3; ++d) v[d] = stick ? Real(0) : g.fields.velocity_new[d][I];
      if (!stick) coulomb_contact<3>(v, n, mu, separable != 0);
      for (int d = 0; d < 3; ++d) g.fields.velocity_new[d][I] = v[d];
    }
  }
};

class Terrain final : public BoundaryCondition {
 public:
  static constexpr const char* type_name = "terrain";
  static ParamSpec spec() {
    ParamSpec s(type_name, "the ground under a 3D flow, read from an STL solid: friction, slip or no slip on the nodes at or "
                           "below it");
    s.word("file", "STL file relative to the case: a closed solid whose top is the ground, e.g. "
                   "\"constant/triSurface/valley.stl\"");
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
    const Entry& file = r.entry("file");
    if (ctx.dimension != 3)
      throw InputError(r.dict().where(), "'" + ctx.name + "': type terrain is a 3D condition (a ground read from an STL "
                                         "surface); in 2D, draw the ground as a friction wall on a halfSpace or box");
    const int up = up_axis(r, ctx);
    const std::string name = file.as_word();
    const auto surface = geometry::TriSurface::load(ctx.case_dir / name, name, file.where());
    const NodeLattice lattice = NodeLattice::of(ctx);
    // The ground over each column of nodes: the solid's top and the normal there.
    const int u = (up + 1) % 3, w = (up + 2) % 3;
    const int nu = lattice.nodes[u], nw = lattice.nodes[w];
    std::vector<Real> level(static_cast<std::size_t>(nu) * nw, -kUnbounded);
    std::vector<Real> normal(3 * level.size(), 0);
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
    auto column = [&](const Real* x) {
      const long i = std::lround((x[u] - lattice.origin[u]) / lattice.h);
      const long j = std::lround((x[w] - lattice.origin[w]) / lattice.h);
      return static_cast<std::size_t>(j) * nu + static_cast<std::size_t>(i);
    };
    hosted_ = select_nodes(lattice, [&](const Real* x) { return x[up] <= level[column(x)]; });
    // Each ground node's normal, in the order of the list (select_nodes' flat node order).
    hosted_normals_.reserve(3 * hosted_.size());
    for (Index I : hosted_) {
      Index rest = I;
      Real x[3];
      for (int d = 0; d < 3; ++d) {
        x[d] = lattice.origin[d] + static_cast<Real>(rest % lattice.nodes[d]) * lattice.h;
        rest /= lattice.nodes[d];
      }
      const std::size_t k = column(x);
      for (int d = 0; d < 3; ++d) hosted_normals_.push_back(normal[3 * k + d]);
    }
    count_ = static_cast<Index>(hosted_.size());
  }

  bool has_node_law() const override { return true; }
  using BoundaryCondition::apply;  // 2D: never constructed (3D only)
  void apply(const Exec& ex, const GridNodes<3>& g) const override {
    if (count_ == 0 || !(g.velocity || g.velocity_new)) return;
    if (nodes_.size() != hosted_.size()) {  // the lists on the backend, once (before any capture)
      nodes_.resize(hosted_.size(), ex.device);
      nodes_.copy_from_host(hosted_);
      normals_.resize(hosted_normals_.size(), ex.device);
      normals_.copy_from_host(hosted_normals_);
    }
    parallel_for(ex, count_, TerrainKernel{nodes_.data(), normals_.data(), mu_, separable_, stick_, g});
  }

 private:
  /// `up`, or the axis of gravity's largest component (gravity points down it).
  static int up_axis(const ParamReader& r, const SolverContext& ctx) {
    if (r.has("up")) return r.word("up")[0] - 'x';
    int axis = 2;
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
  std::vector<Index> hosted_;   // the ground nodes (flat indices of the grid)
  std::vector<Real> hosted_normals_;  // 3 per ground node
  mutable Buffer<Index> nodes_;
  mutable Buffer<Real> normals_;
  Index count_ = 0;
};

}  // namespace scree::boundary
