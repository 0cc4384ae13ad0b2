// The domain decomposition (case/decomposition.hpp).
#include "scree/case/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace scree {

namespace {
/// The widening of a box: its grid covers the nodes of every point up to `slack` cells
/// outside it (cells c0 - slack .. c1 + slack - 1, nodes c0 - slack - a .. c1 + slack + b - 1),
/// of which the ghost layers of sub_box give `ghost` on each side; and the narrowest box
/// along a cut axis: wider than both neighbours' reach into it.
struct Widening {
  int lo, hi, min_width;
  Widening(int ghost, int a, int b, int slack)
      : lo(std::max(0, slack + a - ghost)), hi(std::max(0, slack + b - 1 - ghost)), min_width(lo + hi + 2 * ghost + 1) {}
};

template <int D>
CellBox<D> whole(const GlobalGrid<D>& g) {
  CellBox<D> b;
  for (int d = 0; d < D; ++d) {
    b.lo[d] = 0;
    b.hi[d] = g.cells[d];
  }
  return b;
}

/// The most boxes of min_width cells the grid can be cut into: the message's bound.
template <int D>
long long most_boxes(const GlobalGrid<D>& g, int min_width) {
  long long n = 1;
  for (int d = 0; d < D; ++d) n *= std::max(1, g.cells[d] / min_width);
  return n;
}

template <int D>
std::string cells_text(const GlobalGrid<D>& g) {
  std::string s = std::to_string(g.cells[0]);
  for (int d = 1; d < D; ++d) s += " x " + std::to_string(g.cells[d]);
  return s;
}

/// The boxes, grids, owned nodes and neighbours of a complete tree.
template <int D>
void finish(Decomposition<D>& dc, const GlobalGrid<D>& g, int a, int b) {
  const Widening w(g.ghost, a, b, dc.slack);
  dc.boxes.assign(static_cast<std::size_t>(dc.ranks), whole(g));
  std::vector<int> seen(static_cast<std::size_t>(dc.ranks), 0);
  // Depth first from the root, each child's box its parent's cut.
  struct Item {
    int node;
    CellBox<D> box;
  };
  std::vector<Item> stack;
  if (!dc.tree.empty()) stack.push_back({0, whole(g)});
  std::size_t visited = 0;
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    if (++visited > dc.tree.size()) throw std::invalid_argument("the decomposition's tree has a cycle");
    const auto& s = dc.tree[static_cast<std::size_t>(it.node)];
    if (s.axis < 0 || s.axis >= D || s.cut - it.box.lo[s.axis] < w.min_width || it.box.hi[s.axis] - s.cut < w.min_width)
      throw std::invalid_argument("a box of the decomposition is thinner than " + std::to_string(w.min_width) +
                                  " cells along a cut axis");
    for (int k = 0; k < 2; ++k) {
      CellBox<D> part = it.box;
      (k == 0 ? part.hi : part.lo)[s.axis] = s.cut;
      const int c = s.child[k];
      if (c >= 0) {
        if (static_cast<std::size_t>(c) >= dc.tree.size()) throw std::invalid_argument("the decomposition's tree is broken");
        stack.push_back({c, part});
      } else {
        const int r = -c - 1;
        if (r >= dc.ranks || seen[static_cast<std::size_t>(r)]++)
          throw std::invalid_argument("the decomposition's tree does not give each of " + std::to_string(dc.ranks) +
                                      " ranks one box");
        dc.boxes[static_cast<std::size_t>(r)] = part;
      }
    }
  }
  if (dc.ranks > 1 && std::count(seen.begin(), seen.end(), 1) != dc.ranks)
    throw std::invalid_argument("the decomposition's tree does not give each of " + std::to_string(dc.ranks) +
                                " ranks one box");
  dc.local.clear();
  dc.owned.clear();
  for (const CellBox<D>& bx : dc.boxes) {
    int lo[D], hi[D];
    NodeRange<D> own;
    for (int d = 0; d < D; ++d) {
      lo[d] = std::max(0, bx.lo[d] - w.lo);
      hi[d] = std::min(g.cells[d], bx.hi[d] + w.hi);
      own.lo[d] = bx.lo[d] == 0 ? 0 : bx.lo[d] + g.ghost;
      own.hi[d] = bx.hi[d] == g.cells[d] ? g.n[d] : bx.hi[d] + g.ghost;
    }
    dc.local.push_back(g.sub_box(lo, hi));
    dc.owned.push_back(own);
  }
  dc.neighbours.clear();
  for (int q = 0; q < dc.ranks; ++q) {
    NodeRange<D> s;
    if (q != dc.rank && dc.overlap(q, s)) dc.neighbours.push_back(q);
  }
}
}  // namespace

template <int D>
int domain_cell(const GlobalGrid<D>& g, int d, Real x) {
  const Real c = std::floor((x - g.lower[d]) / g.h);
  if (!(c >= 0)) return 0;  // below the domain, or NaN
  return c >= g.cells[d] ? g.cells[d] - 1 : static_cast<int>(c);
}

template <int D>
int Decomposition<D>::owner_of_cell(const int* c) const {
  if (tree.empty()) return 0;
  int node = 0;
  for (;;) {
    const Split& s = tree[static_cast<std::size_t>(node)];
    const int next = s.child[c[s.axis] >= s.cut ? 1 : 0];
    if (next < 0) return -next - 1;
    node = next;
  }
}

template <int D>
int Decomposition<D>::owner(const Vec<D>& x, const GlobalGrid<D>& g) const {
  if (tree.empty()) return 0;
  int c[D];
  for (int d = 0; d < D; ++d) c[d] = domain_cell(g, d, x[d]);
  return owner_of_cell(c);
}

template <int D>
NodeRange<D> Decomposition<D>::owned_local() const {
  NodeRange<D> r = owned[static_cast<std::size_t>(rank)];
  for (int d = 0; d < D; ++d) {
    r.lo[d] -= grid().offset[d];
    r.hi[d] -= grid().offset[d];
  }
  return r;
}

template <int D>
bool Decomposition<D>::overlap(int peer, NodeRange<D>& s) const {
  const GridGeometry<D>& me = grid();
  const GridGeometry<D>& other = local[static_cast<std::size_t>(peer)];
  bool any = true;
  for (int d = 0; d < D; ++d) {
    const int a0 = me.offset[d], a1 = a0 + me.n[d];
    const int b0 = other.offset[d], b1 = b0 + other.n[d];
    s.lo[d] = std::max(a0, b0) - a0;
    s.hi[d] = std::min(a1, b1) - a0;
    if (s.hi[d] <= s.lo[d]) {
      s.hi[d] = s.lo[d];
      any = false;
    }
  }
  return any;
}

template <int D>
std::string Decomposition<D>::describe_box(int r) const {
  std::ostringstream m;
  const CellBox<D>& b = boxes[static_cast<std::size_t>(r)];
  for (int d = 0; d < D; ++d) m << (d ? " x [" : "[") << b.lo[d] << ", " << b.hi[d] << ")";
  return m.str();
}

template <int D>
std::vector<std::int32_t> Decomposition<D>::tree_code() const {
  std::vector<std::int32_t> code;
  for (const Split& s : tree) code.insert(code.end(), {s.axis, s.cut, s.child[0], s.child[1]});
  return code;
}

template <int D>
bool Decomposition<D>::same_boxes(const Decomposition& o) const {
  if (boxes.size() != o.boxes.size()) return false;
  for (std::size_t r = 0; r < boxes.size(); ++r)
    for (int d = 0; d < D; ++d)
      if (boxes[r].lo[d] != o.boxes[r].lo[d] || boxes[r].hi[d] != o.boxes[r].hi[d]) return false;
  return true;
}

template <int D>
Decomposition<D> bisect(const GlobalGrid<D>& g, int ranks, int rank, int a, int b, int slack,
                        const CountBoxes<D>& count) {
  using Dc = Decomposition<D>;
  Dc dc;
  dc.ranks = std::max(1, ranks);
  dc.rank = rank;
  dc.slack = slack;
  const Widening w(g.ghost, a, b, slack);
  // The boxes still to cut, each with its first rank and its number of ranks, and where its
  // parent refers to it (the tree's node and side; -1 for the root).
  struct Part {
    CellBox<D> box;
    int first, n, parent, side;
  };
  std::vector<Part> level;
  dc.counted.assign(static_cast<std::size_t>(dc.ranks), 0);
  if (dc.ranks > 1) level.push_back({whole(g), 0, dc.ranks, -1, 0});
  // The level's boxes are found by walking the tree built so far: a leaf holds -(rank + 1),
  // a box still to cut kPending - its index in `level`.
  constexpr int kPending = -(1 << 30);
  int root = kPending;  // the root's slot until the first cut
  auto slot = [&](const Part& p) -> int& {
    return p.parent < 0 ? root : dc.tree[static_cast<std::size_t>(p.parent)].child[p.side];
  };
  while (!level.empty()) {
    std::vector<CellBox<D>> boxes;
    for (std::size_t k = 0; k < level.size(); ++k) {
      boxes.push_back(level[k].box);
      slot(level[k]) = kPending - static_cast<int>(k);
    }
    const auto which = [&](const int* c) {
      int node = root;
      while (node >= 0) {
        const auto& s = dc.tree[static_cast<std::size_t>(node)];
        node = s.child[c[s.axis] >= s.cut ? 1 : 0];
      }
      return node <= kPending ? kPending - node : -1;
    };
    const std::vector<LayerCounts<D>> counts = count(boxes, which);
    std::vector<Part> next;
    for (std::size_t k = 0; k < level.size(); ++k) {
      const Part& p = level[k];
      const LayerCounts<D>& h = counts[k];
      // The axis of the widest span of points (of the longest box when none), among those
      // the box can be cut across: each part must hold as many boxes of min_width cells as
      // it has ranks, counting the boxes the other axes can hold (at least one).
      const int lower_ranks = p.n / 2;
      int axis = -1, best = -1, need_lo = 0, need_hi = 0;
      for (int d = 0; d < D; ++d) {
        const int width = p.box.hi[d] - p.box.lo[d];
        long long across = 1;
        for (int e = 0; e < D; ++e)
          if (e != d) across *= std::max(1, (p.box.hi[e] - p.box.lo[e]) / w.min_width);
        const int lo_cells = w.min_width * static_cast<int>((lower_ranks + across - 1) / across);
        const int hi_cells = w.min_width * static_cast<int>((p.n - lower_ranks + across - 1) / across);
        if (width < lo_cells + hi_cells) continue;
        const auto& l = h[static_cast<std::size_t>(d)];
        const auto first = std::find_if(l.begin(), l.end(), [](auto c) { return c > 0; });
        const auto last = std::find_if(l.rbegin(), l.rend(), [](auto c) { return c > 0; });
        const int span = first == l.end() ? 0 : static_cast<int>((l.rend() - last) - (first - l.begin()));
        if (span > best || (span == best && width > p.box.hi[axis] - p.box.lo[axis])) {
          best = span;
          axis = d;
          need_lo = lo_cells;
          need_hi = hi_cells;
        }
      }
      if (axis < 0)
        throw std::invalid_argument("the grid of " + cells_text(g) + " cells cannot be cut into " +
                                    std::to_string(dc.ranks) + " boxes of at least " + std::to_string(w.min_width) +
                                    " cells along each cut (the halo of their neighbours): run on at most about " +
                                    std::to_string(most_boxes(g, w.min_width)) + " ranks, or refine cellSize");
      // Equal counts: the lower part holds floor(n/2) / n of the box's points.
      const auto& l = h[static_cast<std::size_t>(axis)];
      std::uint64_t total = 0;
      for (auto c : l) total += c;
      const double target = static_cast<double>(total) * lower_ranks / p.n;
      const int lo = p.box.lo[axis], hi = p.box.hi[axis];
      int c = lo;
      std::uint64_t cum = 0;
      if (total == 0)
        c = lo + (hi - lo) * lower_ranks / p.n;
      else
        while (c < hi && static_cast<double>(cum + l[static_cast<std::size_t>(c - lo)]) <= target)
          cum += l[static_cast<std::size_t>(c++ - lo)];
      c = std::min(std::max(c, lo + need_lo), hi - need_hi);
      std::uint64_t below_count = 0;
      for (int j = lo; j < c; ++j) below_count += l[static_cast<std::size_t>(j - lo)];
      const int node = static_cast<int>(dc.tree.size());
      dc.tree.push_back({axis, c, {0, 0}});
      slot(p) = node;
      CellBox<D> below = p.box, above = p.box;
      below.hi[axis] = c;
      above.lo[axis] = c;
      const Part parts[2] = {{below, p.first, lower_ranks, node, 0}, {above, p.first + lower_ranks, p.n - lower_ranks, node, 1}};
      for (const Part& q : parts) {
        if (q.n > 1)
          next.push_back(q);
        else {
          dc.tree[static_cast<std::size_t>(node)].child[q.side] = -q.first - 1;
          dc.counted[static_cast<std::size_t>(q.first)] = q.side == 0 ? below_count : total - below_count;
        }
      }
    }
    level = std::move(next);
  }
  finish(dc, g, a, b);
  return dc;
}

template <int D>
Decomposition<D> from_tree_code(const GlobalGrid<D>& g, const std::vector<std::int32_t>& code, int ranks, int rank,
                                int a, int b, int slack) {
  Decomposition<D> dc;
  dc.ranks = ranks;
  dc.rank = rank;
  dc.slack = slack;
  if (code.size() % 4 != 0 || code.size() / 4 != static_cast<std::size_t>(std::max(0, ranks - 1)))
    throw std::invalid_argument("the decomposition's tree has " + std::to_string(code.size() / 4) + " cuts, not " +
                                std::to_string(ranks - 1));
  for (std::size_t i = 0; i < code.size(); i += 4)
    dc.tree.push_back({code[i], code[i + 1], {code[i + 2], code[i + 3]}});
  finish(dc, g, a, b);
  return dc;
}

template int domain_cell<2>(const GlobalGrid<2>&, int, Real);
template int domain_cell<3>(const GlobalGrid<3>&, int, Real);
template struct Decomposition<2>;
template struct Decomposition<3>;
template Decomposition<2> bisect<2>(const GlobalGrid<2>&, int, int, int, int, int, const CountBoxes<2>&);
template Decomposition<3> bisect<3>(const GlobalGrid<3>&, int, int, int, int, int, const CountBoxes<3>&);
template Decomposition<2> from_tree_code<2>(const GlobalGrid<2>&, const std::vector<std::int32_t>&, int, int, int, int,
                                            int);
template Decomposition<3> from_tree_code<3>(const GlobalGrid<3>&, const std::vector<std::int32_t>&, int, int, int, int,
                                            int);

}  // namespace scree
