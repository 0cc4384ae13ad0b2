// particleProbes (see ParticleProbes.hpp).
#include "ParticleProbes.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>

#include "scree/output/writer.hpp"

namespace fs = std::filesystem;

namespace scree::fo {

namespace {

const char* kAxes[] = {"x", "y", "z"};

}  // namespace

ParamSpec ParticleProbes::spec() {
  ParamSpec s(type_name,
              "follows the particles nearest given points (picked at the first execution, then tracked by id) "
              "and writes their position and fields to postProcessing/<name>/<probe>.csv");
  s.list("points", "probe points, one (x y [z]) per probe: each probe follows the particle nearest its point "
                   "at the first execution");
  s.word_list("names", "probe names, one per point (file names <name>.csv; default probe0, probe1, ...)").optional();
  s.word_list("fields",
              "particle fields to write, e.g. (pressure granularTemperature); (all): every field of the "
              "particle's body. Vectors and tensors are expanded per component")
      .default_value("(all)");
  s.word_list("bodies", "bodies in which the particles are picked (default: all bodies)").optional();
  return s;
}

ParticleProbes::ParticleProbes(const ParamReader& r, const SolverContext& ctx)
    : who_("particleProbes '" + ctx.name + "'"),
      dir_(ctx.post_processing_dir()),
      dimension_(ctx.dimension),
      start_time_(ctx.start_time),
      bodies_(read_bodies(r, ctx)),
      ranks_(ctx.comm) {
  lost_ = LostPoints(ctx, who_);
  // points ((x y) (x y) ...)
  const Entry& pe = r.entry("points");
  const Item& list = pe.single_item();
  if (list.kind() != Item::Kind::list || list.list().empty())
    throw InputError(pe.where(), "points: expected a non-empty list of points, e.g. ((0.05 0.09) (0.1 0.05))");
  const int dim = dimension_ == 3 ? 3 : 2;
  for (std::size_t i = 0; i < list.list().size(); ++i) {
    const Item& it = list.list()[i];
    bool ok = it.kind() == Item::Kind::list && static_cast<int>(it.list().size()) == dim;
    Probe p;
    for (int d = 0; ok && d < dim; ++d) {
      ok = it.list()[d].kind() == Item::Kind::number && std::isfinite(it.list()[d].number());
      if (ok) p.point[d] = it.list()[d].number();
    }
    if (!ok)
      throw InputError(it.where().file ? it.where() : pe.where(),
                       "points: element " + std::to_string(i + 1) + " must be a point of " + std::to_string(dim) +
                           " numbers (" + std::string(dim == 3 ? "x y z" : "x y") + "), found " + it.to_string());
    p.name = "probe" + std::to_string(i);
    probes_.push_back(std::move(p));
  }
  // names (A B C)
  if (r.has("names")) {
    const auto names = r.words("names");
    if (names.size() != probes_.size())
      throw InputError(where_of(r, "names"), "names: " + std::to_string(names.size()) + " name(s) for " +
                                                 std::to_string(probes_.size()) + " point(s)");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string& n = names[i];
      if (n.empty() || n.find('/') != std::string::npos || n == "." || n == ".." || n == "selection")
        throw InputError(where_of(r, "names"), "names: '" + n + "' cannot be used as a file name");
      if (!seen.insert(n).second) throw InputError(where_of(r, "names"), "names: '" + n + "' appears twice");
      probes_[i].name = n;
    }
  }
  for (const auto& f : r.words("fields")) {
    if (f == "all") continue;
    if (std::find(fields_.begin(), fields_.end(), f) == fields_.end()) fields_.push_back(f);
  }
  const auto fw = r.words("fields");
  all_fields_ = fw.empty() || std::find(fw.begin(), fw.end(), "all") != fw.end();
  if (ranks_.root()) check_writable_dir(dir_, who_);  // made at the first execution
}

std::vector<std::int64_t> ParticleProbes::tracked_ids() const {
  std::vector<std::int64_t> ids;
  for (const auto& p : probes_) ids.push_back(p.id);
  return ids;
}

// ------------------------------------------------------------------ picking

void ParticleProbes::pick(const Snapshot& s) {
  // Each probe's nearest point over every rank; on a tie the smallest id, so that the
  // choice does not depend on the order of the points in memory or on the ranks.
  const std::size_t np = probes_.size();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> best(np, inf), best_id(np, inf);
  for (std::size_t i = 0; i < np; ++i) {
    const Probe& pr = probes_[i];
    for (const auto& b : s.bodies) {
      if (!selected(bodies_, b)) continue;
      for (Index p = 0; p < b.n; ++p) {
        if (b.is_lost(p)) continue;  // left the grid (LostPoints)
        double d2 = 0;
        for (int d = 0; d < 3; ++d) {
          const double dx = b.position[3 * p + d] - pr.point[d];
          d2 += dx * dx;
        }
        const auto id = static_cast<double>(b.id[p]);  // exact: ids are below 2^53
        if (d2 < best[i] || (d2 == best[i] && id < best_id[i])) {
          best[i] = d2;
          best_id[i] = id;
        }
      }
    }
  }
  std::vector<double> nearest = best;
  ranks_.min(nearest);
  for (std::size_t i = 0; i < np; ++i)
    if (best[i] != nearest[i]) best_id[i] = inf;
  ranks_.min(best_id);
  for (std::size_t i = 0; i < np; ++i) {
    if (best_id[i] == inf)
      throw std::runtime_error(who_ + ": no particle to follow (the selected bodies have no particles)");
    probes_[i].id = static_cast<std::int64_t>(best_id[i]);
  }
}

Snapshot ParticleProbes::followed(const Snapshot& s) const {
  // Each rank sends the probes' points it holds: probe, body, lost, x y z, then every
  // field's values in the body's order of fields.
  std::vector<double> mine;
  for (std::size_t bi = 0; bi < s.bodies.size(); ++bi) {
    const BodySnapshot& b = s.bodies[bi];
    for (Index p = 0; p < b.n; ++p)
      for (std::size_t i = 0; i < probes_.size(); ++i) {
        if (probes_[i].id != b.id[p]) continue;
        mine.insert(mine.end(), {static_cast<double>(i), static_cast<double>(bi), b.is_lost(p) ? 1.0 : 0.0});
        mine.insert(mine.end(), &b.position[3 * p], &b.position[3 * p] + 3);
        for (const FieldData& f : b.fields)
          mine.insert(mine.end(), f.values.begin() + static_cast<std::ptrdiff_t>(p) * f.components,
                      f.values.begin() + static_cast<std::ptrdiff_t>(p + 1) * f.components);
      }
  }
  const std::vector<double> all = ranks_.gather(mine);
  Snapshot out;  // the root's: the case's bodies, each with the probes' points it holds
  out.time = s.time;
  out.step = s.step;
  out.dimension = s.dimension;
  for (const BodySnapshot& b : s.bodies) {
    BodySnapshot e;
    e.name = b.name;
    e.body_id = b.body_id;
    e.material = b.material;
    e.material_type = b.material_type;
    e.scalars = b.scalars;
    for (const FieldData& f : b.fields) e.fields.push_back({f.name, f.components, f.unit, f.doc, {}});
    out.bodies.push_back(std::move(e));
  }
  for (std::size_t at = 0; at < all.size();) {
    const auto i = static_cast<std::size_t>(all[at]);
    BodySnapshot& b = out.bodies[static_cast<std::size_t>(all[at + 1])];
    b.lost.push_back(all[at + 2] != 0 ? 1 : 0);
    b.position.insert(b.position.end(), all.begin() + static_cast<std::ptrdiff_t>(at + 3),
                      all.begin() + static_cast<std::ptrdiff_t>(at + 6));
    b.id.push_back(probes_[i].id);
    ++b.n;
    at += 6;
    for (FieldData& f : b.fields) {
      f.values.insert(f.values.end(), all.begin() + static_cast<std::ptrdiff_t>(at),
                      all.begin() + static_cast<std::ptrdiff_t>(at + static_cast<std::size_t>(f.components)));
      at += static_cast<std::size_t>(f.components);
    }
  }
  return out;
}

bool ParticleProbes::load_selection() {
  std::ifstream in(dir_ / "selection.csv");
  std::string line;
  if (!in || !std::getline(in, line)) return false;
  const auto header = csv_split(line);
  const auto col = std::find(header.begin(), header.end(), "particle_id [-]");
  if (col == header.end()) return false;
  const auto k = static_cast<std::size_t>(col - header.begin());
  std::vector<std::int64_t> ids(probes_.size(), -1);
  while (std::getline(in, line)) {
    const auto cells = csv_split(line);
    if (cells.size() <= k) continue;
    for (std::size_t i = 0; i < probes_.size(); ++i)
      if (cells[0] == probes_[i].name) ids[i] = std::stoll(cells[k]);
  }
  if (std::find(ids.begin(), ids.end(), -1) != ids.end()) return false;  // another set of probes
  for (std::size_t i = 0; i < probes_.size(); ++i) probes_[i].id = ids[i];
  return true;
}

void ParticleProbes::save_selection(const Snapshot& s) const {
  const int dim = dimension_ == 3 ? 3 : 2;
  write_file_atomically(dir_ / "selection.csv", [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::trunc);
    out << "probe";
    for (int d = 0; d < dim; ++d) out << ",point_" << kAxes[d] << " [m]";
    out << ",particle_id [-],body";
    for (int d = 0; d < dim; ++d) out << "," << kAxes[d] << " [m]";
    out << ",distance [m],time [s]\n";
    for (const auto& pr : probes_) {
      const BodySnapshot* body = nullptr;
      Index at = 0;
      for (const auto& b : s.bodies)
        for (Index p = 0; p < b.n && !body; ++p)
          if (b.id[p] == pr.id) {
            body = &b;
            at = p;
          }
      out << csv_text(pr.name);
      for (int d = 0; d < dim; ++d) out << "," << csv_number(pr.point[d]);
      out << "," << pr.id << "," << csv_text(body ? body->name : "");
      double d2 = 0;
      for (int d = 0; d < dim; ++d) {
        const double x = body ? body->position[3 * at + d] : std::numeric_limits<double>::quiet_NaN();
        d2 += (x - pr.point[d]) * (x - pr.point[d]);
        out << "," << csv_number(x);
      }
      out << "," << csv_number(std::sqrt(d2)) << "," << csv_number(s.time) << "\n";
    }
    out.close();
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  });
}

// ------------------------------------------------------------------ rows

void ParticleProbes::open_probe(Probe& pr, const BodySnapshot& b) {
  pr.columns.clear();
  std::vector<std::string> missing;
  auto add = [&](const FieldData& f) {
    for (const auto& [suffix, c] : component_suffixes(f.components, dimension_)) pr.columns.push_back({f.name, c});
  };
  if (all_fields_)
    for (const auto& f : b.fields)
      if (f.name != "bodyId") add(f);
  for (const auto& name : fields_) {
    const FieldData* f = b.find(name);
    if (!f) {
      missing.push_back(name);
      continue;
    }
    if (std::none_of(pr.columns.begin(), pr.columns.end(), [&](const Column& c) { return c.field == name; })) add(*f);
  }
  if (!missing.empty()) {
    std::vector<std::string> have;
    for (const auto& f : b.fields) have.push_back(f.name);
    std::cerr << "warning: " << who_ << ": probe '" << pr.name << "' follows a particle of body '" << b.name
              << "' (material '" << b.material << "'), which has no field " << join(missing)
              << "; not written. Its fields: " << join(have) << "\n";
  }
  std::vector<std::string> header = {"time [s]"};
  for (int d = 0; d < (dimension_ == 3 ? 3 : 2); ++d) header.push_back(std::string(kAxes[d]) + " [m]");
  for (const auto& col : pr.columns) {
    const FieldData* f = b.find(col.field);
    const auto suffixes = component_suffixes(f->components, dimension_);
    std::string suffix;
    for (const auto& [sfx, c] : suffixes)
      if (c == col.component) suffix = sfx;
    header.push_back(col.field + suffix + " [" + (f->unit.empty() ? "-" : f->unit) + "]");
  }
  pr.csv.open(dir_ / (pr.name + ".csv"), header, start_time_);
}

void ParticleProbes::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  bool fresh = false;
  if (!picked_) {
    // A restart takes the root's saved selection (every rank learns it); else pick anew.
    // The last entry says that the root failed to make its directory or read the
    // selection: every rank stops then, none is left waiting in the next reduction.
    std::vector<double> saved(probes_.size() + 1, -1);
    std::string error;
    if (ranks_.root()) try {
        ensure_writable_dir(dir_, who_);
        if (start_time_ > 0 && load_selection())
          for (std::size_t i = 0; i < probes_.size(); ++i) saved[i] = static_cast<double>(probes_[i].id);
      } catch (const std::exception& e) {
        error = e.what();
        saved.back() = 1;
      }
    ranks_.max(saved);
    if (saved.back() > 0) throw std::runtime_error(ranks_.root() ? error : who_ + ": rank 0 could not prepare its files");
    fresh = saved[0] < 0;
    if (fresh)
      pick(s);
    else
      for (std::size_t i = 0; i < probes_.size(); ++i) probes_[i].id = static_cast<std::int64_t>(saved[i]);
    picked_ = true;
  }
  std::optional<Snapshot> gathered;  // several ranks: the followed points, on the root
  if (ranks_.size() > 1) gathered = followed(s);
  lost_.record(s, bodies_);  // after every reduction: the root's writes come last
  if (!ranks_.root()) return;
  const Snapshot& view = gathered ? *gathered : s;
  if (fresh) save_selection(view);
  write_rows(view);
}

void ParticleProbes::write_rows(const Snapshot& s) {
  // Find each probe's particle by id (one pass over the particles).
  std::vector<std::pair<std::int64_t, std::size_t>> wanted;  // (id, probe), sorted by id
  for (std::size_t i = 0; i < probes_.size(); ++i) wanted.emplace_back(probes_[i].id, i);
  std::sort(wanted.begin(), wanted.end());
  std::vector<const BodySnapshot*> body(probes_.size(), nullptr);
  std::vector<Index> index(probes_.size(), 0);
  std::size_t found = 0;
  for (const auto& b : s.bodies) {
    for (Index p = 0; p < b.n && found < probes_.size(); ++p) {
      auto it = std::lower_bound(wanted.begin(), wanted.end(), std::make_pair(b.id[p], std::size_t{0}));
      for (; it != wanted.end() && it->first == b.id[p]; ++it) {
        body[it->second] = &b;
        index[it->second] = p;
        ++found;
      }
    }
  }
  const int dim = dimension_ == 3 ? 3 : 2;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < probes_.size(); ++i) {
    Probe& pr = probes_[i];
    const BodySnapshot* b = body[i];
    if (!pr.csv.is_open()) {
      if (!b) throw std::runtime_error(who_ + ": particle " + std::to_string(pr.id) + " of probe '" + pr.name +
                                       "' is not in the snapshot");
      open_probe(pr, *b);
    }
    std::vector<double> row = {s.time};
    const bool lost = b && b->is_lost(index[i]);  // frozen where it left the grid: not the flow's values
    if (!b || lost) {
      if (!pr.missing_reported)
        std::cerr << "warning: " << who_ << ": particle " << pr.id << " of probe '" << pr.name << "' "
                  << (lost ? "has left the grid" : "is no longer in the snapshot") << "; its rows are nan from t = "
                  << s.time << "\n";
      pr.missing_reported = true;
      row.resize(1 + dim + pr.columns.size(), nan);
      pr.csv.row(row);
      continue;
    }
    const Index p = index[i];
    for (int d = 0; d < dim; ++d) row.push_back(b->position[3 * p + d]);
    for (const auto& col : pr.columns) {
      const FieldData* f = b->find(col.field);
      row.push_back(f ? f->values[static_cast<std::size_t>(p) * f->components + col.component] : nan);
    }
    pr.csv.row(row);
  }
}

}  // namespace scree::fo
