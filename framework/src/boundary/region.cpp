// Regions of grid nodes and the set of walls built from boundary conditions.
#include <cmath>
#include <stdexcept>
#include <utility>

#include "scree/boundary/boundary_condition.hpp"

namespace scree {

BoundaryCondition::~BoundaryCondition() = default;

void BoundaryCondition::declare_time_window(ParamSpec& spec) {
  spec.scalar("startTime", "s", "the condition acts from this time").default_value(-1e300);
  spec.scalar("endTime", "s", "the condition acts until this time (e.g. a gate removed at 0.2 s)")
      .default_value(1e300);
  spec.boolean("drained", "two-phase bodies: the pore liquid crosses this wall freely (a drained boundary); "
                          "default: the wall is impermeable, the liquid's velocity obeys it as the solid's")
      .default_value("false");
}

void BoundaryCondition::read_time_window(const ParamReader& r, Wall& w) {
  w.t_start = r.scalar("startTime");
  w.t_end = r.scalar("endTime");
  if (r.has("drained")) w.drained = r.boolean("drained") ? 1 : 0;
}

void BoundaryCondition::declare_normal(ParamSpec& spec) {
  spec.vector("normal", "-", "wall normal pointing into the material (default: the face's or half-space's)")
      .size(-1)
      .optional();
}

void BoundaryCondition::read_normal(const ParamReader& r, const Region& region, Wall& w) {
  std::vector<Real> n = region.normal();
  if (r.has("normal")) n = r.scalars("normal");
  Real len = 0;
  for (Real x : n) len += x * x;
  len = std::sqrt(len);
  if (len == 0)
    throw InputError(r.dict().where(), "'" + r.dict().name() + "': a wall on a " + region.description() +
                                           " needs `normal (..)`, the direction pointing into the material");
  for (std::size_t d = 0; d < n.size() && d < 3; ++d) w.normal[d] = n[d] / len;
}

void Region::declare(ParamSpec& spec) {
  spec.word("face", "a face of the domain box: the nodes on it and the ghost nodes beyond")
      .choices({"xMin", "xMax", "yMin", "yMax", "zMin", "zMax"})
      .optional();
  auto box = std::make_shared<ParamSpec>("box", "nodes inside an axis-aligned box");
  box->vector("min", "m", "lower corner").size(-1);
  box->vector("max", "m", "upper corner").size(-1);
  spec.dict("box", "nodes inside an axis-aligned box { min (..); max (..); } (bounds included)")
      .sub_spec(box)
      .optional();
  auto half = std::make_shared<ParamSpec>("halfSpace", "nodes on or behind a plane");
  half->vector("point", "m", "a point on the plane").size(-1);
  half->vector("normal", "-", "normal pointing from the selected nodes into the material").size(-1);
  spec.dict("halfSpace", "nodes on or behind a plane { point (..); normal (..); }").sub_spec(half).optional();
  spec.check([](const Dictionary& d, std::vector<InputError>& errors) {
    const int n = int(d.has("face")) + int(d.has("box")) + int(d.has("halfSpace"));
    if (n != 1)
      errors.emplace_back(d.where(), "'" + d.name() + "': give exactly one region: face, box or halfSpace (found " +
                                         std::to_string(n) + ")");
  });
}

RegionWall::RegionWall(const ParamReader& r, const NodeLattice& grid, std::string name)
    : region_(Region::read(r, grid)), name_(std::move(name)) {
  read_time_window(r, wall_);
}

void RegionWall::constrain(WallSet& set) const {
  set.add(wall_, [this](const Real* x) { return region_.contains(x); }, name_);
}

Region Region::read(const ParamReader& r, const NodeLattice& grid) {
  Region g;
  g.dim_ = grid.dimension;
  g.tol_ = 1e-6 * grid.h;
  const Dictionary& d = r.dict();
  if (d.has("face")) {
    g.kind_ = Kind::face;
    const std::string f = d.get_word("face");
    g.axis_ = f[0] - 'x';
    g.upper_ = f.substr(1) == "Max";
    if (g.axis_ >= g.dim_)
      throw InputError(d.at("face").where(), "face: " + f + " does not exist in a " + std::to_string(g.dim_) +
                                                 "D case; expected one of " +
                                                 (g.dim_ == 2 ? "xMin, xMax, yMin, yMax" : "xMin, xMax, yMin, yMax, zMin, zMax"));
    g.plane_ = g.upper_ ? grid.upper[g.axis_] : grid.lower[g.axis_];
    g.normal_.assign(g.dim_, 0.0);
    g.normal_[g.axis_] = g.upper_ ? -1 : 1;
    g.description_ = "face " + f;
  } else if (d.has("box")) {
    g.kind_ = Kind::box;
    const Dictionary& b = d.sub("box");
    g.lo_ = b.at("min").as_scalar_list();
    g.hi_ = b.at("max").as_scalar_list();
    g.normal_.assign(g.dim_, 0.0);
    g.description_ = "box";
  } else {
    g.kind_ = Kind::halfSpace;
    const Dictionary& h = d.sub("halfSpace");
    g.point_ = h.at("point").as_scalar_list();
    g.normal_ = h.at("normal").as_scalar_list();
    Real len = 0;
    for (Real c : g.normal_) len += c * c;
    len = std::sqrt(len);
    if (len == 0) throw InputError(h.at("normal").where(), "normal: must not be zero");
    for (Real& c : g.normal_) c /= len;
    g.description_ = "halfSpace";
  }
  return g;
}

bool Region::contains(const Real* x) const {
  switch (kind_) {
    case Kind::face:
      return upper_ ? x[axis_] >= plane_ - tol_ : x[axis_] <= plane_ + tol_;
    case Kind::box:
      for (int d = 0; d < dim_; ++d)
        if (x[d] < lo_[d] - tol_ || x[d] > hi_[d] + tol_) return false;
      return true;
    case Kind::halfSpace: {
      Real s = 0;
      for (int d = 0; d < dim_; ++d) s += (x[d] - point_[d]) * normal_[d];
      return s <= tol_;
    }
  }
  return false;
}

namespace {
/// Visit every grid node: f(flat index, position).
template <class F>
void for_each_node(const NodeLattice& grid, F&& f) {
  const Index n = grid.count();
  Real x[3] = {0, 0, 0};
  for (Index flat = 0; flat < n; ++flat) {
    Index r = flat;
    for (int d = 0; d < grid.dimension; ++d) {
      const int i = static_cast<int>(r % grid.nodes[d]);
      r /= grid.nodes[d];
      x[d] = grid.origin[d] + grid.h * i;
    }
    f(flat, x);
  }
}
}  // namespace

std::vector<Index> select_nodes(const NodeLattice& grid, const std::function<bool(const Real*)>& select) {
  std::vector<Index> nodes;
  for_each_node(grid, [&](Index flat, const Real* x) {
    if (select(x)) nodes.push_back(flat);
  });
  return nodes;
}

WallSet::WallSet(const NodeLattice& grid) : grid_(grid) { masks_.assign(static_cast<std::size_t>(grid.count()), 0); }

int WallSet::add(const Wall& w, Selector select, const std::string& owner) {
  if (static_cast<int>(table_.size()) >= kMaxWalls)
    throw std::runtime_error("too many walls (at most " + std::to_string(kMaxWalls) + " per case); " + owner +
                             " is one too many");
  const int index = static_cast<int>(table_.size());
  table_.push_back(w);
  owners_.push_back(owner);
  Index count = 0;
  for_each_node(grid_, [&](Index flat, const Real* x) {
    if (select(x)) {
      masks_[static_cast<std::size_t>(flat)] |= WallMask(1) << index;
      ++count;
    }
  });
  counts_.push_back(count);
  return index;
}

}  // namespace scree
