// The decomposition of a grid over ranks by recursive coordinate bisection
// (case/decomposition.hpp), checked against what equal counts and a tiling of the domain
// require: every cell owned once and inside its owner's box, the parts' counts, the
// neighbours symmetric, nodes shared by more than two grids where boxes meet at a corner, the
// tree's code read back, and the refusal of more ranks than the grid can be cut for.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "scree/case/decomposition.hpp"
#include "scree/case/settings.hpp"

using namespace scree;

namespace {

GlobalGrid<2> grid(int nx, int ny, int ghost = 2) {
  GridSettings gs;
  gs.dimension = 2;
  gs.lower = {0, 0, 0};
  gs.upper = {0.1 * nx, 0.1 * ny, 0};
  gs.cell_size = 0.1;
  gs.ghost_layers = ghost;
  return grid_geometry<2>(gs);
}

/// One point per cell over cells [x0, x1) x [y0, y1): the counts of a uniform block.
CountBoxes<2> block(int x0, int x1, int y0, int y1) {
  return [=](const std::vector<CellBox<2>>& boxes, const std::function<int(const int*)>& which) {
    std::vector<LayerCounts<2>> h(boxes.size());
    for (std::size_t k = 0; k < boxes.size(); ++k)
      for (int d = 0; d < 2; ++d) h[k][d].assign(static_cast<std::size_t>(boxes[k].hi[d] - boxes[k].lo[d]), 0);
    for (int i = x0; i < x1; ++i)
      for (int j = y0; j < y1; ++j) {
        const int c[2] = {i, j};
        const int k = which(c);
        if (k < 0) continue;
        ++h[static_cast<std::size_t>(k)][0][static_cast<std::size_t>(i - boxes[static_cast<std::size_t>(k)].lo[0])];
        ++h[static_cast<std::size_t>(k)][1][static_cast<std::size_t>(j - boxes[static_cast<std::size_t>(k)].lo[1])];
      }
    return h;
  };
}

/// Every cell owned by exactly the rank whose box holds it.
void expect_tiling(const Decomposition<2>& dc, const GlobalGrid<2>& g) {
  for (int i = 0; i < g.cells[0]; ++i)
    for (int j = 0; j < g.cells[1]; ++j) {
      const int c[2] = {i, j};
      const int r = dc.owner_of_cell(c);
      int holders = 0;
      for (const CellBox<2>& b : dc.boxes) holders += b.contains(c);
      ASSERT_EQ(holders, 1) << "cell " << i << ", " << j;
      ASSERT_TRUE(dc.boxes[static_cast<std::size_t>(r)].contains(c)) << "cell " << i << ", " << j;
    }
}

}  // namespace

TEST(Bisection, TwoRanksAreTwoSlabsOfEqualCountsAcrossTheLongestSpan) {
  const GlobalGrid<2> g = grid(60, 20);
  // A block 40 cells long and 10 high: cut across x at its middle, x = 10 + 20.
  const Decomposition<2> dc = bisect<2>(g, 2, 0, 1, 2, kSlackCells, block(10, 50, 0, 10));
  ASSERT_EQ(dc.tree.size(), 1u);
  EXPECT_EQ(dc.tree[0].axis, 0);
  EXPECT_EQ(dc.tree[0].cut, 30);
  EXPECT_EQ(dc.counted, (std::vector<std::uint64_t>{200, 200}));
  EXPECT_EQ(dc.boxes[0].lo[1], 0);
  EXPECT_EQ(dc.boxes[0].hi[1], 20);
  expect_tiling(dc, g);
}

TEST(Bisection, FourRanksOnASquareAreTwoByTwoBoxesOfEqualCounts) {
  const GlobalGrid<2> g = grid(40, 40);
  const Decomposition<2> dc = bisect<2>(g, 4, 0, 1, 2, kSlackCells, block(0, 40, 0, 40));
  std::set<int> axes;
  for (const auto& s : dc.tree) axes.insert(s.axis);
  EXPECT_EQ(axes.size(), 2u) << "a square is cut across both axes";
  EXPECT_EQ(dc.counted, (std::vector<std::uint64_t>{400, 400, 400, 400}));
  expect_tiling(dc, g);
  // The node at the corner where the four boxes meet lies in all four grids.
  const int corner[2] = {dc.boxes[0].hi[0] + g.ghost, dc.boxes[0].hi[1] + g.ghost};
  int holders = 0;
  for (const GridGeometry<2>& l : dc.local) {
    bool in = true;
    for (int d = 0; d < 2; ++d) in = in && corner[d] >= l.offset[d] && corner[d] < l.offset[d] + l.n[d];
    holders += in;
  }
  EXPECT_EQ(holders, 4);
}

TEST(Bisection, NeighboursAreSymmetricAndOwnedNodesTileTheGrid) {
  const GlobalGrid<2> g = grid(50, 45);
  for (int ranks : {3, 5, 6}) {
    std::vector<Decomposition<2>> per;
    for (int r = 0; r < ranks; ++r) per.push_back(bisect<2>(g, ranks, r, 1, 2, kSlackCells, block(5, 45, 0, 30)));
    std::map<std::pair<int, int>, int> seen;
    for (int r = 0; r < ranks; ++r)
      for (int q : per[static_cast<std::size_t>(r)].neighbours) ++seen[{std::min(r, q), std::max(r, q)}];
    for (const auto& [pair, n] : seen) EXPECT_EQ(n, 2) << ranks << " ranks: " << pair.first << " and " << pair.second;
    // every global node owned by one rank, and inside that rank's grid
    std::vector<int> owners(static_cast<std::size_t>(g.n[0] * g.n[1]), 0);
    for (int r = 0; r < ranks; ++r) {
      const NodeRange<2>& o = per[0].owned[static_cast<std::size_t>(r)];
      const GridGeometry<2>& l = per[0].local[static_cast<std::size_t>(r)];
      for (int i = o.lo[0]; i < o.hi[0]; ++i)
        for (int j = o.lo[1]; j < o.hi[1]; ++j) {
          ++owners[static_cast<std::size_t>(i + j * g.n[0])];
          EXPECT_TRUE(i >= l.offset[0] && i < l.offset[0] + l.n[0] && j >= l.offset[1] && j < l.offset[1] + l.n[1]);
        }
    }
    for (int n : owners) ASSERT_EQ(n, 1) << ranks << " ranks";
    std::uint64_t total = 0;
    for (auto c : per[0].counted) total += c;
    EXPECT_EQ(total, 40u * 30u);
  }
}

TEST(Bisection, TheTreesCodeGivesTheSameBoxesAndABrokenOneIsRefused) {
  const GlobalGrid<2> g = grid(50, 45);
  const Decomposition<2> dc = bisect<2>(g, 5, 2, 1, 2, kSlackCells, block(5, 45, 0, 30));
  const Decomposition<2> back = from_tree_code<2>(g, dc.tree_code(), 5, 2, 1, 2, kSlackCells);
  EXPECT_TRUE(back.same_boxes(dc));
  EXPECT_EQ(back.neighbours, dc.neighbours);
  EXPECT_THROW(from_tree_code<2>(g, dc.tree_code(), 4, 2, 1, 2, kSlackCells), std::invalid_argument);
  std::vector<std::int32_t> code = dc.tree_code();
  code[1] = 1;  // the root's cut one cell from the domain's edge: a box thinner than its halo
  EXPECT_THROW(from_tree_code<2>(g, code, 5, 2, 1, 2, kSlackCells), std::invalid_argument);
  code = dc.tree_code();
  code[2] = code[3];  // one child twice, a rank without a box
  EXPECT_THROW(from_tree_code<2>(g, code, 5, 2, 1, 2, kSlackCells), std::invalid_argument);
}

TEST(Bisection, MoreRanksThanTheGridCanBeCutForAreRefusedSayingHowMany) {
  const GlobalGrid<2> g = grid(20, 20);  // boxes of at least 7 cells: 2 x 2 at most
  EXPECT_NO_THROW(bisect<2>(g, 4, 0, 1, 2, kSlackCells, block(0, 20, 0, 20)));
  try {
    bisect<2>(g, 5, 0, 1, 2, kSlackCells, block(0, 20, 0, 20));
    FAIL() << "5 ranks accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at most about 4 ranks"), std::string::npos) << e.what();
  }
}
