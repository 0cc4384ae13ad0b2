// pack_box, ordered_sum and stamp_box_tiles (see mpm/halo_box.hpp); compiled as CUDA with the
// CUDA backend.
#include "scree/mpm/halo_box.hpp"

namespace scree {
namespace {

/// The tiles along each axis that hold a box's nodes (t0 to t1 of count).
template <int D>
struct TileRange {
  Index t0[D], t1[D], count[D];
};

}  // namespace

template <int D>
void pack_box(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>& peer, const HaloFields& f, Real* buf) {
  const HaloPeer<D> p = peer;
  const Index per = p.nodes();
  Real* out = buf + p.offset * f.count;
  parallel_for(ex, per * f.count, [=] SCREE_HD(Index k) {
    int i[D];
    p.node(k % per, i);
    out[k] = f.field[k / per][g.flat(i)];
  });
}

template <int D>
void clear_box(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>& peer, const HaloFields& f) {
  const HaloPeer<D> p = peer;
  const Index per = p.nodes();
  parallel_for(ex, per * f.count, [=] SCREE_HD(Index k) {
    int i[D];
    p.node(k % per, i);
    f.field[k / per][g.flat(i)] = 0;
  });
}

template <int D>
void ordered_sum(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>* peers, const HaloPeer<D>* host_peers,
                 int count, int self, const HaloFields& f, const Real* buf) {
  for (int b = 0; b < count; ++b) {
    const HaloPeer<D> box = host_peers[b];
    parallel_for(ex, box.nodes(), [=] SCREE_HD(Index k) {
      int i[D];
      box.node(k, i);
      for (int j = 0; j < b; ++j)
        if (peers[j].holds(i)) return;  // an earlier box's pass sums it
      const Index I = g.flat(i);
      for (int c = 0; c < f.count; ++c) {
        // -0 + x is x for every x, -0 included: the first term enters exactly.
        Real acc = -Real(0);
        for (int j = 0; j <= count; ++j) {
          if (j == self) acc += f.field[c][I];
          if (j < count && peers[j].holds(i)) acc += buf[peers[j].offset * f.count + c * peers[j].size + peers[j].at(i)];
        }
        f.field[c][I] = acc;
      }
    });
  }
}

template <int D>
void stamp_box_tiles(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>& peer, std::uint32_t* stamps,
                     std::uint32_t stamp) {
  TileRange<D> r;
  for (int d = 0; d < D; ++d) {
    r.t0[d] = peer.lo[d] / Tiles<D>::extent(d);
    r.t1[d] = (peer.hi[d] - 1) / Tiles<D>::extent(d);
    r.count[d] = Tiles<D>::count(g.n[d], d);
  }
  parallel_for(ex, Tiles<D>::total(g), [=] SCREE_HD(Index t) {
    Index rest = t;
    for (int d = 0; d < D; ++d) {
      const Index td = rest % r.count[d];
      rest /= r.count[d];
      if (td < r.t0[d] || td > r.t1[d]) return;
    }
    stamps[t] = stamp;
  });
}

template void pack_box<2>(const Exec&, const GridGeometry<2>&, const HaloPeer<2>&, const HaloFields&, Real*);
template void pack_box<3>(const Exec&, const GridGeometry<3>&, const HaloPeer<3>&, const HaloFields&, Real*);
template void clear_box<2>(const Exec&, const GridGeometry<2>&, const HaloPeer<2>&, const HaloFields&);
template void clear_box<3>(const Exec&, const GridGeometry<3>&, const HaloPeer<3>&, const HaloFields&);
template void ordered_sum<2>(const Exec&, const GridGeometry<2>&, const HaloPeer<2>*, const HaloPeer<2>*, int, int,
                             const HaloFields&, const Real*);
template void ordered_sum<3>(const Exec&, const GridGeometry<3>&, const HaloPeer<3>*, const HaloPeer<3>*, int, int,
                             const HaloFields&, const Real*);
template void stamp_box_tiles<2>(const Exec&, const GridGeometry<2>&, const HaloPeer<2>&, std::uint32_t*,
                                 std::uint32_t);
template void stamp_box_tiles<3>(const Exec&, const GridGeometry<3>&, const HaloPeer<3>&, std::uint32_t*,
                                 std::uint32_t);

}  // namespace scree
