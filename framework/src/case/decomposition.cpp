// The domain decomposition (case/decomposition.hpp).
#include "scree/case/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace scree {

namespace {
/// The widening of a box: its grid covers the nodes of every point up to `slack` cells
/// outside it (cells c0 - slack .. c1 + slack - 1, nodes c0 - slack - a .. c1 + slack + b - 1),
/// of which the ghost layers of sub_box give `ghost` on each side; and the narrowest box, so
/// that no node lies in three grids (a box between two others is wider than both
/// neighbours' reach).
struct Widening {
  int lo, hi, min_width;
  Widening(int ghost, int a, int b, int slack)
      : lo(std::max(0, slack + a - ghost)), hi(std::max(0, slack + b - 1 - ghost)), min_width(lo + hi + 2 * ghost + 1) {}
};
}  // namespace

template <int D>
int domain_cell(const GlobalGrid<D>& g, int d, Real x) {
  const Real c = std::floor((x - g.lower[d]) / g.h);
  if (!(c >= 0)) return 0;  // below the domain, or NaN
  return c >= g.cells[d] ? g.cells[d] - 1 : static_cast<int>(c);
}

template <int D>
int Decomposition<D>::owner_of_cell(int c) const {
  if (ranks == 1) return 0;
  const auto it = std::upper_bound(cuts.begin(), cuts.end(), c);
  return std::clamp(static_cast<int>(it - cuts.begin()) - 1, 0, ranks - 1);
}

template <int D>
int Decomposition<D>::owner(Real x, const GlobalGrid<D>& g) const {
  return owner_of_cell(domain_cell(g, axis, x));
}

template <int D>
void Decomposition<D>::owned_local(int& lo, int& hi) const {
  const int off = grid().offset[axis];
  lo = owned[static_cast<std::size_t>(rank)] - off;
  hi = owned[static_cast<std::size_t>(rank) + 1] - off;
}

template <int D>
void Decomposition<D>::overlap(int peer, int& lo, int& hi) const {
  const GridGeometry<D>& me = grid();
  const GridGeometry<D>& other = local[static_cast<std::size_t>(peer)];
  const int a0 = me.offset[axis], a1 = a0 + me.n[axis];
  const int b0 = other.offset[axis], b1 = b0 + other.n[axis];
  lo = std::max(a0, b0) - a0;
  hi = std::min(a1, b1) - a0;
  if (hi < lo) hi = lo;
}

template <int D>
Decomposition<D> decompose_layers(const GlobalGrid<D>& g, const std::array<std::vector<std::uint64_t>, D>& hist,
                                  int ranks, int rank, int a, int b, int slack) {
  Decomposition<D> dc;
  dc.ranks = ranks;
  dc.rank = rank;
  dc.slack = slack;
  const int whole_lo[D > 0 ? D : 1] = {};
  if (ranks <= 1) {
    dc.cuts = {0, g.cells[0]};
    dc.local.push_back(g.sub_box(whole_lo, g.cells));
    dc.owned = {0, g.n[0]};
    return dc;
  }
  // The axis of the widest span of points is cut.
  int best = -1;
  for (int d = 0; d < D; ++d) {
    const auto& h = hist[d];
    const auto first = std::find_if(h.begin(), h.end(), [](auto c) { return c > 0; });
    const auto last = std::find_if(h.rbegin(), h.rend(), [](auto c) { return c > 0; });
    const int span = first == h.end() ? 0 : static_cast<int>((h.rend() - last) - (first - h.begin()));
    if (span > best || (span == best && g.cells[d] > g.cells[dc.axis])) {
      best = span;
      dc.axis = d;
    }
  }
  return cut_slabs<D>(g, hist[dc.axis], dc.axis, ranks, rank, a, b, slack);
}

template <int D>
Decomposition<D> cut_slabs(const GlobalGrid<D>& g, const std::vector<std::uint64_t>& h, int axis, int ranks, int rank,
                           int a, int b, int slack) {
  Decomposition<D> dc;
  dc.ranks = ranks;
  dc.rank = rank;
  dc.slack = slack;
  dc.axis = axis;
  std::uint64_t n = 0;
  for (auto c : h) n += c;
  const int ax = dc.axis, cells = g.cells[ax];
  const Widening w(g.ghost, a, b, slack);
  const int min_width = w.min_width;
  if (cells < ranks * min_width)
    throw std::invalid_argument("the grid has " + std::to_string(cells) + " cells along its longest axis of points (" +
                                std::to_string(ax) + "), and each of " + std::to_string(ranks) +
                                " ranks needs at least " + std::to_string(min_width) +
                                " (the halo of its neighbours): run on at most " + std::to_string(cells / min_width) +
                                " ranks, or refine cellSize");
  // Equal counts: cut r where the cumulative count first reaches r/ranks of the points.
  dc.cuts.assign(static_cast<std::size_t>(ranks) + 1, 0);
  dc.cuts[static_cast<std::size_t>(ranks)] = cells;
  std::uint64_t cum = 0;
  int c = 0;
  for (int r = 1; r < ranks; ++r) {
    const double target = static_cast<double>(n) * r / ranks;
    while (c < cells && static_cast<double>(cum + h[static_cast<std::size_t>(c)]) <= target) cum += h[static_cast<std::size_t>(c++)];
    dc.cuts[static_cast<std::size_t>(r)] = c;
  }
  // Every box at least min_width cells: forward, then backward from the end.
  for (int r = 1; r < ranks; ++r)
    dc.cuts[static_cast<std::size_t>(r)] = std::max(dc.cuts[static_cast<std::size_t>(r)], dc.cuts[static_cast<std::size_t>(r) - 1] + min_width);
  for (int r = ranks - 1; r >= 1; --r)
    dc.cuts[static_cast<std::size_t>(r)] = std::min(dc.cuts[static_cast<std::size_t>(r)], dc.cuts[static_cast<std::size_t>(r) + 1] - min_width);
  return slabs_from_cuts<D>(g, ax, dc.cuts, rank, a, b, slack);
}

template <int D>
Decomposition<D> slabs_from_cuts(const GlobalGrid<D>& g, int axis, const std::vector<int>& cuts, int rank, int a,
                                 int b, int slack) {
  Decomposition<D> dc;
  dc.ranks = static_cast<int>(cuts.size()) - 1;
  dc.rank = rank;
  dc.slack = slack;
  dc.axis = axis;
  dc.cuts = cuts;
  const int ranks = dc.ranks, ax = axis;
  if (ranks < 1 || axis < 0 || axis >= D || cuts.front() != 0 || cuts.back() != g.cells[ax])
    throw std::invalid_argument("the cuts do not span the grid's " + std::to_string(g.cells[std::max(0, std::min(axis, D - 1))]) + " cells");
  const int cells = g.cells[ax];
  const Widening w(g.ghost, a, b, slack);
  const int e_lo = w.lo, e_hi = w.hi, min_width = w.min_width;
  for (int r = 0; r < ranks; ++r)
    if (ranks > 1 && cuts[static_cast<std::size_t>(r) + 1] - cuts[static_cast<std::size_t>(r)] < min_width)
      throw std::invalid_argument("a slab of the cuts is thinner than " + std::to_string(min_width) + " cells");
  for (int r = 0; r < ranks; ++r) {
    int lo[D], hi[D];
    for (int d = 0; d < D; ++d) {
      lo[d] = 0;
      hi[d] = g.cells[d];
    }
    lo[ax] = std::max(0, dc.cuts[static_cast<std::size_t>(r)] - e_lo);
    hi[ax] = std::min(cells, dc.cuts[static_cast<std::size_t>(r) + 1] + e_hi);
    dc.local.push_back(g.sub_box(lo, hi));
  }
  dc.owned.assign(static_cast<std::size_t>(ranks) + 1, 0);
  for (int r = 1; r < ranks; ++r) dc.owned[static_cast<std::size_t>(r)] = dc.cuts[static_cast<std::size_t>(r)] + g.ghost;
  dc.owned[static_cast<std::size_t>(ranks)] = g.n[ax];
  return dc;
}

template int domain_cell<2>(const GlobalGrid<2>&, int, Real);
template int domain_cell<3>(const GlobalGrid<3>&, int, Real);
template struct Decomposition<2>;
template struct Decomposition<3>;
template Decomposition<2> decompose_layers<2>(const GlobalGrid<2>&, const std::array<std::vector<std::uint64_t>, 2>&,
                                             int, int, int, int, int);
template Decomposition<3> decompose_layers<3>(const GlobalGrid<3>&, const std::array<std::vector<std::uint64_t>, 3>&,
                                             int, int, int, int, int);
template Decomposition<2> slabs_from_cuts<2>(const GlobalGrid<2>&, int, const std::vector<int>&, int, int, int, int);
template Decomposition<3> slabs_from_cuts<3>(const GlobalGrid<3>&, int, const std::vector<int>&, int, int, int, int);
template Decomposition<2> cut_slabs<2>(const GlobalGrid<2>&, const std::vector<std::uint64_t>&, int, int, int, int, int,
                                       int);
template Decomposition<3> cut_slabs<3>(const GlobalGrid<3>&, const std::vector<std::uint64_t>&, int, int, int, int, int,
                                       int);

}  // namespace scree
