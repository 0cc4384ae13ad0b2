// estimate_memory and check_memory (see memory_estimate.hpp).
#include "scree/case/memory_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "scree/case/case_model.hpp"
#include "scree/case/decomposition.hpp"
#include "scree/case/particle_generation.hpp"
#include "scree/material/material.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/particle_pass.hpp"
#include "scree/mpm/wall_law.hpp"
#include "scree/output/field_info.hpp"
#include "scree/porous/two_phase.hpp"

namespace scree {

double MemoryEstimate::backend_bytes() const {
  double b = 0;
  for (const MemoryPart& p : parts) b += p.backend();
  return b;
}
double MemoryEstimate::host_bytes() const {
  const int per_node = std::max(1, layout.per_node);
  double b = device == Device::cpu ? backend_bytes() * per_node : 0;
  for (const MemoryPart& p : parts) b += p.node_host(per_node);
  return b;
}
double MemoryEstimate::device_bytes() const { return device == Device::cuda ? backend_bytes() : 0; }

namespace {

constexpr double kReal = sizeof(Real);

/// What the estimate depends on, read once; evaluate() gives the estimate for any cell
/// size, and for another particlesPerCell of one body (what would fit).
struct Model {
  struct Body {
    std::string name;
    const Dictionary* dict = nullptr;
    SourceLocation where;  ///< its particlesPerCell (its dictionary where defaulted)
    int ppc = 2;
    int state_reals = 0;   ///< the material's State (K columns)
    bool turns = false;    ///< the material's update runs in turns (the split's Handoff)
    int output_reals = 0;  ///< the material's output fields' components
    bool two_phase = false;
  };
  int dim = 2;
  Device device = Device::cpu;
  RankLayout layout;
  bool output = false;  ///< snapshots are taken (writers or function objects)
  bool gathers = false;  ///< a function object that does not reduce over ranks: a decomposed run's first rank gathers the case for it
  GridSettings grid;
  std::filesystem::path case_dir;  ///< an stl region's file is relative to it
  SourceLocation cell_size_where;
  bool walls = false, two_phase = false, apic = false, sorts = false;
  std::vector<Body> bodies;
};

Model read_model(const Case& c, const Registry& reg, Device device, bool with_output, RankLayout layout) {
  const CaseSettings& s = c.settings();
  Model m;
  m.layout = layout;
  m.dim = c.dimension();
  m.case_dir = c.dir();
  m.device = device;
  m.output = with_output && (c.control().has("writers") || c.control().has("functions"));
  for (const Entry* e : with_output ? c.function_entries() : std::vector<const Entry*>{})
    m.gathers = m.gathers || !plugin_of(reg, PluginKind::functionObject, e->dict()).reduces_over_ranks;
  m.grid = s.grid;
  m.cell_size_where = c.grid().has("cellSize") ? c.grid().at("cellSize").where() : c.grid().where();
  m.walls = !c.boundary_entries().empty();
  m.apic = s.schemes.transfer == Transfer::apic;
  m.sorts = s.schemes.sort_interval > 0;
  for (const Entry* e : c.body_entries()) {
    const Dictionary& d = e->dict();
    Model::Body b;
    b.name = e->key();
    b.dict = &d;
    const Entry* ppc = d.find("particlesPerCell");
    b.where = ppc ? ppc->where() : d.where();
    b.two_phase = d.has("twoPhase");
    m.two_phase = m.two_phase || b.two_phase;
    try {
      const BodySettings bs = BodySettings::read(d);
      b.ppc = bs.particles_per_cell;
      const auto point = reg.make_point_material(c.materials().sub(bs.material));
      b.state_reals = static_cast<int>(point->state().size());
      b.turns = point->updates_in_turns();
      for (const OutputField& f : point->output_fields()) b.output_reals += f.components;
    } catch (const std::exception&) {
      // Case::read reported it; the estimate takes the columns every material has.
    }
    m.bodies.push_back(std::move(b));
  }
  return m;
}

double grid_nodes(const GridSettings& g, double h) {
  double n = 1;
  for (int d = 0; d < g.dimension && d < static_cast<int>(g.lower.size()) && d < static_cast<int>(g.upper.size()); ++d)
    n *= domain_cells(g.lower[d], g.upper[d], h) + 1 + 2 * g.ghost_layers;  // GlobalGrid<D>::n[d]
  return n;
}

template <int D>
double points(const Dictionary& body, double h, int ppc, const std::filesystem::path& case_dir) {
  return estimate_particle_count<D>(body, static_cast<Real>(h), ppc, case_dir);
}

/// The estimate for cell size h, with `ppc` particles per cell in body `body` (-1: as given).
MemoryEstimate evaluate(const Model& m, double h, int body = -1, int ppc = 0) {
  MemoryEstimate e;
  e.device = m.device;
  e.layout = m.layout;
  const int D = m.dim;
  const bool gpu = m.device == Device::cuda;
  const int R = std::max(1, m.layout.ranks);

  MemoryPart g{"the grid", "cellSize", m.cell_size_where, grid_nodes(m.grid, h)};
  if (R > 1) {
    // Estimated as slabs across the grid's longest axis: a rank's share of it, and the
    // halo's node layers on both sides (the shape's reach and the migration slack,
    // case/decomposition.hpp; 3 + kSlackCells covers every shape). Boxes cut across shorter
    // axes carry a little more halo; once the boxes are cut, each rank's is checked exactly
    // against its backend's free memory before anything is allocated.
    double longest = 1;
    for (int d = 0; d < m.grid.dimension && d < static_cast<int>(m.grid.lower.size()); ++d)
      longest = std::max(longest, static_cast<double>(domain_cells(m.grid.lower[d], m.grid.upper[d], h)));
    g.rank_share = std::min(1.0, 1.0 / R + 2.0 * (3 + kSlackCells) / longest);
  }
  // Solver::setup_grid: two sets of kGridFieldCount nodal fields, and a stamp (uint32) per
  // tile of Tiles<D>::kNodes nodes for each set.
  g.backend_each = 2.0 * (D == 2 ? kGridFieldCount<2> : kGridFieldCount<3>) * kReal + 2.0 * sizeof(std::uint32_t) / (D == 2 ? Tiles<2>::kNodes : Tiles<3>::kNodes);
  if (m.walls) {  // a WallMask per node on the backend, and the WallSet's on the host while it is built
    g.backend_each += sizeof(WallMask);
    g.host_each += sizeof(WallMask);
  }
  if (m.two_phase) {
    // porous_media.cpp: the liquid's two sets of kLiquidFieldCount fields, two cell counts,
    // the surface flags (a byte), the balance ((3 + D) Reals, zeroed from a host copy), the
    // cells' reconstructed pressures (1 + 2 D Reals) and the liquid's wall masks.
    const int liquid = D == 2 ? kLiquidFieldCount<2> : kLiquidFieldCount<3>;
    g.backend_each += 2.0 * liquid * kReal + 2 * kReal + 1 + (3 + D) * kReal + (1 + 2 * D) * kReal +
                      (m.walls ? sizeof(WallMask) : 0);
    g.host_each += (3 + D) * kReal;
  }
  e.parts.push_back(g);

  for (std::size_t i = 0; i < m.bodies.size(); ++i) {
    const Model::Body& b = m.bodies[i];
    const int n_ppc = static_cast<int>(i) == body ? ppc : b.ppc;
    MemoryPart p{"body '" + b.name + "'", "particlesPerCell", b.where,
                 D == 2 ? points<2>(*b.dict, h, n_ppc, m.case_dir) : points<3>(*b.dict, h, n_ppc, m.case_dir)};
    if (R > 1) p.rank_share = std::min(1.0, kRebalanceRatio / R);  // the most a rank holds before a recut
    // particle_storage.hpp: x, v, x0 (D each), F (D^2), sigma (4 in 2D, 6 in 3D), mass,
    // volume0, id, C (D^2, APIC), the state, a two-phase body's extra columns (PoreColumn).
    const double columns = 3 * D + D * D + (D == 2 ? 4 : 6) + 3 + (m.apic ? D * D : 0) + b.state_reals +
                           (b.two_phase ? (D == 2 ? kPoreColumns<2> : kPoreColumns<3>) : 0);
    const double block = columns * kReal;
    // particle_sort.hpp: keys and permutation (2 uint32 each, double-buffered), and a
    // scratch block of every column (a block up to 64 MiB) or 4 of them.
    const double chunk = p.count * block <= double(64 << 20) ? columns : std::min(columns, 4.0);
    p.backend_each = block + sizeof(Index) /* the elastic-first split's list */ +
                     (b.turns ? (D == 2 ? Handoff<2>::kColumns : Handoff<3>::kColumns) * kReal : 0) /* its Handoff (particle_pass.hpp) */ +
                     (m.sorts ? 4 * sizeof(std::uint32_t) + chunk * kReal : 0) +
                     (gpu && R == 1 ? block : 0) /* the snapshot's device copy (snapshot_copy.hpp): one
                                                    process's asynchronous output; a rank of a decomposed
                                                    run copies its block to the host directly */;
    // Host, the larger of the setup's and the output's copies. Setup (particle_generation,
    // material_body.hpp): positions and volumes grown by push_back (capacity the next power
    // of 2), velocities and stresses (Sym3), the host block; a two-phase body's pore
    // pressure, saturation, porosity and suction and their copies in the extra columns.
    const double growth = p.count >= 1 ? std::exp2(std::ceil(std::log2(p.count))) / p.count : 1;
    const double setup = growth * (D + 1) * kReal + (D + 6) * kReal + block + (b.two_phase ? 8 * kReal : 0);
    // Output: the host copy of the block (pinned on the GPU), and the fields of three
    // snapshots (one being written, the writer's own copy of it, the next one being
    // taken): position (3), id, velocity, displacement (3 each), stress (6), pressure,
    // deviatoric stress, volume, mass, density, bodyId, the material's and a two-phase
    // body's (two_phase_fields: vectors of 3).
    double two_phase_reals = 0;
    if (b.two_phase)
      for (const FieldInfo& f : two_phase_fields()) two_phase_reals += f.components;
    const double fields = (3 + 1 + 3 + 3 + 6 + 6 + b.output_reals + two_phase_reals) * kReal;
    // A decomposed run: each rank writes its own points as a piece, on its main thread (one
    // snapshot at a time, and the writer's copy of it); the first also gathers the whole
    // case when a function object that does not reduce over ranks is due.
    const double output =
        m.output ? block + (R > 1 ? 2 : 3) * fields : block /* the time step's check reads a host copy */;
    p.host_each = std::max(setup, output);
    if (R > 1 && m.gathers) p.host_root_each = block + 3 * fields;
    e.parts.push_back(p);
  }
  return e;
}

/// "12,345,678", or "5.71e+10" beyond what is read at a glance.
std::string count_text(double n) {
  char buf[48];
  if (n >= 1e15) {
    std::snprintf(buf, sizeof buf, "%.3g", n);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.0f", n);
  std::string s = buf, out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i > 0 && (s.size() - i) % 3 == 0) out += ',';
    out += s[i];
  }
  return out;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

/// The bytes of the space checked (host or device) that part `p` takes.
double part_bytes(const MemoryPart& p, Device space, Device backend) {
  if (space == Device::cuda) return p.backend();
  return (backend == Device::cpu ? p.backend() : 0) + p.host();
}
double total(const MemoryEstimate& e, Device space) { return space == Device::cuda ? e.device_bytes() : e.host_bytes(); }

/// The smallest cell size (3 significant digits, rounded up) at which the case fits in
/// `free` bytes of `space`, or 0 where none found.
double fitting_cell_size(const Model& m, Device space, double free) {
  double lo = m.grid.cell_size, hi = lo;
  for (int i = 0; i < 64 && total(evaluate(m, hi), space) > free; ++i) hi *= 2;
  if (total(evaluate(m, hi), space) > free) return 0;
  for (int i = 0; i < 60; ++i) {
    const double mid = std::sqrt(lo * hi);
    (total(evaluate(m, mid), space) > free ? lo : hi) = mid;
  }
  const double scale = std::pow(10.0, std::floor(std::log10(hi)) - 2);
  double h = std::ceil(hi / scale) * scale;
  if (total(evaluate(m, h), space) > free) h = hi;
  return h;
}

}  // namespace

MemoryEstimate estimate_memory(const Case& c, const Registry& reg, Device device, bool with_output,
                               RankLayout layout) {
  const Model m = read_model(c, reg, device, with_output, layout);
  return evaluate(m, m.grid.cell_size);
}

std::vector<InputError> check_memory(const Case& c, const Registry& reg, Device device, bool with_output,
                                     RankLayout layout) {
  std::vector<InputError> errors;
  const Model m = read_model(c, reg, device, with_output, layout);
  const MemoryEstimate e = evaluate(m, m.grid.cell_size);
  std::vector<Device> spaces{Device::cpu};
  if (device == Device::cuda) spaces.push_back(Device::cuda);
  for (Device space : spaces) {
    const mem::Available a = mem::available(space);
    const double need = total(e, space);
    if (!a.known || need <= static_cast<double>(a.bytes)) continue;
    const double free = static_cast<double>(a.bytes);
    // The driver: the part that takes most of this space.
    std::size_t top = 0;
    for (std::size_t i = 1; i < e.parts.size(); ++i)
      if (part_bytes(e.parts[i], space, device) > part_bytes(e.parts[top], space, device)) top = i;
    const MemoryPart& driver = e.parts[top];
    const char* space_name = space == Device::cuda ? "GPU" : "host";
    // A decomposed run: what one GPU holds, or what the ranks of one machine need of its host.
    const int R = std::max(1, layout.ranks);
    const std::string whose =
        R == 1 ? std::string()
        : space == Device::cuda
            ? " per rank (one GPU each, " + std::to_string(R) + " ranks)"
            : " on each machine (its " + std::to_string(std::max(1, layout.per_node)) + " rank(s) of " +
                  std::to_string(R) + ", each making its own points" +
                  (m.gathers ? ", the first gathering the case for a function object that does not reduce over ranks)"
                             : ")");
    std::string msg = driver.key + ": the run needs about " + mem::format_bytes(need) + " of " + space_name +
                      " memory" + whose + ", more than the " + mem::format_bytes(free) + " free (" + a.source + "): ";
    for (std::size_t i = 0; i < e.parts.size(); ++i) {
      const MemoryPart& p = e.parts[i];
      const double bytes = space == Device::cpu ? (device == Device::cpu ? p.backend() * std::max(1, layout.per_node) : 0) +
                                                      p.node_host(std::max(1, layout.per_node))
                                                : p.backend();
      msg += i ? ", " : "";
      if (i == 0)
        msg += "the grid's " + count_text(p.count) + " nodes (cellSize " + number_text(m.grid.cell_size) + " m at " +
               p.where.str() + ") take " + mem::format_bytes(bytes);
      else
        msg += "the " + count_text(p.count) + " particles of " + p.what + " (particlesPerCell " +
               std::to_string(m.bodies[i - 1].ppc) + " at " + p.where.str() + ") take " + mem::format_bytes(bytes);
      if (p.count > 0) msg += " (" + count_text(std::round(bytes / p.count)) + " bytes each)";
    }
    // What would fit: fewer points in the driving body, or else larger cells.
    std::string fit;
    bool fewer_points = false;
    if (top > 0) {
      const int body = static_cast<int>(top) - 1;
      for (int ppc = m.bodies[body].ppc - 1; ppc >= 1 && !fewer_points; --ppc) {
        const MemoryEstimate f = evaluate(m, m.grid.cell_size, body, ppc);
        if (total(f, space) > free) continue;
        fewer_points = true;
        fit = "particlesPerCell " + std::to_string(ppc) + " fits (" + count_text(f.parts[top].count) +
              " particles, about " + mem::format_bytes(total(f, space)) + ")";
      }
      if (fit.empty() && m.bodies[body].ppc > 1) fit = "particlesPerCell 1 does not fit either";
    }
    if (!fewer_points) {
      const double h = fitting_cell_size(m, space, free);
      if (h > 0) {
        const MemoryEstimate f = evaluate(m, h);
        const std::string cells = "a cellSize of at least " + number_text(h) + " m (" + m.cell_size_where.str() +
                                  ") fits (about " + mem::format_bytes(total(f, space)) + ")";
        fit = fit.empty() ? cells : fit + "; " + cells;
      }
    }
    msg += "; " + (fit.empty() ? std::string("nothing smaller was found to fit") : fit);
    errors.emplace_back(driver.where, msg);
  }
  return errors;
}

}  // namespace scree
