// pack_slab and add_slab (see mpm/halo_slab.hpp); compiled as CUDA with the CUDA backend.
#include "scree/mpm/halo_slab.hpp"

namespace scree {
namespace {

/// The slab's shape: `rows` rows of `width` nodes, `pitch` apart, starting at `first`.
struct Slab {
  Index width, rows, pitch, first;
  template <int D>
  Slab(const GridGeometry<D>& g, int axis, int lo, int hi) {
    const Index stride = g.stride(axis);
    width = stride * (hi - lo);
    pitch = stride * g.n[axis];
    first = stride * lo;
    rows = 1;
    for (int d = axis + 1; d < D; ++d) rows *= g.n[d];
  }
  Index size() const { return width * rows; }
  SCREE_HD Index node(Index k) const { return (k / width) * pitch + first + k % width; }
};

}  // namespace

template <int D>
void pack_slab(const Exec& ex, const GridGeometry<D>& g, int axis, int lo, int hi, const SlabFields& f, Real* buf) {
  const Slab s(g, axis, lo, hi);
  const Index per = s.size();
  parallel_for(ex, per * f.count, [=] SCREE_HD(Index i) { buf[i] = f.field[i / per][s.node(i % per)]; });
}

template <int D>
void add_slab(const Exec& ex, const GridGeometry<D>& g, int axis, int lo, int hi, const SlabFields& f,
              const Real* buf) {
  const Slab s(g, axis, lo, hi);
  const Index per = s.size();
  parallel_for(ex, per * f.count, [=] SCREE_HD(Index i) { f.field[i / per][s.node(i % per)] += buf[i]; });
}

template <int D>
Index slab_size(const GridGeometry<D>& g, int axis, int lo, int hi) {
  return Slab(g, axis, lo, hi).size();
}

template <int D>
void stamp_slab_tiles(const Exec& ex, const GridGeometry<D>& g, int axis, int lo, int hi, std::uint32_t* stamps,
                      std::uint32_t stamp) {
  Index below = 1;
  for (int d = 0; d < axis && d < D; ++d) below *= Tiles<D>::count(g.n[d], d);
  const Index along = Tiles<D>::count(g.n[axis], axis);
  const Index t0 = lo / Tiles<D>::extent(axis), t1 = (hi - 1) / Tiles<D>::extent(axis);
  parallel_for(ex, Tiles<D>::total(g), [=] SCREE_HD(Index t) {
    const Index ta = (t / below) % along;
    if (ta >= t0 && ta <= t1) stamps[t] = stamp;
  });
}

template Index slab_size<2>(const GridGeometry<2>&, int, int, int);
template Index slab_size<3>(const GridGeometry<3>&, int, int, int);
template void stamp_slab_tiles<2>(const Exec&, const GridGeometry<2>&, int, int, int, std::uint32_t*, std::uint32_t);
template void stamp_slab_tiles<3>(const Exec&, const GridGeometry<3>&, int, int, int, std::uint32_t*, std::uint32_t);
template void pack_slab<2>(const Exec&, const GridGeometry<2>&, int, int, int, const SlabFields&, Real*);
template void pack_slab<3>(const Exec&, const GridGeometry<3>&, int, int, int, const SlabFields&, Real*);
template void add_slab<2>(const Exec&, const GridGeometry<2>&, int, int, int, const SlabFields&, const Real*);
template void add_slab<3>(const Exec&, const GridGeometry<3>&, int, int, int, const SlabFields&, const Real*);

}  // namespace scree
