// NodeLawCondition<Law>: a boundary condition with a node law of its own, run as the
// plugin's own kernel after every grid update (boundary_condition.hpp).
//
// Law is a plain struct, copied to the device:
//
//   struct MyLaw {
//     Real amplitude;   // whatever the law needs, trivially copyable
//     template <int D>
//     SCREE_HD void apply(Real* v, const Real* x, Real t) const;  // v: a node's velocity
//   };
//
// and the condition is `class MyBC : public NodeLawCondition<MyLaw>` with a spec() that
// calls Region::declare. A law that reads a function of time holds its TimeTable and the
// condition overrides on(ex) to give the table's view on the launch's backend. The law acts on the nodes of the region that carry mass, on the
// velocities the grid update just produced (v^k and/or v^{k+1}), at the step's time t.
// The plugin is compiled as CUDA (scree_add_plugin(... KIND boundary CUDA_KERNELS)), so
// the kernel exists for both backends. boundary/shakingTable is the example to copy.
#pragma once

#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/exec/memory.hpp"

namespace scree {

/// What a node law keeps per node (the nodes' flat indices, a plugin's own data per node):
/// made on the host at setup, copied to the backend once, at the first grid update (before
/// any capture of the step in a graph).
template <class T>
class HostedList {
 public:
  std::vector<T>& host() { return host_; }
  const std::vector<T>& host() const { return host_; }
  /// The list on `ex`'s backend.
  const T* on(const Exec& ex) const {
    if (backend_.size() != host_.size()) {
      backend_.resize(host_.size(), ex.device);
      backend_.copy_from_host(host_);
    }
    return backend_.data();
  }

 private:
  std::vector<T> host_;
  mutable Buffer<T> backend_;
};

namespace detail {
/// The law over the listed nodes: node i of the list is grid node nodes[i].
template <class Law, int D>
struct NodeLawKernel {
  const Index* nodes;
  Law law;
  GridNodes<D> g;
  SCREE_HD void operator()(Index i) const {
    const Index I = nodes[i];
    if (!(g.fields.mass[I] > 0)) return;  // no material at the node: no velocity
    const Vec<D> xn = g.grid.node_position(I);
    Real x[D], v[D];
    for (int d = 0; d < D; ++d) x[d] = xn[d];
    const Real t = g.control->t[g.parity];
    if (g.velocity) {
      for (int d = 0; d < D; ++d) v[d] = g.fields.velocity[d][I];
      law.template apply<D>(v, x, t);
      for (int d = 0; d < D; ++d) g.fields.velocity[d][I] = v[d];
    }
    if (g.velocity_new) {
      for (int d = 0; d < D; ++d) v[d] = g.fields.velocity_new[d][I];
      law.template apply<D>(v, x, t);
      for (int d = 0; d < D; ++d) g.fields.velocity_new[d][I] = v[d];
    }
  }
};
}  // namespace detail

template <class Law>
class NodeLawCondition : public BoundaryCondition {

 public:
  NodeLawCondition(const ParamReader& r, const SolverContext& ctx, const Law& law)
      : region_(Region::read(r, ctx)), law_(law) {
    nodes_.host() = select_nodes(NodeLattice::of(ctx), [this](const Real* x) { return region_.contains(x); });
  }

  bool has_node_law() const override { return true; }
  void apply(const Exec& ex, const GridNodes<2>& g) const override { run(ex, g); }
  void apply(const Exec& ex, const GridNodes<3>& g) const override { run(ex, g); }
 private:
  template <int D>
  void run(const Exec& ex, const GridNodes<D>& g) const {
    const Index n = static_cast<Index>(nodes_.host().size());
    if (n == 0 || !(g.velocity || g.velocity_new)) return;
    parallel_for(ex, n, detail::NodeLawKernel<Law, D>{nodes_.on(ex), on(ex), g});
  }

 protected:
  /// The law as a launch on `ex` takes it: a law that points to tables (a function of
  /// time, time/function_of_time.hpp) sets their views on `ex`'s backend here.
  virtual Law on(const Exec& ex) const {
    (void)ex;
    return law_;
  }
  const Law& law() const { return law_; }

 private:
  Region region_;
  Law law_;
  HostedList<Index> nodes_;  // the region's nodes (flat indices)
};

}  // namespace scree
