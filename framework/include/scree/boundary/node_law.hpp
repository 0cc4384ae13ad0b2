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
// calls Region::declare. The law acts on the nodes of the region that carry mass, on the
// velocities the grid update just produced (v^k and/or v^{k+1}), at the step's time t.
// The plugin is compiled as CUDA (scree_add_plugin(... KIND boundary CUDA_KERNELS)), so
// the kernel exists for both backends. boundary/shakingTable is the example to copy.
#pragma once

#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/exec/memory.hpp"

namespace scree {

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
    hosted_ = select_nodes(NodeLattice::of(ctx), [this](const Real* x) { return region_.contains(x); });
    count_ = static_cast<Index>(hosted_.size());
  }

  bool has_node_law() const override { return true; }
  void apply(const Exec& ex, const GridNodes<2>& g) const override { run(ex, g); }
  void apply(const Exec& ex, const GridNodes<3>& g) const override { run(ex, g); }
 private:
  template <int D>
  void run(const Exec& ex, const GridNodes<D>& g) const {
    if (count_ == 0 || !(g.velocity || g.velocity_new)) return;
    if (nodes_.size() != hosted_.size()) {  // the node list on the backend, once (before any capture)
      nodes_.resize(hosted_.size(), ex.device);
      nodes_.copy_from_host(hosted_);
    }
    parallel_for(ex, count_, detail::NodeLawKernel<Law, D>{nodes_.data(), law_, g});
  }

  Region region_;
  Law law_;
  std::vector<Index> hosted_;       // the region's nodes (flat indices)
  mutable Buffer<Index> nodes_;     // ... on the backend
  Index count_ = 0;
};

}  // namespace scree
