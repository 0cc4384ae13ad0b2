// check_setup, output_places and existing_results (see setup_check.hpp).
#include "scree/case/setup_check.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <exception>
#include <iomanip>
#include <iterator>
#include <memory>
#include <sstream>
#include <system_error>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/porous/hydraulic_condition.hpp"
#include "scree/case/case_model.hpp"
#include "scree/plugin/hydraulic_models.hpp"
#include "scree/case/checkpoint.hpp"
#include "scree/case/memory_estimate.hpp"
#include "scree/output/writer.hpp"
#include "hydraulic_nodes.hpp"
#include "scree/case/particle_generation.hpp"

namespace fs = std::filesystem;

namespace scree {

namespace {

/// Why `dir` cannot be created and written to, or "" if it can; nothing is created.
std::string unwritable(const fs::path& dir) {
  std::error_code ec;
  fs::path target = fs::absolute(dir, ec);
  if (ec) target = dir;
  target = target.lexically_normal();
  // The deepest part of the path that exists decides.
  fs::path p = target;
  while (!fs::exists(p, ec) && p.has_relative_path()) p = p.parent_path();
  if (!fs::is_directory(p, ec))
    return p == target ? p.string() + " exists and is not a directory"
                       : "it cannot be created: " + p.string() + " is not a directory";
  if (::access(p.c_str(), W_OK | X_OK) != 0) {
    const std::string why = std::system_category().message(errno);
    return p == target ? "it is not writable (" + why + ")"
                       : "it cannot be created: " + p.string() + " is not writable (" + why + ")";
  }
  return {};
}

/// Whether `dir` lies inside `case_dir` (after resolving links, "..", and so on).
bool inside(const fs::path& dir, const fs::path& case_dir) {
  std::error_code ec;
  const fs::path d = fs::weakly_canonical(fs::absolute(dir, ec), ec);
  const fs::path c = fs::weakly_canonical(fs::absolute(case_dir, ec), ec);
  auto di = d.begin();
  for (auto ci = c.begin(); ci != c.end(); ++ci, ++di) {
    if (ci->empty()) continue;  // a trailing separator
    if (di == d.end() || *di != *ci) return false;
  }
  return true;
}

template <int D>
void check_geometry(const Case& c, PluginRuntime& rt, SetupReport& report) {
  const GlobalGrid<D> grid = grid_geometry<D>(c.settings().grid);
  check_bodies<D>(c.bodies(), grid, report.errors, c.dir());

  // Boundary conditions: built on the host against this grid, as the run builds them.
  const SolverContext ctx = plugin_context<D>(c, grid, Device::cpu);
  WallSet walls(NodeLattice::of(ctx));
  const Registry& reg = rt.registry();
  bool two_phase = false;
  for (const Entry* b : c.body_entries()) {
    const Entry* tp = b->dict().find("twoPhase");
    if (!tp || !tp->is_dict()) continue;
    two_phase = true;
    try {  // the models as the run reads them (porous/hydraulic_model.hpp)
      (void)read_hydraulics(tp->dict(), hydraulic_models(reg));
    } catch (const InputError& err) {
      report.errors.push_back(err);
    }
  }
  std::vector<std::unique_ptr<BoundaryCondition>> made;
  std::vector<const Entry*> made_from;
  for (const Entry* e : c.boundary_entries()) {
    const Dictionary& d = e->dict();
    try {
      auto bc = plugin_of(reg, PluginKind::boundaryCondition, d).boundary(d, named(ctx, e->key()));
      bc->constrain(walls);
      for (InputError& err : needs_two_phase(*e, *bc, two_phase)) report.errors.push_back(std::move(err));
      made_from.push_back(e);
      made.push_back(std::move(bc));
    } catch (const InputError& err) {
      report.errors.push_back(err);
    } catch (const std::exception& err) {
      report.errors.emplace_back(d.where(), "boundary condition '" + e->key() + "': " + err.what());
    }
  }
  std::vector<const BoundaryCondition*> conditions;
  for (const auto& bc : made) conditions.push_back(bc.get());
  for (InputError& err : overlapping_hydraulic_conditions(made_from, conditions, NodeLattice::of(ctx)))
    report.errors.push_back(std::move(err));
}

}  // namespace

std::vector<InputError> needs_two_phase(const Entry& e, const BoundaryCondition& made, bool two_phase) {
  std::vector<InputError> errors;
  if (two_phase) return errors;
  const Dictionary& d = e.dict();
  const std::string none = "no body of this case is two-phase (a body with a twoPhase { ... } block in constant/bodies)";
  if (dynamic_cast<const HydraulicCondition*>(&made))
    errors.emplace_back(d.at("type").where(),
                        "type " + d.get_word("type") + ": '" + e.key() + "' acts on the pore liquid, and " + none);
  else if (const Entry* dr = d.find("drained"); dr && dr->as_bool())
    errors.emplace_back(dr->where(), "drained: '" + e.key() +
                                         "' lets the pore liquid of two-phase bodies through, and " + none +
                                         "; leave drained out");
  return errors;
}

HydraulicReach hydraulic_reach(const HydraulicCondition& hc, const NodeLattice& grid) {
  std::vector<OpenSurface> surfaces;
  std::vector<PorePressureLaw> laws;
  hc.open_surfaces(surfaces);
  hc.constrain_pores(laws);
  HydraulicReach r;
  r.from = kUnbounded;
  r.to = -kUnbounded;
  for (const OpenSurface& o : surfaces) r.from = std::min(r.from, o.t_start), r.to = std::max(r.to, o.t_end);
  for (const PorePressureLaw& l : laws) r.from = std::min(r.from, l.t_start), r.to = std::max(r.to, l.t_end);
  r.nodes = select_nodes(grid, [&](const Real* x) {  // visits the nodes in ascending order
    for (const OpenSurface& s : surfaces)
      if (s.select(x)) return true;
    for (const PorePressureLaw& l : laws) {
      bool inside = true;
      for (int d = 0; d < grid.dimension; ++d) inside = inside && x[d] >= l.lo[d] && x[d] <= l.hi[d];
      if (inside) return true;
    }
    return false;
  });
  return r;
}

std::vector<InputError> overlapping_hydraulic_conditions(const std::vector<const Entry*>& entries,
                                                        const std::vector<const BoundaryCondition*>& made,
                                                        const NodeLattice& grid) {
  struct Acting {
    std::size_t entry;
    std::string type;
    HydraulicReach reach;
  };
  std::vector<Acting> acting;
  for (std::size_t i = 0; i < entries.size() && i < made.size(); ++i)
    if (const auto* hc = dynamic_cast<const HydraulicCondition*>(made[i]))
      acting.push_back({i, entries[i]->dict().get_word("type"), hydraulic_reach(*hc, grid)});
  auto time = [](Real t) {
    std::ostringstream os;
    if (t <= -kUnbounded) os << "the start";
    else if (t >= kUnbounded) os << "the end";
    else os << t << " s";
    return os.str();
  };
  std::vector<InputError> errors;
  for (std::size_t j = 0; j < acting.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      const Acting &a = acting[i], &b = acting[j];
      const Real from = std::max(a.reach.from, b.reach.from), to = std::min(a.reach.to, b.reach.to);
      if (a.type != b.type || !(from < to)) continue;
      std::vector<Index> both;
      std::set_intersection(a.reach.nodes.begin(), a.reach.nodes.end(), b.reach.nodes.begin(), b.reach.nodes.end(),
                            std::back_inserter(both));
      if (both.empty()) continue;
      const Entry& ea = *entries[a.entry];
      const Entry& eb = *entries[b.entry];
      Real x[3] = {0, 0, 0};
      Index k = both.front();
      for (int d = 0; d < grid.dimension; ++d) {
        x[d] = grid.origin[d] + grid.h * static_cast<Real>(k % grid.nodes[d]);
        k /= grid.nodes[d];
      }
      std::ostringstream m;
      m << "'" << eb.key() << "' and '" << ea.key() << "' (" << ea.where().str() << ") are both " << b.type
        << " conditions on the same " << both.size() << " grid node(s), the first at (";
      for (int d = 0; d < grid.dimension; ++d) m << (d ? " " : "") << x[d];
      m << "), from " << time(from) << " to " << time(to)
        << ": the run would apply one after the other, and the result is neither entry's (two rainfalls give the "
           "smaller intensity, two pore pressures the later one). Expected regions or times that do not overlap: "
           "merge them into one entry, or set their box, face or startTime/endTime apart";
      errors.emplace_back(eb.dict().at("type").where(), m.str());
    }
  return errors;
}

std::vector<std::string> run_summary(const Case& c, const MemoryEstimate& m) {
  std::vector<std::string> lines;
  auto count = [](double n) {
    std::ostringstream os;
    if (n >= 1e6)
      os << std::setprecision(3) << n / 1e6 << " million";
    else
      os << static_cast<long long>(std::llround(n));
    return os.str();
  };
  double points = 0;
  std::string bodies;
  constexpr std::size_t kNamed = 4;  // bodies named one by one; the rest counted
  for (std::size_t i = 1; i < m.parts.size(); ++i) {
    points += m.parts[i].count;
    if (i <= kNamed)
      bodies += (i > 1 ? ", " : "") + m.parts[i].what.substr(m.parts[i].what.find(' ') + 1) + " " +
                count(m.parts[i].count);
  }
  if (m.parts.size() > kNamed + 1) bodies += " and " + std::to_string(m.parts.size() - 1 - kNamed) + " more bodies";
  const auto& g = c.settings().grid;
  std::ostringstream grid;
  grid << c.dimension() << "D, about " << count(points) << " points (" << bodies << ")";
  if (!m.parts.empty()) grid << ", " << count(m.parts.front().count) << " grid nodes of " << g.cell_size << " m";
  lines.push_back(grid.str());
  const TimeSettings& t = c.settings().control.time;
  const double span = t.end_time - t.start_time;
  std::ostringstream steps;
  steps << "from t = " << t.start_time << " to " << t.end_time << " s, ";
  if (t.adjust_time_step)
    steps << "at least " << count(std::ceil(span / t.max_delta_t - 1e-9)) << " steps (the step follows maxCo "
          << t.max_co << " up to maxDeltaT " << t.max_delta_t << " s; the first, from the points' wave speed, is "
          << "printed when the run starts)";
  else
    steps << count(std::ceil(span / t.delta_t - 1e-9)) << " steps of " << t.delta_t << " s";
  lines.push_back(steps.str());
  const ControlSettings& cs = c.settings().control;
  if (!c.writer_entries().empty() || !c.function_entries().empty()) {
    std::ostringstream w;
    if (cs.write_control == WriteControl::timeStep)
      w << "writes every " << cs.write_interval << " steps";
    else
      w << count(std::floor(span / cs.write_interval + 1e-9) + 1) << " writes (every " << cs.write_interval << " s)";
    w << " by " << c.writer_entries().size() << " writer(s) and " << c.function_entries().size()
      << " function object(s)";
    if (cs.checkpoint_interval > 0)
      w << "; a checkpoint every " << cs.checkpoint_interval << " write(s), the newest " << cs.checkpoint_keep
        << " kept";
    lines.push_back(w.str());
  }
  return lines;
}

namespace {

void check_output(const Case& c, const Registry& reg, SetupReport& report) {
  for (const OutputPlace& place : output_places(c, reg)) {
    if (!place.dir.has_filename()) {  // `directory "";` would write into the case directory itself
      report.errors.emplace_back(place.where, "directory: must not be empty; expected a directory name, e.g. VTK");
      continue;
    }
    const std::string why = unwritable(place.dir);
    if (!why.empty()) {
      report.errors.emplace_back(place.where, "directory: the output directory " + place.dir.string() + " of " +
                                                  place.owner + " cannot be used: " + why +
                                                  "; expected a directory that can be created and written");
      continue;
    }
    if (!inside(place.dir, c.dir())) {
      std::error_code ec;
      report.warnings.emplace_back(
          place.where, "directory: the output directory of " + place.owner + ", " +
                           fs::weakly_canonical(fs::absolute(place.dir, ec), ec).string() +
                           ", is outside the case directory " +
                           fs::weakly_canonical(fs::absolute(c.dir(), ec), ec).string() +
                           ": the results will not be with the case, and another case writing there replaces them "
                           "(a directory relative to the case, such as VTK, keeps them inside)");
    }
  }
}

}  // namespace

SetupReport check_setup(const Case& c, PluginRuntime& rt, bool with_output, Device device, RankLayout layout) {
  SetupReport report;
  report.errors = check_memory(c, rt.registry(), device, with_output, layout);
  if (!report.errors.empty()) return report;
  {
    const MemoryEstimate m = estimate_memory(c, rt.registry(), device, with_output, layout);
    auto space = [&](double need, Device d) {
      const mem::Available a = mem::available(d);
      const std::string whose = layout.ranks <= 1 ? std::string()
                                : d == Device::cuda ? " per rank"
                                                    : " on each machine";
      return "about " + mem::format_bytes(need) + " of " + (d == Device::cuda ? "GPU" : "host") + " memory" + whose +
             (a.known ? " (" + mem::format_bytes(static_cast<double>(a.bytes)) + " free)" : std::string());
    };
    report.memory = space(m.host_bytes(), Device::cpu);
    if (device == Device::cuda) report.memory += " and " + space(m.device_bytes(), Device::cuda);
    report.summary = run_summary(c, m);
  }
  if (c.dimension() == 3)
    check_geometry<3>(c, rt, report);
  else
    check_geometry<2>(c, rt, report);
  if (with_output) check_output(c, rt.registry(), report);
  return report;
}

std::vector<OutputPlace> output_places(const Case& c, const Registry& reg) {
  std::vector<OutputPlace> places;
  auto visit = [&](const std::vector<const Entry*>& entries, PluginKind kind) {
    for (const Entry* entry : entries) {
      const Entry& e = *entry;
      const Dictionary& d = e.dict();
      const Entry* type = d.find("type");
      const PluginEntry* pe = type ? reg.find(kind, type->as_word()) : nullptr;
      if (!pe) continue;  // Case::read has reported it
      const std::string owner = std::string(kind == PluginKind::writer ? "writer" : "function object") + " '" +
                                e.key() + "'";
      const Param* dir = pe->spec->find("directory");
      if (dir && dir->type() == ParamType::word) {
        const ParamReader r(*pe->spec, d);
        const std::string text = r.word("directory");
        const Entry* given = d.find("directory");
        places.push_back({owner, c.dir() / text, given ? given->where() : d.where(),
                          kind == PluginKind::writer ? e.key() : std::string()});
      } else if (kind == PluginKind::functionObject) {
        SolverContext ctx;
        ctx.case_dir = c.dir();
        ctx.name = e.key();
        places.push_back({owner, ctx.post_processing_dir(), d.where(), std::string()});
      }
    }
  };
  visit(c.writer_entries(), PluginKind::writer);
  visit(c.function_entries(), PluginKind::functionObject);
  if (c.settings().control.checkpoint_interval > 0) {  // case/checkpoint.hpp
    const Entry* e = c.control().find("checkpointInterval");
    places.push_back({"the checkpoints", checkpoint_dir(c.dir()), e ? e->where() : c.control().where(), ""});
  }
  return places;
}

std::size_t remove_temporaries(const Case& c, const Registry& reg) {
  std::size_t removed = 0;
  for (const OutputPlace& place : output_places(c, reg)) {
    std::error_code ec;
    if (!fs::is_directory(place.dir, ec)) continue;
    for (const auto& de : fs::directory_iterator(place.dir, ec))
      if (!atomic_temporary_target(de.path().filename().string()).empty() && fs::remove(de.path(), ec)) ++removed;
  }
  return removed;
}

std::vector<fs::path> existing_results(const Case& c, const Registry& reg) {
  std::vector<fs::path> found;
  for (const OutputPlace& place : output_places(c, reg)) {
    std::error_code ec;
    if (!fs::is_directory(place.dir, ec)) continue;
    std::vector<fs::path> here;
    for (const auto& de : fs::directory_iterator(place.dir, ec)) {
      const std::string name = de.path().filename().string();
      if (name.empty() || name[0] == '.') continue;  // temporaries of a killed run
      const std::string& p = place.prefix;
      if (!p.empty() && name.rfind(p + ".", 0) != 0 && name.rfind(p + "_", 0) != 0) continue;
      here.push_back(de.path());
    }
    std::sort(here.begin(), here.end());
    for (auto& f : here)
      if (std::find(found.begin(), found.end(), f) == found.end()) found.push_back(f);
  }
  return found;
}

}  // namespace scree
