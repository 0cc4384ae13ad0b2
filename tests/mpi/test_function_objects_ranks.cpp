// The function objects of plugins/functionObjects over the ranks of `mpirun -np N`: each
// rank executes them on its share of one hand-made snapshot, and what rank 0 writes must
// be what one process writes from the whole snapshot (output/ranks.hpp).
//
// The points are dealt to the ranks by a hash of their ids and in reverse order, as a
// decomposed run holds them (no rank's share in the order of the ids). Maxima, minima,
// counts, quantiles, the probes' choice and their followed values do not depend on how the
// points are shared, so those columns must be equal to the last printed digit. A sum adds
// the ranks' partial sums, whose rounding differs from one sum in another order by a
// relative 1e-16 per term; over the 3,000 points here that stays below 1e-12 of the
// row's largest value, the bound the other columns get.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "scree/comm/comm.hpp"
#include "scree/output/ranks.hpp"
#include "../unit/output/test_util.hpp"

using namespace scree_test;
using scree::BodySnapshot;
using scree::Snapshot;

namespace {

scree::Comm& world_comm() {
  static std::shared_ptr<scree::Comm> w = scree::world();
  return *w;
}
bool is_root() { return world_comm().rank() == 0; }

/// One directory every rank sees (the root names and makes it), removed at the end.
class SharedDir {
 public:
  explicit SharedDir(const std::string& tag) {
    std::string name = "scree_fo_ranks_" + tag + "_" + std::to_string(::getpid());
    std::uint64_t len = name.size();
    world_comm().broadcast(&len, sizeof len, 0);
    name.resize(len);
    world_comm().broadcast(name.data(), len, 0);
    path_ = fs::temp_directory_path() / name;
    if (is_root()) {
      fs::remove_all(path_);
      fs::create_directories(path_ / "decomposed");
      fs::create_directories(path_ / "alone");
    }
    world_comm().barrier();
  }
  ~SharedDir() {
    world_comm().barrier();
    if (is_root()) fs::remove_all(path_);
  }
  fs::path path(const char* which) const { return path_ / which; }

 private:
  fs::path path_;
};

/// Body "left" (elastic, 2,000 points) and body "right" (two-phase, 1,000 points) at time
/// t: positions and fields from a fixed seed, a few points lost.
Snapshot whole(int dim, double t, std::int64_t step) {
  std::mt19937_64 rng(1234 + static_cast<unsigned>(step));
  std::uniform_real_distribution<double> u(0, 1);
  Snapshot s;
  s.time = t;
  s.step = step;
  s.dimension = dim;
  s.energy.kept = true;
  for (int k = 0; k < scree::kEnergyTerms; ++k) s.energy.term[k] = 0.1 * (k + 1) * (1 + t);
  const int counts[2] = {2000, 1000};
  std::int64_t id = 0;
  for (int bi = 0; bi < 2; ++bi) {
    std::vector<std::array<double, 3>> pos;
    std::vector<std::int64_t> ids;
    for (int p = 0; p < counts[bi]; ++p) {
      // a heap of points, on a lattice of 0.01 m so that some probes meet ties
      const double x = std::round(100 * (bi + 2 * u(rng) + t)) / 100, y = std::round(100 * u(rng) * (1 - 0.3 * x)) / 100;
      pos.push_back(dim == 3 ? std::array<double, 3>{x, std::round(100 * u(rng)) / 100, y} : std::array<double, 3>{x, y, 0});
      if (bi == 0 && p < 3)  // three points at the first probe's point: a tie
        pos.back() = dim == 3 ? std::array<double, 3>{0.5, 0.5, 0.2} : std::array<double, 3>{0.5, 0.2, 0};
      ids.push_back(id++);
    }
    BodySnapshot b = make_body(bi == 0 ? "left" : "right", bi, pos, ids);
    const std::size_t n = pos.size();
    auto values = [&](int comps, double lo, double hi) {
      std::vector<double> v(comps * n);
      for (double& x : v) x = lo + (hi - lo) * u(rng);
      return v;
    };
    add_field(b, "velocity", 3, values(3, -1, 1), "m/s");
    if (dim == 2)
      for (std::size_t p = 0; p < n; ++p) b.fields.back().values[3 * p + 2] = 0;
    add_field(b, "mass", 1, values(1, 0.5, 1.5), "kg");
    add_field(b, "stress", 6, values(6, -1e4, 1e3), "Pa");
    add_field(b, "pressure", 1, values(1, 0, 1e4), "Pa");
    add_field(b, "volume", 1, values(1, 1e-4, 2e-4), "m^2");
    add_field(b, "elasticEnergy", 1, values(1, 0, 10), "J/m^3");
    add_field(b, "granularTemperature", 1, values(1, 0, 1e-3), "m^2/s^2");
    if (bi == 1) {
      b.material_type = "unsaturatedSoil";
      add_field(b, "porePressure", 1, values(1, -2e4, 1e4), "Pa");
      add_field(b, "saturation", 1, values(1, 0.3, 1), "-");
      add_field(b, "porosity", 1, values(1, 0.35, 0.45), "-");
      b.scalars = {{"liquidDensity", "kg/m^3", "", 1000},
                   {"liquidBulkModulus", "Pa", "", 2e9},
                   {"liquidInflowSurface", "kg", "", 3.5 * t},
                   {"liquidInflowPrescribed", "kg", "", -0.25 * t}};
    }
    b.lost.assign(n, 0);
    for (std::size_t p = 7; p < n; p += 301) b.lost[p] = 1;
    s.bodies.push_back(std::move(b));
  }
  return s;
}

/// Rank me's share of `s` among R ranks: the points whose id hashes to it, in reverse
/// order (one rank: every point, as one process may hold them). From three ranks on, the
/// last holds none, as a rank whose box is empty.
Snapshot share(const Snapshot& s, int R, int me) {
  const int holders = R > 2 ? R - 1 : R;
  Snapshot out = s;
  for (BodySnapshot& b : out.bodies) {
    const BodySnapshot& w = s.bodies[static_cast<std::size_t>(b.body_id)];
    std::vector<std::size_t> keep;
    for (std::size_t p = w.id.size(); p-- > 0;)
      if (static_cast<int>((w.id[p] * 7919) % holders) == me) keep.push_back(p);
    b.n = static_cast<scree::Index>(keep.size());
    b.id.clear();
    b.position.clear();
    b.lost.clear();
    for (std::size_t p : keep) {
      b.id.push_back(w.id[p]);
      b.position.insert(b.position.end(), &w.position[3 * p], &w.position[3 * p] + 3);
      b.lost.push_back(w.lost[p]);
    }
    for (std::size_t f = 0; f < b.fields.size(); ++f) {
      const auto& src = w.fields[f];
      auto& v = b.fields[f].values;
      v.clear();
      for (std::size_t p : keep)
        v.insert(v.end(), src.values.begin() + static_cast<std::ptrdiff_t>(p) * src.components,
                 src.values.begin() + static_cast<std::ptrdiff_t>(p + 1) * src.components);
    }
  }
  return out;
}

struct Entry {
  std::string name, type, text;
};

std::vector<Entry> entries(int dim) {
  if (dim == 2)
    return {{"front", "runOut", ""},
            {"front99", "runOut", "frontQuantile 0.99; heightQuantile 0.95; heightWindow (1 2);"},
            {"spread", "runOut", "frontQuantile 0.97; radial { centre (1.5 0); directions ((1 0) (-1 0)); }"},
            {"probes", "particleProbes", "points ((0.5 0.2) (2.5 0.3) (1.0 0.0)); fields (pressure stress);"},
            {"energy", "energies", "budget yes;"},
            {"profile", "surfaceProfile", "binWidth 0.05;"},
            {"line", "lineProfile", "start (1 0); end (2 0.5); width 0.1; bins 7; fields (pressure velocity);"},
            {"water", "waterBalance", ""}};
  return {{"front", "runOut", "direction (1 1 0); frontQuantile 0.999;"},
          {"spread", "runOut", "radial { centre (1.5 0.5 0); directions ((1 0 0) (0 1 0) (-1 0 0)); }"},
          {"probes", "particleProbes", "points ((0.5 0.5 0.2) (2.5 0.1 0.3)); fields (all);"},
          {"energy", "energies", ""},
          {"heights", "surfaceProfile", "binWidth 0.1;"},
          {"section", "surfaceProfile", "binWidth 0.05; direction (1 0 0); origin (0 0.5 0); width 0.1;"},
          {"line", "lineProfile", "start (1 0.5 0); end (2 0.5 0.5); width 0.2; binWidth 0.1;"},
          {"water", "waterBalance", ""}};
}

/// Run every entry over three times: on this rank's share with the ranks (`comm`), or on
/// the whole snapshot alone (comm null).
void run(const fs::path& dir, int dim, std::shared_ptr<scree::Comm> comm) {
  std::vector<std::unique_ptr<scree::FunctionObject>> fos;
  for (const Entry& e : entries(dim)) {
    scree::SolverContext ctx = make_context(dir, e.name, dim);
    ctx.comm = comm;
    fos.push_back(make_function(e.type, e.text, ctx));
  }
  for (int k = 0; k < 3; ++k) {
    const Snapshot s = whole(dim, 0.25 * k, 10 * k);
    const Snapshot part = comm ? share(s, comm->size(), comm->rank()) : share(s, 1, 0);
    for (auto& f : fos) f->execute(part);
  }
  for (auto& f : fos) f->finish();
}

/// Every file under a/postProcessing and b/postProcessing, the same names, headers and
/// rows; each number equal or, in a sum's column, within 1e-12 of its row's largest value.
void expect_same_files(const fs::path& a, const fs::path& b) {
  std::set<std::string> names_a, names_b;
  for (const auto& e : fs::recursive_directory_iterator(a / "postProcessing"))
    if (e.is_regular_file()) names_a.insert(fs::relative(e.path(), a).string());
  for (const auto& e : fs::recursive_directory_iterator(b / "postProcessing"))
    if (e.is_regular_file()) names_b.insert(fs::relative(e.path(), b).string());
  EXPECT_EQ(names_a, names_b);
  EXPECT_GT(names_a.size(), 15u);
  auto is_sum = [](const std::string& file, const std::string& column) {
    for (const char* exact : {"runout", "height [", "max_speed", "particles", "points [", "lost points", "distance"})
      if (column.rfind(exact, 0) == 0) return false;
    // The probes follow one point; a profile's heights are maxima; the rest sum or average.
    return file.find("/probes/") == std::string::npos && file.find("surfaceProfile") == std::string::npos &&
           file.find("/profile/") == std::string::npos && file.find("/heights/") == std::string::npos &&
           file.find("/section/") == std::string::npos;
  };
  for (const std::string& f : names_a) {
    if (!names_b.count(f)) continue;
    const Csv x = read_csv(a / f), y = read_csv(b / f);
    ASSERT_EQ(x.header, y.header) << f;
    ASSERT_EQ(x.rows.size(), y.rows.size()) << f;
    for (std::size_t r = 0; r < x.rows.size(); ++r) {
      double scale = 0;
      for (std::size_t c = 1; c < x.rows[r].size(); ++c)
        if (std::isfinite(std::atof(x.rows[r][c].c_str()))) scale = std::max(scale, std::fabs(std::atof(x.rows[r][c].c_str())));
      for (std::size_t c = 0; c < x.rows[r].size(); ++c) {
        const std::string &p = x.rows[r][c], &q = y.rows[r][c];
        if (p == q) continue;
        EXPECT_TRUE(is_sum(f, x.header[c])) << f << " row " << r << " " << x.header[c] << ": " << p << " against "
                                            << q << " alone";
        EXPECT_NEAR(std::atof(p.c_str()), std::atof(q.c_str()), 1e-12 * scale)
            << f << " row " << r << " " << x.header[c];
      }
    }
  }
}

class FunctionObjectsOverRanks : public ::testing::TestWithParam<int> {};

TEST_P(FunctionObjectsOverRanks, WriteWhatOneProcessWritesFromTheWholeCase) {
  const int dim = GetParam();
  SharedDir dir("d" + std::to_string(dim));
  run(dir.path("decomposed"), dim, scree::world());
  world_comm().barrier();
  if (!is_root()) return;
  run(dir.path("alone"), dim, nullptr);
  expect_same_files(dir.path("decomposed"), dir.path("alone"));
  // The cases above are not trivial: points were lost, quantiles and probes were taken.
  EXPECT_TRUE(fs::exists(dir.path("alone") / "postProcessing/front/lostPoints.csv"));
  EXPECT_EQ(read_csv(dir.path("alone") / "postProcessing/probes/selection.csv").rows.size(), dim == 2 ? 3u : 2u);
}

INSTANTIATE_TEST_SUITE_P(Dimensions, FunctionObjectsOverRanks, ::testing::Values(2, 3),
                         [](const ::testing::TestParamInfo<int>& i) { return std::to_string(i.param) + "D"; });

/// The root's files fail (here: a file where its directory should be) after its reductions
/// began: every rank stops with an error, none waits in a reduction the root never makes.
TEST(FunctionObjectsOverRanks, ARootThatCannotWriteStopsEveryRank) {
  SharedDir dir("unwritable");
  scree::SolverContext ctx = make_context(dir.path("decomposed"), "probes", 2);
  ctx.comm = scree::world();
  auto fo = make_function("particleProbes", "points ((0.5 0.2));", ctx);
  if (is_root()) {
    fs::create_directories(dir.path("decomposed") / "postProcessing");
    std::ofstream(dir.path("decomposed") / "postProcessing" / "probes") << "in the way\n";
  }
  world_comm().barrier();
  const Snapshot s = whole(2, 0, 0);
  EXPECT_THROW(fo->execute(share(s, world_comm().size(), world_comm().rank())), std::runtime_error);
}

/// The quantile over the ranks against the one-process rule on values with repeats,
/// negative values and zeros of both signs, for every k.
TEST(RanksQuantile, IsTheKthSmallestOfEveryRanksValues) {
  const int R = world_comm().size(), me = world_comm().rank();
  std::vector<double> all;
  for (int i = 0; i < 61; ++i) all.push_back(i % 7 == 0 ? (i % 2 ? -0.0 : 0.0) : std::ldexp(i % 13 - 6, i % 5 - 2));
  const scree::Ranks ranks(scree::world()), alone;
  for (int k = 1; k <= static_cast<int>(all.size()); ++k) {
    const double q = static_cast<double>(k) / static_cast<double>(all.size());
    std::vector<double> mine;
    for (std::size_t i = 0; i < all.size(); ++i)
      if (static_cast<int>(i % static_cast<std::size_t>(R)) == me) mine.push_back(all[i]);
    std::vector<double> copy = all;
    const double got = ranks.quantile(mine, q), want = alone.quantile(copy, q);
    EXPECT_EQ(got, want) << "k = " << k;
  }
  std::vector<double> none;
  EXPECT_TRUE(std::isnan(ranks.quantile(none, 0.5)));
}

}  // namespace

int main(int argc, char** argv) {
  scree::comm_init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (world_comm().rank() != 0) {  // the root reports
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int rc = RUN_ALL_TESTS();
  std::uint64_t failed = rc != 0 ? 1 : 0;
  failed = world_comm().sum(failed);
  scree::comm_finalize();
  return failed != 0 ? 1 : 0;
}
