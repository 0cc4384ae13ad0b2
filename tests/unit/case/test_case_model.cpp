// The case model (case/case_model.hpp): the grid geometry derived once from gridDict, its
// owned range and sub_box() (the grid of a range of cells, for a domain decomposition),
// the plugin context, and the named objects a Case hands out.
#include <gtest/gtest.h>

#include "scree/case/case_model.hpp"
#include "scree_test.hpp"

namespace scree::test {
namespace {

GridSettings grid_settings(std::vector<Real> lower, std::vector<Real> upper, Real h, int ghost) {
  GridSettings g;
  g.dimension = static_cast<int>(lower.size());
  g.lower = std::move(lower);
  g.upper = std::move(upper);
  g.cell_size = h;
  g.ghost_layers = ghost;
  return g;
}

template <int D>
void expect_same(const GridGeometry<D>& a, const GridGeometry<D>& b) {
  EXPECT_EQ(a.h, b.h);
  EXPECT_EQ(a.ghost, b.ghost);
  for (int d = 0; d < D; ++d) {
    EXPECT_EQ(a.n[d], b.n[d]) << "axis " << d;
    EXPECT_EQ(a.offset[d], b.offset[d]) << "axis " << d;
    EXPECT_DOUBLE_EQ(a.origin[d], b.origin[d]) << "axis " << d;
    EXPECT_DOUBLE_EQ(a.lower[d], b.lower[d]) << "axis " << d;
    EXPECT_DOUBLE_EQ(a.upper[d], b.upper[d]) << "axis " << d;
  }
}

TEST(CaseModel, GridIsTheDomainInWholeCellsWithGhostLayers) {
  // 1 m in 0.25 m cells: 4 cells; 0.9 m: extended to 4 cells (1.0 m); 2 ghost layers.
  const GlobalGrid<2> g = grid_geometry<2>(grid_settings({0, -0.5}, {1, 0.4}, 0.25, 2));
  EXPECT_EQ(g.cells[0], 4);
  EXPECT_EQ(g.cells[1], 4);
  EXPECT_EQ(g.n[0], 4 + 1 + 2 * 2);
  EXPECT_DOUBLE_EQ(g.origin[0], -0.5);
  EXPECT_DOUBLE_EQ(g.origin[1], -1.0);
  EXPECT_DOUBLE_EQ(g.upper[1], 0.5);
  EXPECT_EQ(g.offset[0], 0);
  // Today a run owns the whole grid.
  for (int d = 0; d < 2; ++d) {
    EXPECT_EQ(g.owned.lo[d], 0);
    EXPECT_EQ(g.owned.hi[d], g.n[d]);
  }
  EXPECT_EQ(g.owned.count(), g.num_nodes());
  EXPECT_TRUE(whole_cells(0, 1, 0.25));
  EXPECT_FALSE(whole_cells(-0.5, 0.4, 0.25));
}

TEST(CaseModel, AnExtentARoundingErrorOverWholeCellsIsThoseCells) {
  // 0.3 / 0.1 = 2.9999999999999996 and 0.7 / 0.1 = 6.999999999999999: 3 and 7 cells.
  EXPECT_EQ(domain_cells(0, 0.3, 0.1), 3);
  EXPECT_EQ(domain_cells(0, 0.7, 0.1), 7);
  EXPECT_EQ(domain_cells(0, 0.7 + 1e-6, 0.1), 8);
}

TEST(CaseModel, SubBoxOfAllCellsIsTheGlobalGrid) {
  const GlobalGrid<3> g = grid_geometry<3>(grid_settings({0, 0, 0}, {1, 0.5, 0.75}, 0.25, 1));
  const int lo[3] = {0, 0, 0};
  expect_same<3>(g.sub_box(lo, g.cells), g);
}

TEST(CaseModel, SubBoxIsThePartOfTheLatticeOverItsCells) {
  const GlobalGrid<2> g = grid_geometry<2>(grid_settings({0, 0}, {2, 1}, 0.1, 2));
  const int lo[2] = {5, 3}, hi[2] = {12, 10};
  const GridGeometry<2> s = g.sub_box(lo, hi);
  for (int d = 0; d < 2; ++d) {
    EXPECT_EQ(s.n[d], hi[d] - lo[d] + 1 + 2 * g.ghost);
    EXPECT_EQ(s.offset[d], lo[d]);
    EXPECT_DOUBLE_EQ(s.lower[d], g.lower[d] + lo[d] * g.h);
    EXPECT_DOUBLE_EQ(s.upper[d], g.lower[d] + hi[d] * g.h);
  }
  // Every node of the sub-box is the global node `offset` further on, at the same place.
  for (Index f = 0; f < s.num_nodes(); ++f) {
    int idx[2], global[2];
    s.unflat(f, idx);
    for (int d = 0; d < 2; ++d) global[d] = idx[d] + s.offset[d];
    const Vec<2> a = s.node_position(f), b = g.node_position(g.flat(global));
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(a[d], b[d], 1e-12);
  }
  // Two boxes side by side share the nodes of their common face and overlap by the ghosts.
  const int lo2[2] = {12, 3}, hi2[2] = {20, 10};
  const GridGeometry<2> t = g.sub_box(lo2, hi2);
  EXPECT_EQ(t.offset[0] - s.offset[0], hi[0] - lo[0]);
  EXPECT_DOUBLE_EQ(t.lower[0], s.upper[0]);
}

TEST(CaseModel, PluginContextAndNamedObjectsComeFromTheCase) {
  TempCase tc("case_model");
  // Variables ($macros, keys starting with '_') beside the named objects are not objects.
  const std::pair<const char*, const char*> files[] = {
      {"system/controlDict", "endTime 0.01; deltaT 1e-3; writeInterval 0.005; writers { _unused 1; vtk { type vtk; } }"},
      {"system/gridDict", "dimension 2; lower (0 0); upper (1 1); cellSize 0.1;"},
      {"constant/g", "value (0 -9.81);"},
      {"constant/materialProperties", "soil { type linearElastic; E 1e6; nu 0.3; rho 1000; }"},
      {"constant/bodies", "_lowerLeft (0 0);\n"
                          "a { material soil; region { type rectangle; lower $_lowerLeft; upper (0.5 0.5); } }\n"
                          "b { material soil; region { type rectangle; lower (0.6 0); upper (0.9 0.3); } }"},
      {"constant/boundaryConditions", "floor { type fixed; face yMin; }"}};
  for (const auto& [file, text] : files) tc.write(file, text);
  const Case c = Case::read(tc.dir(), runtime());
  ASSERT_EQ(c.body_entries().size(), 2u);
  EXPECT_EQ(c.body_entries()[1]->key(), "b");
  EXPECT_EQ(c.boundary_entries().size(), 1u);
  EXPECT_EQ(c.writer_entries().size(), 1u);
  EXPECT_TRUE(c.function_entries().empty());

  const GlobalGrid<2> g = grid_geometry<2>(c.settings().grid);
  const SolverContext ctx = plugin_context<2>(c, g, Device::cpu);
  EXPECT_EQ(ctx.dimension, 2);
  EXPECT_EQ(ctx.body_names, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(ctx.grid_nodes.size(), 2u);
  EXPECT_EQ(ctx.grid_nodes[0], g.n[0]);
  EXPECT_DOUBLE_EQ(ctx.grid_origin[1], g.origin[1]);
  EXPECT_DOUBLE_EQ(ctx.gravity[1], -9.81);
  EXPECT_DOUBLE_EQ(ctx.cell_size, 0.1);
  EXPECT_DOUBLE_EQ(ctx.end_time, 0.01);
}

}  // namespace
}  // namespace scree::test
