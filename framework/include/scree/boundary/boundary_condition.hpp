// Boundary-condition plugins.
//
// A boundary condition declares its parameters (static spec()) and, once the grid
// exists, adds node constraints (constraints.hpp) for the nodes it selects; the core
// applies them inside the grid update on either backend. A region selects nodes:
//   face xMin;                                  a face of the domain box (and the ghost
//                                               nodes beyond it): xMin xMax yMin yMax zMin zMax
//   box { min (0.2 -1); max (0.2 1); }          nodes inside an axis-aligned box
//   halfSpace { point (0 0); normal (1 -1); }   nodes on or behind a plane (n points out
//                                               of the selected side, into the material)
// and startTime/endTime give the window in which it acts (a gate removed at t = 0.2 s
// has endTime 0.2).
//
//   struct MyBC : BoundaryCondition {
//     static constexpr const char* type_name = "myBC";
//     static ParamSpec spec();
//     MyBC(const ParamReader& r, const SolverContext& ctx);
//     void constrain(ConstraintSet& set) const override;
//   };
//   SCREE_PLUGIN(r) { r.add_boundary_condition<MyBC>(); }
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scree/boundary/constraints.hpp"
#include "scree/params/spec.hpp"
#include "scree/solver/context.hpp"

namespace scree {

/// A set of grid nodes chosen by position (host-side; evaluated once at setup).
class SCREE_API Region {
 public:
  /// Declare the region parameters (face | box | halfSpace) in a spec.
  static void declare(ParamSpec& spec);
  /// Read from a validated dictionary. Throws InputError for an incomplete region.
  static Region read(const ParamReader& r, const SolverContext& ctx);

  bool contains(const Real* x) const;
  /// The unit normal pointing into the material for a face or half-space (zero for a box).
  const std::vector<Real>& normal() const { return normal_; }
  const std::string& description() const { return description_; }

 private:
  enum class Kind { face, box, halfSpace } kind_ = Kind::box;
  int dim_ = 2;
  int axis_ = 0;
  bool upper_ = false;
  Real plane_ = 0, tol_ = 0;
  std::vector<Real> lo_, hi_, point_, normal_;
  std::string description_;
};

/// Collects constraints and the nodes they act on.
class SCREE_API ConstraintSet {
 public:
  using Selector = std::function<bool(const Real* node_position)>;
  explicit ConstraintSet(const SolverContext& grid);
  /// Add a constraint on the nodes `select` accepts. Returns its index. Throws when more
  /// than kMaxConstraints are added (the message names the limit).
  int add(const Constraint& c, Selector select, const std::string& owner);
  const std::vector<Constraint>& table() const { return table_; }
  /// One mask per node (the grid's flat node order).
  const std::vector<ConstraintMask>& masks() const { return masks_; }
  /// How many nodes the constraint at `index` selected (boundary conditions that select
  /// nothing are reported as a warning).
  Index count(int index) const { return counts_.at(index); }
  const std::vector<std::string>& owners() const { return owners_; }

 private:
  SolverContext grid_;
  std::vector<Constraint> table_;
  std::vector<ConstraintMask> masks_;
  std::vector<Index> counts_;
  std::vector<std::string> owners_;
};

class SCREE_API BoundaryCondition {
 public:
  virtual ~BoundaryCondition();
  /// Add node constraints (called once the grid exists).
  virtual void constrain(ConstraintSet&) const {}

  // Helpers shared by the wall conditions (fixed, slip, friction).
  /// Declare startTime/endTime (the window in which the condition acts).
  static void declare_time_window(ParamSpec& spec);
  static void read_time_window(const ParamReader& r, Constraint& c);
  /// Declare `normal` (optional: faces and half-spaces have their own).
  static void declare_normal(ParamSpec& spec);
  /// The wall normal pointing into the material: `normal` if given, else the region's;
  /// throws InputError when neither gives one (a box without `normal`).
  static void read_normal(const ParamReader& r, const Region& region, Constraint& c);
};

/// Base of the wall conditions: one constraint on the nodes of one region. Derived
/// classes fill `constraint_` in their constructor.
class SCREE_API RegionConstraint : public BoundaryCondition {
 public:
  RegionConstraint(const ParamReader& r, const SolverContext& ctx);
  void constrain(ConstraintSet& set) const override;

 protected:
  Region region_;
  std::string name_;
  Constraint constraint_;
};

}  // namespace scree
