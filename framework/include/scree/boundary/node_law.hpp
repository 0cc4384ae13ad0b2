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
  /// How many grid nodes the region selected.
  Index nodes() const { return count_; }

 protected:
  const Region& region() const { return region_; }

 private:
  template <int D>
  void run(const Exec& ex, const GridNodes<D>& g) const {
    if (count_ == 0 || !(g.velocity || g.velocity_new)) return;
    if (nodes_.size() != hosted_.size()) {  // the node list on the backend, once (before any capture)
      nodes_.resize(hosted_.size(), ex.device);
      nodes_.copy_from_host(hosted_);
    }
    const Index* nodes = nodes_.data();
    const Law law = law_;
    const GridNodes<D> G = g;
    parallel_for(ex, count_, [=] SCREE_HD(Index i) {
      const Index I = nodes[i];
      if (!(G.fields.mass[I] > 0)) return;  // no material at the node: no velocity
      const Vec<D> xn = G.grid.node_position(I);
      Real x[D], v[D];
      for (int d = 0; d < D; ++d) x[d] = xn[d];
      const Real t = G.control->t[G.parity];
      if (G.velocity) {
        for (int d = 0; d < D; ++d) v[d] = G.fields.velocity[d][I];
        law.template apply<D>(v, x, t);
        for (int d = 0; d < D; ++d) G.fields.velocity[d][I] = v[d];
      }
      if (G.velocity_new) {
        for (int d = 0; d < D; ++d) v[d] = G.fields.velocity_new[d][I];
        law.template apply<D>(v, x, t);
        for (int d = 0; d < D; ++d) G.fields.velocity_new[d][I] = v[d];
      }
    });
  }

  Region region_;
  Law law_;
  std::vector<Index> hosted_;       // the region's nodes (flat indices)
  mutable Buffer<Index> nodes_;     // ... on the backend
  Index count_ = 0;
};

}  // namespace scree
