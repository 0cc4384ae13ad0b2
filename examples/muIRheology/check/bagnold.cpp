// muI-bagnold: verification of the muI material plugin, built out of tree against an
// installed Scree (Scree::scree) like the plugin itself.
//
//   muI-bagnold CASE [--threads N] [--perturb-mu2 F]
//
// 1. Point test through the registry's PointMaterial (the host adapter every registered
//    material gets): steady simple shear at a fixed pressure must give tau = mu(I) p
//    (Jop, Forterre & Pouliquen 2006, eq. 2) at three shear rates; a tensile state must be
//    stress free; a small shear strain below mu_s p must be elastic (tau = G gamma).
//    update_elastic must agree bit for bit with update where it accepts a step (random
//    states; the GPU relies on it, the CPU never takes that path).
// 2. Case test: the steady flow of a layer of depth h down a rough plane inclined at
//    theta, mu_s < tan(theta) < mu_2, has a uniform inertial number and Bagnold's profile
//    (GDR MiDi 2004, Eur. Phys. J. E 14; Jop et al. 2006):
//        I_theta = I0 (tan theta - mu_s) / (mu_2 - tan theta),
//        u(z) = (2/3) (I_theta / d) sqrt(phi g cos theta) [h^{3/2} - (h - z)^{3/2}],
//    z measured from the base. Scree has no periodic boundaries, so the case is a long
//    layer under gravity tilted by theta on a fixed (no-slip) floor, started with the
//    analytic u(z) (Simulation::set_velocities); the check compares the velocity profile
//    in the middle of the layer, away from its two ends, after the case's endTime: the
//    points' velocities averaged over cell-high bins (the first cell above the floor
//    reported only, see below) and the grid's nodal velocities at z = dx, 2 dx, ..., h.
//    The ends are free: their disturbance moves into the layer at the speed of shallow
//    surface waves sqrt(g h cos theta) relative to the flow, so the window is
//        [x0 + (u_s + c_g) T + 2h,  x1 - c_g T - 2h]    (c_g = sqrt(g h cos theta)).
//
// --perturb-mu2 F: simulate with mu2 multiplied by F but compare with the analytic profile
// of the case's own mu2: the check must then fail; the program exits 0 only if it does
// (a test that the check can see a wrong rheology).
//
// Exit status: 0 pass, 1 mismatch, 2 usage or input error.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "../MuIRheology.hpp"
#include "scree/core/constants.hpp"
#include "scree/material/material.hpp"
#include "scree/solver/simulation.hpp"

namespace fs = std::filesystem;
using scree::Real;
using scree::Sym3;

namespace {

struct MuI {
  double mu_s, mu_2, I0, d, rho_s, phi;
  double mu(double I) const { return mu_s + (mu_2 - mu_s) * I / (I0 + I); }
};

MuI read_params(const scree::Dictionary& md) {
  return {md.get_scalar("muS"),          md.get_scalar("mu2"),          md.get_scalar("I0"),
          md.get_scalar("grainDiameter"), md.get_scalar("grainDensity"), md.get_scalar("solidFraction")};
}

double shear_stress(const Sym3& sig) {
  const Sym3 s = scree::deviator(sig);
  return std::sqrt(0.5 * scree::ddot(s, s));
}

// ---- 1. point test ---------------------------------------------------------------------
bool point_test(const scree::Registry& reg, const scree::Dictionary& md, const MuI& m) {
  bool ok = true;
  const double p0 = 100.0;  // [Pa]
  std::printf("point test (PointMaterial, steady simple shear at p = %g Pa):\n", p0);
  const double G = md.has("shearModulus") ? md.get_scalar("shearModulus")
                                          : md.get_scalar("E") / (2 * (1 + md.get_scalar("nu")));
  std::printf("  %10s %12s %12s %12s %10s %10s %10s\n", "rate [1/s]", "I [-]", "tau/p", "mu(I)", "err.solve",
              "err.rate", "tol.rate");
  for (const double rate : {0.5, 5.0, 50.0}) {
    auto pm = reg.make_point_material(md);
    Sym3 sig{{-p0, -p0, -p0, 0, 0, 0}};
    pm->initialise(sig);
    const double dt = 1e-5;
    scree::StrainIncrement inc{};
    inc.deps = Sym3{{0, 0, 0, 0.5 * rate * dt, 0, 0}};  // sym(L) dt for v_x = rate y
    inc.spin = scree::Spin3{0.5 * rate * dt, 0, 0};    // skew(L) dt
    inc.dt = dt;
    inc.J = 1;
    for (int k = 0; k < 20000; ++k) pm->update(sig, inc);
    const double p = scree::pressure(sig), I = rate * m.d / std::sqrt(p / m.rho_s);
    double I_state = -1;  // the inertial number of the plastic shear rate the update solved for
    for (const auto& f : pm->output_fields())
      if (f.name == "inertialNumber") pm->evaluate(f, sig, &I_state);
    const double ratio = shear_stress(sig) / p;
    // The update's own equation tau = mu(I(gammadot_p)) p holds to round-off; at steady state
    // gammadot_p = gammadot but for the co-rotation's O((tau/G)^2) (the stress's rotation
    // by the spin takes part of each increment), so I_state = I within 10 (tau/G)^2.
    const double err_solve = std::fabs(ratio - m.mu(I_state)) / m.mu(I_state);
    const double err_rate = std::fabs(I_state - I) / I;
    const double tau_G = shear_stress(sig) / G;
    std::printf("  %10g %12.6g %12.8f %12.8f %10.2e %10.2e %10.2e\n", rate, I, ratio, m.mu(I), err_solve, err_rate,
                10 * tau_G * tau_G);
    if (!(err_solve < 1e-9) || !(err_rate < 10 * tau_G * tau_G + 1e-9) || !(std::fabs(p - p0) < 1e-9 * p0)) ok = false;
  }
  {  // tension: stress free, and stays so under further expansion
    auto pm = reg.make_point_material(md);
    Sym3 sig{{10, 10, 10, 0, 0, 0}};
    pm->initialise(sig);
    scree::StrainIncrement inc{Sym3{{1e-4, 1e-4, 0, 0, 0, 0}}, scree::Spin3{0, 0, 0}, 1e-5, 1.0002};
    pm->update(sig, inc);
    const bool free = scree::norm(sig) == 0;
    std::printf("  tension: stress free %s\n", free ? "yes" : "NO");
    ok = ok && free;
  }
  {  // below the yield stress: elastic shear, tau = G gamma
    auto pm = reg.make_point_material(md);
    Sym3 sig{{-p0, -p0, -p0, 0, 0, 0}};
    pm->initialise(sig);
    const double gamma = 1e-6;  // engineering shear strain, G gamma << mu_s p
    scree::StrainIncrement inc{Sym3{{0, 0, 0, 0.5 * gamma, 0, 0}}, scree::Spin3{0, 0, 0}, 1e-5, 1};
    pm->update(sig, inc);
    const double err = std::fabs(sig[3] - G * gamma) / (G * gamma);
    std::printf("  elastic shear: sigma_xy / (G gamma) - 1 = %.2e\n", err);
    ok = ok && err < 1e-9;
  }
  std::printf("point test %s\n\n", ok ? "passed" : "FAILED");
  return ok;
}

// ---- 1b. update_elastic against update ------------------------------------------------
// The GPU runs update_elastic first and update only where it declines, so the two must
// agree: when update_elastic accepts a step, bit for bit the result of update; when it
// declines, state and stress untouched. Random stresses near the yield surface, in
// tension and far inside, and random increments (the CPU never takes this path).
bool elastic_path_test(const scree::ParamReader& r) {
  using M = mui_example::MuIRheology;
  const M::Params p = M::read(r);
  std::uint64_t seed = 12345;
  auto rnd = [&seed] {  // uniform in [-1, 1), a fixed sequence (splitmix64)
    seed += 0x9e3779b97f4a7c15ull;
    std::uint64_t z = seed;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) / 4503599627370496.0 - 1.0;
  };
  int accepted = 0, declined = 0, bad = 0;
  for (int k = 0; k < 100000; ++k) {
    const double pr = 100 * rnd() + 20;  // some in tension
    Sym3 sig{{-pr, -pr, -pr, 0, 0, 0}};
    for (int i = 0; i < 6; ++i) sig[i] += 0.5 * p.mu_2 * std::fabs(pr) * rnd();
    Sym3 de;
    for (int i = 0; i < 6; ++i) de[i] = 1e-3 * rnd() * (k % 3 == 0 ? 0.01 : 1);
    const scree::StrainIncrement inc{de, scree::Spin3{0, 0, 0}, 1e-4, 1 + de.trace()};
    M::State s1{1, 2, 3}, s2{1, 2, 3};
    Sym3 a = sig, b = sig;
    const bool took = M::update_elastic(p, s1, a, inc);
    if (took) {
      M::update(p, s2, b, inc);
      ++accepted;
      if (std::memcmp(&a, &b, sizeof a) != 0 || std::memcmp(&s1, &s2, sizeof s1) != 0) ++bad;
    } else {
      ++declined;
      if (std::memcmp(&a, &sig, sizeof a) != 0 || s1.gp != 1 || s1.I != 2 || s1.gamma != 3) ++bad;
    }
  }
  std::printf("update_elastic against update: %d accepted, %d declined, %d mismatches\n\n", accepted, declined,
              bad);
  return bad == 0 && accepted > 0 && declined > 0;
}

// ---- 2. inclined plane -----------------------------------------------------------------
fs::path perturbed_copy(const fs::path& dir, double factor) {
  const fs::path tmp = fs::temp_directory_path() / ("muI-bagnold-" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  fs::copy(dir / "system", tmp / "system", fs::copy_options::recursive);
  fs::copy(dir / "constant", tmp / "constant", fs::copy_options::recursive);
  const fs::path f = tmp / "constant/materialProperties";
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::regex re(R"((\bmu2\s+)([-+0-9.eE]+))");
  std::smatch mt;
  std::string text = ss.str();
  if (!std::regex_search(text, mt, re)) throw std::runtime_error("no mu2 in " + f.string());
  const double mu2 = std::stod(mt[2]) * factor;
  text = mt.prefix().str() + mt[1].str() + std::to_string(mu2) + mt.suffix().str();
  std::ofstream(f) << text;
  std::printf("simulating with mu2 = %g (x %g), comparing with the analytic profile of the case's mu2\n", mu2,
              factor);
  return tmp;
}

struct Profile {
  std::vector<double> z, num, ana;  // per bin: mean height [m], mean u_x numerical, analytic [m/s]
  std::vector<int> count;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: muI-bagnold CASE [--threads N] [--perturb-mu2 F] [--verbose]\n";
    return 2;
  }
  const fs::path dir = argv[1];
  int threads = 2;
  double perturb = 0;
  bool verbose = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc) threads = std::stoi(argv[++i]);
    else if (a == "--verbose") verbose = true;
    else if (a == "--perturb-mu2" && i + 1 < argc) perturb = std::stod(argv[++i]);
    else {
      std::cerr << "muI-bagnold: unknown argument '" << a << "'\n";
      return 2;
    }
  }
  scree::PluginRuntime rt;  // outlives every object a plugin made (declared first)
  try {
    rt.load_default_plugins();
    const scree::Case cs = scree::Case::read(dir, rt);  // loads libs ("libmuI.so")
    const scree::Dictionary& bodies = cs.bodies();
    if (bodies.entries().empty() || !bodies.entries().front().is_dict()) throw std::runtime_error("no body");
    const scree::Dictionary& body = bodies.entries().front().dict();
    const scree::Dictionary& md = cs.materials().sub(body.get_word("material"));
    if (md.get_word("type") != "muI") throw std::runtime_error("the body's material is not of type muI");
    const MuI m = read_params(md);

    const bool point_ok = point_test(rt.registry(), md, m);
    const scree::PluginEntry& entry = rt.registry().get(scree::PluginKind::material, "muI", md.where());
    const bool elastic_ok = elastic_path_test(scree::ParamReader(*entry.spec, md));
    if (!(point_ok && elastic_ok) && perturb == 0) return 1;

    // Geometry and the analytic steady state.
    const auto g = cs.gravity().at("value").as_scalar_list();
    const double gmag = std::hypot(g[0], g[1]), theta = std::atan2(g[0], -g[1]);
    const auto lo = body.sub("region").at("lower").as_scalar_list();
    const auto up = body.sub("region").at("upper").as_scalar_list();
    const double x0 = lo[0], x1 = up[0], y0 = lo[1], h = up[1] - lo[1];
    const double dx = cs.grid().get_scalar("cellSize");
    const double T = cs.control().get_scalar("endTime");
    const double t = std::tan(theta);
    if (!(m.mu_s < t && t < m.mu_2)) throw std::runtime_error("need mu_s < tan(theta) < mu_2 for a steady flow");
    const double I_theta = m.I0 * (t - m.mu_s) / (m.mu_2 - t);
    const double coef = 2.0 / 3.0 * I_theta / m.d * std::sqrt(m.phi * gmag * std::cos(theta));
    auto u = [&](double z) {
      z = std::clamp(z, 0.0, h);
      return coef * (std::pow(h, 1.5) - std::pow(h - z, 1.5));
    };
    const double us = u(h), cg = std::sqrt(gmag * h * std::cos(theta));
    const double xa = x0 + (us + cg) * T + 2 * h, xb = x1 - cg * T - 2 * h;
    std::printf("inclined plane: theta = %.3f deg, tan = %.4f, I_theta = %.5f, h = %g m (%g cells), "
                "u_s = %.5f m/s, T = %g s\n",
                theta * 180 / scree::kPi, t, I_theta, h, h / dx, us, T);
    std::printf("window x in [%.4f, %.4f] m (layer [%g, %g])\n", xa, xb, x0, x1);
    if (!(xb > xa + dx)) throw std::runtime_error("the layer is too short for endTime: no undisturbed window");

    const fs::path run_dir = perturb > 0 ? perturbed_copy(dir, perturb) : dir;
    const scree::Case run_case = perturb > 0 ? scree::Case::read(run_dir, rt) : cs;
    scree::RunOptions opt;
    opt.device = scree::Device::cpu;
    opt.threads = threads;
    opt.progress = false;
    scree::Simulation sim(run_case, rt, opt);
    {
      const scree::Snapshot s0 = sim.snapshot();
      const scree::BodySnapshot& b = s0.bodies.at(0);
      std::vector<double> v(2 * b.n, 0.0);
      for (scree::Index p = 0; p < b.n; ++p) v[2 * p] = u(b.position[3 * p + 1] - y0);
      sim.set_velocities(0, v);
      std::printf("%lld particles\n", static_cast<long long>(b.n));
    }
    const int nbins = static_cast<int>(std::lround(h / dx));
    auto profile = [&](const scree::Snapshot& s) {
      const scree::BodySnapshot& b = s.bodies.at(0);
      const scree::FieldData* vel = b.find("velocity");
      Profile pr;
      pr.z.assign(nbins, 0);
      pr.num.assign(nbins, 0);
      pr.ana.assign(nbins, 0);
      pr.count.assign(nbins, 0);
      for (scree::Index p = 0; p < b.n; ++p) {
        const double x = b.position[3 * p], z = b.position[3 * p + 1] - y0;
        if (x < xa || x > xb) continue;
        const int k = std::clamp(static_cast<int>(z / dx), 0, nbins - 1);
        pr.z[k] += z;
        pr.num[k] += vel->values[vel->components * p];
        pr.ana[k] += u(z);
        pr.count[k] += 1;
      }
      for (int k = 0; k < nbins; ++k)
        if (pr.count[k] > 0) {
          pr.z[k] /= pr.count[k];
          pr.num[k] /= pr.count[k];
          pr.ana[k] /= pr.count[k];
        }
      return pr;
    };
    // The bins of the first cell above the floor are reported but not checked: with FLIP
    // and a no-slip node at the base, the velocity of the points in that cell lags (the
    // fixed node's correction is mapped back to them every step), a property of the
    // boundary cell of the discretisation, not of the material (README.md).
    auto max_dev = [&](const Profile& pr) {
      double e = 0;
      for (int k = 1; k < nbins; ++k)
        if (pr.count[k] > 0) e = std::max(e, std::fabs(pr.num[k] - pr.ana[k]) / us);
      return e;
    };
    // The nodal velocities in the window, at the nodes z = k dx above the floor (k >= 1; the
    // floor's node is held at 0): the grid solution itself, free of the points' FLIP lag.
    auto grid_dev = [&](const scree::Snapshot& s, std::vector<double>* out) {
      const scree::GridSnapshot& gr = s.grid;
      const scree::FieldData *gm = nullptr, *gv = nullptr;
      for (const auto& f : gr.fields) {
        if (f.name == "mass") gm = &f;
        if (f.name == "velocity") gv = &f;
      }
      if (!gm || !gv) throw std::runtime_error("no grid mass or velocity in the snapshot");
      double e = 0;
      for (int k = 1; k <= nbins; ++k) {
        const long iy = std::lround((y0 + k * dx - gr.origin[1]) / gr.h);
        double sum = 0;
        int n = 0;
        for (long ix = 0; ix < gr.n[0]; ++ix) {
          const double x = gr.origin[0] + ix * gr.h;
          const long i = ix + static_cast<long>(gr.n[0]) * iy;
          if (x < xa || x > xb || !(gm->values[i] > 0)) continue;
          sum += gv->values[3 * i];
          ++n;
        }
        if (n == 0) throw std::runtime_error("no grid node with mass in the window");
        const double dev = (sum / n - u(k * dx)) / us;
        if (out) out->push_back(dev);
        e = std::max(e, std::fabs(dev));
      }
      return e;
    };
    const int samples = 10;
    std::printf("\n%10s %16s %16s\n", "t [s]", "points: max", "nodes: max");
    std::printf("%10s %16s %16s\n", "", "|u - u_an| / u_s", "|u - u_an| / u_s");
    auto print_profile = [&](const Profile& pr) {
      std::printf("\nprofile at t = %g s (window mean per cell-high bin):\n%10s %12s %12s %10s %6s\n", sim.time(),
                  "z [m]", "u [m/s]", "u_an [m/s]", "dev/u_s", "n");
      for (int k = 0; k < nbins; ++k)
        std::printf("%10.5f %12.6f %12.6f %10.5f %6d\n", pr.z[k], pr.num[k], pr.ana[k], (pr.num[k] - pr.ana[k]) / us,
                    pr.count[k]);
    };
    Profile last;
    double grid_last = 0;
    std::vector<double> grid_devs;
    for (int k = 1; k <= samples; ++k) {
      sim.advance_to(T * k / samples);
      const scree::Snapshot s = sim.snapshot(true);
      last = profile(s);
      grid_devs.clear();
      grid_last = grid_dev(s, &grid_devs);
      std::printf("%10.4f %16.5f %16.5f  (%lld steps)\n", sim.time(), max_dev(last), grid_last,
                  static_cast<long long>(sim.steps()));
      if (verbose && k < samples) print_profile(last);
    }
    print_profile(last);
    std::printf("\nnodes at t = %g s (window mean):\n%10s %10s\n", sim.time(), "z [m]", "dev/u_s");
    for (int k = 1; k <= nbins; ++k) std::printf("%10.5f %10.5f\n", k * dx, grid_devs[k - 1]);
    for (int k = 0; k < nbins; ++k)
      if (last.count[k] == 0) throw std::runtime_error("an empty bin in the window");
    const double dev = max_dev(last);
    // Tolerance 3 % of the surface speed, on the points above the first cell and on the
    // nodes, from the estimates in README.md: the start-up transient of a layer released
    // stress free (g sin(theta) h / c_s ~ 2.4 % u_s; it rings as an elastic oscillation of
    // the layer, 0.3-2.2 % during the run), the elastic compression of the layer (p / K:
    // ~0.5 % u_s), and 10 cells across the depth. mu_2 20 % off gives ~10 % at endTime.
    const double tol = 0.03;
    const bool pass = dev <= tol && grid_last <= tol;
    std::printf("\nmax deviation: points %.4f u_s, nodes %.4f u_s; tolerance %.4f u_s: %s\n", dev, grid_last, tol,
                pass ? "PASS" : "MISMATCH");
    if (perturb > 0) {
      fs::remove_all(run_dir);
      std::printf("perturbed rheology %s, as it must be\n", pass ? "NOT detected" : "detected");
      return pass ? 1 : 0;
    }
    return pass ? 0 : 1;
  } catch (const scree::InputErrors& e) {
    for (const auto& err : e.errors()) std::cerr << err.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "muI-bagnold: " << e.what() << "\n";
    return 2;
  }
}
