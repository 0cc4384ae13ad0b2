// Boundary-condition plugins: what a boundary does to the grid nodes it selects.
//
// A boundary condition declares its parameters (static spec()) and, once the grid exists,
// acts on the nodes its region selects in one of two ways, as OpenFOAM's patch types
// carry their own behaviour:
//
//   walls      constrain() adds rigid walls (mpm/wall_law.hpp: stick or Coulomb contact
//              against a wall of any rigid motion). The grid update applies them fused
//              into its kernel: no launch, no cost beyond the nodes' own. fixed, slip,
//              friction and rotatingWall are such walls.
//   node laws  a plugin with a law of its own overrides apply(): after every grid update
//              (after the walls) it runs its own kernel on the grid set just updated, on
//              either backend, inside the CUDA graphs of the steps. NodeLawCondition
//              (node_law.hpp) does the bookkeeping; shakingTable is the example to copy.
//
// A region selects nodes:
//   face xMin;                                  a face of the domain box (and the ghost
//                                               nodes beyond it): xMin xMax yMin yMax zMin zMax
//   box { min (0.2 -1); max (0.2 1); }          nodes inside an axis-aligned box
//   halfSpace { point (0 0); normal (1 -1); }   nodes on or behind a plane (n points out
//                                               of the selected side, into the material)
// and startTime/endTime give the window in which it acts (a gate removed at t = 0.2 s
// has endTime 0.2). In a two-phase case a wall also stops the pore liquid (impermeable)
// unless it is `drained`.
//
// A condition on the pore liquid of two-phase bodies (rainfall, ponding, seepageFace,
// porePressure) implements the porous formulation's HydraulicCondition beside this class
// (porous/hydraulic_condition.hpp).
//
//   struct MyWall : RegionWall {
//     static constexpr const char* type_name = "myWall";
//     static ParamSpec spec();
//     MyWall(const ParamReader& r, const SolverContext& ctx);  // fills wall_
//   };
//   SCREE_PLUGIN(r) { r.add_boundary_condition<MyWall>(); }
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/wall_law.hpp"
#include "scree/params/spec.hpp"

namespace scree {

struct SolverContext;  // what plugins learn about the case (scree/plugin/context.hpp)

/// The grid's nodes as WallSet and select_nodes visit them, and the domain box that
/// regions (faces) are read against.
struct NodeLattice {
  int dimension = 2;
  Real origin[3] = {0, 0, 0};  ///< position of node (0, 0, 0) [m]
  int nodes[3] = {1, 1, 1};    ///< nodes per axis
  Real h = 0;                  ///< spacing [m]
  Real lower[3] = {0, 0, 0}, upper[3] = {0, 0, 0};  ///< the domain box (gridDict lower, upper) [m]
  /// The case's grid as plugins learn it. Defined in the plugin layer (src/plugin/context.cpp),
  /// where SolverContext is known: this folder is below plugin/ in the README's layering.
  SCREE_API static NodeLattice of(const SolverContext& ctx);
  Index count() const { return static_cast<Index>(nodes[0]) * nodes[1] * nodes[2]; }
};

/// A set of grid nodes chosen by position (host-side; evaluated once at setup).
class SCREE_API Region {
 public:
  /// Declare the region parameters (face | box | halfSpace) in a spec.
  static void declare(ParamSpec& spec);
  /// Read from a validated dictionary against the case's grid (faces: its domain box).
  /// Throws InputError for an incomplete region.
  static Region read(const ParamReader& r, const NodeLattice& grid);
  /// The same with the grid of a plugin's context (src/plugin/context.cpp).
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

/// The grid nodes (flat indices) whose positions `select` accepts.
SCREE_API std::vector<Index> select_nodes(const NodeLattice& grid, const std::function<bool(const Real*)>& select);

/// Collects the walls of a case and the nodes they act on.
class SCREE_API WallSet {
 public:
  using Selector = std::function<bool(const Real* node_position)>;
  explicit WallSet(const NodeLattice& grid);
  /// Add a wall on the nodes `select` accepts. Returns its index. Throws when more than
  /// kMaxWalls are added (the message names the limit).
  int add(const Wall& w, Selector select, const std::string& owner);
  const std::vector<Wall>& table() const { return table_; }
  /// One mask per node (the grid's flat node order).
  const std::vector<WallMask>& masks() const { return masks_; }
  /// How many nodes the wall at `index` selected (boundary conditions that select nothing
  /// are reported as a warning).
  Index count(int index) const { return counts_.at(index); }
  const std::vector<std::string>& owners() const { return owners_; }

 private:
  NodeLattice grid_;
  std::vector<Wall> table_;
  std::vector<WallMask> masks_;
  std::vector<Index> counts_;
  std::vector<std::string> owners_;
};

/// What a node law sees after a grid update: the grid set it updated (device pointers),
/// the clock, and which velocities that update produced.
template <int D>
struct GridNodes {
  GridGeometry<D> grid;
  GridFields<D> fields;
  const StepControl* control = nullptr;
  int parity = 0;             ///< the step's clock slot: its time is control->t[parity]
  bool velocity = false;      ///< fields.velocity was set (v^k, or MUSL's remapped velocity)
  bool velocity_new = false;  ///< fields.velocity_new was set (v^{k+1})
};

class SCREE_API BoundaryCondition {
 public:
  virtual ~BoundaryCondition();
  /// Add walls (called once the grid exists).
  virtual void constrain(WallSet&) const {}
  /// Whether apply() runs a node law of the plugin's own.
  virtual bool has_node_law() const { return false; }
  /// The node law: queue a kernel on `ex` (its stream) over the nodes it acts on.
  virtual void apply(const Exec& ex, const GridNodes<2>& g) const {
    (void)ex;
    (void)g;
  }
  virtual void apply(const Exec& ex, const GridNodes<3>& g) const {
    (void)ex;
    (void)g;
  }

  // Helpers shared by the wall conditions (fixed, slip, friction).
  /// Declare startTime/endTime (the window in which the condition acts).
  static void declare_time_window(ParamSpec& spec);
  static void read_time_window(const ParamReader& r, Wall& w);
  /// Declare `normal` (optional: faces and half-spaces have their own).
  static void declare_normal(ParamSpec& spec);
  /// The wall normal pointing into the material: `normal` if given, else the region's;
  /// throws InputError when neither gives one (a box without `normal`).
  static void read_normal(const ParamReader& r, const Region& region, Wall& w);
};

/// Base of the wall conditions: one wall on the nodes of one region. Derived classes fill
/// `wall_` in their constructor.
class SCREE_API RegionWall : public BoundaryCondition {
 public:
  /// `ctx`: the region's grid and the condition's name (src/plugin/context.cpp).
  RegionWall(const ParamReader& r, const SolverContext& ctx);
  RegionWall(const ParamReader& r, const NodeLattice& grid, std::string name);
  void constrain(WallSet& set) const override;

 protected:
  Region region_;
  std::string name_;
  Wall wall_;
};

}  // namespace scree
