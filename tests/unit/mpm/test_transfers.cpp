// Particle-grid transfers: shape-function identities, and conservation of mass and
// linear momentum by P2G / grid update / G2P on random particle clouds, for every shape
// function, both transfers, in 2D and 3D. Runs on the CPU backend; compiled as
// CUDA (test_transfers_gpu) the same checks run on the GPU.
//
// Exact statements checked (up to round-off, relative 1e-12):
//   sum_I N_I = 1, sum_I N_I x_I = x_p, sum_I grad N_I = 0, sum_I x_I (x) grad N_I = I
//   sum_I m_I = sum_p m_p                          (P2G conserves mass)
//   sum_I p_I = sum_p m_p v_p                      (P2G conserves momentum, APIC too)
//   sum_I f_I = sum_p m_p g                        (internal forces cancel: sum grad N = 0)
//   sum_p m_p v_p' = sum_p m_p v_p + dt sum_p m_p g  (a whole step, FLIP/PIC/APIC)
// and the volume ratio J = prod det(I + L dt) of eq. (8) through a stretch of 1e17.
#include <gtest/gtest.h>

#include <random>

#include "LinearElastic.hpp"
#include "scree/mpm/material_body.hpp"
#include "scree/mpm/grid_update.hpp"
#include "scree_test.hpp"

namespace scree::test {
namespace {

using materials::LinearElastic;

template <class Shape>
void check_shape_identities(const Shape& sh) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(2.0, 7.0);
  for (int k = 0; k < 2000; ++k) {
    const double xi = u(rng);
    int base;
    double w[Shape::kStencil], dw[Shape::kStencil];
    sh.eval(xi, base, w, dw);
    double s = 0, sx = 0, sd = 0, sdx = 0;
    for (int a = 0; a < Shape::kStencil; ++a) {
      EXPECT_GE(w[a], -1e-15);
      s += w[a];
      sx += w[a] * (base + a);
      sd += dw[a];
      sdx += dw[a] * (base + a);  // inv_h = 1: d/dxi
    }
    ASSERT_NEAR(s, 1.0, 1e-13) << "partition of unity at " << xi;
    ASSERT_NEAR(sx, xi, 1e-12) << "linear reproduction at " << xi;
    ASSERT_NEAR(sd, 0.0, 1e-12) << "gradients sum to zero at " << xi;
    ASSERT_NEAR(sdx, 1.0, 1e-12) << "gradient of x is 1 at " << xi;
  }
}

TEST(ShapeFunctions, PartitionOfUnityAndLinearCompleteness) {
  check_shape_identities(ShapeLinear{1.0});
  check_shape_identities(ShapeBspline2{1.0});
  check_shape_identities(ShapeGimp{1.0, 0.25});
  check_shape_identities(ShapeGimp{1.0, 0.5});
  check_shape_identities(ShapeGimp{1.0, 1.0 / 6});
}

template <int D>
struct Cloud {
  GridGeometry<D> grid{};
  Buffer<Real> data[2];
  GridFields<D> sets[2]{};
  Buffer<StepControl> ctl;
  std::unique_ptr<Body<D>> body;
  std::vector<Real> m;
  std::vector<Vec<D>> v;
};

/// The grid (16 cells of 0.1 m per direction) and a step control of step dt; no body yet.
template <int D>
Cloud<D> empty_cloud(double dt) {
  Cloud<D> c;
  const Device dev = test_device();
  c.grid.h = 0.1;
  c.grid.ghost = 2;
  for (int d = 0; d < D; ++d) {
    c.grid.n[d] = 16;
    c.grid.origin[d] = -0.2;
    c.grid.lower[d] = 0;
    c.grid.upper[d] = 1.1;
    c.grid.offset[d] = 0;
  }
  const Index nn = c.grid.num_nodes();
  for (int s = 0; s < 2; ++s) {
    c.data[s].resize(static_cast<std::size_t>(nn) * (1 + 4 * D), dev);
    Real* b = c.data[s].data();
    int k = 0;
    auto next = [&] { return b + static_cast<std::size_t>(k++) * nn; };
    c.sets[s].mass = next();
    for (int d = 0; d < D; ++d) c.sets[s].momentum[d] = next();
    for (int d = 0; d < D; ++d) c.sets[s].force[d] = next();
    for (int d = 0; d < D; ++d) c.sets[s].velocity[d] = next();
    for (int d = 0; d < D; ++d) c.sets[s].velocity_new[d] = next();
  }
  StepControl sc{};
  sc.dt[0] = sc.dt[1] = dt;
  sc.t_target = 1e9;
  sc.dt_max = dt;
  sc.h = c.grid.h;
  c.ctl.resize(1, dev);
  c.ctl.copy_from_host(&sc, 1);
  return c;
}

/// linearElastic, E 1 MPa, nu 0.3, rho 2000 kg/m^3.
LinearElastic::Params elastic_params() {
  LinearElastic::Params mp{1e6, 0.3, 2000, 0, 0};
  mp.lambda = mp.E * mp.nu / ((1 + mp.nu) * (1 - 2 * mp.nu));
  mp.G = mp.E / (2 * (1 + mp.nu));
  return mp;
}

/// A 2D FLIP body with linear shape functions on the cloud's grid; the caller adds the points.
BodySetup<2> flip_setup(const Cloud<2>& c, const char* name) {
  BodySetup<2> s;
  s.name = name;
  s.exec = Exec{test_device(), nullptr, 2};
  s.shape = ShapeKind::linear;
  s.transfer = Transfer::flip;
  s.cell_size = c.grid.h;
  return s;
}

/// Pass parameters on the cloud's grid and step control, without gravity.
PassParams<2> pass_params_of(Cloud<2>& c) {
  PassParams<2> pp;
  pp.grid = c.grid;
  pp.control = c.ctl.data();
  pp.physics.gravity = Vec<2>::zero();
  return pp;
}

/// The body's snapshot once the device is done (the cloud's one body).
BodySnapshot snapshot_of(Cloud<2>& c) {
  mem::synchronize(test_device());
  Snapshot snap;
  snap.bodies.resize(1);
  c.body->snapshot(snap.bodies[0]);
  return std::move(snap.bodies[0]);
}

template <int D>
Cloud<D> make_cloud(ShapeKind shape, Transfer transfer, double dt) {
  Cloud<D> c = empty_cloud<D>(dt);
  Exec ex{test_device(), nullptr, 2};
  std::mt19937_64 rng(42 + D);
  std::uniform_real_distribution<double> pos(0.05, 1.05), vel(-1, 1), vol(0.2e-3, 1e-3), sig(-1e4, 1e4);
  BodySetup<D> s;
  s.name = "cloud";
  s.exec = ex;
  s.shape = shape;
  s.gimp_half_length = 0.25;
  s.transfer = transfer;
  s.cell_size = c.grid.h;
  for (int p = 0; p < 500; ++p) {
    Vec<D> x, vv;
    for (int d = 0; d < D; ++d) {
      x[d] = pos(rng);
      vv[d] = vel(rng);
    }
    s.x.push_back(x);
    s.v.push_back(vv);
    s.volume.push_back(vol(rng));
    Sym3 st{{sig(rng), sig(rng), sig(rng), sig(rng), D == 3 ? sig(rng) : 0, D == 3 ? sig(rng) : 0}};
    s.sigma.push_back(st);
  }
  for (int d = 0; d < D; ++d)
    for (int e = 0; e < D; ++e) s.velocity_gradient.a[d][e] = vel(rng);  // APIC: a random affine part
  const LinearElastic::Params mp = elastic_params();
  for (Index p = 0; p < 500; ++p) c.m.push_back(mp.rho * s.volume[p]);
  c.v = s.v;
  c.body = make_material_body<D, LinearElastic>(mp, s);
  return c;
}

template <int D>
std::vector<Real> host(const Real* p, Index n) {
  std::vector<Real> v(n);
  mem::copy(v.data(), Device::cpu, p, test_device(), n * sizeof(Real));
  return v;
}

template <int D>
void conservation(ShapeKind shape, Transfer transfer, Real pic) {
  const double dt = 1e-4;
  Cloud<D> c = make_cloud<D>(shape, transfer, dt);
  Exec ex{test_device(), nullptr, 2};
  Vec<D> g;
  for (int d = 0; d < D; ++d) g[d] = -1.0 - d;
  PassParams<D> pp;
  pp.flags = kScatterMassMomentum | kScatterForce;
  pp.parity = 0;
  pp.gather_parity = 0;
  pp.grid = c.grid;
  pp.gather = c.sets[1];
  pp.scatter = c.sets[0];
  pp.control = c.ctl.data();
  pp.physics.gravity = g;
  pp.physics.pic_fraction = pic;
  pp.physics.transfer = transfer;
  c.body->pass(pp);
  mem::synchronize(ex.device);

  const Index nn = c.grid.num_nodes();
  double M = 0, Mg = 0;
  Vec<D> P = Vec<D>::zero(), Pg = Vec<D>::zero(), Fg = Vec<D>::zero();
  for (Index p = 0; p < 500; ++p) {
    M += c.m[p];
    P += c.m[p] * c.v[p];
  }
  const auto mass = host<D>(c.sets[0].mass, nn);
  for (Real x : mass) Mg += x;
  for (int d = 0; d < D; ++d) {
    for (Real x : host<D>(c.sets[0].momentum[d], nn)) Pg[d] += x;
    for (Real x : host<D>(c.sets[0].force[d], nn)) Fg[d] += x;
  }
  EXPECT_NEAR(Mg / M, 1.0, 1e-12);
  for (int d = 0; d < D; ++d) {
    EXPECT_NEAR(Pg[d], P[d], 1e-12 * M) << "momentum component " << d;
    EXPECT_NEAR(Fg[d], M * g[d], 1e-9 * std::fabs(M * g[d]) + 1e-9) << "force component " << d;
  }

  // Grid update and G2P (velocity and position): momentum after = before + dt M g.
  GridUpdateParams<D> gp;
  gp.modes = kNormalize | kIntegrate;
  gp.grid = c.grid;
  gp.cur = c.sets[0];
  gp.other = c.sets[1];
  gp.control = c.ctl.data();
  grid_update<D>(ex, gp);
  pp.flags = kGatherVelocity | kGatherPosition;
  pp.gather = c.sets[0];
  c.body->pass(pp);
  Snapshot s;
  s.bodies.resize(1);
  c.body->snapshot(s.bodies[0]);
  const auto& vel = s.bodies[0].find("velocity")->values;
  Vec<D> P1 = Vec<D>::zero();
  for (Index p = 0; p < 500; ++p)
    for (int d = 0; d < D; ++d) P1[d] += c.m[p] * vel[3 * p + d];
  for (int d = 0; d < D; ++d)
    EXPECT_NEAR(P1[d], P[d] + dt * M * g[d], 1e-12 * M) << "momentum after a step, component " << d;
}

/// The FLIP/PIC blend's damping against the time step. One cell of 3 x 3 points at
/// xi, eta in {1/6, 1/2, 5/6} (cell coordinates) moving along x with u s_i, s = (1, -2, 1) by
/// column i, at rest otherwise, stress-free, no gravity: sum_p N_I(x_p) m v_p = 0 at every
/// node (sum s = sum s xi = 0, and the bilinear N_I factorises), so the grid sees no motion.
/// FLIP keeps such a mode for ever; the blend v <- a v_PIC + (1 - a) v_FLIP = (1 - a) v
/// removes it, and nothing else happens (L = 0, the points do not move). After a time T in
/// steps dt: v/v0 = (1 - a)^(T/dt) exactly. Returns that ratio from the kernels.
double invisible_mode_left(double dt, double T, double pic_fraction, double pic_rate) {
  Cloud<2> c = empty_cloud<2>(dt);
  BodySetup<2> s = flip_setup(c, "mode");
  const Exec ex = s.exec;
  const double h = c.grid.h, x0 = 0.5, y0 = 0.5, u = 0.3;  // the cell [0.5, 0.6]^2
  const double xi[3] = {1.0 / 6, 0.5, 5.0 / 6}, sgn[3] = {1, -2, 1};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      s.x.push_back(Vec<2>{{x0 + xi[i] * h, y0 + xi[j] * h}});
      s.v.push_back(Vec<2>{{u * sgn[i], 0}});
      s.volume.push_back(h * h / 9);
      s.sigma.push_back(Sym3::zero());
    }
  c.body = make_material_body<2, LinearElastic>(elastic_params(), s);
  PassParams<2> pp = pass_params_of(c);
  pp.physics.pic_fraction = pic_fraction;
  pp.physics.pic_rate = pic_rate;
  GridUpdateParams<2> gp;
  gp.modes = kNormalize | kIntegrate;
  gp.grid = c.grid;
  gp.control = c.ctl.data();
  const int steps = static_cast<int>(std::lround(T / dt));
  for (int n = 0; n < steps; ++n) {
    for (int k = 0; k < 2; ++k) mem::fill_zero(c.data[k].data(), c.data[k].size() * sizeof(Real), ex.device);
    pp.flags = kScatterMassMomentum | kScatterForce;
    pp.gather = c.sets[1];
    pp.scatter = c.sets[0];
    c.body->pass(pp);
    gp.cur = c.sets[0];
    gp.other = c.sets[1];
    grid_update<2>(ex, gp);
    pp.flags = kGatherVelocity | kGatherPosition;
    pp.gather = c.sets[0];
    c.body->pass(pp);
  }
  const BodySnapshot b = snapshot_of(c);
  const auto& vel = b.find("velocity")->values;
  const auto& pos = b.position;
  double ratio = vel[0] / u;
  for (int p = 0; p < 9; ++p) {
    EXPECT_NEAR(vel[3 * p], ratio * u * sgn[p % 3], 1e-12) << "the mode keeps its shape, point " << p;
    EXPECT_NEAR(vel[3 * p + 1], 0, 1e-12) << "no motion across, point " << p;
    EXPECT_NEAR(pos[3 * p], x0 + xi[p % 3] * h, 1e-12) << "the grid saw no motion, point " << p;
  }
  return ratio;
}

TEST(PicBlend, PicRateDampsAModeTheGridCannotSeeAtItsRateWhateverTheStep) {
  // picRate R: the mode decays as exp(-R T) for any dt (a = 1 - exp(-R dt) per step).
  const double R = 10, T = 0.05;
  for (double dt : {1e-3, 5e-4, 1e-4}) {
    const double left = invisible_mode_left(dt, T, 0, R);
    EXPECT_NEAR(left, std::exp(-R * T), 1e-12) << "picRate " << R << ", dt " << dt;
  }
  // picFraction a: (1 - a)^(T/dt), so halving dt doubles the damping rate. The contrast the
  // rate removes: 0.99^50 = 0.605 against 0.99^100 = 0.366.
  const double a = 0.01;
  EXPECT_NEAR(invisible_mode_left(1e-3, T, a, 0), std::pow(1 - a, 50), 1e-12);
  EXPECT_NEAR(invisible_mode_left(5e-4, T, a, 0), std::pow(1 - a, 100), 1e-12);
  // Pure FLIP keeps it.
  EXPECT_NEAR(invisible_mode_left(1e-3, T, 0, 0), 1.0, 1e-12);
}

/// eq. (8) over a long isochoric flow whose principal axes turn: L(t) = Q(t) diag(e, -e)
/// Q(t)^T, Q(t) the rotation by w t, imposed as the affine grid velocity v_I = L (x_I - x_c)
/// (linear shape functions reproduce its gradient exactly). Every step has det(I + L dt) =
/// 1 - e^2 dt^2, so the volume ratio after n steps is (1 - e^2 dt^2)^n exactly (the
/// continuum's J = 1 up to that first-order term), whatever the accumulated stretch. F itself
/// reaches a stretch of 2.3e17 here (e T = 40), where det F computed from F's entries is
/// pure cancellation (2.5e17 instead of 0.992 in double precision): the 10 mm flume's points
/// reached stretches of 1e9 and det F < 0 (cases/flume/README.md, "Why the runs blew up").
TEST(VolumeRatio, IsTheProductOfTheStepsDeterminantsThroughAStretchOf1e17) {
  const double e = 2, w = 0.05, dt = 1e-4, T = 20;
  const int n = static_cast<int>(std::lround(T / dt));
  Cloud<2> c = empty_cloud<2>(dt);
  BodySetup<2> s = flip_setup(c, "stretched");
  const double xc = 0.55, V0 = 0.25e-2;
  for (double dx : {-0.025, 0.025})
    for (double dy : {-0.025, 0.025}) {
      s.x.push_back(Vec<2>{{xc + dx, xc + dy}});
      s.v.push_back(Vec<2>::zero());
      s.volume.push_back(V0);
      s.sigma.push_back(Sym3::zero());
    }
  c.body = make_material_body<2, LinearElastic>(elastic_params(), s);
  PassParams<2> pp = pass_params_of(c);
  pp.flags = kStressFromNew;  // the stress update alone: the points stay where they are
  pp.gather = c.sets[0];
  const Index nn = c.grid.num_nodes();
  std::vector<Real> vx(nn), vy(nn), one(nn, 1.0);
  mem::copy(c.sets[0].mass, test_device(), one.data(), Device::cpu, nn * sizeof(Real));
  for (int k = 0; k < n; ++k) {
    const double a = w * k * dt, co = std::cos(a), si = std::sin(a);
    // Q diag(e, -e) Q^T = e [[cos 2a, sin 2a], [sin 2a, -cos 2a]]
    const double l00 = e * (co * co - si * si), l01 = e * 2 * co * si;
    for (Index I = 0; I < nn; ++I) {
      const Vec<2> x = c.grid.node_position(I);
      vx[I] = l00 * (x[0] - xc) + l01 * (x[1] - xc);
      vy[I] = l01 * (x[0] - xc) - l00 * (x[1] - xc);
    }
    for (Real* dst : {c.sets[0].velocity[0], c.sets[0].velocity_new[0]})
      mem::copy(dst, test_device(), vx.data(), Device::cpu, nn * sizeof(Real));
    for (Real* dst : {c.sets[0].velocity[1], c.sets[0].velocity_new[1]})
      mem::copy(dst, test_device(), vy.data(), Device::cpu, nn * sizeof(Real));
    c.body->pass(pp);
  }
  const BodySnapshot b = snapshot_of(c);
  const auto& vol = b.find("volume")->values;
  const double J = std::pow(1 - e * e * dt * dt, n);  // 0.99203
  // Round-off: n steps of a product and of L's sums, each ~1e-16 relative.
  for (int p = 0; p < 4; ++p) EXPECT_NEAR(vol[p] / V0, J, 1e-9) << "point " << p;
}

class Transfers : public ::testing::TestWithParam<std::tuple<ShapeKind, Transfer, double>> {};

TEST_P(Transfers, ConserveMassAndMomentum2D) {
  const auto [shape, transfer, pic] = GetParam();
  conservation<2>(shape, transfer, pic);
}
TEST_P(Transfers, ConserveMassAndMomentum3D) {
  const auto [shape, transfer, pic] = GetParam();
  conservation<3>(shape, transfer, pic);
}

INSTANTIATE_TEST_SUITE_P(
    AllShapes, Transfers,
    ::testing::Values(std::make_tuple(ShapeKind::linear, Transfer::flip, 0.0),
                      std::make_tuple(ShapeKind::linear, Transfer::flip, 1.0),
                      std::make_tuple(ShapeKind::gimp, Transfer::flip, 0.0),
                      std::make_tuple(ShapeKind::gimp, Transfer::apic, 0.0),
                      std::make_tuple(ShapeKind::bspline2, Transfer::flip, 0.3),
                      std::make_tuple(ShapeKind::bspline2, Transfer::apic, 0.0)));

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()
