// The granular materials in the 3D engine: a plane-strain problem run in 3D, as a slab one cell
// thick between rollers on its z faces, must give the 2D (plane-strain) run. This exercises the
// 3D particle kernels of simsand and phaseTransition (ParticlePass<3, ..., M>: six stored stress
// components, phaseTransition's sigma_f with yz and zx, the 3x3 velocity gradient and spin)
// against the 2D kernels on the same problem: the granular column of Feng et al. (2025, Table 3,
// cases/columnCollapse) at 1 cm cells, geostatic K0 = 0.5, released at once.
//
// Why they must agree: the 3D slab's particles sit in two layers (2 per cell and axis) with the
// 2D particles' (x, y) each; the rollers hold v_z = 0 at both node planes; with linear shape
// functions every nodal value of the 3D grid is then a weighted mean of identical layer values,
// so the in-plane motion and stresses (sigma_zz included) are the 2D ones, and sigma_yz =
// sigma_zx = 0. What differs is the order and number of terms in each nodal sum: round-off,
// which the collapse amplifies where points shear apart and separate. Measured (printed), the
// largest differences over the column relative to each field's largest magnitude: 2e-12 after
// 1000 steps (10 ms after release, |v| up to 0.08 m/s), growing to 6e-7 by 3000 steps as the
// front starts to separate. So 1000 steps, one thread on the CPU (atomics on several threads add
// a run-to-run scatter of the same kind), and a bound of 1e-8 of each field's scale: 4 orders
// above the measured round-off (room for the GPU's differently ordered atomic sums), far below
// any difference in how the 3D kernels treat a plane-strain point (a stress component or a
// state slot stored, loaded or rotated differently: of order 1 in the stress). Lode-angle and
// rotation behaviour off the plane are tested in tests/unit/materials/test_materials_3d.cpp.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "scree_test.hpp"

namespace scree::test {
namespace {

Snapshot collapse(const std::string& material, int dim, int steps) {
  std::ifstream f(std::string(SCREE_SOURCE_DIR) + "/cases/columnCollapse/constant/materialProperties");
  std::stringstream mats;
  mats << f.rdbuf();
  // The substepping tolerance the round-off above was measured with. The case's own, 1e-2,
  // lets a round-off difference flip one of the error control's accept/reject
  // decisions, each worth up to STOL x 100 Pa in the stress: 1e-6-1e-5 of the fields' scales
  // after 1000 steps, a difference of integration paths, not of the 3D kernels.
  mats << "\n#inputMode overwrite\nsand { $sand; integrationTolerance 1e-3; }\nsandFrictional { $sandFrictional; integrationTolerance 1e-3; }\n";
  TempCase tc("slab");
  tc.write("system/controlDict", "endTime 1; deltaT 1e-5; writeInterval 1;");
  tc.write("system/mpmSchemes", "updateScheme USF;");
  tc.write("constant/materialProperties", mats.str());
  const std::string column = "column { material " + material + "; particlesPerCell 2; "
                             "initialStress { type geostatic; K0 0.5; } region { type ";
  if (dim == 2) {
    tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.4 0.12); cellSize 0.01;");
    tc.write("constant/g", "value (0 -9.81);");
    tc.write("constant/bodies", column + "rectangle; lower (0 0); upper (0.2 0.1); } }");
    tc.write("constant/boundaryConditions", "floor { type fixed; face yMin; } leftWall { type slip; face xMin; }");
  } else {
    tc.write("system/gridDict", "dimension 3; lower (0 0 0); upper (0.4 0.12 0.01); cellSize 0.01;");
    tc.write("constant/g", "value (0 -9.81 0);");
    tc.write("constant/bodies", column + "box; lower (0 0 0); upper (0.2 0.1 0.01); } }");
    tc.write("constant/boundaryConditions",
             "floor { type fixed; face yMin; } leftWall { type slip; face xMin; } "
             "back { type slip; face zMin; } front { type slip; face zMax; }");
  }
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options(1));
  sim.run_steps(steps);
  return sim.snapshot();
}

/// The initial (x, y) of a particle, on a 1 um lattice, as a key.
std::pair<long, long> key(const BodySnapshot& b, Index p) {
  const auto& d = field(b, "displacement").values;
  return {std::lround((b.position[3 * p] - d[3 * p]) * 1e6), std::lround((b.position[3 * p + 1] - d[3 * p + 1]) * 1e6)};
}

struct Diff {
  double position = 0, velocity = 0, stress = 0, out_of_plane = 0, z_motion = 0;
  double v_scale = 0, s_scale = 0;
  int matched = 0;
};

Diff compare(const BodySnapshot& a, const BodySnapshot& b) {
  std::map<std::pair<long, long>, Index> index2;
  for (Index p = 0; p < a.n; ++p) index2[key(a, p)] = p;
  const auto &va = field(a, "velocity").values, &vb = field(b, "velocity").values;
  const auto &sa = field(a, "stress").values, &sb = field(b, "stress").values;
  Diff d;
  for (Index p = 0; p < a.n; ++p) {
    for (int c = 0; c < 2; ++c) d.v_scale = std::max(d.v_scale, std::fabs(va[3 * p + c]));
    for (int c = 0; c < 4; ++c) d.s_scale = std::max(d.s_scale, std::fabs(sa[6 * p + c]));
  }
  for (Index q = 0; q < b.n; ++q) {
    const auto it = index2.find(key(b, q));
    if (it == index2.end()) continue;
    const Index p = it->second;
    ++d.matched;
    for (int c = 0; c < 2; ++c) {
      d.position = std::max(d.position, std::fabs(a.position[3 * p + c] - b.position[3 * q + c]));
      d.velocity = std::max(d.velocity, std::fabs(va[3 * p + c] - vb[3 * q + c]));
    }
    d.z_motion = std::max(d.z_motion, std::fabs(vb[3 * q + 2]));
    for (int c = 0; c < 4; ++c) d.stress = std::max(d.stress, std::fabs(sa[6 * p + c] - sb[6 * q + c]));
    d.out_of_plane = std::max({d.out_of_plane, std::fabs(sb[6 * q + 4]), std::fabs(sb[6 * q + 5])});
  }
  return d;
}

void expect_slab_equals_plane_strain(const std::string& material) {
  const int steps = 1000;
  const Snapshot s2 = collapse(material, 2, steps), s3 = collapse(material, 3, steps);
  const BodySnapshot &a = s2.bodies[0], &b = s3.bodies[0];
  ASSERT_EQ(b.n, 2 * a.n) << "two layers of the 2D particles";
  const Diff d = compare(a, b);
  EXPECT_EQ(d.matched, b.n) << "every 3D particle has its 2D twin";
  ASSERT_GT(d.v_scale, 1e-3) << "the column has started to collapse";
  EXPECT_LE(d.velocity, 1e-8 * d.v_scale) << material;
  EXPECT_LE(d.position, 1e-8 * 0.01) << material << " (1e-8 of a cell)";
  EXPECT_LE(d.stress, 1e-8 * d.s_scale) << material << ": sigma_xx, yy, zz, xy";
  EXPECT_LE(d.out_of_plane, 1e-8 * d.s_scale) << material << ": sigma_yz, sigma_zx";
  EXPECT_EQ(d.z_motion, 0.0) << material << ": the rollers hold v_z = 0";
  std::printf("%s, 3D slab vs 2D after %d steps: max |dv| %.2e (of %.3g m/s), |dx| %.2e m, |dsigma| %.2e (of %.4g Pa), "
              "|sigma_yz|, |sigma_zx| %.2e Pa\n",
              material.c_str(), steps, d.velocity, d.v_scale, d.position, d.stress, d.s_scale, d.out_of_plane);
}

TEST(ThreeD, SimsandSlabEqualsPlaneStrain) { expect_slab_equals_plane_strain("sandFrictional"); }
TEST(ThreeD, PhaseTransitionSlabEqualsPlaneStrain) { expect_slab_equals_plane_strain("sand"); }

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
