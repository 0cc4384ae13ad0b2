// energies (see Energies.hpp).
#include "Energies.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>

namespace scree::fo {

namespace {
/// The budget's columns after time, kinetic, potential, total (Energies.hpp says what each
/// is): the stored energies, the ledger's terms in its order (output/energy_ledger.hpp) with
/// the derived plastic dissipation after the stress work, and the residual.
std::vector<std::string> budget_columns() {
  std::vector<std::string> c{"elastic", "granular"};
  for (int t = 0; t < kEnergyTerms; ++t) {
    c.push_back(kEnergyTermInfo[t].name);
    if (t == kEnergyStressWork) c.push_back("plastic");
  }
  c.push_back("residual");
  return c;
}
}  // namespace

ParamSpec Energies::spec() {
  ParamSpec s(type_name,
              "kinetic, gravitational potential and total energy of the selected bodies and, with budget, the whole "
              "energy budget (stored, dissipated, numerical losses, residual), one CSV row per execution "
              "(postProcessing/<name>/energies.csv)");
  s.word_list("bodies", "bodies to sum over (default: all bodies; the budget needs all)").optional();
  s.vector("origin", "m", "where the potential energy is zero (default: the origin)").size(-1).optional();
  s.boolean("budget",
            "also the energy budget: elastic and granular energy, the stress work, plastic and collisional "
            "dissipation, the PIC, damping and wall losses and the residual (the kernels keep a ledger: a little "
            "slower)")
      .default_value("no");
  return s;
}

Energies::Energies(const ParamReader& r, const SolverContext& ctx)
    : who_("energies '" + ctx.name + "'"),
      bodies_(read_bodies(r, ctx)),
      origin_(read_point(r, "origin", ctx)),
      budget_(r.boolean("budget")),
      ranks_(ctx.comm) {
  lost_ = LostPoints(ctx, who_);
  if (budget_ && !bodies_.empty())
    throw InputError(where_of(r, "bodies"),
                     "bodies: the energy budget is kept over every body of the case (the kernels' ledger is not "
                     "split by body); remove `bodies` or set `budget no`");
  for (std::size_t d = 0; d < ctx.gravity.size() && d < 3; ++d) gravity_[d] = ctx.gravity[d];
  const std::string unit = ctx.dimension == 3 ? " [J]" : " [J/m]";
  std::vector<std::string> header{"time [s]", "kinetic" + unit, "potential" + unit, "total" + unit};
  if (budget_) {
    for (const auto& c : budget_columns()) header.push_back(c + unit);
    header.push_back("residualFraction [-]");
  }
  const auto file = ctx.post_processing_dir() / "energies.csv";
  if (budget_ && ctx.start_time > 0) {
    // A restart: the first row's values come from the rows the file keeps (CsvFile::open).
    std::ifstream in(file);
    std::string line;
    if (std::getline(in, line) && std::getline(in, line)) {
      const auto c = csv_split(line);
      if (c.size() == header.size()) {
        auto at = [&](const std::string& name) {
          for (std::size_t i = 0; i < header.size(); ++i)
            if (header[i] == name + unit) return std::strtod(c[i].c_str(), nullptr);
          return 0.0;
        };
        Result f;
        f.kinetic = at("kinetic");
        f.potential = at("potential");
        f.elastic = at("elastic");
        f.granular = at("granular");
        first_ = f;
        EnergyLedger ledger;
        for (int t = 0; t < kEnergyTerms; ++t) ledger.term[t] = at(kEnergyTermInfo[t].name);
        first_balance_ = ledger.balance(f.kinetic, f.potential);
      }
    }
  }
  if (ranks_.root()) csv_.open_at_first_row(file, std::move(header), ctx.start_time, who_);
}

Energies::Result Energies::evaluate(const Snapshot& s) const {
  Result res;
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    const FieldData& v = require_field(b, "velocity", who_);
    const FieldData& m = require_field(b, "mass", who_);
    const FieldData* vol = budget_ ? b.find("volume") : nullptr;
    const FieldData* we = budget_ ? b.find("elasticEnergy") : nullptr;
    const FieldData* T = budget_ ? b.find("granularTemperature") : nullptr;
    for (Index p = 0; p < b.n; ++p) {
      if (b.is_lost(p)) continue;  // left the grid (LostPoints)
      const double* vp = &v.values[3 * p];
      const double* x = &b.position[3 * p];
      const double mp = m.values[p];
      res.kinetic += 0.5 * mp * (vp[0] * vp[0] + vp[1] * vp[1] + vp[2] * vp[2]);
      double gx = 0;
      for (int d = 0; d < 3; ++d) gx += gravity_[d] * (x[d] - origin_[d]);
      res.potential -= mp * gx;
      if (we && vol) res.elastic += we->values[p] * vol->values[p];
      if (T) res.granular += 1.5 * mp * T->values[p];  // 3/2 T per unit mass (eq. 27)
    }
  }
  std::vector<double> sums = {res.kinetic, res.potential, res.elastic, res.granular};
  ranks_.sum(sums);  // over the ranks
  return {sums[0], sums[1], sums[2], sums[3]};
}

std::vector<double> Energies::budget(const Result& r, const EnergyLedger& e, const Result& first,
                                     double first_balance) {
  std::vector<double> row{r.elastic, r.granular};
  for (int t = 0; t < kEnergyTerms; ++t) {
    row.push_back(e.term[t]);
    if (t == kEnergyStressWork)  // D_p = W - (elastic - elastic_0) - (granular - granular_0) - D_col
      row.push_back(e[kEnergyStressWork] - (r.elastic - first.elastic) - (r.granular - first.granular) -
                    e[kEnergyCollisional]);
  }
  const double residual = e.balance(r.kinetic, r.potential) - first_balance;
  row.push_back(residual);
  row.push_back(first.potential != 0 ? residual / std::fabs(first.potential) : 0.0);
  return row;
}

void Energies::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  const Result r = evaluate(s);
  lost_.record(s, bodies_);  // after every reduction: the root's writes come last
  std::vector<double> row{s.time, r.kinetic, r.potential, r.total()};
  if (budget_) {
    if (!s.energy.kept)
      throw std::runtime_error(who_ + ": the snapshot carries no energy ledger (the solver did not keep it)");
    if (!first_) {
      first_ = r;
      first_balance_ = s.energy.balance(r.kinetic, r.potential);
    }
    const std::vector<double> b = budget(r, s.energy, *first_, first_balance_);
    row.insert(row.end(), b.begin(), b.end());
  }
  if (ranks_.root()) csv_.row(row);
}

}  // namespace scree::fo
