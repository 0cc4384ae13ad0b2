// One case decomposed over the ranks of `mpirun -np N` (case/decomposition.hpp,
// solver/decomposed.cpp) against the same case run by one process. Every rank runs the
// decomposed case; the root rank also runs it alone (RunOptions::comm = self()) and
// compares, point by point through the ids:
//
// - Migration is a copy: after points crossed the cuts many times every id is present
//   exactly once, and each point's mass and initial volume are the very same numbers.
// - The decomposed run follows the undecomposed one within round-off: it adds the same
//   contributions to a shared node in another grouping (each rank's partial sum, then the
//   two partials), a relative 1e-16 per node and step. On an elastic block that stays
//   elastic such differences do not grow (no bifurcation), so after a few hundred steps
//   positions agree to 1e-12 of the block's size and velocities and stresses to 1e-9 of
//   their largest magnitude (the stress of a point sums the gradients of a few nodes each
//   step: the looser bound of the two; the observed differences are listed in the test's
//   output).
// - The cuts move with the mass: a block sliding off its first ranks makes them cut anew
//   (RunStats::rebalances), with the same bounds.
// - A decomposed run restarted from its own checkpoint ends in the uninterrupted
//   decomposed run's state bit for bit (one thread per rank: the same operations in the
//   same order), and its files are one case's: one .pvd, one CSV per function object.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>
#include <unistd.h>

#include "scree/case/checkpoint.hpp"
#include "scree/case/memory_estimate.hpp"
#include "scree/comm/comm.hpp"
#include "scree_test.hpp"

namespace fs = std::filesystem;

namespace scree::test {
namespace {

Comm& world_comm() {
  static std::shared_ptr<Comm> w = world();
  return *w;
}
bool is_root() { return world_comm().rank() == 0; }

/// One case directory every rank sees (the root names it), removed at the end.
class SharedCase {
 public:
  explicit SharedCase(const std::string& tag) {
    std::string name = "scree_mpi_" + tag + "_" + std::to_string(::getpid());
    std::uint64_t len = name.size();
    world_comm().broadcast(&len, sizeof len, 0);
    name.resize(len);
    world_comm().broadcast(name.data(), len, 0);
    dir_ = fs::temp_directory_path() / name;
    if (is_root()) {
      fs::remove_all(dir_);
      fs::create_directories(dir_ / "system");
      fs::create_directories(dir_ / "constant");
    }
    world_comm().barrier();
  }
  ~SharedCase() {
    world_comm().barrier();
    if (is_root() && !std::getenv("SCREE_KEEP_TEST_CASES")) fs::remove_all(dir_);
  }
  void write(const std::string& rel, const std::string& text) const {
    if (is_root()) std::ofstream(dir_ / rel) << text;
    world_comm().barrier();
  }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

struct Variant {
  std::string name, control, schemes, grid, materials, bodies, boundaries, g = "value (0 -9.81);";
  /// The bounds on the differences (position, of the block's length; velocity and stress,
  /// of their largest magnitude). Linear shape functions: their gradient jumps when a point
  /// crosses a cell face, so a round-off difference in a position decides on which side a
  /// point's force is taken that step, and differences grow a hundredfold more than with
  /// the smooth shapes (measured: 1.2e-12, 5.9e-11, 1.5e-9 after 1000 steps on 2 ranks).
  double tol_x = 1e-12, tol_v = 1e-9, tol_s = 1e-9;
  std::vector<std::pair<std::string, std::string>> files = {};  ///< other files of the case: path, text
};

void PrintTo(const Variant& v, std::ostream* os) { *os << v.name; }

void write_case(const SharedCase& c, const Variant& s) {
  write_case_files(c, CaseFiles{s.control, s.schemes, s.grid, s.g, s.materials, s.bodies, s.boundaries});
  for (const auto& [path, text] : s.files) c.write(path, text);
}

/// An ASCII STL of the solid under the ground z = z0 - tan(slope) x, from z = -0.3 m, over
/// x in [-0.1, 0.9] and y in [-0.1, 0.22]: the ground of a terrain condition.
std::string inclined_ground_stl(double z0, double slope_degrees) {
  const double t = std::tan(slope_degrees * 3.14159265358979323846 / 180);
  auto corner = [&](int i, int j, int k) {
    const double x = i ? 0.9 : -0.1, y = j ? 0.22 : -0.1;
    return std::array<double, 3>{x, y, k ? z0 - t * x : -0.3};
  };
  // Each face's corners counter-clockwise seen from outside.
  static const int quads[6][4][3] = {{{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},
                                     {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
                                     {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
  std::ostringstream o;
  o.precision(17);
  o << "solid ground\n";
  for (const auto& q : quads)
    for (const std::array<int, 3> idx : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
      o << " facet normal 0 0 0\n  outer loop\n";
      for (int v : idx) {
        const auto p = corner(q[v][0], q[v][1], q[v][2]);
        o << "   vertex " << p[0] << " " << p[1] << " " << p[2] << "\n";
      }
      o << "  endloop\n endfacet\n";
    }
  o << "endsolid ground\n";
  return o.str();
}

RunOptions opts(std::shared_ptr<Comm> comm, bool output = false) {
  RunOptions o = options(1);  // one thread per rank: every run is deterministic
  o.comm = std::move(comm);
  o.output = output;
  return o;
}

/// The case run to time t: decomposed over every rank (comm = world()) or alone (self()).
Snapshot run_to(const fs::path& dir, std::shared_ptr<Comm> comm, double t, RunStats* stats = nullptr,
                std::ostream* log = nullptr) {
  Case c = Case::read(dir, runtime());
  RunOptions o = opts(std::move(comm));
  if (log) o.log = log;
  Simulation sim(c, runtime(), o);
  sim.advance_to(t);
  if (stats) *stats = sim.stats();
  return sim.snapshot();
}

/// The case run to its endTime over every rank, with its writers, function objects and
/// checkpoints; from the checkpoint `restart` when given.
Snapshot run_with_output(const fs::path& dir, const fs::path& restart = {}) {
  Case c = Case::read(dir, runtime());
  RunOptions o = opts(world(), true);
  o.restart = restart;
  Simulation sim(c, runtime(), o);
  sim.run();
  return sim.snapshot();
}

/// The same points with the same values, bit for bit: ids, positions and every field.
void expect_bitwise_same(const BodySnapshot& a, const BodySnapshot& b) {
  ASSERT_EQ(a.id, b.id);
  EXPECT_EQ(0, std::memcmp(a.position.data(), b.position.data(), a.position.size() * sizeof(Real)));
  for (const FieldData& f : a.fields) {
    const FieldData& g = field(b, f.name.c_str());
    EXPECT_EQ(0, std::memcmp(f.values.data(), g.values.data(), f.values.size() * sizeof(Real))) << f.name;
  }
}

/// Point p's row of a snapshot field, found through the ids.
struct ById {
  explicit ById(const BodySnapshot& b) : b(b) {
    for (Index p = 0; p < b.n; ++p) at[b.id[static_cast<std::size_t>(p)]] = p;
  }
  const BodySnapshot& b;
  std::map<std::int64_t, Index> at;
};

/// The largest difference of field `name` between the runs over the common ids, relative
/// to the field's largest magnitude (or absolute when `scale` is given).
double difference(const BodySnapshot& a, const BodySnapshot& b, const std::string& name, double scale = 0) {
  const ById ia(a), ib(b);
  const FieldData& fa = field(a, name.c_str());
  const FieldData& fb = field(b, name.c_str());
  double big = 0, worst = 0;
  for (double v : fa.values) big = std::max(big, std::fabs(v));
  for (const auto& [id, p] : ia.at) {
    const auto it = ib.at.find(id);
    if (it == ib.at.end()) return INFINITY;
    for (int c = 0; c < fa.components; ++c)
      worst = std::max(worst, std::fabs(fa.values[static_cast<std::size_t>(fa.components * p + c)] -
                                        fb.values[static_cast<std::size_t>(fb.components * it->second + c)]));
  }
  return worst / (scale > 0 ? scale : (big > 0 ? big : 1));
}

double position_difference(const BodySnapshot& a, const BodySnapshot& b) {
  const ById ia(a), ib(b);
  double worst = 0;
  for (const auto& [id, p] : ia.at) {
    const auto it = ib.at.find(id);
    if (it == ib.at.end()) return INFINITY;
    for (int d = 0; d < 3; ++d)
      worst = std::max(worst, std::fabs(a.position[3 * static_cast<std::size_t>(p) + d] -
                                        b.position[3 * static_cast<std::size_t>(it->second) + d]));
  }
  return worst;
}

/// Every id of `b` once, the same set as `ref`, and the same mass and volume per id, bit for bit.
void expect_same_points(const BodySnapshot& b, const BodySnapshot& ref) {
  ASSERT_EQ(b.n, ref.n) << "points of body " << b.name;
  std::vector<std::int64_t> ids = b.id, rids = ref.id;
  std::sort(ids.begin(), ids.end());
  std::sort(rids.begin(), rids.end());
  EXPECT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end()) << "an id twice in body " << b.name;
  EXPECT_EQ(ids, rids);
  const ById ia(b), ib(ref);
  const FieldData &m = field(b, "mass"), &mr = field(ref, "mass");
  double total = 0, total_ref = 0;
  for (const auto& [id, p] : ia.at) {
    const Index q = ib.at.at(id);
    EXPECT_EQ(0, std::memcmp(&m.values[static_cast<std::size_t>(p)], &mr.values[static_cast<std::size_t>(q)], sizeof(Real)))
        << "mass of point " << id;
    total += m.values[static_cast<std::size_t>(p)];
    total_ref += mr.values[static_cast<std::size_t>(q)];
  }
  EXPECT_EQ(total, total_ref);
}

/// A body of a decomposed run against the same body run by one process: every point once
/// with its mass (expect_same_points), then the largest differences of the positions (of
/// the body's extent along x) and of the velocities and stresses (of their largest).
struct Differences {
  double x = 0, v = 0, s = 0;
  double lo = INFINITY, hi = -INFINITY;  ///< the one-process body's extent along x
};
Differences compare_bodies(const BodySnapshot& a, const BodySnapshot& b) {
  expect_same_points(a, b);
  Differences d;
  for (Index p = 0; p < b.n; ++p) {
    d.lo = std::min(d.lo, b.position[3 * static_cast<std::size_t>(p)]);
    d.hi = std::max(d.hi, b.position[3 * static_cast<std::size_t>(p)]);
  }
  d.x = position_difference(a, b) / (d.hi - d.lo);
  d.v = difference(a, b, "velocity");
  d.s = difference(a, b, "stress");
  return d;
}

void expect_within(const Differences& d, const Variant& s) {
  EXPECT_LT(d.x, s.tol_x);
  EXPECT_LT(d.v, s.tol_v);
  EXPECT_LT(d.s, s.tol_s);
}

const char* kElastic = "m { type linearElastic; E 2e5; nu 0.3; rho 1000; }";

std::vector<Variant> setups() {
  return {
      // A block sliding across the domain at 3 m/s on a frictional floor: its points
      // cross the cuts (along x, the longest extent) many times.
      {"slidingUSLlinear", "endTime 0.2; deltaT 2e-4; writeInterval 1;", "updateScheme USL; sortInterval 7;",
       "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;", kElastic,
       "b { material m; velocity (3 0); region { type rectangle; lower (0.1 0); upper (0.4 0.06); } }",
       "floor { type slip; face yMin; }", "value (0 -9.81);", 1e-10, 1e-8, 1e-7},
      {"slidingUSFgimp", "endTime 0.2; deltaT 2e-4; writeInterval 1;", "updateScheme USF; shapeFunction gimp; sortInterval 5;",
       "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;", kElastic,
       "b { material m; velocity (3 0); region { type rectangle; lower (0.1 0); upper (0.4 0.06); } }",
       "floor { type slip; face yMin; }"},
      {"slidingMUSLbsplineAPIC", "endTime 0.2; deltaT 1e-3; adjustTimeStep yes; maxCo 0.4; writeInterval 1;",
       "updateScheme MUSL; shapeFunction bspline2; transfer APIC; sortInterval 11;",
       "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;", kElastic,
       "b { material m; velocity (3 0); region { type rectangle; lower (0.1 0); upper (0.4 0.06); } }",
       "floor { type slip; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; }"},
      // An elastic column settling under gravity on a fixed floor (cut along y).
      {"columnUSLbspline", "endTime 0.1; deltaT 2e-4; writeInterval 1;", "updateScheme USL; shapeFunction bspline2;",
       "dimension 2; lower (0 0); upper (0.2 1.0); cellSize 0.02;", "m { type linearElastic; E 1e6; nu 0.3; rho 1000; }",
       "b { material m; region { type rectangle; lower (0.04 0); upper (0.16 0.8); } }",
       "floor { type fixed; face yMin; }"},
      // A slope drawn as one polygon on a base layer of another density, both started from
      // the geostatic stress of the material above (every body's columns, which every rank
      // builds from every body's whole lattice), cut along x across the face.
      {"layeredSlopeGeostatic", "endTime 0.05; deltaT 2e-4; writeInterval 1;", "updateScheme USL; shapeFunction bspline2;",
       "dimension 2; lower (0 0); upper (1.2 0.5); cellSize 0.02;",
       "m { type linearElastic; E 1e6; nu 0.3; rho 1000; } s { type linearElastic; E 1e6; nu 0.3; rho 1500; }",
       "base { material m; region { type rectangle; lower (0 0); upper (1.2 0.1); } "
       "initialStress { type geostatic; K0 0.5; } } "
       "slope { material s; region { type polygon; points ((0 0.1) (0.705 0.1) (0.405 0.4) (0 0.4)); } "
       "initialStress { type geostatic; K0 0.5; } }",
       "floor { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; }"},
      // 3D: a box thrown along x over a slip floor, B-spline.
      {"box3D", "endTime 0.08; deltaT 5e-4; writeInterval 1;", "updateScheme USL; shapeFunction bspline2;",
       "dimension 3; lower (0 0 0); upper (0.8 0.12 0.12); cellSize 0.02;", kElastic,
       "b { material m; velocity (2 0 0); region { type box; lower (0.06 0.02 0); upper (0.3 0.1 0.06); } }",
       "floor { type slip; face zMin; }", "value (0 0 -9.81);"},
      // 3D: a block sliding down a 25-degree ground read from an STL solid (the terrain
      // condition on each rank's part of the grid), across the cut. A step of Courant
      // number 0.08: at 0.2 and above this USL update blew the block up, on a friction
      // halfSpace wall alike (USL's own: tests/verification/boundary/test_inclined_plane.cpp).
      {"terrain3D", "endTime 0.15; deltaT 1e-4; writeInterval 1;", "updateScheme USL;",
       "dimension 3; lower (0 0 0); upper (0.8 0.12 0.4); cellSize 0.02;", kElastic,
       "b { material m; region { type extrudedPolygon; axis y; range (0.02 0.1); "
       "points ((0.322022 0.06) (0.210108 0.3) (0.270108 0.3) (0.382022 0.06)); } }",
       "ground { type terrain; file \"ground.stl\"; coefficient 0.2; }", "value (0 0 -9.81);", 1e-12, 1e-9, 1e-9,
       {{"ground.stl", inclined_ground_stl(0.35, 25)}}},
      // 2D, a square block thrown across a square domain: on 3 ranks a slab and two boxes
      // (nodes in three grids where they meet), on 4 two by two (nodes in four grids at
      // the corner), the boxes following the block as it moves.
      {"squareUSLbspline", "endTime 0.1; deltaT 2e-4; writeInterval 1;", "updateScheme USL; shapeFunction bspline2;",
       "dimension 2; lower (0 0); upper (0.6 0.6); cellSize 0.02;", kElastic,
       "b { material m; velocity (1 0.5); region { type rectangle; lower (0.1 0); upper (0.5 0.4); } }",
       "floor { type slip; face yMin; } right { type slip; face xMax; }"},
      // 3D, a cube thrown across a cubic domain, GIMP and MUSL: on 4 ranks a slab cut into
      // boxes on each side (nodes in up to eight grids).
      {"cube3DMUSLgimp", "endTime 0.04; deltaT 4e-4; writeInterval 1;", "updateScheme MUSL; shapeFunction gimp;",
       "dimension 3; lower (0 0 0); upper (0.4 0.4 0.4); cellSize 0.02;", kElastic,
       "b { material m; velocity (1 0.5 0.25); region { type box; lower (0.05 0.05 0); upper (0.3 0.3 0.25); } }",
       "floor { type slip; face zMin; }", "value (0 0 -9.81);"},
  };
}

class Decomposed : public ::testing::TestWithParam<Variant> {};

/// The axes across which the first "boxes of cells" line of a run's log cuts the grid: those
/// along which some box does not span what the widest box spans.
int axes_cut(const std::string& log) {
  const std::size_t at = log.find("boxes of cells");
  if (at == std::string::npos) return 0;
  const std::string line = log.substr(at, log.find('\n', at) - at);
  std::vector<std::vector<std::pair<int, int>>> boxes(1);
  for (std::size_t i = line.find('['); i != std::string::npos; i = line.find('[', i + 1)) {
    int lo = 0, hi = 0;
    if (std::sscanf(line.c_str() + i, "[%d, %d)", &lo, &hi) != 2) break;
    boxes.back().emplace_back(lo, hi);
    const std::size_t close = line.find(')', i);
    if (close + 1 < line.size() && line[close + 1] == ',') boxes.emplace_back();
  }
  int cut = 0;
  for (std::size_t d = 0; d < boxes[0].size(); ++d) {
    int lo = INT_MAX, hi = INT_MIN;
    for (const auto& b : boxes)
      if (d < b.size()) lo = std::min(lo, b[d].first), hi = std::max(hi, b[d].second);
    bool any = false;
    for (const auto& b : boxes) any = any || (d < b.size() && (b[d].first != lo || b[d].second != hi));
    cut += any;
  }
  return cut;
}

TEST_P(Decomposed, FollowsTheUndecomposedRunAndKeepsEveryPoint) {
  const Variant& s = GetParam();
  SharedCase c(s.name);
  write_case(c, s);
  Case cs = Case::read(c.dir(), runtime());
  const double t_end = cs.settings().control.time.end_time;
  RunStats st;
  std::ostringstream log;
  const Snapshot dec = run_to(c.dir(), world(), t_end, &st, &log);
  if (!is_root()) return;
  // On three ranks and more the square and the cube are cut across more than one axis (the
  // log's boxes, "[x0, x1) x [y0, y1) ...", as they were first cut).
  const int cut_axes = axes_cut(log.str());
  std::cout << "[ " << s.name << " ] cut across " << cut_axes << " axes\n";
  if ((s.name.rfind("square", 0) == 0 || s.name.rfind("cube", 0) == 0) && world_comm().size() >= 3)
    EXPECT_GE(cut_axes, 2) << log.str();
  const Snapshot one = run_to(c.dir(), self(), t_end);
  ASSERT_EQ(dec.bodies.size(), one.bodies.size());
  for (std::size_t k = 0; k < one.bodies.size(); ++k) {
    const Differences d = compare_bodies(dec.bodies[k], one.bodies[k]);
    if (s.name.rfind("sliding", 0) == 0) {  // every point crossed the cuts, which start inside the block
      EXPECT_GT(d.lo, 0.4) << "the block did not slide past where it started";
      // and the mass left its first ranks: the cuts moved with it
      EXPECT_GT(st.rebalances, 0) << "no rebalance";
    }
    std::cout << "[ " << s.name << " ] " << world_comm().size() << " ranks (" << st.rebalances
              << " rebalances) against one: position " << d.x
              << " of the block's length, velocity " << d.v << ", stress " << d.s << " of the largest\n";
    expect_within(d, s);
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Decomposed, ::testing::ValuesIn(setups()),
                         [](const auto& info) { return info.param.name; });

// ---------------------------------------------------------------------------------
// Two-phase bodies over the ranks (porous/porous_media.hpp): the pore liquid's three
// exchanges (its mass balance per cell, both phases' P2G with the cells' filling, the
// surface's sums) and its inflow totals, counted by the owner of each node and summed over
// the ranks. The decomposed run follows the one-rank run within round-off, as the
// single-phase cases above: positions, both phases' velocities, the effective stress and
// the pore pressure, and the totals of the liquid that entered, which must also match the
// rain that fell (rho_l w L t, the inflow's independent measure, within the 2% the
// one-rank tests of the rain hold: tests/verification/twophase). Where the rain ponds, the
// pond the points carry matches too, and the surface's own balance holds over the ranks:
// what it did not take less what ran off is the pond, within 1e-9 of the rain (the pond
// moves between points and nodes exactly; a node shared by two ranks holds the pond's full
// sum on both, and each rank's points gather their own shares of it).

const char* kSlopeSoil =
    "twoPhase { porosity 0.487; liquidDensity 1000; liquidBulkModulus 2e7; viscosity 1e-3; hydraulicConductivity "
    "1e-2; retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } permeability { type "
    "mualemVanGenuchten; } initialPorePressure { type hydrostatic; waterTable -0.5; } }";

struct TwoPhaseVariant {
  Variant v;
  double rain = 0;     ///< intensity [m/s] on the whole top
  double top = 0;      ///< the top's horizontal area (per metre in 2D) [m^2]
  bool slides = false; ///< the body crosses the cuts: the boxes must move with it
  double rain_total = 0;  ///< rain that ponds: the rain's mass [kg] (the pond's balance's scale)
};

void PrintTo(const TwoPhaseVariant& v, std::ostream* os) { *os << v.v.name; }

std::vector<TwoPhaseVariant> two_phase_setups() {
  const std::string rain2 = "rain { type rainfall; box { min (-1 0.15); max (3 2); } intensity 2e-3; unit m/s; }";
  return {
      // The inclined slope under rain (tests/verification/twophase), cut across the face:
      // the surface, its exposure test and the rain's nodes on both sides of a cut.
      {{"slopeRainGimp", "endTime 0.3; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; writeInterval 1;",
        "updateScheme USL; shapeFunction gimp;", "dimension 2; lower (0 0); upper (2.0 1.4); cellSize 0.1;",
        "soil { type linearElastic; E 5e7; nu 0.2; rho 2650; }",
        std::string("slope { material soil; region { type polygon; points ((0 0) (2 0) (2 0.2) (1.5 0.2) (0.9 1.1) "
                    "(0 1.1)); } particlesPerCell 2; initialStress { type geostatic; K0 0.5; } ") +
            kSlopeSoil + " }",
        "base { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; } " + rain2,
        "value (0 -9.81);", 1e-12, 1e-9, 1e-9},
       2e-3, 2.0},
      // The same slope under a rain of 10 K_sat that ponds on the crest (pondingDepth 5 mm)
      // and runs off beyond it: the pond on the nodes of both sides of a cut.
      {{"slopeRainPonds", "endTime 0.3; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; writeInterval 1;",
        "updateScheme USL; shapeFunction gimp;", "dimension 2; lower (0 0); upper (2.0 1.4); cellSize 0.1;",
        "soil { type linearElastic; E 5e7; nu 0.2; rho 2650; }",
        std::string("slope { material soil; region { type polygon; points ((0 0) (2 0) (2 0.2) (1.5 0.2) (0.9 1.1) "
                    "(0 1.1)); } particlesPerCell 2; initialStress { type geostatic; K0 0.5; } ") +
            kSlopeSoil + " }",
        "base { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; } "
        "rain { type rainfall; box { min (-1 0.15); max (3 2); } intensity 0.1; unit m/s; pondingDepth 0.005; }",
        "value (0 -9.81);", 1e-12, 1e-9, 1e-9},
       0, 2.0, false, 1000 * 0.1 * 2.0 * 0.3},
      // A saturated body at rest beside a single-phase block that slides at 3 m/s across
      // the cuts over a slip floor: the cuts move with the block (rebalances), and every
      // rank's grid, the pore liquid's included, is set up anew; linear shape functions.
      // The bounds are the sliding block's: with the saturated body made single-phase the
      // block differs as much (linear shapes amplify round-off at cell crossings, above);
      // the saturated body's fields agree to round-off.
      {{"restingSaturatedBesideSlidingBlock", "endTime 0.15; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; writeInterval 1;",
        "updateScheme USL;", "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;",
        "soil { type linearElastic; E 1e6; nu 0.3; rho 2000; }",
        "b { material soil; velocity (3 0); region { type rectangle; lower (0.1 0); upper (0.4 0.06); } } "
        "w { material soil; region { type rectangle; lower (1.0 0); upper (1.16 0.1); } "
        "initialStress { type geostatic; K0 0.5; } "
        "twoPhase { porosity 0.4; liquidBulkModulus 2e6; hydraulicConductivity 1e-3; } }",
        "floor { type slip; face yMin; }", "value (0 -9.81);", 1e-7, 1e-5, 1e-5},
       0, 0, true},
      // 3D: an unsaturated column under rain, GIMP: cut into boxes on 3 and 4 ranks.
      {{"columnRain3D", "endTime 0.05; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; writeInterval 1;",
        "updateScheme USL; shapeFunction gimp;", "dimension 3; lower (0 0 0); upper (0.56 0.56 0.72); cellSize 0.04;",
        "soil { type linearElastic; E 5e7; nu 0.2; rho 2650; }",
        std::string("col { material soil; region { type box; lower (0 0 0); upper (0.56 0.56 0.4); } "
                    "particlesPerCell 1; initialStress { type geostatic; K0 0.5; } ") +
            kSlopeSoil + " }",
        "base { type fixed; face zMin; } x0 { type slip; face xMin; } x1 { type slip; face xMax; } "
        "y0 { type slip; face yMin; } y1 { type slip; face yMax; } "
        "rain { type rainfall; box { min (-1 -1 0.35); max (1 1 1); } intensity 2e-3; unit m/s; }",
        "value (0 0 -9.81);", 1e-12, 1e-9, 1e-9},
       2e-3, 0.56 * 0.56},
  };
}

class DecomposedTwoPhase : public ::testing::TestWithParam<TwoPhaseVariant> {};

// A granular collapse (the phase-transition sand of the paper's column, Feng et al. 2025,
// Table 3) across the cuts. Frictional flow is not smooth in the round-off: a point's
// substepping, its yield and its collisional switch are decisions, and a difference in the
// last bit can take the other branch, which then grows with the flow. So the bound on the
// decomposed run is the spread of the one-process run itself under another order of the
// same sums (its points sorted by cell every 3 steps instead of never, which changes the
// order in which the P2G adds them at each node): a decomposition that did something
// other than regroup the sums would stand out of that spread by orders of magnitude.
TEST(DecomposedCollapse, FollowsTheUndecomposedRunWithinItsOwnRoundOffSpread) {
  Variant s{"collapseSandUSFgimp", "endTime 0.08; deltaT 1e-5; adjustTimeStep yes; maxCo 0.4; writeInterval 1;",
            "updateScheme USF; shapeFunction gimp;", "dimension 2; lower (0 0); upper (0.3 0.12); cellSize 0.005;",
            "sand { #includeEtc \"materials/feng2025/table3-columnCollapse\" integrationTolerance 1e-2; "
            "minSolidFraction 0.01; }",
            "b { material sand; region { type rectangle; lower (0 0); upper (0.05 0.1); } "
            "initialStress { type geostatic; K0 0.5; } }",
            "floor { type fixed; face yMin; } left { type slip; face xMin; }"};
  SharedCase c("collapse"), sorted("collapseSorted");
  write_case(c, s);
  Variant resorted = s;
  resorted.schemes += " sortInterval 3;";
  write_case(sorted, resorted);
  RunStats st;
  const Snapshot dec = run_to(c.dir(), world(), 0.08, &st);
  if (!is_root()) return;
  const Snapshot one = run_to(c.dir(), self(), 0.08), other = run_to(sorted.dir(), self(), 0.08);
  const Differences d = compare_bodies(dec.bodies[0], one.bodies[0]), spread = compare_bodies(other.bodies[0], one.bodies[0]);
  std::cout << "[ collapse ] " << world_comm().size() << " ranks (" << st.rebalances << " rebalances) against one: "
            << "position " << d.x << " of the column's extent, velocity " << d.v << ", stress " << d.s
            << "; one process sorted otherwise: " << spread.x << ", " << spread.v << ", " << spread.s << "\n";
  EXPECT_GT(d.hi - d.lo, 0.06) << "the column did not spread (its points 0.049 m apart at the start)";
  EXPECT_GT(spread.v, 0) << "the other order of the sums changed nothing: no spread to compare with";
  EXPECT_LT(d.x, 10 * spread.x + 1e-12);
  EXPECT_LT(d.v, 10 * spread.v + 1e-9);
  EXPECT_LT(d.s, 10 * spread.s + 1e-9);
}

TEST_P(DecomposedTwoPhase, FollowsTheUndecomposedRunAndCountsTheWaterOnce) {
  const TwoPhaseVariant& tp = GetParam();
  const Variant& s = tp.v;
  SharedCase c(s.name);
  write_case(c, s);
  Case cs = Case::read(c.dir(), runtime());
  const double t_end = cs.settings().control.time.end_time;
  RunStats st;
  std::ostringstream log;
  const Snapshot dec = run_to(c.dir(), world(), t_end, &st, &log);
  if (!is_root()) return;
  std::cout << "[ " << s.name << " ] cut across " << axes_cut(log.str()) << " axes, " << st.rebalances
            << " rebalances\n";
  if (tp.slides) EXPECT_GT(st.rebalances, 0) << "no rebalance";
  const Snapshot one = run_to(c.dir(), self(), t_end);
  ASSERT_EQ(dec.bodies.size(), one.bodies.size());
  for (std::size_t k = 0; k < one.bodies.size(); ++k) {
    const BodySnapshot &a = dec.bodies[k], &b = one.bodies[k];
    const Differences d = compare_bodies(a, b);
    std::cout << "[ " << s.name << " ] body " << a.name << ", " << world_comm().size()
              << " ranks against one: position " << d.x << ", velocity " << d.v << ", stress " << d.s;
    expect_within(d, s);
    if (!b.find("porePressure")) {
      std::cout << "\n";
      continue;
    }
    const double dp = difference(a, b, "porePressure"), dl = difference(a, b, "liquidVelocity"),
                 dS = difference(a, b, "saturation");
    std::cout << ", pore pressure " << dp << ", liquid velocity " << dl << ", saturation " << dS << "\n";
    EXPECT_LT(dp, s.tol_s);
    EXPECT_LT(dl, s.tol_v);
    EXPECT_LT(dS, s.tol_s);
    // The liquid's totals: one count of every node over the ranks.
    for (const char* name :
         {"liquidInflowSurface", "liquidInflowPrescribed", "liquidRainOffered", "liquidRainNotTaken", "liquidRunOff"}) {
      const auto *x = a.scalar(name), *y = b.scalar(name);
      if (k > 0 && !y) continue;  // the totals go with the first two-phase body
      ASSERT_TRUE(x && y) << name;
      std::cout << "[ " << s.name << " ] " << name << " " << x->value << " kg against " << y->value << " on one rank\n";
      EXPECT_NEAR(x->value, y->value, 1e-9 * std::max(1.0, std::fabs(y->value))) << name;
    }
    if (tp.rain_total > 0) {
      double pa = 0, pb = 0;
      for (double v : a.find("pond")->values) pa += v;
      for (double v : b.find("pond")->values) pb += v;
      const double not_taken = a.scalar("liquidRainNotTaken")->value, run_off = a.scalar("liquidRunOff")->value;
      std::cout << "[ " << s.name << " ] pond " << pa << " kg against " << pb << " on one rank; not taken " << not_taken
                << ", run off " << run_off << "\n";
      EXPECT_GT(pb, 1e-3 * tp.rain_total) << "kg: the rain did not pond";
      EXPECT_GT(run_off, 1e-3 * tp.rain_total) << "kg: nothing ran off";
      EXPECT_NEAR(pa, pb, 1e-9 * tp.rain_total) << "kg: the pond";
      EXPECT_NEAR(not_taken - run_off, pa, 1e-9 * tp.rain_total) << "kg: the surface's balance over the ranks";
    }
    if (tp.rain > 0) {
      const double rain = 1000 * tp.rain * tp.top * t_end;
      const double offered = a.scalar("liquidRainOffered")->value, entered = a.scalar("liquidInflowSurface")->value;
      EXPECT_NEAR(offered, rain, 0.02 * rain) << "kg: the rain offered to the surface";
      EXPECT_NEAR(entered, rain, 0.02 * rain) << "kg: what entered through the surface";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, DecomposedTwoPhase, ::testing::ValuesIn(two_phase_setups()),
                         [](const auto& info) { return info.param.v.name; });

// A decomposed two-phase run restarted from its own checkpoint ends in the uninterrupted
// run's state bit for bit (every point's fields, the pore liquid's columns included); the
// liquid's totals, summed over the ranks into the checkpoint and continued from the root's
// share, within round-off of the uninterrupted run's.
TEST(DecomposedTwoPhaseRestart, EndsInTheUninterruptedRunsState) {
  Variant s = two_phase_setups()[0].v;
  s.control = "endTime 0.2; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; writeInterval 0.1; "
              "checkpointKeep 10; writers { particles { type vtk; } }";
  SharedCase c("restartTwoPhase");
  write_case(c, s);
  const Snapshot whole = run_with_output(c.dir());
  world_comm().barrier();
  const Snapshot again = run_with_output(c.dir(), checkpoint_file(c.dir(), 0.1));
  if (!is_root()) return;
  const BodySnapshot &a = whole.bodies[0], &b = again.bodies[0];
  expect_bitwise_same(a, b);
  for (const char* name : {"liquidInflowSurface", "liquidRainOffered", "liquidRainNotTaken"}) {
    const auto *x = a.scalar(name), *y = b.scalar(name);
    ASSERT_TRUE(x && y) << name;
    EXPECT_NEAR(x->value, y->value, 1e-12 * std::max(1.0, std::fabs(x->value))) << name;
    EXPECT_NE(x->value, 0) << name;
  }
}

/// The text of a file ("" when it cannot be read).
std::string slurp(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The values of attribute `name` of every element that has one, in order.
std::vector<std::string> attributes(const std::string& xml, const std::string& name) {
  std::vector<std::string> out;
  const std::string key = " " + name + "=\"";
  for (std::size_t at = xml.find(key); at != std::string::npos; at = xml.find(key, at + 1)) {
    const std::size_t b = at + key.size();
    out.push_back(xml.substr(b, xml.find('"', b) - b));
  }
  return out;
}

/// The numbers of the ASCII DataArray named `name` of a .vtp.
std::vector<double> ascii_array(const std::string& vtp, const std::string& name) {
  std::vector<double> v;
  const std::size_t at = vtp.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return v;
  const std::size_t b = vtp.find('>', at) + 1, e = vtp.find("</DataArray>", b);
  std::istringstream in(vtp.substr(b, e - b));
  for (double x; in >> x;) v.push_back(x);
  return v;
}

/// Every file a .pvd lists exists, and every piece of a listed .pvtp; returns the files.
std::vector<std::string> expect_complete_series(const fs::path& pvd) {
  const std::vector<std::string> files = attributes(slurp(pvd), "file");
  for (const std::string& f : files) {
    const fs::path frame = pvd.parent_path() / f;
    EXPECT_TRUE(fs::exists(frame)) << pvd << " lists " << f << ", which is missing";
    if (frame.extension() == ".pvtp")
      for (const std::string& piece : attributes(slurp(frame), "Source"))
        EXPECT_TRUE(fs::exists(pvd.parent_path() / piece)) << frame << " lists " << piece << ", which is missing";
  }
  return files;
}

TEST(DecomposedOutput, EveryRankWritesItsPointsAsAPieceOfOneDataset) {
  // The vtk writer of a decomposed run: one piece per rank and a .pvtp per write time that
  // lists them, the .pvtp files in one .pvd. Over the pieces of a frame, every id once, and
  // each piece the points of one rank only (positions in disjoint ranges along the cut).
  Variant s = setups()[0];
  s.control = "endTime 0.1; deltaT 2e-4; writeInterval 0.05; writers { particles { type vtk; format ascii; "
              "fields (velocity); } }";
  SharedCase c("pieces");
  write_case(c, s);
  const Snapshot whole = run_with_output(c.dir());
  if (!is_root()) return;
  const int R = world_comm().size();
  const std::vector<std::string> frames = expect_complete_series(c.dir() / "VTK/particles.pvd");
  ASSERT_EQ(frames.size(), 3u) << "t = 0, 0.05, 0.1";
  for (const std::string& f : frames) {
    ASSERT_EQ(fs::path(f).extension(), ".pvtp") << f;
    const std::vector<std::string> pieces = attributes(slurp(c.dir() / "VTK" / f), "Source");
    ASSERT_EQ(pieces.size(), static_cast<std::size_t>(R)) << f;
    std::vector<std::int64_t> ids;
    std::vector<std::pair<double, double>> range;  // each piece's extent along x
    for (const std::string& p : pieces) {
      const std::string vtp = slurp(c.dir() / "VTK" / p);
      const std::vector<double> id = ascii_array(vtp, "particleId");
      const std::vector<double> xyz = ascii_array(vtp, "Points");
      ASSERT_EQ(xyz.size(), 3 * id.size()) << p;
      double lo = INFINITY, hi = -INFINITY;
      for (std::size_t k = 0; k < id.size(); ++k) {
        ids.push_back(static_cast<std::int64_t>(id[k]));
        lo = std::min(lo, xyz[3 * k]);
        hi = std::max(hi, xyz[3 * k]);
      }
      if (!id.empty()) range.emplace_back(lo, hi);
    }
    std::sort(ids.begin(), ids.end());
    std::vector<std::int64_t> expect = whole.bodies[0].id;
    std::sort(expect.begin(), expect.end());
    EXPECT_EQ(ids, expect) << f << ": the pieces do not hold every point once";
    std::sort(range.begin(), range.end());
    for (std::size_t k = 1; k < range.size(); ++k)
      EXPECT_LE(range[k - 1].second, range[k].first) << f << ": two pieces overlap along the cut";
    EXPECT_GE(range.size(), 2u) << f << ": the points were not shared among the ranks";
  }
}

TEST(DecomposedRestart, EndsInTheUninterruptedRunsStateBitForBit) {
  Variant s = setups()[0];
  s.control =
      "endTime 0.2; deltaT 2e-4; writeInterval 0.05; checkpointKeep 10; writers { particles { type vtk; } } "
      "functions { front { type runOut; } }";
  SharedCase c("restart");
  write_case(c, s);
  const Snapshot whole = run_with_output(c.dir());
  std::string front_whole;
  if (is_root()) {
    std::ifstream in(c.dir() / "postProcessing/front/runOut.csv");
    std::stringstream ss;
    ss << in.rdbuf();
    front_whole = ss.str();
    EXPECT_TRUE(fs::exists(c.dir() / "VTK/particles.pvd"));
    EXPECT_FALSE(front_whole.empty());
  }
  world_comm().barrier();
  const Snapshot again = run_with_output(c.dir(), checkpoint_file(c.dir(), 0.1));
  if (!is_root()) return;
  ASSERT_EQ(whole.bodies.size(), again.bodies.size());
  expect_bitwise_same(whole.bodies[0], again.bodies[0]);
  std::ifstream in(c.dir() / "postProcessing/front/runOut.csv");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), front_whole) << "the run-out CSV after the restart";
  EXPECT_EQ(expect_complete_series(c.dir() / "VTK/particles.pvd").size(), 5u) << "t = 0, 0.05, ..., 0.2";

  // The checkpoints: a manifest with no points and one piece per rank.
  const int R = world_comm().size();
  const fs::path mid = checkpoint_file(c.dir(), 0.1), early = checkpoint_file(c.dir(), 0.05);
  const Checkpoint manifest = Checkpoint::read(early, 0, 1);
  EXPECT_EQ(manifest.pieces.size(), static_cast<std::size_t>(R));
  for (int r = 0; r < R; ++r) EXPECT_TRUE(fs::exists(checkpoint_piece(early, r))) << "piece " << r;
  EXPECT_LT(fs::file_size(early), fs::file_size(checkpoint_piece(early, 0))) << "the manifest holds points";
  EXPECT_EQ(manifest.bodies[0].particles, static_cast<std::uint64_t>(whole.bodies[0].n));
  // A piece lost: the checkpoint is refused, naming it.
  fs::remove(checkpoint_piece(early, R - 1));
  try {
    Checkpoint::read(early, 0, 1);
    ADD_FAILURE() << "a checkpoint with a piece missing was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(checkpoint_piece(early, R - 1).string() + " is missing"), std::string::npos)
        << e.what();
  }
  // A run killed between the pieces and the manifest: the pieces without a manifest, older
  // than the newest, go with the next purge; the newest's stay.
  fs::remove(mid);
  purge_checkpoints(c.dir(), 10);
  EXPECT_FALSE(fs::exists(checkpoint_piece(mid, 0).parent_path()));
  EXPECT_TRUE(fs::exists(checkpoint_piece(checkpoint_file(c.dir(), 0.2), 0)));
}

// The function objects reduce over the ranks (output/ranks.hpp): every rank executes them
// on the points it holds and the root writes. A decomposed run writes the files one
// process writes, their numbers within the bounds the decomposed state itself keeps to the
// one-process state (the block's velocities within 1e-9 of their largest: here, of the
// largest number of the row), the counts exactly. tests/mpi/test_function_objects_ranks.cpp
// checks the reductions on one state exactly.
TEST(DecomposedOutput, FunctionObjectsWriteWhatOneProcessWrites) {
  Variant s = setups()[1];
  s.control =
      "endTime 0.2; deltaT 2e-4; writeInterval 0.05; "
      "functions { front { type runOut; frontQuantile 0.99; } "
      "probes { type particleProbes; points ((0.2 0.03) (0.35 0.05)); fields (velocity stress); } "
      "energy { type energies; budget yes; executeControl timeStep; executeInterval 100; } "
      "profile { type surfaceProfile; binWidth 0.02; } "
      "line { type lineProfile; start (0 0.02); end (1.2 0.02); bins 30; fields (velocity); } "
      "whole { type testWholeCase; } }";
  register_whole_case();  // one that does not reduce: run on the root with the case gathered
  SharedCase dec("foDecomposed"), one("foOne");
  write_case(dec, s);
  write_case(one, s);
  std::ostringstream log;
  {
    Case c = Case::read(dec.dir(), runtime());
    RunOptions o = opts(world(), true);
    o.log = &log;
    Simulation sim(c, runtime(), o);
    sim.run();
  }
  if (!is_root()) return;
  EXPECT_NE(log.str().find("Function objects reduced over the ranks: front probes energy profile line\n"), std::string::npos)
      << log.str();
  EXPECT_NE(log.str().find("Function objects on rank 0, the whole case gathered there when they are due: whole\n"),
            std::string::npos)
      << log.str();
  {
    Case c = Case::read(one.dir(), runtime());
    Simulation sim(c, runtime(), opts(self(), true));
    sim.run();
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(one.dir() / "postProcessing"))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), one.dir()));
  EXPECT_GE(files.size(), 13u) << "runOut, 2 probes and their selection, energies, 5 + 5 profiles, wholeCase";
  // The one that does not reduce saw the whole case on the root, once per execution.
  EXPECT_EQ(slurp(dec.dir() / "postProcessing/whole/wholeCase.csv"), slurp(one.dir() / "postProcessing/whole/wholeCase.csv"));
  for (const fs::path& f : files) {
    const std::string a = slurp(dec.dir() / f), b = slurp(one.dir() / f);
    ASSERT_FALSE(a.empty()) << f << " was not written by the decomposed run";
    std::istringstream ia(a), ib(b);
    std::string la, lb, header;
    std::getline(ia, header);
    std::getline(ib, lb);
    EXPECT_EQ(header, lb) << f;
    std::vector<std::string> names;
    {
      std::istringstream h(header);
      for (std::string cell; std::getline(h, cell, ',');) names.push_back(cell);
    }
    int rows = 0;
    while (std::getline(ib, lb)) {
      ASSERT_TRUE(std::getline(ia, la)) << f << ": fewer rows";
      ++rows;
      std::vector<double> x, y;
      for (auto [line, out] : {std::pair{&la, &x}, std::pair{&lb, &y}}) {
        std::istringstream r(*line);
        for (std::string cell; std::getline(r, cell, ',');) out->push_back(std::atof(cell.c_str()));
      }
      ASSERT_EQ(x.size(), y.size()) << f;
      double scale = 0;
      for (double v : y)
        if (std::isfinite(v)) scale = std::max(scale, std::fabs(v));
      for (std::size_t c = 0; c < x.size(); ++c) {
        const std::string& name = c < names.size() ? names[c] : "";
        if (name.find("particle") != std::string::npos || name.find("points") != std::string::npos || c == 0)
          EXPECT_EQ(x[c], y[c]) << f << " " << name;  // time, counts, the probes' ids
        else if (!std::isnan(y[c]))
          EXPECT_NEAR(x[c], y[c], 1e-9 * scale) << f << " row " << rows << " " << name;
      }
    }
    EXPECT_FALSE(std::getline(ia, la)) << f << ": more rows";
    EXPECT_GT(rows, 0) << f;
  }
}

TEST(DecomposedRestart, ContinuesOnOneRankWithinRoundOff) {
  // The checkpoint of a decomposed run (a manifest and a piece per rank) is the whole case:
  // one process reads every piece, continues it, and ends where the decomposed run ends,
  // within the bounds of the comparison above.
  Variant s = setups()[1];
  s.control = "endTime 0.2; deltaT 2e-4; writeInterval 0.1; checkpointKeep 10; writers { particles { type vtk; } }";
  SharedCase c("restartOne");
  write_case(c, s);
  const Snapshot whole = run_with_output(c.dir());
  if (!is_root()) return;
  Case cs = Case::read(c.dir(), runtime());
  RunOptions o = opts(self(), true);
  o.restart = checkpoint_file(c.dir(), 0.1);
  Simulation sim(cs, runtime(), o);
  sim.run();
  const Snapshot one = sim.snapshot();
  expect_same_points(one.bodies[0], whole.bodies[0]);
  EXPECT_LT(difference(one.bodies[0], whole.bodies[0], "velocity"), s.tol_v);
  EXPECT_LT(difference(one.bodies[0], whole.bodies[0], "stress"), s.tol_s);
}

// A rank whose slab lies over empty space holds most of the grid. The memory estimate
// before the run assumes equal shares; once the slabs are cut every rank checks every
// rank's grid and points against that rank's free memory, before anything of the slabs
// is allocated. A block in the first 6% of a 4 m channel: with the free memory at 60% of
// what the whole case takes on one rank, the last rank (the empty 94% of the grid) is
// refused by name, on every rank; with 120%, the run sets up.
TEST(DecomposedMemory, ARankWhoseSlabDoesNotFitIsRefusedBeforeAllocation) {
  SharedCase c("memory_slab");
  write_case_files(c, CaseFiles{"endTime 0.01; deltaT 1e-4; writeInterval 1;", "updateScheme USL;",
                                "dimension 2; lower (0 0); upper (4 0.2); cellSize 0.01;", "value (0 -9.81);", kElastic,
                                "b { material m; region { type rectangle; lower (0.02 0); upper (0.22 0.1); } }",
                                "floor { type slip; face yMin; }"});
  Case cs = Case::read(c.dir(), runtime());
  const double whole = estimate_memory(cs, runtime().registry(), test_device(), false).backend_bytes();
  const int R = world_comm().size();
  RunOptions o = opts(world());
  o.check_setup = false;  // as scree does after its own check with the ranks' layout: the slabs' check alone
  std::string what;
  ::setenv("SCREE_TEST_FREE_MEMORY", std::to_string(0.6 * whole).c_str(), 1);
  try {
    Simulation sim(cs, runtime(), o);
  } catch (const InputError& e) {
    what = e.what();
  }
  ::setenv("SCREE_TEST_FREE_MEMORY", std::to_string(1.2 * whole).c_str(), 1);
  bool fits = true;
  try {
    Simulation sim(cs, runtime(), o);
  } catch (const InputError& e) {
    fits = false;
    ADD_FAILURE() << "refused with 120% of the whole case free: " << e.what();
  }
  ::unsetenv("SCREE_TEST_FREE_MEMORY");
  if (is_root()) std::cout << what << "\n";
  EXPECT_NE(what.find("system/gridDict"), std::string::npos) << what;
  EXPECT_NE(what.find("cellSize: rank " + std::to_string(R - 1) + " of " + std::to_string(R) + " needs about"),
            std::string::npos)
      << what;
  EXPECT_NE(what.find("nothing was allocated"), std::string::npos) << what;
  EXPECT_TRUE(fits);
}

// A fixed step four times the stable one: the Courant check (stopCo), or the non-finite
// values that follow, stop the run. Every rank throws the same RunFailure, which names the
// rank that diagnosed it (no rank waits for another that has stopped: the diagnosis of one
// rank takes no collective step, the pore liquid's sums over the ranks included).
void expect_one_diagnosis(Variant s, const std::string& tag, const std::string& control) {
  s.control = control;
  SharedCase c(tag);
  write_case(c, s);
  Case cs = Case::read(c.dir(), runtime());
  Simulation sim(cs, runtime(), opts(world()));
  std::string what;
  try {
    sim.advance_to(0.1);
  } catch (const RunFailure& e) {
    what = e.what();
  }
  EXPECT_EQ(what.rfind("rank ", 0), 0u) << what;
  EXPECT_NE(what.find(" of " + std::to_string(world_comm().size()) + ": "), std::string::npos) << what;
}

TEST(DecomposedFailure, StopsEveryRankWithOneDiagnosis) {
  expect_one_diagnosis(setups()[3], "failure", "endTime 0.1; deltaT 2e-3; writeInterval 1;");
}

TEST(DecomposedFailure, StopsEveryRankOfATwoPhaseRunWithOneDiagnosis) {
  expect_one_diagnosis(two_phase_setups()[0].v, "failureTwoPhase", "endTime 0.1; deltaT 2e-3; writeInterval 1;");
}

}  // namespace
}  // namespace scree::test

int main(int argc, char** argv) {
  scree::comm_init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  scree::test::parse_device_flag(argc, argv);
  if (scree::test::world_comm().rank() != 0) {  // the root reports
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int rc = RUN_ALL_TESTS();
  std::uint64_t failed = rc != 0 ? 1 : 0;
  failed = scree::test::world_comm().sum(failed);
  scree::comm_finalize();
  return failed != 0 ? 1 : 0;
}
