// Verification of the two-phase formulation (scree/porous/two_phase.hpp) against answers
// known independently of the code: hydrostatics, Terzaghi's consolidation, the conservation
// of the mixture's momentum by the rainfall correction, and the time step of a dry column.
// CPU in CI; with --device=cuda the same on the GPU.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "Rainfall.hpp"
#include "scree/core/constants.hpp"
#include "scree_test.hpp"

namespace scree::test {
namespace {

constexpr double kG = 9.81;

const FieldData& field(const BodySnapshot& b, const char* name) {
  const FieldData* f = b.find(name);
  if (!f) throw std::runtime_error(std::string("no field ") + name);
  return *f;
}

/// The seed's soil (Table A, K_sat 2e-4 m/s), hydrostatic above a water table at the base,
/// and rain of 5e-4 m/s on the top of a 1.05 m column: the infiltration case's reading.
const char* const kSeedSoil =
    "porosity 0.33; liquidDensity 1000; liquidBulkModulus 2e8; viscosity 1e-3; hydraulicConductivity 2e-4; "
    "retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } "
    "permeability { type mualemVanGenuchten; } initialPorePressure { type hydrostatic; waterTable 0; }";
const char* const kRainOnTop = "rain { type rainfall; box { min (-1 1.0); max (1 1.2); } intensity 5e-4; unit m/s; }";

/// A column of two-phase soil, width w, height H, cells h, between slip walls on a fixed
/// (impermeable) base; `two_phase` is the body's twoPhase block.
void write_column(const TempCase& tc, double w, double H, double top, double h, const std::string& two_phase,
                  const std::string& extra_bodies = "", const std::string& extra_bcs = "",
                  const std::string& materials = "soil { type linearElastic; E 1e6; nu 0; rho 2650; }",
                  const std::string& shape = "linear") {
  tc.write("system/controlDict", "endTime 1; deltaT 1e-3; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; "
                                 "writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (" + std::to_string(w) + " " + std::to_string(top) +
                                  "); cellSize " + std::to_string(h) + ";");
  tc.write("system/mpmSchemes", "updateScheme USL; shapeFunction " + shape + ";");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", materials);
  // The column starts under its own weight alone (overburden body): a body put on it (the
  // plate of Terzaghi's problem) is a load applied at t = 0, not part of the initial state.
  tc.write("constant/bodies", "column { material soil; region { type rectangle; lower (0 0); upper (" +
                                  std::to_string(w) + " " + std::to_string(H) +
                                  "); } initialStress { type geostatic; K0 0; overburden body; } twoPhase { " +
                                  two_phase + " } } " + extra_bodies);
  tc.write("constant/boundaryConditions",
           "base { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; } " +
               extra_bcs);
}

// ---------------------------------------------------------------------------------
// A saturated column with its water table at the surface (ponded: the surface is open), started
// in the equilibrium of
// its own weight (geostatic effective stress, hydrostatic pore pressure), stays there:
// p_w = rho_l g depth within 1% (the acceptance bound; the discrete equilibrium of a
// uniform column is exact up to round-off), and both phases at rest.
TEST(TwoPhase, HydrostaticSaturatedColumn) {
  TempCase tc("hydrostatic");
  const double H = 1.0;
  write_column(tc, 0.1, H, H, 0.05,
               "porosity 0.4; liquidBulkModulus 2e8; hydraulicConductivity 1e-3; "
               "initialPorePressure { type hydrostatic; waterTable 1.0; }",
               "", "pond { type ponding; face yMax; }");
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  sim.advance_to(0.05);
  Snapshot s = sim.snapshot();
  const BodySnapshot& b = s.bodies.at(0);
  const FieldData &p = field(b, "porePressure"), &vs = field(b, "velocity"), &vl = field(b, "liquidVelocity");
  double worst = 0, vmax = 0;
  for (Index i = 0; i < b.n; ++i) {
    const double depth = H - b.position[3 * i + 1];
    const double exact = 1000 * kG * depth;
    worst = std::max(worst, std::fabs(p.values[i] - exact) / (1000 * kG * H));
    for (int d = 0; d < 2; ++d)
      vmax = std::max({vmax, std::fabs(vs.values[3 * i + d]), std::fabs(vl.values[3 * i + d])});
  }
  EXPECT_LT(worst, 0.01) << "pore pressure against rho_l g depth, relative to its value at the base";
  EXPECT_LT(vmax, 1e-6) << "m/s: the column must stay at rest";
}

// ---------------------------------------------------------------------------------
// Layers start under the weight of what lies above them (initialStress geostatic, overburden
// all): a dry single-phase layer (rho 1600, 0.2 m) on a saturated two-phase layer (rho_s
// 2000, n0 0.3: mixture (1 - n0) rho_s + n0 rho_l = 1700, 0.5 m) on another (rho_s 2650, n0
// 0.4: 1990, 1 m), the water table at the top of the two-phase layers (y = 1.5). The total
// vertical stress is -g sum rho_i t_i over the layers above, the pore pressure rho_l g (1.5 -
// y), and the effective stress sigma' = sigma + S_l p_w with S_l = 1 (Bishop), its horizontal
// part K0 sigma'_v. Every layer's faces lie on sub-cell edges (multiples of 0.025 m) and the
// densities are constant, so the column sums are the integrals to round-off: 1e-9 of the
// largest stress (3.7e4 Pa).
TEST(TwoPhase, LayersStartUnderTheWeightOfTheirMixturesAbove) {
  TempCase tc("layers");
  tc.write("system/controlDict", "endTime 1; deltaT 1e-4; writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.1 2); cellSize 0.05;");
  tc.write("system/mpmSchemes", "updateScheme USL;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "low { type linearElastic; E 1e7; nu 0.3; rho 2650; } "
                                          "mid { type linearElastic; E 1e7; nu 0.3; rho 2000; } "
                                          "dry { type linearElastic; E 1e7; nu 0.3; rho 1600; }");
  const std::string water = "liquidBulkModulus 2e8; hydraulicConductivity 1e-3; "
                            "initialPorePressure { type hydrostatic; waterTable 1.5; }";
  tc.write("constant/bodies",
           "low { material low; region { type rectangle; lower (0 0); upper (0.1 1); } "
           "initialStress { type geostatic; K0 0.5; } twoPhase { porosity 0.4; " + water + " } } "
           "mid { material mid; region { type rectangle; lower (0 1); upper (0.1 1.5); } "
           "initialStress { type geostatic; K0 0.5; } twoPhase { porosity 0.3; " + water + " } } "
           "dry { material dry; region { type rectangle; lower (0 1.5); upper (0.1 1.7); } "
           "initialStress { type geostatic; K0 0.5; } }");
  tc.write("constant/boundaryConditions", "base { type fixed; face yMin; }");
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  const Snapshot s = sim.snapshot();
  const double tol = 1e-9 * 3.7e4;
  for (const BodySnapshot& b : s.bodies) {
    const auto& sig = field(b, "stress").values;
    ASSERT_GT(b.n, 0);
    for (Index i = 0; i < b.n; ++i) {
      const double y = b.position[3 * i + 1];
      double total, pw = 0;
      if (b.name == "low") {
        total = -kG * (1600 * 0.2 + 1700 * 0.5 + 1990 * (1 - y));
        pw = 1000 * kG * (1.5 - y);
      } else if (b.name == "mid") {
        total = -kG * (1600 * 0.2 + 1700 * (1.5 - y));
        pw = 1000 * kG * (1.5 - y);
      } else {
        total = -kG * 1600 * (1.7 - y);
      }
      const double eff = total + pw;
      ASSERT_NEAR(sig[6 * i + 1], eff, tol) << b.name << " at y = " << y;
      ASSERT_NEAR(sig[6 * i + 0], 0.5 * eff, tol) << b.name << " at y = " << y;
      if (b.name != "dry") ASSERT_NEAR(field(b, "porePressure").values[i], pw, tol);
    }
  }
}

// ---------------------------------------------------------------------------------
// The same with unsaturated layers, whose mixture's density varies with the suction: two
// two-phase layers (rho_s 2650, n0 0.4, 0-1 m; rho_s 2000, n0 0.3, 1-2 m), van Genuchten
// S_l(s) = S_min + (S_max - S_min) [1 + (s/p0)^(1/(1-lambda))]^-lambda (p0 1e4 Pa, lambda 0.5,
// S_min 0.1, S_max 1), the water table at y = 0.5 (suction up to 14.7 kPa at the top, S_l
// down to 0.56). Analytic, with p_w(z) = rho_l g (0.5 - z) and S_l(p_w) from the formula:
//   sigma_v(y) = -g int_y^2 [(1 - n0(z)) rho_s(z) + n0(z) S_l(p_w(z)) rho_l] dz,
//   sigma'_v = sigma_v + S_l p_w,  sigma'_h = K0 sigma'_v,
// integrated here by Simpson's rule in steps of 0.1 mm. The code takes S_l from its table,
// within 1e-5 of the curve, and integrates in steps of at most 1 mm: at most n0 rho_l g 1e-5
// 2 m + 1e-5 p_w, about 0.3 Pa; tolerance 1 Pa (a sub-cell of the overburden missing would be
// over 400 Pa).
TEST(TwoPhase, UnsaturatedLayersStartUnderTheWeightOfTheirMixturesAbove) {
  TempCase tc("unsaturated_layers");
  tc.write("system/controlDict", "endTime 1; deltaT 1e-4; writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.1 2.2); cellSize 0.05;");
  tc.write("system/mpmSchemes", "updateScheme USL;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "low { type linearElastic; E 1e7; nu 0.3; rho 2650; } "
                                          "high { type linearElastic; E 1e7; nu 0.3; rho 2000; }");
  const std::string water = "liquidBulkModulus 2e8; hydraulicConductivity 1e-3; "
                            "retention { type vanGenuchten; p0 1e4; lambda 0.5; Smin 0.1; Smax 1; } "
                            "initialPorePressure { type hydrostatic; waterTable 0.5; }";
  tc.write("constant/bodies",
           "low { material low; region { type rectangle; lower (0 0); upper (0.1 1); } "
           "initialStress { type geostatic; K0 0.5; } twoPhase { porosity 0.4; " + water + " } } "
           "high { material high; region { type rectangle; lower (0 1); upper (0.1 2); } "
           "initialStress { type geostatic; K0 0.5; } twoPhase { porosity 0.3; " + water + " } }");
  tc.write("constant/boundaryConditions", "base { type fixed; face yMin; }");
  auto pw_at = [](double z) { return 1000 * kG * (0.5 - z); };
  auto sat = [](double pw) {
    if (pw >= 0) return 1.0;
    return 0.1 + 0.9 * std::pow(1 + std::pow(-pw / 1e4, 1 / (1 - 0.5)), -0.5);
  };
  auto rho_mix = [&](double z) {
    const double n0 = z < 1 ? 0.4 : 0.3, rho_s = z < 1 ? 2650 : 2000;
    return (1 - n0) * rho_s + n0 * sat(pw_at(z)) * 1000;
  };
  auto overburden = [&](double y) {  // int_y^2 rho_mix dz, Simpson on each layer apart
    auto simpson = [&](double a, double b) {
      if (!(b > a)) return 0.0;
      const int n = 2 * static_cast<int>(std::ceil((b - a) / 2e-4));
      const double dz = (b - a) / n;
      double sum = rho_mix(a) + rho_mix(b - 1e-12);
      for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * rho_mix(a + i * dz);
      return sum * dz / 3;
    };
    return y < 1 ? simpson(y, 1 - 1e-12) + simpson(1, 2) : simpson(y, 2);
  };
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  const Snapshot s = sim.snapshot();
  double worst = 0;
  for (const BodySnapshot& b : s.bodies) {
    const auto& sig = field(b, "stress").values;
    const auto& p = field(b, "porePressure").values;
    ASSERT_GT(b.n, 0);
    for (Index i = 0; i < b.n; ++i) {
      const double y = b.position[3 * i + 1], pw = pw_at(y);
      const double eff = -kG * overburden(y) + sat(pw) * pw;
      ASSERT_NEAR(p[i], pw, 1e-9 * 1e4) << b.name << " at y = " << y;
      ASSERT_NEAR(sig[6 * i + 1], eff, 1.0) << b.name << " at y = " << y;
      ASSERT_NEAR(sig[6 * i + 0], 0.5 * eff, 1.0) << b.name << " at y = " << y;
      worst = std::max(worst, std::fabs(sig[6 * i + 1] - eff));
    }
  }
  std::printf("largest |sigma'_v - analytic| %.3g Pa\n", worst);
}

// ---------------------------------------------------------------------------------
// cases/rainfallSlope draws its slope as one polygon tracing a staircase of whole cells, and
// its variants/columns as the staircase's 18 rectangles, one body per column (makeBodies.py),
// each of which alone would start from its own top. The two make the same
// points (the staircase's corners lie on sub-cell edges, so every point is inside one region
// or the other alike), and with the overburden of the material above each point they start
// from the same state: the same pore pressure and saturation (the same formula at the same
// places, to the bit), and the same stress. The stresses differ only by the quadrature of
// the mixture's density, a 1 mm midpoint table laid from each body's lowest point
// (measured: 1.2e-5 Pa of 31.6 kPa); a column's material off by one sub-cell would be
// rho_mix g s/2, over 400 Pa. Tolerance 1 Pa: far above the quadrature, far below any error
// of the overburden.
TEST(TwoPhase, RainfallSlopeAsOnePolygonStartsAsItsEighteenColumns) {
  TempCase shipped("slope_shipped");
  copy_case(std::filesystem::path(SCREE_SOURCE_DIR) / "cases/rainfallSlope", shipped.dir());
  const std::filesystem::path polygon = shipped.dir(), columns = shipped.dir() / "variants/columns";
  struct Point {
    double sigma[6], pw, sat;
  };
  auto initial = [](const std::filesystem::path& dir, std::size_t& bodies) {
    Case cs = Case::read(dir, runtime());
    Simulation sim(cs, runtime(), options());
    const Snapshot s = sim.snapshot();
    bodies = s.bodies.size();
    std::map<std::pair<long, long>, Point> out;  // by position, in micrometres
    for (const BodySnapshot& b : s.bodies) {
      const auto &sig = field(b, "stress").values, &pw = field(b, "porePressure").values,
                 &sat = field(b, "saturation").values;
      for (Index i = 0; i < b.n; ++i) {
        Point p;
        for (int c = 0; c < 6; ++c) p.sigma[c] = sig[6 * i + c];
        p.pw = pw[i];
        p.sat = sat[i];
        out[{std::lround(b.position[3 * i] * 1e6), std::lround(b.position[3 * i + 1] * 1e6)}] = p;
      }
    }
    return out;
  };
  std::size_t nc = 0, np = 0;
  const auto a = initial(columns, nc), b = initial(polygon, np);
  EXPECT_EQ(nc, 18u);
  EXPECT_EQ(np, 1u);
  ASSERT_EQ(a.size(), b.size());
  double worst = 0, largest = 0;
  for (const auto& [at, p] : a) {
    const auto q = b.find(at);
    ASSERT_NE(q, b.end()) << "no point of the polygon at (" << at.first * 1e-6 << " " << at.second * 1e-6 << ")";
    EXPECT_EQ(p.pw, q->second.pw);
    EXPECT_EQ(p.sat, q->second.sat);
    for (int c = 0; c < 6; ++c) {
      ASSERT_NEAR(p.sigma[c], q->second.sigma[c], 1.0) << "component " << c;
      worst = std::max(worst, std::fabs(p.sigma[c] - q->second.sigma[c]));
      largest = std::max(largest, std::fabs(p.sigma[c]));
    }
  }
  std::printf("%zu points: largest |sigma_columns - sigma_polygon| %.3g Pa of %.4g Pa\n", a.size(), worst, largest);
}

// ---------------------------------------------------------------------------------
// Terzaghi's 1D consolidation: a saturated elastic column (E_oed = E, nu = 0) of height H on
// an impermeable base, drained at its top (`ponding`: the surface open), loaded at t = 0 by a stiff plate of weight q per
// unit width. The excess pore pressure u = p_w - rho_l g (H - y) follows (Terzaghi 1943;
// Verruijt, Soil Mechanics, ch. 15, with the liquid's compressibility in the storage):
//   u(z, t) = B q sum_m (2/M) sin(M z/H) exp(-M^2 T_v),  M = (2m+1) pi/2,  z = H - y,
//   T_v = c_v t / H^2,  c_v = K / (gamma_w (m_v + n/K_l)),  m_v = 1/E_oed,
//   B = m_v / (m_v + n/K_l)  (the undrained share of the load the liquid takes).
// Tolerance: 5% of q after the first wave transient (T_v >= 0.02), the acceptance bound.
// Measured, the largest error sits at the point next to the drained top (where the analytic
// gradient is steepest): with linear shape functions 3.9% at T_v = 0.02 and 3.0% at 0.1 at
// h = 0.025 m (6.0% and 4.0% at h = 0.05: it converges with h); but once the settling top
// points cross a cell boundary (T_v ~ 0.35) linear shape functions give a cell-crossing error
// of half of q there. uGIMP (used here) has none: 1.0-1.4% from T_v = 0.05 to 0.5.
// K = 3e-3 m/s keeps the run short (the time to T_v scales with 1/K) while the sudden load's
// wave transient dies before the first reading: T_v = 0.02 comes 33 transits of the P wave
// through the column after the load, and the error there is 2.7% (0.9% at K = 1e-3 with 98
// transits; 32% at K = 1e-2 with 10).
// The settlement of the plate follows the degree of consolidation,
//   s(t) = s_0 + (s_inf - s_0) U(T_v),  U = 1 - sum_m (2/M^2) exp(-M^2 T_v),
//   s_inf = q H / E_oed, s_0 = (1 - B) s_inf, within 5% of s_inf.
TEST(TwoPhase, TerzaghiConsolidation) {
  TempCase tc("terzaghi");
  const double H = 1.0, h = 0.025, w = 0.05, E = 1e6, n = 0.4, Kl = 2e8, K = 3e-3, gw = 1000 * kG;
  const double rho_plate = 10194, t_plate = 0.1, q = rho_plate * kG * t_plate;
  write_column(tc, w, H, 1.2, h,
               "porosity 0.4; liquidBulkModulus 2e8; hydraulicConductivity 3e-3; "
               "initialPorePressure { type hydrostatic; waterTable 1.0; }",
               "load { material plate; region { type rectangle; lower (0 1.0); upper (0.05 1.1); } "
               "initialStress { type geostatic; K0 0; } }",
               "drainedTop { type ponding; box { min (-1 0.99); max (1 1.01); } }", "soil { type linearElastic; E 1e6; nu 0; rho 2650; } plate { type linearElastic; E 1e8; nu 0; rho 10194; }",
               "gimp");
  const double mv = 1 / E, storage = mv + n / Kl, cv = K / (gw * storage), B = mv / storage;
  auto excess = [&](double z, double Tv) {
    double s = 0;
    for (int m = 0; m < 400; ++m) {
      const double M = (2 * m + 1) * kPi / 2;
      s += 2 / M * std::sin(M * z / H) * std::exp(-M * M * Tv);
    }
    return B * q * s;
  };
  auto degree = [&](double Tv) {
    double s = 0;
    for (int m = 0; m < 400; ++m) {
      const double M = (2 * m + 1) * kPi / 2;
      s += 2 / (M * M) * std::exp(-M * M * Tv);
    }
    return 1 - s;
  };
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  const double s_inf = q * H / E, s0 = (1 - B) * s_inf;
  for (double Tv : {0.02, 0.05, 0.1, 0.2, 0.5}) {
    const double t = Tv * H * H / cv;
    sim.advance_to(t);
    Snapshot s = sim.snapshot();
    const BodySnapshot& soil = s.bodies.at(0);
    const FieldData& p = field(soil, "porePressure");
    double worst = 0;
    for (Index i = 0; i < soil.n; ++i) {
      const double y = soil.position[3 * i + 1];
      const double u = p.values[i] - gw * (H - y);
      worst = std::max(worst, std::fabs(u - excess(H - y, Tv)) / q);
    }
    EXPECT_LT(worst, 0.05) << "T_v = " << Tv << ": largest |u - u_exact| / q";
    const BodySnapshot& plate = s.bodies.at(1);
    const FieldData& disp = field(plate, "displacement");
    double settle = 0;
    for (Index i = 0; i < plate.n; ++i) settle -= disp.values[3 * i + 1] / plate.n;
    const double exact = s0 + (s_inf - s0) * degree(Tv);
    std::printf("T_v %.2f: worst |u - u_exact| / q %.4f, settlement %.4g m (exact %.4g)\n", Tv, worst, settle, exact);
    EXPECT_NEAR(settle, exact, 0.05 * s_inf) << "T_v = " << Tv << ": settlement of the plate [m]";
  }
}

// ---------------------------------------------------------------------------------
// A saturated block falling from rest, free (no boundary, no support): both phases fall
// together, x(t) = x0 - g t^2 / 2 and v = -g t, and no pore pressure builds (nothing loads
// the mixture). GIMP over 0.1 s, while the block's points cross two cell faces: positions
// within 1e-8 m of the 0.049 m fall, velocities within 1e-7 of their 0.98 m/s, the pore
// pressure within 1e-3 Pa, 1e-6 of the 1.2 kPa the block's weight would put on its base at
// rest (a few times what the cell crossings leave; the linear run below reaches kPa).
// Linear shape functions with USL (two-phase bodies run USL): where the points linger just
// past the first face they cross, the new cell's nodes carry a sliver of the mass and the
// whole pressure gradient; the run stops, and its diagnosis names the cause and what keeps
// it stable. With massTolerance 0.1 (those nodes not accelerated) the block falls to the end,
// every point within 2% of the fall and of the velocity of free fall and its pore pressure
// within 10% of the block's weight at rest: its points lose the weight of the nodes left
// unaccelerated while they cross, which GIMP does not.
/// A saturated block `b` (entries `body`: its region, its velocity) of a soft skeleton, USL
/// on a 1.2 x 0.3 m grid of 0.02 m cells under gravity.
void write_saturated_block(const TempCase& tc, const std::string& control, const std::string& schemes,
                           const std::string& body, const std::string& conditions) {
  tc.write("system/controlDict", control);
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1.2 0.3); cellSize 0.02;");
  tc.write("system/mpmSchemes", "updateScheme USL; " + schemes);
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 1e6; nu 0.3; rho 2000; }");
  tc.write("constant/bodies", "b { material soil; " + body +
                                  " twoPhase { porosity 0.4; liquidBulkModulus 2e6; intrinsicPermeability 1e-10; } }");
  tc.write("constant/boundaryConditions", conditions);
}

void write_falling_block(const TempCase& tc, const std::string& shape, const std::string& schemes = "") {
  write_saturated_block(tc, "endTime 0.1; deltaT 1e-4; writeInterval 1;",  // a Courant number of about 0.3
                        "shapeFunction " + shape + "; " + schemes,
                        "region { type rectangle; lower (0.1 0.1); upper (0.4 0.16); }", "");
}

/// The largest departures of a falling block's points from free fall after 0.1 s.
struct FreeFall {
  double dx = 0, dv = 0, dvl = 0, pmax = 0;  ///< position [m], both phases' velocities [m/s], |p_w| [Pa]
};
FreeFall fall_freely(const std::string& name, const std::string& shape, const std::string& schemes = "") {
  TempCase tc(name);
  write_falling_block(tc, shape, schemes);
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  const BodySnapshot b0 = sim.snapshot().bodies.at(0);
  const double t = 0.1, g = 9.81, dt = 1e-4;
  // The update x^{k+1} = x^k + dt v^{k+1} falls g t dt / 2 further than g t^2 / 2 (5e-5 m
  // here): the exact solution of the discrete equations is x0 - g t (t + dt) / 2.
  const double fall = 0.5 * g * t * (t + dt);
  sim.advance_to(t);
  const BodySnapshot b = sim.snapshot().bodies.at(0);
  const FieldData &v = field(b, "velocity"), &vl = field(b, "liquidVelocity"), &p = field(b, "porePressure");
  std::map<std::int64_t, std::size_t> start;  // the points are sorted as they move: found by id
  for (Index i = 0; i < b0.n; ++i) start[b0.id[static_cast<std::size_t>(i)]] = static_cast<std::size_t>(i);
  FreeFall f;
  for (Index i = 0; i < b.n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i), k0 = start.at(b.id[k]);
    f.dx = std::max({f.dx, std::fabs(b.position[3 * k] - b0.position[3 * k0]),
                     std::fabs(b.position[3 * k + 1] - (b0.position[3 * k0 + 1] - fall))});
    f.dv = std::max({f.dv, std::fabs(v.values[3 * k]), std::fabs(v.values[3 * k + 1] + g * t)});
    f.dvl = std::max({f.dvl, std::fabs(vl.values[3 * k]), std::fabs(vl.values[3 * k + 1] + g * t)});
    f.pmax = std::max(f.pmax, std::fabs(p.values[k]));
  }
  std::printf("%s after %g s: position %.3g m, solid velocity %.3g, liquid velocity %.3g m/s from free fall; |p_w| "
              "%.3g Pa\n",
              name.c_str(), t, f.dx, f.dv, f.dvl, f.pmax);
  return f;
}

TEST(TwoPhase, SaturatedBlockFallsFreely) {
  const FreeFall f = fall_freely("falling_gimp", "gimp");
  EXPECT_LT(f.dx, 1e-8);
  EXPECT_LT(f.dv, 1e-7);
  EXPECT_LT(f.dvl, 1e-7);
  EXPECT_LT(f.pmax, 1e-3);

  TempCase lin("falling_linear");
  write_falling_block(lin, "linear");
  Case cl = Case::read(lin.dir(), runtime());
  Simulation bad(cl, runtime(), options());
  try {
    bad.advance_to(0.1);
    ADD_FAILURE() << "the falling block with linear shape functions ran to the end: the test no longer shows "
                     "the instability it documents";
  } catch (const RunFailure& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("runs USL with linear shape functions"), std::string::npos) << what;
    EXPECT_NE(what.find("two-phase bodies: their pore liquid"), std::string::npos) << what;
    EXPECT_NE(what.find("massTolerance 0.1"), std::string::npos) << what;
    EXPECT_NE(what.find("shapeFunction gimp"), std::string::npos) << what;
  }
}

TEST(TwoPhase, LinearShapesFallWithAMassTolerance) {
  const FreeFall f = fall_freely("falling_linear_mass_tolerance", "linear", "massTolerance 0.1;");
  const double t = 0.1, fall = 0.5 * kG * t * (t + 1e-4), weight = (0.6 * 2000 + 0.4 * 1000) * kG * 0.06;
  EXPECT_LT(f.dx, 0.02 * fall);
  EXPECT_LT(f.dv, 0.02 * kG * t);
  EXPECT_LT(f.dvl, 0.02 * kG * t);
  EXPECT_LT(f.pmax, 0.1 * weight) << "Pa";
}

// A saturated block (0.3 x 0.06 m, closed surface) sliding at 2 m/s on a slip floor for 0.2 s,
// USL at maxCo 0.5. With linear shape functions it blows up as its points cross cell faces;
// with massTolerance 0.1 it slides to the end. Nothing acts on it along x (the
// floor holds only the normal), so its mean velocity stays 2 m/s: the skeleton's within 1e-6
// of it with GIMP (the drag trades a little momentum with the liquid), within 1e-3 with the
// mass tolerance (the nodes left unaccelerated drop their share of the internal forces, whose
// sum is zero); its
// pore pressure under its own weight, the mean over the bottom row of points, within 5% of
// the same run with GIMP (an independent discretisation, exact on the mean velocity).
/// The mean horizontal velocity, the spread of the points' horizontal velocities, the
/// largest pore pressure and the bottom row's mean pore pressure.
struct Slide {
  bool finished = false;
  double mean_vx = 0, spread_vx = 0, pmax = 0, base_p = 0;
};
Slide slide(const std::string& name, const std::string& shape, const std::string& schemes) {
  TempCase tc(name);
  write_saturated_block(tc, "endTime 0.2; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; writeInterval 1;",
                        "shapeFunction " + shape + "; " + schemes,
                        "velocity (2 0); region { type rectangle; lower (0.1 0); upper (0.4 0.06); }",
                        "floor { type slip; face yMin; }");
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  Slide r;
  try {
    sim.advance_to(0.2);
  } catch (const RunFailure&) {
    return r;
  }
  r.finished = true;
  const BodySnapshot b = sim.snapshot().bodies.at(0);
  const FieldData &v = field(b, "velocity"), &p = field(b, "porePressure");
  double lo = 1e300, hi = -1e300, sum = 0, nb = 0;
  for (Index i = 0; i < b.n; ++i) {
    const double vx = v.values[3 * i];
    r.mean_vx += vx / b.n;
    lo = std::min(lo, vx);
    hi = std::max(hi, vx);
    r.pmax = std::max(r.pmax, std::fabs(p.values[i]));
    if (b.position[3 * i + 1] < 0.01) sum += p.values[i], ++nb;
  }
  r.spread_vx = hi - lo;
  r.base_p = nb > 0 ? sum / nb : 0;
  std::printf("%s: finished %d, mean vx %.12g m/s, spread %.3g m/s, |p_w| max %.4g Pa, base row mean %.4g Pa\n",
              name.c_str(), r.finished, r.mean_vx, r.spread_vx, r.pmax, r.base_p);
  return r;
}

TEST(TwoPhase, LinearShapesSlideWithAMassTolerance) {
  const Slide g = slide("slide_gimp", "gimp", "");
  const Slide l = slide("slide_linear", "linear", "");
  const Slide m = slide("slide_linear_mass_tolerance", "linear", "massTolerance 0.1;");
  ASSERT_TRUE(g.finished && m.finished);
  EXPECT_FALSE(l.finished) << "the linear block slid to the end: the test no longer shows the instability it documents";
  EXPECT_NEAR(g.mean_vx, 2, 1e-6);
  EXPECT_NEAR(m.mean_vx, 2, 1e-3);
  EXPECT_NEAR(m.base_p, g.base_p, 0.05 * std::fabs(g.base_p)) << "Pa";
}

// ---------------------------------------------------------------------------------
// A dry-ish column (a water table 20 m below its base: S_l below 0.24 against S_min = 0.23,
// Mualem's k_rel below 1e-7) with a hydraulic conductivity of 1e-7 m/s: an explicit drag would limit the
// step to about 2 k k_rel / (n g) (4e-8 s at k_rel = 1, less as it dries); the implicit drag
// leaves the acoustic limit alone. The run must take the acoustic step (within 10% of
// maxCo h / c_max) and keep the column at rest with its pore pressure.
TEST(TwoPhase, DryColumnRunsAtTheAcousticStep) {
  TempCase tc("dry");
  const double H = 1.0, h = 0.05;
  write_column(tc, 0.1, H, H, h,
               "porosity 0.33; liquidBulkModulus 2e8; hydraulicConductivity 1e-7; "
               "retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } "
               "permeability { type mualemVanGenuchten; } "
               "initialPorePressure { type hydrostatic; waterTable -20; }",
               "", "", "soil { type linearElastic; E 5e6; nu 0; rho 2700; }");
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  Snapshot s0 = sim.snapshot();
  const double end = 0.02;
  sim.advance_to(end);
  Snapshot s = sim.snapshot();
  const BodySnapshot& b = s.bodies.at(0);
  const FieldData &p = field(b, "porePressure"), &S = field(b, "saturation"), &vs = field(b, "velocity");
  double smax = 0, worst = 0, vmax = 0;
  for (Index i = 0; i < b.n; ++i) {
    smax = std::max(smax, S.values[i]);
    const double y = b.position[3 * i + 1];
    worst = std::max(worst, std::fabs(p.values[i] - 1000 * kG * (-20 - y)) / (1000 * kG * 20));
    vmax = std::max(vmax, std::hypot(vs.values[3 * i], vs.values[3 * i + 1]));
  }
  // van Genuchten at 196-206 kPa of suction (p0 = 22.3 kPa): S_l = 0.2391 at the base.
  EXPECT_LT(smax, 0.24) << "the column stays near its residual saturation (S_min = 0.23)";
  EXPECT_LT(worst, 0.01) << "hydrostatic suction kept";
  EXPECT_LT(vmax, 1e-3) << "m/s";
  // The acoustic step: the undrained wave speed of the unsaturated mixture is dominated by
  // the skeleton here (the retention's storage makes the liquid soft); bound the step count
  // from above by the saturated liquid's speed, the fastest the step may be set by.
  const double rho_mix = (1 - 0.33) * 2700 + 0.33 * 0.23 * 1000;
  const double c_skel = std::sqrt(5e6 / ((1 - 0.33) * 2700));
  const double c_sat = std::sqrt(2e8 / (0.33 * rho_mix));
  const double steps_max = end / (0.5 * h / (c_skel + c_sat)) * 1.1;
  const double explicit_drag_steps = end / 4e-8;
  EXPECT_LT(static_cast<double>(sim.steps()), steps_max) << "steps taken; the explicit drag would need "
                                                          << explicit_drag_steps;
}

// ---------------------------------------------------------------------------------
// Unit-gradient infiltration and the water balance. Rain of w = 5e-3 m/s on a dry column
// (water table 0.5 m below its impermeable base; S_l from 0.72 at the base to 0.31 at the
// top) of K_sat = 1e-2 m/s, van Genuchten p0 = 5 kPa, Mualem. Behind the flux-driven front the
// suction gradient dies out and gravity alone drives the flow: K_sat k_rel(S) = w, so
// S -> S* with k_rel(S*) = 1/2 (S* = 0.9230). The 1D Richards reference (utilities/richards1d,
// the same problem, 200 cells) is still settling at 25 s: S = 0.919 at the surface and 0.916
// at 0.1 m depth. Tolerance 0.012 in S (2% of the rise S* - S_0 = 0.61): that unfinished
// settling (0.007) and the MPM's discretisation (h = 50 mm against a capillary length
// p*/(rho g) of 0.28 m). The skeleton is stiff (E = 50 MPa: volume change 2e-4 against the
// 0.2 of n dS) as the reference's is rigid; K_l = 2 MPa makes the liquid's storage n S/K_l
// 1.6e-7 1/Pa, below 1e-3 of the retention's.
// The water balance: the liquid that entered through the surface (the solver's counter)
// equals the rain w t per unit area (all of it enters: K_sat k_rel(S) >= w until the surface
// saturates, which it does not), and the stored liquid sum rho_l (1 + p/K_l) n S V grows by
// what entered (no outflow: closed base, slip walls), each within 1% (the acceptance bound).
TEST(TwoPhase, UnitGradientInfiltrationKeepsTheWaterBalance) {
  TempCase tc("unit_gradient");
  const double H = 1.0, width = 0.05, w = 5e-3, Ksat = 1e-2, Kl = 2e6, rho_l = 1000, m = 0.671;
  write_column(tc, width, H, 1.1, 0.05,
               "porosity 0.33; liquidBulkModulus 2e6; hydraulicConductivity 1e-2; "
               "retention { type vanGenuchten; p0 5000; lambda 0.671; Smin 0.23; Smax 1; } "
               "permeability { type mualemVanGenuchten; } "
               "initialPorePressure { type hydrostatic; waterTable -0.5; }",
               "", "rain { type rainfall; box { min (-1 0.95); max (1 1.2); } intensity 5e-3; unit m/s; }",
               "soil { type linearElastic; E 5e7; nu 0; rho 2700; }", "gimp");
  // S* from Mualem-van Genuchten: k_rel(S_e) = sqrt(S_e) [1 - (1 - S_e^(1/m))^m]^2 = w / K_sat.
  auto krel = [&](double se) { return std::sqrt(se) * std::pow(1 - std::pow(1 - std::pow(se, 1 / m), m), 2); };
  double lo = 0, hi = 1;
  for (int i = 0; i < 100; ++i) (krel(0.5 * (lo + hi)) < w / Ksat ? lo : hi) = 0.5 * (lo + hi);
  const double S_star = 0.23 + 0.77 * 0.5 * (lo + hi);
  ASSERT_NEAR(S_star, 0.9230, 1e-4);

  auto stored = [&](const BodySnapshot& b) {
    const FieldData &p = field(b, "porePressure"), &S = field(b, "saturation"), &n = field(b, "porosity"),
                    &V = field(b, "volume");
    double W = 0;
    for (Index i = 0; i < b.n; ++i) W += rho_l * (1 + p.values[i] / Kl) * n.values[i] * S.values[i] * V.values[i];
    return W;
  };
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  const double W0 = stored(sim.snapshot().bodies.at(0));
  const double end = 25;
  sim.advance_to(end);
  Snapshot s = sim.snapshot();
  const BodySnapshot& b = s.bodies.at(0);
  const FieldData& S = field(b, "saturation");
  double top = 0;
  for (Index i = 0; i < b.n; ++i) top = std::max(top, b.position[3 * i + 1]);
  int checked = 0;
  for (Index i = 0; i < b.n; ++i) {
    const double depth = top - b.position[3 * i + 1];
    if (depth > 0.15) continue;
    ++checked;
    EXPECT_NEAR(S.values[i], S_star, 0.012) << "S behind the front at depth " << depth << " m";
  }
  EXPECT_GE(checked, 4);
  const auto* surface = b.scalar("liquidInflowSurface");
  const auto* prescribed = b.scalar("liquidInflowPrescribed");
  ASSERT_TRUE(surface && prescribed);
  const double rain = rho_l * w * width * end, gained = stored(b) - W0;
  EXPECT_NEAR(surface->value, rain, 0.01 * rain) << "kg/m: the liquid that entered against the rain";
  EXPECT_NEAR(gained, surface->value + prescribed->value, 0.01 * rain)
      << "kg/m: the stored liquid's gain against what entered";
}

// ---------------------------------------------------------------------------------
// Rain on a soft column takes in the rain and no more (cases/infiltration1D, its K_sat
// 2e-4 m/s reading: Table A's soil, a 1.05 m column of one 25 mm cell's width, uGIMP, 168
// points; here on an impermeable base, so that no liquid leaves). Under a rain of
// w = 5e-4 m/s on soil at 8-10 kPa of suction the surface takes all of it (it could take
// more: the rain correction, eq. B, clips it), and the seepage falls with depth as the soil
// stores the water. As the suction falls the skeleton swells, and the top points' uGIMP
// domains, whose edge sat on the top node row at t = 0, reach into the cell above: the node
// row there takes mass, and must be a surface node like the row below (surface_node). Before
// it was, that node was an open surface at p_w = 0 a hair from the top points in suction and
// pumped water into the top cell. With massTolerance 0 (every node with mass is accelerated:
// the strictest setting; the default, 1e-6 of a point's mass, only waits until the top has
// risen 0.025 mm, 1.1 s into the case on Table A's skeleton) it failed here within
// 0.6 s on both skeletons, also the stiff one (E = 500 MPa: the rise is 100 times smaller,
// but the node's share of div q does not shrink with it): at 0.6 s the top cell's rows took
// +1.7e-3 and -1.3e-3 m/s (E = 5 MPa; -2.0e-3 and +1.7e-5 at 500 MPa), and the column had
// stored 3.2 (2.5) times the rain that fell.
// Checked at 0.6 s, for E = 5 MPa and 500 MPa:
// - the seepage of every point of the top cell (two rows, 6 and 19 mm deep) is downward and
//   at most 1.5 w. While the soil wets, what it stores between the surface and a depth is
//   the difference of the fluxes there: the flux falls from w at the surface, downward, and
//   never exceeds it. The MPM's top row reads 1.07 w (the correction holds w at the nodes;
//   the points lie between them), the second 0.8 w; 1.5 w leaves room for that and is far
//   below the failure (2.6 w down, 3.5 w up);
// - all the rain entered and was stored: the stored liquid sum rho_l (1 + p/K_l) n S V grew
//   by w t (per metre of width) within 2%, and the solver's surface counter agrees within
//   2% (measured 0.5% and 0.003%; the unit-gradient test holds 1% over 25 s, here 0.6 s of
//   rain, 0.3 mm, is stored in the top 50 mm, where the top cell's reconstruction and the
//   swelling's change of n V weigh most).
TEST(TwoPhase, SoftColumnUnderRainTakesTheRainAndNoMore) {
  for (const double E : {5e6, 5e8}) {
    const std::string skeleton = E < 1e7 ? "E = 5 MPa" : "E = 500 MPa";
    TempCase tc(E < 1e7 ? "rain_soft" : "rain_stiff");
    const double H = 1.05, width = 0.025, w = 5e-4, Kl = 2e8, rho_l = 1000, end = 0.6;
    write_column(tc, width, H, 1.1, 0.025,
                 kSeedSoil, "", kRainOnTop,
                 "soil { type linearElastic; E " + std::to_string(E) + "; nu 0; rho 2700; }", "gimp");
    tc.write("system/mpmSchemes", "updateScheme USL; shapeFunction gimp; massTolerance 0;");
    auto stored = [&](const BodySnapshot& b) {
      const FieldData &p = field(b, "porePressure"), &S = field(b, "saturation"), &n = field(b, "porosity"),
                      &V = field(b, "volume");
      double W = 0;
      for (Index i = 0; i < b.n; ++i) W += rho_l * (1 + p.values[i] / Kl) * n.values[i] * S.values[i] * V.values[i];
      return W;
    };
    Case cs = Case::read(tc.dir(), runtime());
    Simulation sim(cs, runtime(), options());
    const double W0 = stored(sim.snapshot().bodies.at(0));
    sim.advance_to(end);
    Snapshot s = sim.snapshot();
    const BodySnapshot& b = s.bodies.at(0);
    const FieldData& q = field(b, "seepageVelocity");
    double top = 0;
    for (Index i = 0; i < b.n; ++i) top = std::max(top, b.position[3 * i + 1]);
    int checked = 0;
    for (Index i = 0; i < b.n; ++i) {
      const double y = b.position[3 * i + 1];
      if (top - y > 0.02) continue;  // the top cell's two rows of points
      ++checked;
      const double qy = q.values[3 * i + 1];
      EXPECT_LE(qy, 0.0) << skeleton << ": seepage [m/s] at y = " << y << " flows up under the rain";
      EXPECT_GE(qy, -1.5 * w) << skeleton << ": seepage [m/s] at y = " << y << " against a rain of " << w;
    }
    EXPECT_EQ(checked, 4) << skeleton;
    const double rain = rho_l * w * width * end, gained = stored(b) - W0;
    const auto* surface = b.scalar("liquidInflowSurface");
    ASSERT_TRUE(surface);
    EXPECT_NEAR(gained, rain, 0.02 * rain) << skeleton << ": kg/m: the stored liquid's gain against the rain";
    EXPECT_NEAR(surface->value, rain, 0.02 * rain) << skeleton << ": kg/m: the liquid that entered against the rain";
  }
}

// Rain that varies in time: the stiff column of the test above under a hyetograph, written
// once as a table in the dictionary and once as a CSV file in mm/h: 2.5e-4 m/s for 0.2 s,
// 5e-4 m/s for 0.2 s, then none. The soil takes all of it (the test above: up to 5e-4 m/s),
// so what entered through the surface is rho_l width int I dt at every time, within the 2%
// of the constant rain above (the step's discretisation of the flux at the surface nodes);
// after the rain stops nothing more enters (within 0.5% of the total: the drainage of the
// surface nodes' last step). The two forms of the same hyetograph give the same inflow to
// round-off (900 mm/h and 2.5e-4 m/s are one double apart at most).
TEST(TwoPhase, RainFollowsItsHyetograph) {
  const double width = 0.025, rho_l = 1000, w1 = 2.5e-4, w2 = 5e-4;
  const std::string table = "((0 2.5e-4) (0.2 5e-4) (0.4 0))";
  double inflow_at[2][3] = {};
  for (int form = 0; form < 2; ++form) {
    TempCase tc(form == 0 ? "hyetograph_table" : "hyetograph_csv");
    const std::string rain =
        form == 0 ? "rain { type rainfall; box { min (-1 1.0); max (1 1.2); } "
                    "intensity { type table; values " + table + "; interpolation step; } }"
                  : "rain { type rainfall; box { min (-1 1.0); max (1 1.2); } unit mm/h; "
                    "intensity { type csvFile; file \"constant/hyetograph.csv\"; interpolation step; } }";
    if (form == 1) tc.write("constant/hyetograph.csv", "t_s,mm_per_h\n0,900\n0.2,1800\n0.4,0\n");
    write_column(tc, width, 1.05, 1.1, 0.025, kSeedSoil, "", rain,
                 "soil { type linearElastic; E 5e8; nu 0; rho 2700; }", "gimp");
    tc.write("system/mpmSchemes", "updateScheme USL; shapeFunction gimp; massTolerance 0;");
    Case cs = Case::read(tc.dir(), runtime());
    Simulation sim(cs, runtime(), options());
    const double times[3] = {0.2, 0.4, 0.6};
    for (int k = 0; k < 3; ++k) {
      sim.advance_to(times[k]);
      Snapshot s = sim.snapshot();
      const auto* surface = s.bodies.at(0).scalar("liquidInflowSurface");
      ASSERT_TRUE(surface);
      inflow_at[form][k] = surface->value;
    }
    const double rain1 = rho_l * width * w1 * 0.2, rain2 = rain1 + rho_l * width * w2 * 0.2;
    const char* f = form == 0 ? "table" : "CSV file";
    std::printf("%s: entered %.6g, %.6g, %.6g kg/m at 0.2, 0.4, 0.6 s against the rain's %.6g, %.6g, %.6g\n", f,
                inflow_at[form][0], inflow_at[form][1], inflow_at[form][2], rain1, rain2, rain2);
    EXPECT_NEAR(inflow_at[form][0], rain1, 0.02 * rain1) << f << ": kg/m entered by 0.2 s";
    EXPECT_NEAR(inflow_at[form][1], rain2, 0.02 * rain2) << f << ": kg/m entered by 0.4 s";
    EXPECT_NEAR(inflow_at[form][2], inflow_at[form][1], 0.005 * rain2) << f << ": kg/m entered after the rain";
  }
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(inflow_at[1][k], inflow_at[0][k], 1e-9 * inflow_at[0][1]);
}

// The rain the surface cannot take is counted. The stiff column above under a rain it takes
// whole (5e-4 m/s) and under one ten times heavier (5e-3 m/s, 25 K_sat): the rain offered
// to the surface nodes (liquidRainOffered) is rho_l w width t, the flat top's share of the
// surface being its width, within the 2% of the tests above; the heavy rain ponds, and what
// the surface did not take (liquidRainNotTaken) is the rest of the rain: offered - not taken
// is what entered through the surface (liquidInflowSurface; the rain is the column's only
// open surface, its base and sides closed). The two are counted by the same formula at the
// top's nodes; the surface count also holds the sides' nodes at the slip walls, whose
// normal flux the walls stop to round-off: they agree within 1e-5 of the rain (measured:
// 1.8e-7 and 1.4e-6). The light rain is taken whole: what is not taken is below 1% of the
// rain (measured: 1e-15). The heavy one leaves a share on the surface, more than 5% of it
// (measured: 27% in 0.3 s; the unsaturated top takes more than K_sat while its suction
// lasts).
// Where and since when it ponds, on the points (rainNotTaken, pondingDuration): under the
// light rain every point reads 0. Under the heavy one the top row reads, at the end, the rain
// less what the surface takes: w - q, q the surface inflow's rate over the last 0.01 s
// (liquidInflowSurface, another kernel's count), within 2% of w (the rate drifts over those
// 0.01 s; measured 0.5%); its pondingDuration is the time since the not-taken total began to
// grow (found to 0.01 s by reading the total every 0.01 s, plus a step either side); the
// points more than two cells below the top, beyond the reach of the surface nodes, read 0.
TEST(TwoPhase, RainTheSurfaceCannotTakeIsCountedAsNotTaken) {
  const double width = 0.025, rho_l = 1000, end = 0.3, H = 1.05, h = 0.025, chunk = 0.01;
  for (const double w : {5e-4, 5e-3}) {
    TempCase tc(w < 1e-3 ? "rain_taken" : "rain_ponds");
    const std::string bc =
        "rain { type rainfall; box { min (-1 1.0); max (1 1.2); } intensity " + std::to_string(w) + "; unit m/s; }";
    write_column(tc, width, H, 1.1, h, kSeedSoil, "", bc, "soil { type linearElastic; E 5e8; nu 0; rho 2700; }",
                 "gimp");
    tc.write("system/mpmSchemes", "updateScheme USL; shapeFunction gimp; massTolerance 0;");
    Case cs = Case::read(tc.dir(), runtime());
    Simulation sim(cs, runtime(), options());
    // The first reading of the not-taken total above round-off (1e-6 of the rain so far)
    // brackets the ponding's start.
    const int chunks = static_cast<int>(std::lround(end / chunk));
    Snapshot s;
    double ponds_after = -1, ponds_by = -1, inflow_before_end = 0;
    for (int k = 1; k <= chunks; ++k) {
      const double t = k < chunks ? k * chunk : end;
      if (k == chunks) inflow_before_end = s.bodies.at(0).scalar("liquidInflowSurface")->value;
      sim.advance_to(t);
      s = sim.snapshot();
      if (ponds_by < 0 && s.bodies.at(0).scalar("liquidRainNotTaken")->value > 1e-6 * rho_l * w * width * t) {
        ponds_after = t - chunk;
        ponds_by = t;
      }
    }
    const BodySnapshot& b = s.bodies.at(0);
    const auto *offered = b.scalar("liquidRainOffered"), *not_taken = b.scalar("liquidRainNotTaken"),
               *inflow = b.scalar("liquidInflowSurface");
    ASSERT_TRUE(offered && not_taken && inflow);
    const double rain = rho_l * w * width * end;
    std::printf("w = %g m/s: rain %.6g kg/m, offered %.6g, not taken %.6g, entered %.6g (offered - not taken %.6g)\n", w,
                rain, offered->value, not_taken->value, inflow->value, offered->value - not_taken->value);
    EXPECT_NEAR(offered->value, rain, 0.02 * rain) << "w = " << w;
    EXPECT_NEAR(offered->value - not_taken->value, inflow->value, 1e-5 * rain) << "w = " << w;
    if (w < 1e-3)
      EXPECT_LT(std::fabs(not_taken->value), 0.01 * rain);
    else
      EXPECT_GT(not_taken->value, 0.05 * rain) << "a rain of 25 K_sat ponds";

    const FieldData &rate = field(b, "rainNotTaken"), &lasted = field(b, "pondingDuration");
    const double q = (inflow->value - inflow_before_end) / (rho_l * width * chunk), dt_max = 1e-3;
    double top_lo = 1e300, top_hi = -1e300, lasted_lo = 1e300, lasted_hi = -1e300, deep = 0;
    for (Index i = 0; i < b.n; ++i) {
      const double y = b.position[3 * i + 1];
      if (y > H - h) {
        top_lo = std::min(top_lo, rate.values[i]);
        top_hi = std::max(top_hi, rate.values[i]);
        lasted_lo = std::min(lasted_lo, lasted.values[i]);
        lasted_hi = std::max(lasted_hi, lasted.values[i]);
      } else if (y < H - 2 * h) {
        deep = std::max({deep, std::fabs(rate.values[i]), std::fabs(lasted.values[i])});
      }
    }
    std::printf("w = %g m/s: the top row's rainNotTaken %.4g-%.4g m/s (w - q = %.4g), pondingDuration %.4g-%.4g s "
                "(the total grew from %.2f-%.2f s), deeper points at most %.3g\n",
                w, top_lo, top_hi, w - q, lasted_lo, lasted_hi, ponds_after, ponds_by, deep);
    EXPECT_EQ(deep, 0) << "w = " << w << ": a point beyond the surface nodes' reach";
    if (w < 1e-3) {
      EXPECT_EQ(top_hi, 0) << "the light rain is taken whole";
      EXPECT_EQ(lasted_hi, 0) << "the light rain is taken whole";
      EXPECT_LT(ponds_by, 0) << "the light rain's not-taken total grew";
    } else {
      ASSERT_GT(ponds_by, 0) << "the heavy rain's not-taken total never grew";
      EXPECT_NEAR(top_lo, w - q, 0.02 * w);
      EXPECT_NEAR(top_hi, w - q, 0.02 * w);
      EXPECT_GE(lasted_lo, end - ponds_by - dt_max);
      EXPECT_LE(lasted_hi, end - ponds_after + dt_max);
    }
  }
}

// ---------------------------------------------------------------------------------
// Water the surface cannot take stands on it (rainfall's pondingDepth), drains into the soil
// as the soil takes it, and runs off beyond the pond's depth. A saturated column (no
// retention curve: S_l = 1), L = 0.5 m of stiff skeleton (E = 50 MPa) of K_sat = 0.1 m/s
// between slip walls, its base drained: the bottom cell held at the water table of the base
// (porePressure), so that the head there is 0 at the cell's centre, h/2 above the base. Its
// top is open (ponding) until t0 = 0.25 s, so that the water flows through it at a steady
// rate (reached after a few times the liquid's relaxation to Darcy's flux, rho_l kappa /
// (n mu_l) = 0.026 s) when the rain begins: R = 2 K_sat for 2 s, then none.
// The soil takes Darcy's flux under the head the pond adds, from the total head L + d at the
// surface to 0 at the held cell's centre, L_e = L - h/2 below it: q = K (L + d) / L_e (the
// pressure per cell pairs with the nodal velocities as a staggered grid, porous/
// pore_gather.hpp: the top node's flux sees the head from the surface to the top cell's
// centre over h/2, the others from centre to centre over h), quasi-steadily (the saturated
// column's storage n/K_l makes its consolidation time L^2 rho_l g n / (K K_l), 1e-5 s). So
// the pond's depth d (water of density rho_l per unit width) follows
//   dd/dt = R - K (L + d) / L_e   while it rains,   dd/dt = -K (L + d) / L_e after,
// from d = 0: d = (R L_e / K - L)(1 - exp(-(t - t0)/tau)), tau = L_e / K, then
// L + d = (L + d_2) exp(-(t - t0 - 2)/tau) until the pond has drained, and the surface
// closes again. Checked every 0.25 s against this law, with the depth measured as the
// points' pond over rho_l and the width, within 1% of the largest depth (0.155 m): the law
// leaves out the liquid's inertia, which lags the flux behind a changing head by the
// relaxation time, q' 0.026 s (an excess depth of 0.5 mm at q' = dq/dt = K/L_e dd/dt; with
// the rain on a column at rest, the flux's start from 0 to q lags by q 0.026 s, 2.7 mm); and
// the points' pondDepth at the top agrees with it to 1e-4 of it (the pond stands level in the
// column).
// The surface's own balance: what it did not take, less what ran off, is the water standing on
// it, the points' pond: within 1e-9 of the rain (the pond moves between points and nodes
// exactly; round-off). With pondingDepth 0.05 m the depth stops at 0.05 m (reached 0.6 s into
// the rain) and the rest runs off at R - K (L + 0.05) / L_e: over the rain's second second,
// within 2% of that rate (measured: 0.01%). The first in 3D too (the column one cell square
// between four slip walls: the same law per unit horizontal area).
TEST(TwoPhase, ThePondDrainsAsDarcySaysAndRunsOffBeyondItsDepth) {
  const double width = 0.05, L = 0.5, h = 0.05, K = 0.1, R = 2 * K, rho_l = 1000, t0 = 0.25, t_rain = 2;
  const double Le = L - h / 2, tau = Le / K;
  const double d_inf = R * Le / K - L;
  auto depth_law = [&](double t) {  // t from the rain's start
    if (t <= 0) return 0.0;
    if (t <= t_rain) return d_inf * (1 - std::exp(-t / tau));
    const double d2 = d_inf * (1 - std::exp(-t_rain / tau));
    return std::max(0.0, (L + d2) * std::exp(-(t - t_rain) / tau) - L);
  };
  const std::string soil = "porosity 0.4; liquidBulkModulus 2e6; hydraulicConductivity 0.1; "
                           "initialPorePressure { type hydrostatic; waterTable 0.5; }";
  const std::string rain = "intensity 0.2; startTime 0.25; endTime 2.25; pondingDepth ";
  for (const auto& [dim, cap] : {std::pair{2, 1.0}, std::pair{2, 0.05}, std::pair{3, 1.0}}) {
    TempCase tc(std::string(cap > 0.5 ? "pond_drains" : "pond_runs_off") + (dim == 3 ? "3D" : ""));
    write_column(tc, width, L, 0.6, h, soil, "", "", "soil { type linearElastic; E 5e7; nu 0; rho 2650; }");
    const std::string bcs = dim == 2 ? "base { type fixed; face yMin; drained yes; } "
                                       "waterTable { type porePressure; min (-1 -1); max (1 0.01); waterTable 0; } "
                                       "left { type slip; face xMin; } right { type slip; face xMax; } "
                                       "open { type ponding; box { min (-1 0.45); max (1 0.6); } endTime 0.25; } "
                                       "rain { type rainfall; box { min (-1 0.45); max (1 0.6); } "
                                     : "base { type fixed; face zMin; drained yes; } "
                                       "waterTable { type porePressure; min (-1 -1 -1); max (1 1 0.01); waterTable 0; } "
                                       "x0 { type slip; face xMin; } x1 { type slip; face xMax; } "
                                       "y0 { type slip; face yMin; } y1 { type slip; face yMax; } "
                                       "open { type ponding; box { min (-1 -1 0.45); max (1 1 0.6); } endTime 0.25; } "
                                       "rain { type rainfall; box { min (-1 -1 0.45); max (1 1 0.6); } ";
    tc.write("constant/boundaryConditions", bcs + rain + std::to_string(cap) + "; }");
    if (dim == 3) {  // the same column, one cell square, z up
      tc.write("system/gridDict", "dimension 3; lower (0 0 0); upper (0.05 0.05 0.6); cellSize 0.05;");
      tc.write("constant/g", "value (0 0 -9.81);");
      tc.write("constant/bodies", "column { material soil; region { type box; lower (0 0 0); upper (0.05 0.05 0.5); } "
                                  "initialStress { type geostatic; K0 0; overburden body; } twoPhase { " + soil + " } }");
    }
    const double area = dim == 2 ? width : width * width;  // the top's horizontal area [m per m; m^2]
    Case cs = Case::read(tc.dir(), runtime());
    Simulation sim(cs, runtime(), options());
    double worst = 0, worst_field = 0, worst_balance = 0, run_off_1 = 0, run_off_2 = 0, largest = 0;
    for (int k = 1; k <= 16; ++k) {
      const double t = 0.25 * k;
      sim.advance_to(t);
      const Snapshot s = sim.snapshot();
      const BodySnapshot& b = s.bodies.at(0);
      const FieldData &pond = field(b, "pond"), &depth = field(b, "pondDepth");
      double ponded = 0, top_depth = 0;
      for (Index i = 0; i < b.n; ++i) {
        ponded += pond.values[i];
        top_depth = std::max(top_depth, depth.values[i]);
      }
      const double d = ponded / (rho_l * area);
      const double not_taken = b.scalar("liquidRainNotTaken")->value, run_off = b.scalar("liquidRunOff")->value;
      const double law = cap > 0.5 ? depth_law(t - t0) : std::min(cap, depth_law(std::min(t - t0, t_rain)));
      largest = std::max(largest, law);
      std::printf("%dD, cap %g m, t = %.2f s: depth %.5f m (law %.5f), top pondDepth %.5f, not taken %.6g kg/m, run off "
                  "%.6g, ponded %.6g\n",
                  dim, cap, t, d, law, top_depth, not_taken, run_off, ponded);
      worst_balance = std::max(worst_balance, std::fabs(not_taken - run_off - ponded));
      if (cap > 0.5) {
        worst = std::max(worst, std::fabs(d - law));
        worst_field = std::max(worst_field, std::fabs(top_depth - d));
      } else if (t - t0 <= t_rain && t - t0 >= 1) {
        worst = std::max(worst, std::fabs(d - cap));
        (t - t0 == 1 ? run_off_1 : run_off_2) = run_off;
      }
    }
    const double rained = rho_l * R * area * t_rain;
    std::printf("%dD, cap %g m: worst depth against the law %.3g m, pondDepth against the depth %.3g m, surface balance %.3g kg/m\n",
                dim, cap, worst, worst_field, worst_balance);
    EXPECT_LT(worst_balance, 1e-9 * rained) << "kg/m: not taken - run off - ponded, cap " << cap << ", " << dim << "D";
    if (cap > 0.5) {
      EXPECT_LT(worst, 0.01 * largest) << "m: the pond's depth against Darcy's law, " << dim << "D";
      EXPECT_LT(worst_field, 1e-4 * largest) << "m: the top points' pondDepth against the pond's, " << dim << "D";
    } else {
      EXPECT_LT(worst, 0.02 * cap) << "m: the pond held at its depth, " << dim << "D";
      const double rate = (run_off_2 - run_off_1) / (rho_l * area * 1.0), law = R - K * (L + cap) / Le;
      std::printf("run-off over 1-2 s: %.5f m/s (law %.5f)\n", rate, law);
      EXPECT_NEAR(rate, law, 0.02 * law) << "m/s: the run-off beyond the pond's depth, " << dim << "D";
    }
  }
}

// ---------------------------------------------------------------------------------
// The liquid's mass balance closes through a drained base. Liquid is conserved: the stored
// liquid sum rho_l (1 + p/K_l) n S_l V changes by what entered through the surfaces (net of
// what left through them) plus what the prescribed pore pressures added, the solver's
// counters liquidInflowSurface and liquidInflowPrescribed; the waterBalance function object
// writes the three and their difference. cases/infiltration1D's ponding reading, coarsened:
// Table A's soft skeleton (E = 5 MPa), kappa = 2e-10 m^2 (K_sat 1.96e-3 m/s), h = 50 mm (84
// points), the top ponded, the base drained with the water table held in the bottom cell
// (porePressure). The water crosses the held cell and leaves: the front reaches the base at
// about 0.5 s, and by 1 s the held cell has taken out 0.038 kg/m, 15% of the stored change.
// At every written time (every 0.1 s) the imbalance is within 0.5% of the liquid that came
// in (the acceptance bound). Measured: 0.16% at 0.1 s falling to 0.075% at 1 s, the scheme's
// own error at the onset of ponding on soil at 10 kPa of suction (the storage linearised
// over a step, C dp against the stored rho_l n S_l(p) V, a residue that shrinks with dt; the
// same with the base closed and nothing held). The held cell's own count must not add to it:
// counted against the nonlinear storage at the unheld pressure (PorePressure), the balance
// was off by 2.1% at 0.1 s and 6.5% at 1 s.
TEST(TwoPhase, WaterBalanceClosesThroughADrainedBase) {
  TempCase tc("balance_drained");
  write_column(tc, 0.05, 1.05, 1.1, 0.05,
               "porosity 0.33; liquidDensity 1000; liquidBulkModulus 2e8; viscosity 1e-3; "
               "intrinsicPermeability 2e-10; "
               "retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } "
               "permeability { type mualemVanGenuchten; } initialPorePressure { type hydrostatic; waterTable 0; }",
               "", "", "soil { type linearElastic; E 5e6; nu 0; rho 2700; }", "gimp");
  tc.write("constant/boundaryConditions",
           "base { type fixed; face yMin; drained yes; } "
           "waterTable { type porePressure; min (-1 -1); max (1 0.01); waterTable 0; } "
           "left { type slip; face xMin; } right { type slip; face xMax; } "
           "pond { type ponding; box { min (-1 1.0); max (1 1.2); } }");
  tc.write("system/controlDict", "endTime 1; deltaT 1e-5; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; "
                                 "writeInterval 0.1; functions { water { type waterBalance; } }");
  Case cs = Case::read(tc.dir(), runtime());
  RunOptions o = options();
  o.output = true;
  Simulation sim(cs, runtime(), o);
  sim.run();

  std::ifstream in(tc.dir() / "postProcessing" / "water" / "waterBalance.csv");
  ASSERT_TRUE(in) << "no postProcessing/water/waterBalance.csv";
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line.rfind("time [s],stored [kg/m],storedChange [kg/m],inflowSurface [kg/m],inflowPrescribed [kg/m]", 0),
            0u) << line;
  int rows = 0;
  double last_prescribed = 0;
  while (std::getline(in, line)) {
    std::vector<double> c;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) c.push_back(std::stod(cell));
    ASSERT_GE(c.size(), 5u) << line;
    const double t = c[0], change = c[2], entered = c[3] + c[4];
    last_prescribed = c[4];
    if (t == 0) continue;
    ++rows;
    EXPECT_GT(entered, 0) << "t = " << t << " s";
    EXPECT_NEAR(change, entered, 0.005 * entered)
        << "t = " << t << " s: stored change against the liquid that came in (surfaces " << c[3]
        << " kg/m, prescribed " << c[4] << " kg/m)";
  }
  EXPECT_EQ(rows, 10);
  // The water crossed the held cell and left (else the base's bookkeeping went untested).
  EXPECT_LT(last_prescribed, -0.02) << "kg/m";
}

// ---------------------------------------------------------------------------------
// A slope whose face cuts the cells diagonally (a polygon, tan beta = 1.5 as
// cases/rainfallSlope), 1.1 m high on a 0.2 m toe, cells of 0.1 m, 2 x 2 points per cell,
// GIMP: a stiff elastic skeleton on a fixed (impermeable) base between slip walls, hydrostatic
// suction above a water table at the base (11 kPa at the crest), the slope's soil (K_sat
// 1e-2 m/s). In 3D the same section extruded one cell deep between slip walls (2 x 2 x 2
// points per cell). `rain`: a rainfall condition's intensity [m/s] over the whole top.
struct InclinedSlope {
  int dimension = 2;
  /// The top's horizontal area: per metre of thickness in 2D, the 0.1 m deep slab's in 3D [m^2].
  double top() const { return dimension == 2 ? 2.0 : 0.2; }
  void write(const TempCase& tc, double end, double rain = 0) const {
    const bool three = dimension == 3;
    tc.write("system/controlDict", "endTime " + std::to_string(end) +
                                       "; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; "
                                       "writeInterval 100;");
    tc.write("system/gridDict", three ? "dimension 3; lower (0 0 0); upper (2.0 0.1 1.4); cellSize 0.1;"
                                      : "dimension 2; lower (0 0); upper (2.0 1.4); cellSize 0.1;");
    tc.write("system/mpmSchemes", "updateScheme USL; shapeFunction gimp;");
    tc.write("constant/g", three ? "value (0 0 -9.81);" : "value (0 -9.81);");
    tc.write("constant/materialProperties", "soil { type linearElastic; E 5e7; nu 0.2; rho 2650; }");
    // An extruded polygon along y takes its points as (z, x).
    const std::string region =
        three ? "type extrudedPolygon; axis y; range (0 0.1); points ((0 0) (0 2) (0.2 2) (0.2 1.5) (1.1 0.9) (1.1 0));"
              : "type polygon; points ((0 0) (2 0) (2 0.2) (1.5 0.2) (0.9 1.1) (0 1.1));";
    tc.write("constant/bodies",
             "slope { material soil; region { " + region + " } particlesPerCell 2; "
             "initialStress { type geostatic; K0 0.5; } "
             "twoPhase { porosity 0.487; liquidDensity 1000; liquidBulkModulus 2e7; viscosity 1e-3; "
             "hydraulicConductivity 1e-2; retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } "
             "permeability { type mualemVanGenuchten; } initialPorePressure { type hydrostatic; waterTable -0.5; } } }");
    std::string bcs = three ? "base { type fixed; face zMin; } left { type slip; face xMin; } right { type slip; face "
                              "xMax; } front { type slip; face yMin; } back { type slip; face yMax; } "
                            : "base { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face "
                              "xMax; } ";
    if (rain > 0)
      bcs += std::string("rain { type rainfall; box { min ") + (three ? "(-1 -1 0.15); max (3 1 2);" : "(-1 0.15); max (3 2);") +
             " } intensity " + std::to_string(rain) + "; unit m/s; }";
    tc.write("constant/boundaryConditions", bcs);
  }
};

double stored_liquid(const BodySnapshot& b, double rho_l, double Kl) {
  const FieldData &p = field(b, "porePressure"), &S = field(b, "saturation"), &n = field(b, "porosity"),
                  &V = field(b, "volume");
  double W = 0;
  for (Index i = 0; i < b.n; ++i) W += rho_l * (1 + p.values[i] / Kl) * n.values[i] * S.values[i] * V.values[i];
  return W;
}

// Without rain the inclined slope is closed everywhere: its stored liquid stays. Nodes whose
// cells the face cuts but which touch no empty cell must be on the surface: left off it they
// are open at p_w = 0 and the suction draws water in through them, about 0.2% of the stored
// liquid a second. Bound: 0.5e-4 of the stored liquid a second (the acceptance's 0.1% over
// 30 s is 0.33e-4 a second over the longer run), far below that fault and far above the
// round-off of the closed surface's balance.
void expect_inclined_face_keeps_its_water(const InclinedSlope& slope, double end) {
  TempCase tc("inclined_dry_" + std::to_string(slope.dimension) + "d");
  const double rho_l = 1000, Kl = 2e7;
  slope.write(tc, end);
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  const double W0 = stored_liquid(sim.snapshot().bodies.at(0), rho_l, Kl);
  sim.advance_to(end);
  const Snapshot s = sim.snapshot();
  const double W = stored_liquid(s.bodies.at(0), rho_l, Kl);
  const auto* surface = s.bodies.at(0).scalar("liquidInflowSurface");
  ASSERT_TRUE(surface);
  std::printf("%dD: stored %.9g kg at 0, %.9g at %g s: change %.3g (%.2g of it); through the surface %.3g\n",
              slope.dimension, W0, W, end, W - W0, (W - W0) / W0, surface->value);
  const double bound = 0.5e-4 * end * W0;
  EXPECT_NEAR(W, W0, bound) << "kg: the stored liquid of a closed slope";
  EXPECT_NEAR(surface->value, 0, bound) << "kg: entered through a closed surface";
}

TEST(TwoPhase, InclinedFaceKeepsItsWaterWithoutRain) { expect_inclined_face_keeps_its_water(InclinedSlope{2}, 2); }
TEST(TwoPhase, InclinedFaceKeepsItsWaterWithoutRain3D) { expect_inclined_face_keeps_its_water(InclinedSlope{3}, 0.5); }

// Rain on the inclined slope, below K_sat (2e-3 m/s against 1e-2: the soil in suction takes
// it whole), over the crest, the face and the toe (the whole top between the slip walls):
// what enters is rho_l w A t with A the surface's horizontal projection (the rain per unit
// horizontal area, eq. C with w . n on each node's share a_I of the surface), within 2% as
// the columns under rain above; and the stored liquid grows by it. Where the soil takes the
// rain whole, each node takes what was offered to it: the not-taken count is within 1e-4 of
// the rain (measured 3.1e-5 in 2D and 6.2e-5 in 3D, not located yet; with the correction's
// normal from the mixture's density, which the saturation along the face tilts off a_I,
// -1.3e-3 in 2D), and no point reads ponding.
void expect_rain_enters_at_the_horizontal_projection(const InclinedSlope& slope, double end) {
  TempCase tc("inclined_rain_" + std::to_string(slope.dimension) + "d");
  const double rho_l = 1000, Kl = 2e7, w = 2e-3;
  slope.write(tc, end, w);
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  const double W0 = stored_liquid(sim.snapshot().bodies.at(0), rho_l, Kl);
  sim.advance_to(end);
  const Snapshot s = sim.snapshot();
  const BodySnapshot& b = s.bodies.at(0);
  const double gained = stored_liquid(b, rho_l, Kl) - W0, rain = rho_l * w * slope.top() * end;
  const auto *surface = b.scalar("liquidInflowSurface"), *offered = b.scalar("liquidRainOffered"),
             *not_taken = b.scalar("liquidRainNotTaken");
  ASSERT_TRUE(surface && offered && not_taken);
  std::printf("%dD: rain %.6g kg: offered %.6g, not taken %.6g, entered %.6g, stored %.6g\n", slope.dimension, rain,
              offered->value, not_taken->value, surface->value, gained);
  EXPECT_NEAR(offered->value, rain, 0.02 * rain) << "kg: the rain offered to the surface";
  EXPECT_NEAR(surface->value, rain, 0.02 * rain) << "kg: entered through the surface";
  EXPECT_NEAR(gained, rain, 0.02 * rain) << "kg: the stored liquid's gain";
  EXPECT_NEAR(not_taken->value, 0, 1e-4 * rain) << "kg: not taken, where the soil takes the rain whole";
  double ponding = 0;
  for (double v : field(b, "pondingDuration").values) ponding = std::max(ponding, v);
  EXPECT_EQ(ponding, 0) << "s: the longest ponding, where the soil takes the rain whole";
}

TEST(TwoPhase, RainOnAnInclinedFaceEntersAtItsHorizontalProjection) {
  expect_rain_enters_at_the_horizontal_projection(InclinedSlope{2}, 1);
}
TEST(TwoPhase, RainOnAnInclinedFaceEntersAtItsHorizontalProjection3D) {
  expect_rain_enters_at_the_horizontal_projection(InclinedSlope{3}, 0.5);
}

// ---------------------------------------------------------------------------------
// A closed mass of soil whose points a collapse has disordered makes no liquid. A saturated
// column of the rainfall slope's sand (SIMSAND, cases/rainfallSlope), 0.25 m wide and
// 0.75 m high against a slip wall, its water table at its top, slumps on an impermeable
// base; every surface is closed, so its stored liquid sum rho_l (1 + p/K_l) n S V changes only
// by what the surface counter says crossed the surface. The points' divergence of the seepage
// sums to the nodal seepage times sum_p V_p grad N_I(x_p) over every node; inside the soil
// that sum is the quadrature of int grad N_I dV = 0, which disordered points miss unless the
// divergence is corrected (porous/pore_gather.hpp), and the seepage that goes on in the heap
// at rest would then make liquid at a steady rate. Checked from 0.4 s (the heap at rest) to
// 1 s: the stored liquid less what crossed the surface changes by at most 1e-5 of the stored
// liquid. What may remain at rest is second order in a step's pressure changes (the storage
// linearised over a step), orders below the bound; the uncorrected divergence exceeds it
// twentyfold. The column is checked to have slumped (its foot moved by more than half a
// cell: the points no longer sit where they were generated).
TEST(TwoPhase, ACollapsedClosedHeapMakesNoLiquid) {
  TempCase tc("closed_heap");
  const double rho_l = 1000, Kl = 2e7;
  tc.write("system/controlDict", "endTime 1; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; "
                                 "writeInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1.2 0.9); cellSize 0.05;");
  tc.write("system/mpmSchemes", "updateScheme USL; shapeFunction gimp; picFraction 1e-3;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties",
           "soil { type simsand; particleDensity 2650; referenceBulkModulus 120; poissonRatio 0.2; "
           "atmosphericPressure 101300; elasticExponent 0.5; criticalFrictionAngle 19.8; "
           "referenceCriticalVoidRatio 0.977; criticalStateLambda 0.0596; criticalStateXi 0.365; "
           "dilatancyConstant 0.7; plasticModulusConstant 0.0044; peakStrengthExponent 2.4; "
           "phaseTransformationExponent 2.9; initialVoidRatio 0.95; integrationTolerance 1e-3; }");
  tc.write("constant/bodies",
           "heap { material soil; region { type rectangle; lower (0 0); upper (0.25 0.75); } particlesPerCell 2; "
           "initialStress { type geostatic; K0 0.5; } "
           "twoPhase { porosity 0.487; liquidDensity 1000; liquidBulkModulus 2e7; viscosity 1e-3; "
           "hydraulicConductivity 1e-2; retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } "
           "permeability { type mualemVanGenuchten; } initialPorePressure { type hydrostatic; waterTable 0.75; } } }");
  tc.write("constant/boundaryConditions",
           "base { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; }");
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  auto unaccounted = [&](const BodySnapshot& b) {
    const auto* surface = b.scalar("liquidInflowSurface");
    if (!surface) throw std::runtime_error("no scalar liquidInflowSurface");
    return stored_liquid(b, rho_l, Kl) - surface->value;
  };
  sim.advance_to(0.4);
  const Snapshot rest = sim.snapshot();
  const double W = stored_liquid(rest.bodies.at(0), rho_l, Kl), before = unaccounted(rest.bodies.at(0));
  sim.advance_to(1.0);
  const Snapshot s = sim.snapshot();
  const BodySnapshot& b = s.bodies.at(0);
  const double after = unaccounted(b);
  double foot = 0;
  for (Index i = 0; i < b.n; ++i) foot = std::max(foot, b.position[3 * i]);
  std::printf("stored %.9g kg/m at 0.4 s; stored less entered: %.9g at 0.4 s, %.9g at 1 s; foot at %.3f m\n", W, before,
              after, foot);
  EXPECT_GT(foot, 0.25 + 0.025) << "m: the heap's foot (the column slumped)";
  EXPECT_NEAR(after, before, 1e-5 * W) << "kg/m: liquid made in the closed heap at rest";
}

// ---------------------------------------------------------------------------------
// A run reproduces itself bit for bit on one CPU thread, however its steps are grouped into
// chunks between the host's checks (progressInterval: 1 step, or up to 1000). How many steps
// idle on a target time (dt = 0) depends on where a chunk ends, i.e. on the wall clock in an
// automatic progressInterval; such a step must change nothing. It did: an idle step still
// measured the pore liquid's signal speed, the clock kept it, and the step after each
// target came from it (the VTK frames of cases/rainfallSlope differed at 1e-10 run to run).
// The soft column under rain with an adaptive step, ten targets: every point's position and
// every field compared exactly.
TEST(TwoPhase, RunIsIndependentOfHowItsStepsAreChunked) {
  if (test_device() != Device::cpu) GTEST_SKIP() << "bit-for-bit on one CPU thread only (GPU atomics add in any order)";
  auto run = [](int interval) {
    TempCase tc("chunks_" + std::to_string(interval));
    write_column(tc, 0.025, 1.05, 1.1, 0.025,
                 kSeedSoil, "", kRainOnTop,
                 "soil { type linearElastic; E 5e6; nu 0; rho 2700; }", "gimp");
    tc.write("system/controlDict", "endTime 1; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; maxDeltaT 1e-3; "
                                   "writeInterval 1; progressInterval " + std::to_string(interval) + ";");
    Case cs = Case::read(tc.dir(), runtime());
    Simulation sim(cs, runtime(), options(1));
    for (int k = 1; k <= 10; ++k) sim.advance_to(0.013 * k);
    return sim.snapshot();
  };
  const Snapshot a = run(1), b = run(1000);
  ASSERT_EQ(a.bodies.size(), 1u);
  ASSERT_EQ(b.bodies.size(), 1u);
  const BodySnapshot &x = a.bodies[0], &y = b.bodies[0];
  ASSERT_EQ(x.n, y.n);
  EXPECT_EQ(a.time, b.time);
  int differ = 0;
  for (std::size_t i = 0; i < x.position.size(); ++i) differ += x.position[i] != y.position[i];
  EXPECT_EQ(differ, 0) << "of " << x.position.size() << " position components differ";
  ASSERT_EQ(x.fields.size(), y.fields.size());
  for (std::size_t f = 0; f < x.fields.size(); ++f) {
    const FieldData &u = x.fields[f], &v = y.fields[f];
    ASSERT_EQ(u.values.size(), v.values.size()) << u.name;
    int n = 0;
    double worst = 0;
    for (std::size_t i = 0; i < u.values.size(); ++i)
      if (u.values[i] != v.values[i]) {
        ++n;
        worst = std::max(worst, std::fabs(u.values[i] - v.values[i]));
      }
    EXPECT_EQ(n, 0) << u.name << ": " << n << " values differ, by up to " << worst;
  }
  for (const auto& sc : x.scalars) {
    const auto* o = y.scalar(sc.name);
    ASSERT_TRUE(o) << sc.name;
    EXPECT_EQ(sc.value, o->value) << sc.name;
  }
}

// ---------------------------------------------------------------------------------
// Two layers of different permeability seep at their series conductance. A saturated column
// (H = 1 m, stiff skeleton, cells h = 0.05 m) of two bodies, K_1 = 1e-3 m/s below y = 0.5 m
// and K_2 = 5e-4 m/s above, an artesian head of 1.2 m held in the bottom cell, a seepage
// face on top: the steady upward Darcy flux through layers in series is
//   q = dh / (L_1 / K_1 + L_2 / K_2),  dh = 0.2 m, L_1 = 0.5 - h (from the held cell's top),
// L_2 = 0.5 m, in both layers alike (1.38e-4 m/s). The bodies' mu / kappa differ, so the
// nodal drag and sum N V are scattered point by point (PorePassParams::drag_per_mass = 0),
// the path a case of one soil does not take. Within 3% after 5 consolidation times H^2 / c_v
// (c_v >= 2.5 m^2/s), as the one-layer seepage test. Measured: 1.357e-4 m/s in both layers
// (1.7% below the series value; the surface a quarter cell above the top points is 1.3%).
TEST(TwoPhase, LayeredColumnSeepsAtTheSeriesConductance) {
  TempCase tc("layers");
  const double H = 1.0, h = 0.05, K1 = 1e-3, K2 = 5e-4;
  const std::string common = "porosity 0.33; liquidBulkModulus 2e8; "
                             "initialPorePressure { type hydrostatic; waterTable 1.0; }";
  write_column(tc, 0.05, 0.5, 1.1, h, common + " hydraulicConductivity 1e-3;",
               "top { material soil; region { type rectangle; lower (0 0.5); upper (0.05 1.0); } "
               "initialStress { type geostatic; K0 0; } twoPhase { " + common + " hydraulicConductivity 5e-4; } }",
               "", "soil { type linearElastic; E 5e7; nu 0; rho 2700; }", "gimp");
  tc.write("constant/boundaryConditions",
           "base { type fixed; face yMin; } left { type slip; face xMin; } right { type slip; face xMax; } "
           "face { type seepageFace; box { min (-1 0.99); max (1 1.01); } } "
           "artesian { type porePressure; min (-1 -1); max (1 0.03); waterTable 1.2; }");
  Case cs = Case::read(tc.dir(), runtime());
  Simulation sim(cs, runtime(), options());
  sim.advance_to(2.0);
  const Snapshot s = sim.snapshot();
  ASSERT_EQ(s.bodies.size(), 2u);
  const double exact = 0.2 / ((0.5 - h) / K1 + (H - 0.5) / K2);
  int checked = 0;
  for (const BodySnapshot& b : s.bodies) {
    const FieldData& q = field(b, "seepageVelocity");
    for (Index i = 0; i < b.n; ++i) {
      const double y = b.position[3 * i + 1];
      // Away from the held cell (the points' seepage oscillates by up to 45% in the three
      // cells above it, +-2% at y = 0.2 m), the top and the interface.
      if (y < 0.3 || y > 0.9 || std::fabs(y - 0.5) < 0.1) continue;
      ++checked;
      EXPECT_NEAR(q.values[3 * i + 1], exact, 0.03 * exact) << b.name << ": upward seepage [m/s] at y = " << y;
    }
  }
  EXPECT_GT(checked, 20);
}

// ---------------------------------------------------------------------------------
// A seepage face lets the liquid out, never in. A saturated column (H = 1 m, K = 1e-3 m/s,
// stiff skeleton, cells h = 0.05 m) on an impermeable base; a porePressure condition holds
// the head in the bottom cell (its box cuts the cell: the whole cell is held), a seepage
// face on top.
// 1. Artesian base, water table 0.2 m above the top (t < 1 s): the face is open and the
//    liquid flows up and out, Darcy's q = K dh/L with dh = 0.2 m over L = H - h (from the
//    held cell's top face to the surface); the pore pressure falls linearly to zero at the
//    top. Within 3% of q after 5 consolidation times H^2 / c_v (c_v = 4.6 m^2/s): the
//    transient is then below e^-12 of it, and 3% leaves room for where the open surface
//    sits against the top row of points (a quarter cell: 1.3% of L).
// 2. The base's head drops to 0.6 m (t >= 1 s): the soil at the top goes into suction and
//    the face closes: no water enters, and the column comes to the hydrostatic profile of
//    the new head, p_w = rho g (0.6 - y), suction -3.9 kPa at the top, within 1% of rho g H.
//    A ponded top instead would draw water in and hold p_w near 0 there (checked too).
TEST(TwoPhase, SeepageFaceLetsLiquidOutNeverIn) {
  for (const char* top : {"seepageFace", "ponding"}) {
    TempCase tc(std::string("seepage_") + top);
    const double H = 1.0, K = 1e-3, gw = 1000 * kG, h = 0.05;
    write_column(tc, 0.05, H, 1.1, 0.05,
                 "porosity 0.33; liquidBulkModulus 2e8; hydraulicConductivity 1e-3; "
                 "initialPorePressure { type hydrostatic; waterTable 1.0; }",
                 "", "", "soil { type linearElastic; E 5e7; nu 0; rho 2700; }", "gimp");
    // The base impermeable: the prescribed pore pressure of its row of points is the source
    // (a drained base would add the natural condition p_w = 0 at y = 0 against it).
    tc.write("constant/boundaryConditions",
             "base { type fixed; face yMin; } left { type slip; face xMin; } "
             "right { type slip; face xMax; } face { type " +
                 std::string(top) +
                 "; box { min (-1 0.99); max (1 1.01); } } "
                 "artesian { type porePressure; min (-1 -1); max (1 0.03); waterTable 1.2; endTime 1; } "
                 "lowered { type porePressure; min (-1 -1); max (1 0.03); waterTable 0.6; startTime 1; }");
    Case cs = Case::read(tc.dir(), runtime());
    Simulation sim(cs, runtime(), options());
    sim.advance_to(0.99);
    {
      Snapshot s = sim.snapshot();
      const BodySnapshot& b = s.bodies.at(0);
      const FieldData& q = field(b, "seepageVelocity");
      const double exact = K * 0.2 / (H - h);
      for (Index i = 0; i < b.n; ++i) {
        const double y = b.position[3 * i + 1];
        if (y < 0.3 || y > 0.7) continue;
        EXPECT_NEAR(q.values[3 * i + 1], exact, 0.03 * exact) << top << ": upward seepage [m/s] at y = " << y;
      }
    }
    sim.advance_to(3.0);
    Snapshot s = sim.snapshot();
    const BodySnapshot& b = s.bodies.at(0);
    const FieldData& p = field(b, "porePressure");
    double worst = 0, top_p = -kUnbounded, y_worst = 0;
    for (Index i = 0; i < b.n; ++i) {
      const double y = b.position[3 * i + 1];
      const double e = std::fabs(p.values[i] - gw * (0.6 - y)) / (gw * H);
      if (e > worst) y_worst = y;
      worst = std::max(worst, e);
      if (y > 0.95) top_p = std::max(top_p, p.values[i]);
    }
    if (std::string(top) == "seepageFace") {
      EXPECT_LT(worst, 0.01) << "hydrostatic under the lowered head, the face closed; worst at y = " << y_worst;
    } else {
      EXPECT_GT(top_p, -0.05 * gw * H) << "the pond holds p_w near 0 at the top";
      EXPECT_GT(worst, 0.1) << "the pond draws water in: not hydrostatic";
    }
  }
}

// ---------------------------------------------------------------------------------
// The rainfall correction, eqs. (A)-(E), at one node: afterwards the normal seepage equals
// the rain, n S_l (v_l - v_s) . n = w . n, the mixture's momentum M_s v_s + M_lm v_l is
// unchanged to round-off (D), and where the soil takes less than the rain (B) nothing moves.
TEST(TwoPhase, RainfallCorrectionConservesMixtureMomentum) {
  const double grad[2] = {0.3, 2.0};  // outward: up and a little to the right
  const double ms = 3.7, ml = 1.9, mlm = 0.62, w[2] = {0, -5e-4};
  const double nS = mlm / ml;
  const double len = std::hypot(grad[0], grad[1]), n[2] = {grad[0] / len, grad[1] / len};
  // The soil takes more than the rain: liquid rushing in at 1e-2 m/s relative to the solid.
  double vs[2] = {1e-3, -2e-3}, vl[2] = {1e-3 - 0.01 * n[0], -2e-3 - 0.01 * n[1]};
  const double px = ms * vs[0] + mlm * vl[0], py = ms * vs[1] + mlm * vl[1];
  ASSERT_TRUE((boundary::rainfall_correction<2>(grad, ms, ml, mlm, w, vs, vl)));
  const double seep = nS * ((vl[0] - vs[0]) * n[0] + (vl[1] - vs[1]) * n[1]);
  EXPECT_NEAR(seep, w[0] * n[0] + w[1] * n[1], 1e-15);
  EXPECT_NEAR(ms * vs[0] + mlm * vl[0], px, 1e-15);
  EXPECT_NEAR(ms * vs[1] + mlm * vl[1], py, 1e-15);
  // The soil takes less than the rain (liquid leaving): no correction (B).
  double vs2[2] = {0, 0}, vl2[2] = {0.001 * n[0], 0.001 * n[1]};
  EXPECT_FALSE((boundary::rainfall_correction<2>(grad, ms, ml, mlm, w, vs2, vl2)));
  EXPECT_EQ(vl2[1], 0.001 * n[1]);
  EXPECT_EQ(vs2[1], 0.0);
}

// ---------------------------------------------------------------------------------
// A malformed hydraulic setup is reported with file:line and key before anything runs.
TEST(TwoPhase, MalformedHydraulicSetupIsReported) {
  {
    TempCase tc("bad_retention");
    write_column(tc, 0.1, 1.0, 1.0, 0.05,
                 "porosity 0.33; hydraulicConductivity 1e-4; "
                 "retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.9; Smax 0.5; }");
    try {
      Case::read(tc.dir(), runtime());
      FAIL() << "Smin >= Smax accepted";
    } catch (const InputErrors& e) {
      EXPECT_NE(std::string(e.what()).find("Smin"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("constant/bodies:1"), std::string::npos) << e.what();
    }
  }
  {
    TempCase tc("bad_permeability");
    write_column(tc, 0.1, 1.0, 1.0, 0.05, "porosity 0.33; hydraulicConductivity -1e-4;");
    try {
      Case::read(tc.dir(), runtime());
      FAIL() << "a negative conductivity accepted";
    } catch (const InputErrors& e) {
      EXPECT_NE(std::string(e.what()).find("hydraulicConductivity"), std::string::npos) << e.what();
    }
  }
  {
    // Quadratic B-splines do not keep the liquid's balance at a surface yet: refused, naming
    // the setting.
    TempCase tc("bspline_two_phase");
    write_column(tc, 0.1, 1.0, 1.0, 0.05, "porosity 0.33; hydraulicConductivity 1e-4;", "", "",
                 "soil { type linearElastic; E 1e6; nu 0; rho 2650; }", "bspline2");
    Case cs = Case::read(tc.dir(), runtime());
    try {
      Simulation sim(cs, runtime(), options());
      FAIL() << "a two-phase case with bspline2 accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find("system/mpmSchemes:1"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("linear or gimp"), std::string::npos) << e.what();
    }
  }
  {
    // Rain on a case without a two-phase body.
    TempCase tc("rain_dry_case");
    tc.write("system/controlDict", "endTime 1; deltaT 1e-3; writeInterval 1;");
    tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.1 1); cellSize 0.05;");
    tc.write("system/mpmSchemes", "updateScheme USL;");
    tc.write("constant/g", "value (0 -9.81);");
    tc.write("constant/materialProperties", "soil { type linearElastic; E 1e6; nu 0; rho 2000; }");
    tc.write("constant/bodies", "column { material soil; region { type rectangle; lower (0 0); upper (0.1 1); } }");
    tc.write("constant/boundaryConditions", "rain { type rainfall; face yMax; intensity 10; unit mm/h; }");
    Case cs = Case::read(tc.dir(), runtime());
    try {
      Simulation sim(cs, runtime(), options());
      FAIL() << "rain on a single-phase case accepted";
    } catch (const InputErrors& e) {  // found by the setup check, which --check runs too
      EXPECT_NE(std::string(e.what()).find("boundaryConditions:1"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("two-phase"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
