// waterBalance (see WaterBalance.hpp).
#include "WaterBalance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace scree::fo {

namespace {

const char* const kScalars[] = {"liquidDensity", "liquidBulkModulus", "liquidInflowSurface",
                                "liquidInflowPrescribed"};
const char* const kRainScalars[] = {"liquidRainOffered", "liquidRainNotTaken", "liquidRunOff"};
const char* const kFields[] = {"porePressure", "saturation", "porosity", "volume"};

bool two_phase(const BodySnapshot& b) { return b.scalar("liquidDensity") != nullptr; }

}  // namespace

ParamSpec WaterBalance::spec() {
  ParamSpec s(type_name,
              "pore-liquid mass balance of two-phase bodies: stored liquid mass W = sum rho_l (1 + p_w/K_l) n S_l V, "
              "its change, the cumulative surface and prescribed inflows, the balance error, and the rain offered "
              "to the surface and what it did not take, one CSV row per execution "
              "(postProcessing/<name>/waterBalance.csv)");
  s.word_list("bodies", "two-phase bodies to sum over (default: every two-phase body)").optional();
  return s;
}

WaterBalance::WaterBalance(const ParamReader& r, const SolverContext& ctx)
    : who_("waterBalance '" + ctx.name + "'"), bodies_(read_bodies(r, ctx)), ranks_(ctx.comm) {
  lost_ = LostPoints(ctx, who_);
  const std::string unit = ctx.dimension == 3 ? " [kg]" : " [kg/m]";
  const std::vector<std::string> header = {"time [s]",
                                           "stored" + unit,
                                           "storedChange" + unit,
                                           "inflowSurface" + unit,
                                           "inflowPrescribed" + unit,
                                           "balanceError" + unit,
                                           "relativeError [-]",
                                           "rain" + unit,
                                           "rainNotTaken" + unit,
                                           "ponded" + unit,
                                           "runOff" + unit};
  const auto file = ctx.post_processing_dir() / "waterBalance.csv";
  if (ctx.start_time > 0) {
    // A restart: the reference is the first row the kept file holds (before start_time).
    std::ifstream in(file);
    std::string line;
    if (in && std::getline(in, line) && csv_split(line) == header && std::getline(in, line) && !in.eof()) {
      const auto cells = csv_split(line);
      if (cells.size() == header.size()) {
        const double t = std::strtod(cells[0].c_str(), nullptr);
        const double w = std::strtod(cells[1].c_str(), nullptr);
        const double is = std::strtod(cells[3].c_str(), nullptr);
        const double ip = std::strtod(cells[4].c_str(), nullptr);
        if (t < ctx.start_time * (1 - 1e-9) && std::isfinite(w) && std::isfinite(is) && std::isfinite(ip)) {
          reference_ = {w, is, ip};
          have_reference_ = true;
        }
      }
    }
  }
  if (ranks_.root()) csv_.open_at_first_row(file, header, ctx.start_time, who_);
}

WaterBalance::Totals WaterBalance::evaluate(const Snapshot& s) const {
  Totals t;
  bool any = false, counted = false;
  std::vector<std::string> others, missing;
  const BodySnapshot* first_wet = nullptr;
  // The inflow counters are the case's (all its two-phase bodies), reported with one of them
  // (porous/: the first): add them once, wherever they are, and ask for every two-phase body.
  for (const auto& b : s.bodies) {
    if (!two_phase(b)) continue;
    if (!first_wet) first_wet = &b;
    if (!selected(bodies_, b)) missing.push_back(b.name);
    const auto *in = b.scalar(kScalars[2]), *pre = b.scalar(kScalars[3]);
    if (in && pre) {
      t.inflow_surface += in->value;
      t.inflow_prescribed += pre->value;
      counted = true;
      if (const auto* r = b.scalar(kRainScalars[0])) t.rain += r->value;
      if (const auto* r = b.scalar(kRainScalars[1])) t.rain_not_taken += r->value;
      if (const auto* r = b.scalar(kRainScalars[2])) t.run_off += r->value;
    }
  }
  if (first_wet && !counted) {
    std::vector<std::string> have;
    for (const auto& x : first_wet->scalars) have.push_back(x.name);
    throw std::runtime_error(who_ + ": no two-phase body gives the scalars " + kScalars[2] + " and " + kScalars[3] +
                             " (body '" + first_wet->name + "' has: " + join(have) + ")");
  }
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    if (!two_phase(b)) {
      if (!bodies_.empty())
        throw std::runtime_error(who_ + ": bodies: body '" + b.name + "' (material '" + b.material + "', type " +
                                 b.material_type +
                                 ") is not a two-phase body (its snapshot has no scalar liquidDensity); "
                                 "name only two-phase bodies in `bodies`");
      others.push_back(b.name);
      continue;
    }
    double sc[2];
    for (int i = 0; i < 2; ++i) {
      const auto* v = b.scalar(kScalars[i]);
      if (!v) {
        std::vector<std::string> have;
        for (const auto& x : b.scalars) have.push_back(x.name);
        throw std::runtime_error(who_ + ": two-phase body '" + b.name + "' gives no scalar " + kScalars[i] +
                                 " (its scalars: " + join(have) + "); needed: " + join(std::vector<std::string>(kScalars, kScalars + 4)));
      }
      sc[i] = v->value;
    }
    const double rho = sc[0], bulk = sc[1];
    if (!(bulk > 0))
      throw std::runtime_error(who_ + ": body '" + b.name + "': liquidBulkModulus must be positive, found " +
                               csv_number(bulk));
    const FieldData* f[4];
    for (int i = 0; i < 4; ++i) {
      f[i] = &require_field(b, kFields[i], who_);
      if (f[i]->components != 1 || f[i]->values.size() < static_cast<std::size_t>(b.n))
        throw std::runtime_error(who_ + ": body '" + b.name + "': field " + kFields[i] +
                                 " is not a scalar per point");
    }
    double w = 0;
    for (Index p = 0; p < b.n; ++p) {
      if (b.is_lost(p)) continue;  // left the grid (LostPoints)
      const double pw = f[0]->values[p], sat = f[1]->values[p], n = f[2]->values[p], vol = f[3]->values[p];
      w += (1 + pw / bulk) * n * sat * vol;
    }
    t.stored += rho * w;
    if (const FieldData* pond = b.find("pond"))
      for (Index p = 0; p < b.n; ++p)
        if (!b.is_lost(p)) t.ponded += pond->values[p];
    any = true;
  }
  if (!any)
    throw std::runtime_error(who_ + ": no two-phase body among the selected bodies" +
                             (others.empty() ? std::string(" (none in the snapshot)")
                                             : " (" + join(others) + ": no scalar liquidDensity)") +
                             "; waterBalance needs bodies of a two-phase material (porous/two_phase.hpp)");
  if (!missing.empty())
    throw std::runtime_error(who_ + ": bodies: the liquid's inflows are counted over all two-phase bodies of the case, "
                             "so the balance needs them all; not selected: " + join(missing));
  t.stored = ranks_.sum(t.stored);  // the points' over the ranks; the inflows are the case's already
  t.ponded = ranks_.sum(t.ponded);
  return t;
}

void WaterBalance::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  const Totals t = evaluate(s);
  last_step_ = s.step;
  lost_.record(s, bodies_);
  if (!have_reference_) {
    reference_ = t;
    have_reference_ = true;
  }
  const double dw = t.stored - reference_.stored;
  const double inflow = (t.inflow_surface - reference_.inflow_surface) +
                        (t.inflow_prescribed - reference_.inflow_prescribed);
  const double error = dw - inflow;
  const double tiny = std::max(1e-12 * std::abs(t.stored), std::numeric_limits<double>::min());
  const double relative = error / std::max({std::abs(dw), std::abs(inflow), tiny});
  if (ranks_.root()) csv_.row({s.time, t.stored, dw, t.inflow_surface, t.inflow_prescribed, error, relative, t.rain, t.rain_not_taken, t.ponded, t.run_off});
}

}  // namespace scree::fo
