// Tests of the vtk writer plugin (plugins/vtk): hand-made snapshots are written through
// the plugin runtime and read back with VTK's own XML readers; the .pvd series is parsed
// independently. Checks point counts, array names, types, component counts and names,
// values (NaN where a body lacks a field), field data, the grid, field selection with
// its warning, errors a user can cause, clean-up and restart of the series.
#include <vtkAbstractArray.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>

#include "test_util.hpp"

using namespace scree_test;
using scree::Snapshot;

namespace {

/// Two bodies: "left" (3 particles, linear elastic fields) and "right" (2 particles,
/// with an extra material field voidRatio). Values encode particle and component.
Snapshot two_bodies(double time, std::int64_t step, double shift = 0) {
  Snapshot s;
  s.time = time;
  s.step = step;
  s.dimension = 2;
  auto a = make_body("left", 0, {{0.0 + shift, 0.0, 0}, {0.1 + shift, 0.0, 0}, {0.2 + shift, 0.1, 0}}, {10, 11, 12});
  auto b = make_body("right", 1, {{1.0 + shift, 0.5, 0}, {1.1 + shift, 0.5, 0}}, {20, 21});
  for (auto* body : {&a, &b}) {
    const auto n = static_cast<std::size_t>(body->n);
    std::vector<double> v(3 * n), st(6 * n), p(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double base = static_cast<double>(body->id[i]);
      for (int c = 0; c < 3; ++c) v[3 * i + c] = c == 2 ? 0.0 : base + 0.1 * c;
      for (int c = 0; c < 6; ++c) st[6 * i + c] = -(base * 100 + c);
      p[i] = base * 100 + 1;  // -(xx+yy+zz)/3 = 100 base + 1
    }
    add_field(*body, "velocity", 3, v, "m/s");
    add_field(*body, "stress", 6, st, "Pa");
    add_field(*body, "pressure", 1, p, "Pa");
    add_field(*body, "bodyId", 1, std::vector<double>(n, body->body_id));
  }
  add_field(b, "voidRatio", 1, {0.6, 0.7});
  s.bodies = {a, b};
  return s;
}

vtkSmartPointer<vtkPolyData> read_vtp(const fs::path& p) {
  EXPECT_TRUE(fs::exists(p)) << p;
  vtkNew<vtkXMLPolyDataReader> r;
  r->SetFileName(p.c_str());
  r->Update();
  EXPECT_EQ(r->GetErrorCode(), 0u) << p;
  vtkSmartPointer<vtkPolyData> pd = r->GetOutput();
  return pd;
}

std::vector<std::string> point_array_names(vtkPolyData* pd) {
  std::vector<std::string> names;
  for (int i = 0; i < pd->GetPointData()->GetNumberOfArrays(); ++i)
    names.push_back(pd->GetPointData()->GetArrayName(i));
  return names;
}

}  // namespace

TEST(VtkWriter, WritesParticlesSeriesAndFieldData) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "particles");
  auto w = make_writer("type vtk;", ctx);
  ASSERT_FALSE(w->wants_grid());
  w->write(two_bodies(0.0, 0));
  w->write(two_bodies(0.25, 10, 0.5));
  w->write(two_bodies(0.25, 10, 0.5));  // the same step again: ignored
  w->finish();

  const fs::path vtk = dir.path() / "VTK";
  const auto series = read_pvd(vtk / "particles.pvd");
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].time, 0.0);
  EXPECT_EQ(series[0].file, "particles_0.vtp");
  EXPECT_EQ(series[1].time, 0.25);
  EXPECT_EQ(series[1].file, "particles_1.vtp");
  EXPECT_FALSE(fs::exists(vtk / "particles_2.vtp"));
  EXPECT_TRUE(temporaries(vtk).empty());

  auto pd = read_vtp(vtk / series[1].file);
  ASSERT_EQ(pd->GetNumberOfPoints(), 5);
  EXPECT_EQ(pd->GetNumberOfVerts(), 5);
  EXPECT_EQ(pd->GetNumberOfCells(), 5);
  // Points: bodies one after the other, in snapshot order.
  double x[3];
  pd->GetPoint(3, x);
  EXPECT_DOUBLE_EQ(x[0], 1.5);
  EXPECT_DOUBLE_EQ(x[1], 0.5);
  EXPECT_DOUBLE_EQ(x[2], 0.0);
  EXPECT_EQ(pd->GetPoints()->GetDataType(), VTK_DOUBLE);

  const auto names = point_array_names(pd);
  const std::vector<std::string> expected = {"particleId", "bodyId", "velocity", "stress", "pressure", "voidRatio"};
  EXPECT_EQ(names, expected);
  vtkPointData* pt = pd->GetPointData();

  vtkDataArray* ids = pt->GetArray("particleId");
  ASSERT_NE(ids, nullptr);
  EXPECT_EQ(ids->GetDataTypeSize(), 8);
  EXPECT_TRUE(ids->GetDataType() == VTK_TYPE_INT64 || ids->GetDataType() == VTK_ID_TYPE) << ids->GetDataTypeAsString();
  const std::int64_t want_ids[] = {10, 11, 12, 20, 21};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(static_cast<std::int64_t>(ids->GetTuple1(i)), want_ids[i]);
  vtkDataArray* body = pt->GetArray("bodyId");
  ASSERT_NE(body, nullptr);
  EXPECT_EQ(body->GetDataType(), VTK_INT);
  EXPECT_EQ(body->GetTuple1(2), 0);
  EXPECT_EQ(body->GetTuple1(3), 1);

  vtkDataArray* v = pt->GetArray("velocity");
  ASSERT_EQ(v->GetNumberOfComponents(), 3);
  EXPECT_STREQ(v->GetComponentName(0), "X");
  EXPECT_DOUBLE_EQ(v->GetComponent(4, 0), 21.0);
  EXPECT_DOUBLE_EQ(v->GetComponent(4, 1), 21.1);
  EXPECT_DOUBLE_EQ(v->GetComponent(4, 2), 0.0);
  EXPECT_EQ(pt->GetVectors(), v);

  vtkDataArray* st = pt->GetArray("stress");
  ASSERT_EQ(st->GetNumberOfComponents(), 6);
  const char* comp[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (int c = 0; c < 6; ++c) {
    EXPECT_STREQ(st->GetComponentName(c), comp[c]);
    EXPECT_DOUBLE_EQ(st->GetComponent(1, c), -(1100.0 + c));
  }
  EXPECT_EQ(pt->GetTensors(), st);
  EXPECT_DOUBLE_EQ(pt->GetArray("pressure")->GetTuple1(3), 2001.0);

  // voidRatio exists only in body "right": NaN on the other body's particles.
  vtkDataArray* e = pt->GetArray("voidRatio");
  ASSERT_EQ(e->GetNumberOfComponents(), 1);
  EXPECT_TRUE(std::isnan(e->GetTuple1(0)));
  EXPECT_TRUE(std::isnan(e->GetTuple1(2)));
  EXPECT_DOUBLE_EQ(e->GetTuple1(3), 0.6);
  EXPECT_DOUBLE_EQ(e->GetTuple1(4), 0.7);

  // Field data: time, step, body names, conventions, descriptions.
  vtkFieldData* fd = pd->GetFieldData();
  ASSERT_NE(fd->GetArray("TimeValue"), nullptr);
  EXPECT_DOUBLE_EQ(fd->GetArray("TimeValue")->GetTuple1(0), 0.25);
  EXPECT_EQ(fd->GetArray("step")->GetTuple1(0), 10);
  auto* bodies = vtkStringArray::SafeDownCast(fd->GetAbstractArray("bodyNames"));
  ASSERT_NE(bodies, nullptr);
  ASSERT_EQ(bodies->GetNumberOfValues(), 2);
  EXPECT_EQ(bodies->GetValue(0), "left");
  EXPECT_EQ(bodies->GetValue(1), "right");
  auto* conv = vtkStringArray::SafeDownCast(fd->GetAbstractArray("conventions"));
  ASSERT_NE(conv, nullptr);
  bool tension_positive = false;
  for (vtkIdType i = 0; i < conv->GetNumberOfValues(); ++i)
    tension_positive |= conv->GetValue(i).find("tension positive") != std::string::npos;
  EXPECT_TRUE(tension_positive);
  auto* desc = vtkStringArray::SafeDownCast(fd->GetAbstractArray("fieldDescriptions"));
  ASSERT_NE(desc, nullptr);
  EXPECT_EQ(desc->GetValue(2), "velocity [m/s]: test field velocity");

  // The first file: the first time.
  auto pd0 = read_vtp(vtk / series[0].file);
  EXPECT_EQ(pd0->GetNumberOfPoints(), 5);
  EXPECT_DOUBLE_EQ(pd0->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), 0.0);
}

TEST(VtkWriter, SelectedFieldsSinglePrecisionAsciiAndUnknownNames) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "sel");
  auto w = make_writer(
      "type vtk; fields (velocity stres pressure bodyId); bodies (right); directory \"out/vtk\"; format ascii; "
      "precision single;",
      ctx);
  testing::internal::CaptureStderr();
  w->write(two_bodies(0.5, 3));
  w->write(two_bodies(0.75, 4));
  const std::string err = testing::internal::GetCapturedStderr();
  // Reported once, with a suggestion and the valid names.
  EXPECT_NE(err.find("'stres'"), std::string::npos) << err;
  EXPECT_NE(err.find("did you mean 'stress'"), std::string::npos) << err;
  EXPECT_NE(err.find("voidRatio"), std::string::npos) << err;
  EXPECT_EQ(err.find("'stres'"), err.rfind("'stres'")) << err;

  const fs::path out = dir.path() / "out" / "vtk";
  ASSERT_EQ(read_pvd(out / "sel.pvd").size(), 2u);
  auto pd = read_vtp(out / "sel_1.vtp");
  ASSERT_EQ(pd->GetNumberOfPoints(), 2);  // body "right" only
  const std::vector<std::string> expected = {"particleId", "bodyId", "velocity", "pressure"};
  EXPECT_EQ(point_array_names(pd), expected);
  EXPECT_EQ(pd->GetPointData()->GetArray("pressure")->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(pd->GetPoints()->GetDataType(), VTK_FLOAT);
  EXPECT_FLOAT_EQ(static_cast<float>(pd->GetPointData()->GetArray("velocity")->GetComponent(1, 1)), 21.1f);
  // ASCII: the numbers are readable in the file.
  std::ifstream in(out / "sel_1.vtp");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("format=\"ascii\""), std::string::npos);
  EXPECT_NE(ss.str().find("2001"), std::string::npos);
}

TEST(VtkWriter, GridAsImageData) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "g");
  auto w = make_writer("type vtk; grid yes; compression lz4;", ctx);
  ASSERT_TRUE(w->wants_grid());
  Snapshot s = two_bodies(0.1, 1);
  s.has_grid = true;
  s.grid.n[0] = 3;
  s.grid.n[1] = 2;
  s.grid.origin[0] = -0.1;
  s.grid.origin[1] = -0.2;
  s.grid.h = 0.1;
  std::vector<double> mass(6), vel(18, 0.0);
  for (int i = 0; i < 6; ++i) {
    mass[i] = i + 0.5;
    vel[3 * i + 1] = -i;
  }
  s.grid.fields.push_back({"mass", 1, "kg", "nodal mass", mass});
  s.grid.fields.push_back({"velocity", 3, "m/s", "nodal velocity", vel});
  w->write(s);

  const fs::path vtk = dir.path() / "VTK";
  const auto series = read_pvd(vtk / "g_grid.pvd");
  ASSERT_EQ(series.size(), 1u);
  EXPECT_EQ(series[0].file, "g_grid_0.vti");
  vtkNew<vtkXMLImageDataReader> r;
  r->SetFileName((vtk / series[0].file).c_str());
  r->Update();
  vtkImageData* img = r->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  EXPECT_EQ(dims[0], 3);
  EXPECT_EQ(dims[1], 2);
  EXPECT_EQ(dims[2], 1);
  double origin[3], spacing[3];
  img->GetOrigin(origin);
  img->GetSpacing(spacing);
  EXPECT_DOUBLE_EQ(origin[0], -0.1);
  EXPECT_DOUBLE_EQ(origin[1], -0.2);
  EXPECT_DOUBLE_EQ(spacing[0], 0.1);
  // Node (i, j) is value i + 3 j (x fastest, as in the solver's grid).
  EXPECT_DOUBLE_EQ(img->GetPointData()->GetArray("mass")->GetTuple1(4), 4.5);
  EXPECT_DOUBLE_EQ(img->GetPointData()->GetArray("velocity")->GetComponent(5, 1), -5.0);
  double p[3];
  img->GetPoint(4, p);
  EXPECT_DOUBLE_EQ(p[0], 0.0);
  EXPECT_DOUBLE_EQ(p[1], -0.1);
  EXPECT_TRUE(temporaries(vtk).empty());
}

TEST(VtkWriter, ErrorsUsersCanCause) {
  TempDir dir;
  auto ctx = make_context(dir.path(), "bad");
  // A directory that cannot be created (a file is in the way): an InputError at the
  // entry, before any write.
  std::ofstream(dir.path() / "blocker") << "x";
  try {
    make_writer("type vtk; directory \"blocker/VTK\";", ctx);
    ADD_FAILURE() << "expected an InputError";
  } catch (const scree::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create the output directory"), std::string::npos) << e.what();
    EXPECT_EQ(e.where().line, 1);
  }
  // An unknown body.
  try {
    make_writer("type vtk; bodies (lft);", ctx);
    ADD_FAILURE() << "expected an InputError";
  } catch (const scree::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'left'"), std::string::npos) << e.what();
  }
}

TEST(VtkWriter, FreshRunReplacesOldSeriesRestartContinuesIt) {
  TempDir dir;
  const fs::path vtk = dir.path() / "VTK";
  {
    auto w = make_writer("type vtk;", make_context(dir.path(), "r"));
    for (int i = 0; i < 3; ++i) w->write(two_bodies(0.1 * i, i));
  }
  // Left-overs of a killed longer run, and a file of someone else.
  std::ofstream(vtk / "r_7.vtp") << "old";
  std::ofstream(vtk / ".r_3.vtp.tmp123_0") << "half";
  std::ofstream(vtk / "notes.txt") << "mine";
  std::ofstream(vtk / "rr_1.vtp") << "another writer";

  // A restart from t = 0.1 keeps t = 0, numbers its frames after it (writing r_1 again),
  // keeps the later frame listed until it writes it again (a restart killed early unlists
  // no finished frame), and removes what no series lists: a killed run's temporary, a
  // frame of a longer earlier run.
  {
    auto ctx = make_context(dir.path(), "r");
    ctx.start_time = 0.1;
    auto w = make_writer("type vtk;", ctx);
    w->write(two_bodies(0.1, 1));
    const auto series = read_pvd(vtk / "r.pvd");
    ASSERT_EQ(series.size(), 3u);
    EXPECT_EQ(series[0].file, "r_0.vtp");
    EXPECT_EQ(series[1].file, "r_1.vtp");
    EXPECT_DOUBLE_EQ(series[1].time, 0.1);
    EXPECT_EQ(series[2].file, "r_2.vtp");
    EXPECT_FALSE(fs::exists(vtk / "r_7.vtp"));
    EXPECT_FALSE(fs::exists(vtk / ".r_3.vtp.tmp123_0"));
    w->write(two_bodies(0.2, 2));
    EXPECT_EQ(read_pvd(vtk / "r.pvd").size(), 3u) << "r_2 written again replaces its entry";
  }
  // A fresh run removes the old series (and only it).
  {
    auto w = make_writer("type vtk;", make_context(dir.path(), "r"));
    w->write(two_bodies(0.0, 0));
  }
  EXPECT_FALSE(fs::exists(vtk / "r_7.vtp"));
  EXPECT_FALSE(fs::exists(vtk / "r_2.vtp"));
  EXPECT_FALSE(fs::exists(vtk / ".r_3.vtp.tmp123_0"));
  EXPECT_TRUE(fs::exists(vtk / "r_0.vtp"));
  EXPECT_TRUE(fs::exists(vtk / "notes.txt"));
  EXPECT_TRUE(fs::exists(vtk / "rr_1.vtp"));
  EXPECT_EQ(read_pvd(vtk / "r.pvd").size(), 1u);
}

// A run killed between a frame's rename and the .pvd's rewrite leaves the frame complete but
// unlisted (4 of 20 kill trials did, before restarts existed): the restart lists it at once,
// with the time in its header, before it writes anything.
TEST(VtkWriter, RestartListsTheFrameAKilledRunLeftUnlisted) {
  TempDir dir;
  const fs::path vtk = dir.path() / "VTK";
  {
    auto w = make_writer("type vtk;", make_context(dir.path(), "r"));
    for (int i = 0; i < 4; ++i) w->write(two_bodies(0.1 * i, i));
  }
  {  // the .pvd as it was before the last frame's rewrite
    std::ifstream in(vtk / "r.pvd");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const auto at = text.find("file=\"r_3.vtp\"");
    ASSERT_NE(at, std::string::npos);
    const auto begin = text.rfind("<DataSet", at), end = text.find('\n', at);
    text.erase(begin, end - begin + 1);
    std::ofstream(vtk / "r.pvd") << text;
  }
  ASSERT_EQ(read_pvd(vtk / "r.pvd").size(), 3u);
  auto ctx = make_context(dir.path(), "r");
  ctx.start_time = 0.1;
  auto w = make_writer("type vtk;", ctx);
  w->write(two_bodies(0.1, 1));  // the restart's first write (the series is repaired before it)
  const auto series = read_pvd(vtk / "r.pvd");
  ASSERT_EQ(series.size(), 4u);
  EXPECT_EQ(series[3].file, "r_3.vtp");
  EXPECT_NEAR(series[3].time, 0.3, 1e-9);
  EXPECT_TRUE(fs::exists(vtk / "r_3.vtp"));
}

// The temporaries write_file_atomically makes are recognised by the one function the
// clean-ups use, and nothing else is: a user's hidden file, or one named like a temporary
// but not hidden, stays.
TEST(AtomicFiles, TheTemporariesOfWriteFileAtomicallyAndNothingElse) {
  const fs::path dir = fs::temp_directory_path() / ("scree_atomic_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string seen;
  scree::write_file_atomically(dir / "1.126.csv", [&](const fs::path& tmp) {
    seen = tmp.filename().string();
    std::ofstream(tmp) << "x\n";
  });
  EXPECT_EQ(scree::atomic_temporary_target(seen), "1.126.csv") << seen;
  EXPECT_EQ(scree::atomic_temporary_target(".particles_3.vtp.tmp4375_12"), "particles_3.vtp");
  EXPECT_EQ(scree::atomic_temporary_target(".0.005.ckpt.tmp1_0"), "0.005.ckpt");
  for (const char* other : {".hidden", ".notes.tmp", ".a.tmp12", ".a.tmp_3", ".a.tmpx_3", "a.vtp.tmp1_2", ".tmp1_2", ""})
    EXPECT_EQ(scree::atomic_temporary_target(other), "") << other;
  fs::remove_all(dir);
}
