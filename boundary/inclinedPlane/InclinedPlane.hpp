// inclinedPlane: a rigid plane at any angle to the grid (a chute, a slope), no-slip,
// frictionless or with Coulomb friction, acting on the nodes the material in front of the
// plane reaches rather than on every node behind it.
//   chute { type inclinedPlane; point (0 0.7); normal (0.5 0.866025); condition friction; coefficient 0.4; }
//   bed   { type inclinedPlane; point (0.2 1.626346); normal (1 1); condition slip; }
//
// With d = (x - point).n the signed distance of a node from the plane (n normalised, out of
// the wall into the material), the plane acts on three sets of nodes:
//   0 < d                       in front: free;
//   -1.5 h |n|_1 < d <= 0       on or behind the plane, within reach of points in front of
//                               it: the contact law of mpm/wall_law.hpp with the plane's
//                               normal (slip: mu = 0; friction: Coulomb mu, Bardenhagen,
//                               Brackbill & Sulsky 2000), or stick (noSlip);
//   d <= -1.5 h |n|_1           wholly inside the wall: stick (they move with it).
// |n|_1 = sum |n_i|. A point at d_p > 0 weighs on the nodes within r h of it along each
// axis, r the shape function's reach (mpm/shape_functions.hpp: linear 1, bspline2 1.5, gimp
// 1 + lp <= 1.5), so on nodes with d > d_p - r h |n|_1 > -r h |n|_1. The contact set is
// that reach for the widest of them: with linear shape functions it is the nodes of the
// cells the plane cuts (r = 1) and half a cell more, which only points gone through the
// plane reach. Held instead, such nodes drag the material: a block sliding on a 30-degree
// plane with bspline2 took a 12% (slip) and 24% (mu = 0.2) lower acceleration with r = 1
// (tests/verification/boundary/test_inclined_plane.cpp). A `slip` or `friction` wall on a
// halfSpace applies the contact law on every node behind the plane: the deeper nodes carry
// only points that went through the plane, here held by the wall instead of sliding on
// inside it. Where no point goes that deep the two walls are the same run (that test,
// where USL blows up with either: that is USL's own). noSlip holds both sets: it is the
// `fixed` halfSpace staircase, node for node (cases/flume/README.md, "Inclined plane
// against the staircase").
//
// Errors before anything runs, each at the entry's file:line: a zero normal; a plane that
// misses the grid (every node of the domain in front of it) or leaves it no room (every
// node on or behind it); a negative coefficient; friction without coefficient; coefficient
// with slip or noSlip, or separable with noSlip (an error, not a warning: the entry would
// be ignored, and `condition slip; coefficient 0.4;` most likely meant a rough chute).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/core/constants.hpp"
#include "scree/plugin/context.hpp"

namespace scree::boundary {

class InclinedPlane final : public BoundaryCondition {
 public:
  static constexpr const char* type_name = "inclinedPlane";
  /// The widest reach of a point's shape functions, in cells along each axis (bspline2).
  static constexpr Real kReach = 1.5;
  static ParamSpec spec() {
    ParamSpec s(type_name, "rigid plane at any angle: contact law on the nodes the material reaches, stick behind");
    s.vector("point", "m", "a point on the plane").size(-1);
    s.vector("normal", "-", "plane normal pointing out of the wall into the material (normalised here)").size(-1);
    s.word("condition", "noSlip: the material sticks; slip: frictionless; friction: Coulomb, mu = coefficient")
        .choices({"noSlip", "slip", "friction"});
    s.scalar("coefficient", "-", "Coulomb friction coefficient mu = tan(wall friction angle) (condition friction)")
        .non_negative()
        .optional();
    s.boolean("separable", "slip, friction: the material may leave the plane (only approach is stopped)")
        .default_value("yes");
    declare_time_window(s);
    s.check([](const Dictionary& d, std::vector<InputError>& errors) {
      Real n2 = 0;
      for (Real c : d.at("normal").as_scalar_list()) n2 += c * c;
      if (n2 == 0)
        errors.emplace_back(d.at("normal").where(),
                            "normal: must not be zero; expected the direction out of the wall into the material");
      const std::string condition = d.get_word("condition");
      if (condition == "friction" && !d.has("coefficient"))
        errors.emplace_back(d.where(), "missing required entry 'coefficient' in '" + d.name() +
                                           "': condition friction needs the Coulomb friction coefficient mu >= 0");
      if (condition != "friction" && d.has("coefficient"))
        errors.emplace_back(d.at("coefficient").where(),
                            "coefficient: only condition friction uses it (condition " + condition +
                                " would ignore it); give condition friction, or remove coefficient");
      if (condition == "noSlip" && d.has("separable"))
        errors.emplace_back(d.at("separable").where(),
                            "separable: condition noSlip holds every node it acts on (it would ignore separable); "
                            "give condition slip or friction, or remove separable");
    });
    return s;
  }

  InclinedPlane(const ParamReader& r, const SolverContext& ctx) : name_(ctx.name), dim_(ctx.dimension) {
    const std::vector<Real> p = r.scalars("point"), n = r.scalars("normal");
    Real len = 0;
    for (Real c : n) len += c * c;
    len = std::sqrt(len);
    if (len == 0) throw InputError(r.entry("normal").where(), "normal: must not be zero");
    Real n1 = 0;  // |n|_1
    for (int d = 0; d < dim_; ++d) {
      point_[d] = p[d];
      normal_[d] = n[d] / len;
      n1 += std::fabs(normal_[d]);
    }
    band_ = kReach * ctx.cell_size * n1;
    tol_ = 1e-6 * ctx.cell_size;

    // The domain box's corners bound d over the grid (d is linear in x).
    Real lo = kUnbounded, hi = -kUnbounded;
    for (int c = 0; c < (1 << dim_); ++c) {
      Real x[3];
      for (int d = 0; d < dim_; ++d) x[d] = ((c >> d) & 1) ? ctx.domain_upper[d] : ctx.domain_lower[d];
      lo = std::min(lo, distance(x));
      hi = std::max(hi, distance(x));
    }
    if (lo > tol_ || hi <= tol_)
      throw InputError(r.entry("point").where(),
                       "point: the plane through " + vec(point_) + " with normal " + vec(normal_) +
                           (lo > tol_ ? " misses the grid: every node of the domain " + box(ctx) + " lies in front of it"
                                      : " leaves no room: every node of the domain " + box(ctx) +
                                            " lies on or behind it (the normal points into the material)") +
                           "; expected a plane that cuts the domain");
    // Nodes wholly inside the wall exist if the deepest corner of the lattice (ghost nodes
    // included) is one; otherwise no stick wall is added (it would select no node).
    Real deepest = kUnbounded;
    for (int c = 0; c < (1 << dim_); ++c) {
      Real x[3];
      for (int d = 0; d < dim_; ++d)
        x[d] = ctx.grid_origin[d] + (((c >> d) & 1) ? ctx.cell_size * (ctx.grid_nodes[d] - 1) : Real(0));
      deepest = std::min(deepest, distance(x));
    }
    has_inside_ = deepest <= -band_ + tol_;

    const std::string condition = r.word("condition");
    if (condition == "noSlip") {
      contact_.mode = Wall::Mode::stick;
    } else {
      contact_.mode = Wall::Mode::contact;
      for (int d = 0; d < 3; ++d) contact_.normal[d] = normal_[d];
      contact_.mu = condition == "friction" ? r.scalar("coefficient") : 0;
      contact_.separable = r.boolean("separable") ? 1 : 0;
    }
    read_time_window(r, contact_);
    inside_ = Wall{};  // stick: v = 0
    read_time_window(r, inside_);
  }

  void constrain(WallSet& set) const override {
    const InclinedPlane* self = this;
    if (contact_.mode == Wall::Mode::stick) {  // noSlip: one wall, every node on or behind the plane
      set.add(contact_, [self](const Real* x) { return self->distance(x) <= self->tol_; }, name_);
      return;
    }
    set.add(contact_, [self](const Real* x) {
      const Real d = self->distance(x);
      return d <= self->tol_ && d > -self->band_ + self->tol_;
    }, name_);
    if (has_inside_)
      set.add(inside_, [self](const Real* x) { return self->distance(x) <= -self->band_ + self->tol_; }, name_);
  }

 private:
  Real distance(const Real* x) const {
    Real s = 0;
    for (int d = 0; d < dim_; ++d) s += (x[d] - point_[d]) * normal_[d];
    return s;
  }
  std::string vec(const Real* v) const {
    std::string s = "(";
    for (int d = 0; d < dim_; ++d) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%s%.6g", d ? " " : "", v[d]);
      s += buf;
    }
    return s + ")";
  }
  std::string box(const SolverContext& ctx) const {
    Real lo[3], hi[3];
    for (int d = 0; d < dim_; ++d) {
      lo[d] = ctx.domain_lower[d];
      hi[d] = ctx.domain_upper[d];
    }
    return vec(lo) + "-" + vec(hi);
  }

  std::string name_;
  int dim_ = 2;
  Real point_[3] = {0, 0, 0}, normal_[3] = {0, 0, 0};
  Real band_ = 0, tol_ = 0;  ///< kReach h |n|_1: the depth of the contact set; round-off allowance [m]
  bool has_inside_ = false;
  Wall contact_, inside_;  ///< on the cut cells' nodes; on the nodes wholly inside the wall
};

}  // namespace scree::boundary
