// Solver<D>: the run's health. The device stops the clock on a failure (a non-finite
// value, too many lost points, an unstable fixed step: time/step_control.hpp); the host
// adds a collapsed adaptive step, and says what went wrong in the user's terms: which
// particle of which body and material, which field, in which step, and which entry of the
// case to look at.
#include <cmath>
#include <sstream>

#include "solver.hpp"

namespace scree {

template <int D>
void Solver<D>::check_health() {
  if (host_ctl_.failure == 0 && time_.adaptive()) {
    // The adaptive step collapsed (a material whose signal speed exploded): it cannot add
    // to the clock, or the run would need more steps than any run can take. A step that
    // lands on a target may be a sliver legitimately: only a step short of it counts.
    const int p = parity();
    const double t = host_ctl_.t[p], dt = host_ctl_.dt[p];
    if (dt > 0 && !TimeControl::reached(t + dt, host_ctl_.t_target) &&
        (t + dt == t || (time_.end_time() - t) / dt > TimeControl::kMaxSteps)) {
      host_ctl_.failure = kFailStalled;
      host_ctl_.failed_step = host_ctl_.step[p];
    }
  }
  if (decomposed()) {
    check_health_ranks();
    return;
  }
  if (host_ctl_.failure == 0) return;
  throw RunFailure(diagnosis());
}

namespace {
std::string vec_str(const Real* v, int n) {
  std::ostringstream o;
  o << "(";
  for (int i = 0; i < n; ++i) o << (i ? " " : "") << v[i];
  o << ")";
  return o.str();
}
std::string where(const Dictionary& d, const char* key) {
  const Entry* e = d.find(key);
  if (e) return e->where().str() + ": " + key;
  const auto& file = d.where().file;
  return (file ? *file + ": " : std::string()) + key + " (not set: the default)";
}
}  // namespace

template <int D>
std::string Solver<D>::diagnosis() {
  const StepControl c = host_ctl_;
  // The state the clock stopped in (a host copy of this rank's part; no other rank takes part).
  const Snapshot s = local_snapshot(false, true);
  std::ostringstream m;
  m.precision(6);
  m << "the run went wrong and was stopped in step " << c.failed_step << " (t = " << time() << " s):";
  // Body, material and particle of a point the kernels recorded.
  auto point = [&](const StepControl::BadPoint& b, std::size_t& body, Index& i) -> std::string {
    body = s.bodies.size();
    for (std::size_t k = 0; k < s.bodies.size(); ++k)
      if (s.bodies[k].body_id == b.body) body = k;
    if (body == s.bodies.size() || b.index < 0 || b.index >= s.bodies[body].n) return "a particle";
    i = b.index;
    const BodySnapshot& bs = s.bodies[body];
    const Entry* mat = case_.materials().find(bs.material);
    return "particle " + std::to_string(bs.id[i]) + " of body '" + bs.name + "' (material '" + bs.material + "', " +
           bs.material_type + (mat ? ", " + mat->where().str() : std::string()) + ")";
  };
  if (c.failure & kFailNonFinite) {
    static const char* fields[] = {"position", "velocity", "stress"};
    static const char* axes[] = {"x", "y", "z"};
    static const char* stress[] = {"xx", "yy", "zz", "xy", "yz", "zx"};
    // Found by the grid update (report_nonfinite_node): the point is the first one of the
    // frozen state with a non-finite position, velocity or stress.
    StepControl::BadPoint bad = c.bad;
    if (bad.index < 0) {
      bad.index = -1;
      for (std::size_t k = 0; k < s.bodies.size() && bad.index < 0; ++k) {
        const BodySnapshot& bs = s.bodies[k];
        const FieldData* vel = bs.find("velocity");
        const FieldData* sig = bs.find("stress");
        for (Index q = 0; q < bs.n && bad.index < 0; ++q) {
          const struct { int field, n, stride; const Real* v; } probes[] = {
              {kBadPosition, D, 3, &bs.position[3 * q]},
              {kBadVelocity, D, 3, vel ? &vel->values[3 * q] : nullptr},
              {kBadStress, 6, 6, sig ? &sig->values[6 * q] : nullptr}};
          for (const auto& pr : probes) {
            for (int j = 0; pr.v && j < pr.n && bad.index < 0; ++j)
              if (!std::isfinite(pr.v[j])) {
                bad.body = bs.body_id;
                bad.field = pr.field;
                bad.component = j;
                bad.index = q;
                bad.value = pr.v[j];
              }
          }
        }
      }
    }
    const int f = bad.field;
    const char* comp = f == kBadStress ? stress[bad.component % 6] : axes[bad.component % 3];
    std::size_t b = 0;
    Index i = -1;
    if (bad.index < 0) {
      m << "\n  a nodal velocity or force of the grid update is not finite (step " << bad.step
        << "), and no particle's position, velocity or stress is";
    } else {
      const std::string who = point(bad, b, i);
      m << "\n  " << fields[f % 3] << " " << comp << " = " << bad.value << " (not finite) of " << who
        << ", found in step " << bad.step << "; " << bad.count << " non-finite value(s) in that step";
    }
    if (i >= 0) m << "\n  its position " << vec_str(&s.bodies[b].position[3 * i], D);
    m << "\n  the material's parameters, the time step (" << where(case_.control(), "deltaT")
      << ") or the loads (constant/g, boundary conditions) drove it there";
  }
  if (c.failure & kFailLost) {
    std::size_t b = 0;
    Index i = -1;
    const std::string who = point(c.first_lost, b, i);
    m << "\n  " << c.lost << " of " << stats().particles << " particles have left the grid, more than "
      << where(case_.control(), "maxLostFraction") << " = " << settings_.control.max_lost_fraction << " allows";
    m << "\n  the first, in step " << c.first_lost.step << ": " << who;
    if (i >= 0) {
      const FieldData* v = s.bodies[b].find("velocity");
      m << ", last inside at " << vec_str(&s.bodies[b].position[3 * i], D);
      if (v) m << " with velocity " << vec_str(&v->values[3 * i], D) << " m/s";
    }
    m << "\n  the grid: " << where(case_.grid(), "lower") << " and " << where(case_.grid(), "upper")
      << "; if the particles were flung out, look at the loads (constant/g) and the time step";
  }
  // The body with the largest signal speed c + |v| now (a host copy of each body).
  auto fastest = [&] {
    Real cmax = -1;
    std::string who;
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const Real ck = bodies_[k]->max_signal_speed(grid_.h);
      if (!(ck <= cmax)) {
        cmax = ck;
        const BodySnapshot& bs = s.bodies[k];
        const Entry* mat = case_.materials().find(bs.material);
        who = "body '" + bs.name + "' (material '" + bs.material + "', " + bs.material_type +
              (mat ? ", " + mat->where().str() : std::string()) + ")";
      }
    }
    std::ostringstream o;
    o.precision(6);
    o << "the largest signal speed c + |v| = " << cmax << " m/s is in " << who;
    return o.str();
  };
  if (c.failure & kFailStalled) {
    const int p = parity();
    m << "\n  the adaptive step has collapsed to dt = " << c.dt[p] << " s: reaching endTime " << time_.end_time()
      << " s would take " << (time_.end_time() - c.t[p]) / c.dt[p] << " steps\n  " << fastest()
      << "\n  the adaptive step follows it (" << where(case_.control(), "maxCo")
      << "): a material's parameters out of range, or a blown-up state";
  }
  if (c.failure & kFailUnstable) {
    m << "\n  the step's Courant number dt (c + |v|)_max / h = " << c.failed_co << " is above stopCo "
      << host_ctl_.stop_co << " (" << where(case_.control(), "stopCo") << "): the step is unstable";
    m << "\n  " << fastest();
    m << "\n  the fixed step " << where(case_.control(), "deltaT") << " " << settings_.control.time.delta_t
        << " s exceeds the stable step h / (c + |v|) = " << settings_.control.time.delta_t / c.failed_co
        << " s: reduce it, or use adjustTimeStep yes";
  }
  // USL with linear shape functions: where points linger just past a cell face, the nodes of
  // the cell they entered carry a sliver of a point's mass but a whole share of its force
  // (the stress's or the pore pressure's gradient times V grad N), so the updated nodal
  // velocity, from which USL takes the strain rate, grows without bound there (a block that
  // slides or falls; the liquid's stiff storage makes it fast). GIMP's overlapping domains
  // have no such nodes; USF and MUSL take the strain rate from mass-weighted velocities; a
  // mass tolerance of a tenth of a point leaves them unaccelerated, and so drops their share
  // of the forces (many of them along a wall inclined to the grid).
  const SchemeSettings& sch = settings_.schemes;
  if (sch.update_scheme == UpdateScheme::USL && sch.shape == ShapeKind::linear && sch.mass_tolerance < 0.1 &&
      (c.failure & (kFailNonFinite | kFailLost | kFailStalled))) {
    m << "\n  the case runs USL with linear shape functions (" << where(case_.schemes(), "shapeFunction")
      << "): where points move across cells, the nodes of the cells they have just entered carry a sliver of their "
         "mass and are unstable" << (porous_ ? " (two-phase bodies: their pore liquid)" : "")
      << "; shapeFunction gimp keeps it stable" << (porous_ ? "" : ", as does updateScheme USF or MUSL")
      << "; massTolerance 0.1 (" << where(case_.schemes(), "massTolerance")
      << ": nodes lighter than a tenth of a point are not accelerated) keeps it from blowing up, at the price of "
         "those nodes' share of the forces";
  }
  return m.str();
}

template void Solver<2>::check_health();
template void Solver<3>::check_health();
template std::string Solver<2>::diagnosis();
template std::string Solver<3>::diagnosis();

}  // namespace scree
