// Solver<D>: what a run decomposed over several ranks adds (case/decomposition.hpp,
// comm/comm.hpp). Each rank holds the points in its box and a grid over the box with a
// halo; per step, after a particle-to-grid pass, neighbours add each other's partial sums
// on the nodes they share (halo_sum), and before the grid update that advances the clock
// the ranks reduce its inputs (reduce_clock: the largest signal speed, which sets the next
// dt, the lost and failed points), so that every rank takes the same steps. At the end of
// each chunk of steps the points migrate to the rank whose box holds them; a chunk is
// short enough that no point moves past the halo within it (migration_steps). Each rank
// makes only the points of its box (decompose_case), writes them as its own piece of every
// frame and checkpoint, and sends them to the root only for function objects and writers
// without pieces, which work on the case as a whole.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>

#include "scree/case/memory_estimate.hpp"
#include "scree/case/particle_generation.hpp"
#include "scree/mpm/halo_slab.hpp"
#include "scree/mpm/particle_storage.hpp"
#include "solver.hpp"

namespace scree {

template <int D>
void Solver<D>::decompose_case() {
  if (porous_)
    throw InputError(case_.bodies().where(),
                     "a case with two-phase bodies runs on one rank; this run has " + std::to_string(comm_->size()) +
                         " (run it without mpirun, or with -np 1)");
  // The points per cell layer along every axis, each body's, from the positions
  // generate_particles makes, in the whole grid's lattice.
  std::vector<std::array<std::vector<std::uint64_t>, D>> per_body;
  std::array<std::vector<std::uint64_t>, D> layers;
  for (int d = 0; d < D; ++d) layers[d].assign(static_cast<std::size_t>(global_.cells[d]), 0);
  for (const Entry* e : case_.body_entries()) {
    auto& h = per_body.emplace_back(layers);
    for_each_particle_position<D>(
        e->dict(), global_,
        [&](const Vec<D>& x) {
          for (int d = 0; d < D; ++d) ++h[d][static_cast<std::size_t>(domain_cell(global_, d, x[d]))];
        },
        case_.dir());
    for (int d = 0; d < D; ++d)
      for (std::size_t c = 0; c < layers[d].size(); ++c) layers[d][c] += h[d][c];
  }
  int a = 0, b = 0;
  stencil_reach(settings_.schemes.shape, a, b);
  try {
    decomp_ = decompose_layers<D>(global_, layers, comm_->size(), comm_->rank(), a, b, kSlackCells);
  } catch (const std::invalid_argument& e) {
    throw InputError(case_.grid().where(), std::string("system/gridDict: cellSize: ") + e.what());
  }
  check_rank_memory(per_body);
  set_local_grid();
}

template <int D>
void Solver<D>::check_rank_memory(const std::vector<std::array<std::vector<std::uint64_t>, D>>& per_body) const {
  // What each rank's backend will hold once the points are cut into its slab: its grid and
  // its points, the most of its share before the cuts move (kRebalanceRatio times the mean)
  // or what it starts with if more, at the bytes per node and point of the memory estimate.
  // The estimate before the run assumed equal shares; here the slabs are known, and a slab
  // over empty space carries a large grid. Every rank knows every slab; only the free
  // memory of each rank's backend is exchanged.
  const int R = comm_->size(), ax = decomp_.axis;
  const MemoryEstimate m = estimate_memory(case_, rt_.registry(), exec_.device, opt_.output, {R, 1});
  std::vector<double> grid_bytes(static_cast<std::size_t>(R)), point_bytes(static_cast<std::size_t>(R), 0.0);
  std::vector<std::uint64_t> points(static_cast<std::size_t>(R), 0);
  for (int r = 0; r < R; ++r) {
    const auto ru = static_cast<std::size_t>(r);
    grid_bytes[ru] = static_cast<double>(decomp_.local[ru].num_nodes()) * m.parts.at(0).backend_each;
    for (std::size_t i = 0; i < per_body.size(); ++i) {
      std::uint64_t n = 0, total = 0;
      for (std::size_t c = 0; c < per_body[i][static_cast<std::size_t>(ax)].size(); ++c) {
        const std::uint64_t k = per_body[i][static_cast<std::size_t>(ax)][c];
        total += k;
        if (static_cast<int>(c) >= decomp_.cuts[ru] && static_cast<int>(c) < decomp_.cuts[ru + 1]) n += k;
      }
      points[ru] += n;
      const double most = std::max(static_cast<double>(n), kRebalanceRatio * static_cast<double>(total) / R);
      point_bytes[ru] += most * m.parts.at(i + 1).backend_each;
    }
  }
  const mem::Available a = mem::available(exec_.device);
  std::vector<std::uint64_t> free(static_cast<std::size_t>(R), 0), known(static_cast<std::size_t>(R), 0);
  free[static_cast<std::size_t>(comm_->rank())] = a.bytes;
  known[static_cast<std::size_t>(comm_->rank())] = a.known ? 1 : 0;
  comm_->sum(free.data(), R);
  comm_->sum(known.data(), R);
  int worst = -1;
  double excess = 0;
  for (int r = 0; r < R; ++r) {
    const auto ru = static_cast<std::size_t>(r);
    const double over = grid_bytes[ru] + point_bytes[ru] - static_cast<double>(free[ru]);
    if (known[ru] && over > excess) {
      excess = over;
      worst = r;
    }
  }
  if (worst < 0) return;
  const auto w = static_cast<std::size_t>(worst);
  const char* space = exec_.device == Device::cuda ? "GPU" : "host";
  std::ostringstream msg;
  const Entry* cell = case_.grid().find("cellSize");
  msg << "cellSize: rank " << worst << " of " << R << " needs about " << mem::format_bytes(grid_bytes[w] + point_bytes[w])
      << " of " << space << " memory, more than the " << mem::format_bytes(static_cast<double>(free[w])) << " free"
      << (worst == comm_->rank() ? " (" + a.source + ")" : std::string()) << ": its slab, cells [" << decomp_.cuts[w]
      << ", " << decomp_.cuts[w + 1] << ") across axis " << ax << ", holds " << decomp_.local[w].num_nodes()
      << " grid nodes (" << mem::format_bytes(grid_bytes[w]) << ") and " << points[w] << " points ("
      << mem::format_bytes(point_bytes[w]) << ", allowing for " << kRebalanceRatio
      << " times the mean share before the cuts move). The slabs are cut for equal points, so a slab over empty "
         "space holds a large grid: run on more ranks, narrow the domain to where the material goes, or coarsen "
         "cellSize; nothing was allocated";
  throw InputError(cell ? cell->where() : case_.grid().where(), msg.str());
}

template <int D>
void Solver<D>::report_decomposition() {
  std::ostringstream m;
  m << "Decomposed over " << comm_->size() << " ranks (" << comm_->describe() << "): slabs across axis "
    << decomp_.axis << ", cells";
  for (int r = 0; r < comm_->size(); ++r)
    m << " [" << decomp_.cuts[static_cast<std::size_t>(r)] << ", " << decomp_.cuts[static_cast<std::size_t>(r) + 1]
      << ")";
  std::uint64_t mine = 0;
  for (auto& bd : bodies_) mine += static_cast<std::uint64_t>(bd->size());
  std::vector<std::uint64_t> held(static_cast<std::size_t>(comm_->size()), 0);
  held[static_cast<std::size_t>(comm_->rank())] = mine;
  comm_->sum(held.data(), comm_->size());
  m << ", points per rank";
  for (auto h : held) m << " " << h;
  log_ << m.str() << std::endl;
}

template <int D>
void Solver<D>::set_local_grid() {
  // This rank's grid: its box with the halo, owning its box's nodes along the cut axis.
  static_cast<GridGeometry<D>&>(grid_) = decomp_.grid();
  for (int d = 0; d < D; ++d) {
    grid_.cells[d] = grid_.n[d] - 1 - 2 * grid_.ghost;
    grid_.owned.lo[d] = 0;
    grid_.owned.hi[d] = grid_.n[d];
  }
  decomp_.owned_local(grid_.owned.lo[decomp_.axis], grid_.owned.hi[decomp_.axis]);
  allocate_grid();
  for (int d = 0; d < D; ++d) {  // the boundary conditions' faces are the whole domain's
    ctx_.domain_lower[static_cast<std::size_t>(d)] = global_.lower[d];
    ctx_.domain_upper[static_cast<std::size_t>(d)] = global_.upper[d];
  }
  ctx_.start_time = run_start_;
}

template <int D>
void Solver<D>::adopt(Decomposition<D> d) {
  decomp_ = std::move(d);
  set_local_grid();
  setup_boundaries(false);
  setup_passes();
}

template <int D>
void Solver<D>::apply_recut() {
  flush();  // the pending G2P reads the grid sets, which are about to be made anew
  mem::synchronize(exec_.device);
  adopt(std::move(*recut_));
  recut_.reset();
  ++rebalances_;
  std::ostringstream m;
  m << "rebalanced at t = " << time() << " s: cells";
  for (int r = 0; r < comm_->size(); ++r)
    m << " [" << decomp_.cuts[static_cast<std::size_t>(r)] << ", " << decomp_.cuts[static_cast<std::size_t>(r) + 1]
      << ")";
  log_ << m.str() << "\n";
}

template <int D>
std::vector<Real> Solver<D>::keep_own(const std::vector<Real>& block, Index n, Index& kept) const {
  using S = ParticleStorage<D>;
  const std::size_t C = n > 0 ? block.size() / static_cast<std::size_t>(n) : 0;
  std::vector<Index> own;
  const std::size_t xa = static_cast<std::size_t>(S::kColX + decomp_.axis) * n;
  for (Index p = 0; p < n; ++p)
    if (decomp_.owner(block[xa + p], global_) == comm_->rank()) own.push_back(p);
  kept = static_cast<Index>(own.size());
  std::vector<Real> out(C * own.size());
  for (std::size_t c = 0; c < C; ++c)
    for (std::size_t j = 0; j < own.size(); ++j) out[c * own.size() + j] = block[c * n + own[j]];
  return out;
}

template <int D>
void Solver<D>::exchange_before_grid(int set, unsigned modes) {
  // Profiled, a barrier first separates the wait for the slowest rank (the imbalance of
  // the passes before it) from the exchanges' own cost; unprofiled runs have no barrier.
  if (opt_.profile) phase("ranks: wait for the slowest rank", [&] { comm_->barrier(); });
  phase("ranks: halo sum", [&] {
    sync_control_from_device();
    halo_sum(set, scattered_);
    scattered_ = 0;
  });
  if (modes & kAdvance) phase("ranks: clock reduction", [&] { reduce_clock(); });
}

template <int D>
void Solver<D>::halo_sum(int set, unsigned scattered) {
  SlabFields fields;
  const GridFields<D>& g = sets_[set];
  if (scattered & kScatterMassMomentum) {
    fields.field[fields.count++] = g.mass;
    for (int d = 0; d < D; ++d) fields.field[fields.count++] = g.momentum[d];
  }
  if (scattered & (kScatterForce | kScatterMomentum))  // MUSL re-maps momentum into the force array
    for (int d = 0; d < D; ++d) fields.field[fields.count++] = g.force[d];
  if (fields.count == 0) return;
  const int ax = decomp_.axis;
  const int me = comm_->rank();
  // Both neighbours at once: the slabs shared with each are packed side by side into one
  // block, copied to the host in one copy, exchanged with both in flight together, copied
  // back in one copy and added. A rank's two slabs are disjoint (a box is at least the halo
  // wide), so the order of their sums changes no bit, and no pair waits for another.
  struct Slab {
    int peer, lo, hi;
    std::size_t offset, n;
  };
  Slab slab[2];
  int count = 0;
  std::size_t total = 0;
  for (int peer : {me - 1, me + 1}) {
    if (peer < 0 || peer >= comm_->size()) continue;
    int lo = 0, hi = 0;
    decomp_.overlap(peer, lo, hi);
    if (hi <= lo) continue;
    const std::size_t n = static_cast<std::size_t>(slab_size<D>(grid_, ax, lo, hi) * fields.count);
    slab[count++] = Slab{peer, lo, hi, total, n};
    total += n;
  }
  if (count == 0) return;
  if (halo_buffer_.size() < total) halo_buffer_.resize(total, exec_.device);
  halo_send_.reserve(total);
  halo_recv_.reserve(total);
  for (int i = 0; i < count; ++i)
    pack_slab<D>(exec_, grid_, ax, slab[i].lo, slab[i].hi, fields, halo_buffer_.data() + slab[i].offset);
  mem::synchronize(exec_.device);
  mem::copy(halo_send_.data(), Device::cpu, halo_buffer_.data(), exec_.device, total * sizeof(Real));
  Comm::Exchange with[2];
  for (int i = 0; i < count; ++i)
    with[i] = Comm::Exchange{slab[i].peer, halo_send_.data() + slab[i].offset, slab[i].n * sizeof(Real),
                             halo_recv_.data() + slab[i].offset, slab[i].n * sizeof(Real)};
  comm_->exchange(with, count);
  mem::copy(halo_buffer_.data(), exec_.device, halo_recv_.data(), Device::cpu, total * sizeof(Real));
  mem::synchronize(exec_.device);  // the copy landed before the stream's kernel reads it
  for (int i = 0; i < count; ++i) {
    // Both ranks add the same two partial sums: their copies of a shared node are equal bit for bit.
    add_slab<D>(exec_, grid_, ax, slab[i].lo, slab[i].hi, fields, halo_buffer_.data() + slab[i].offset);
    // The sparse grid update visits only stamped tiles: the shared slab's may hold sums
    // that only the neighbour's points made.
    if (policy_.sparse())
      stamp_slab_tiles<D>(exec_, grid_, ax, slab[i].lo, slab[i].hi, tile_stamps_[set].data(),
                          tile_stamp(host_ctl_.step[parity()]));
  }
}

template <int D>
void Solver<D>::reduce_clock() {
  const int p = parity();
  StepControl& c = host_ctl_;
  double speed = c.max_speed[p];
  comm_->max(&speed, 1);
  // lost points, non-finite nodes, and the ranks whose clock has stopped
  std::uint64_t counts[3] = {c.lost, c.bad.count, c.failure != 0 ? 1u : 0u};
  comm_->sum(counts, 3);
  c.max_speed[p] = speed;
  unsigned fail = 0;
  if (lost_stop_global_ > 0 && counts[0] >= lost_stop_global_) fail |= kFailLost;
  if ((counts[1] > 0 || counts[2] > 0) && c.failure == 0 && c.bad.count == 0) fail |= kFailElsewhere;
  if (fail != 0 && c.failure == 0) {
    c.failure = fail;
    c.failed_step = c.step[p];
    c.failed_co = c.dt[p] * speed / c.h;
  }
  sync_control_to_device();
}

template <int D>
void Solver<D>::agree_chunk(std::int64_t& n, double& t_event) {
  struct {
    std::int64_t n;
    double t_event;
  } agreed{std::min(n, std::max<std::int64_t>(1, next_migration_ - steps_done())), t_event};
  comm_->broadcast(&agreed, sizeof agreed, 0);
  n = agreed.n;
  t_event = agreed.t_event;
}

template <int D>
int Solver<D>::agree_signal() {
  return static_cast<int>(comm_->max(static_cast<std::uint64_t>(stop_requested())));
}

template <int D>
void Solver<D>::check_health_ranks() {
  const int R = comm_->size();
  std::vector<std::uint64_t> own(static_cast<std::size_t>(R), 0);
  own[static_cast<std::size_t>(comm_->rank())] = host_ctl_.failure & ~static_cast<unsigned>(kFailElsewhere);
  comm_->sum(own.data(), R);
  int who = -1;
  for (int r = 0; r < R && who < 0; ++r)
    if (own[static_cast<std::size_t>(r)] != 0) who = r;
  if (who < 0) return;
  std::string msg = comm_->rank() == who ? diagnosis() : std::string();
  std::uint64_t len = msg.size();
  comm_->broadcast(&len, sizeof len, who);
  msg.resize(len);
  comm_->broadcast(msg.data(), len, who);
  if (host_ctl_.failure == 0) host_ctl_.failure = kFailElsewhere;
  throw RunFailure("rank " + std::to_string(who) + " of " + std::to_string(R) + ": " + msg);
}

template <int D>
std::int64_t Solver<D>::migration_steps() const {
  // No point moves more than half the slack within a chunk: in M steps of dt a point at
  // speed v under gravity g moves at most v M dt + g (M dt)^2 / 2 (v of the last
  // migration, doubled for what it gains in between), and with an adaptive step at most
  // maxCo cells a step.
  const double s = 0.5 * kSlackCells * grid_.h;
  const double dt = host_ctl_.dt[parity()] > 0 ? host_ctl_.dt[parity()] : host_ctl_.dt_max;
  double g = 0;
  for (int d = 0; d < D; ++d) g += gravity_[d] * gravity_[d];
  g = std::sqrt(g);
  const double v = 2 * vmax_;
  double m = 1e6;
  if (dt > 0) {
    // v T + g T^2 / 2 = s for T = M dt
    const double T = g > 0 ? (-v + std::sqrt(v * v + 2 * g * s)) / g : (v > 0 ? s / v : 1e300);
    m = std::min(m, T / dt);
  }
  if (host_ctl_.cfl > 0) m = std::max(m, s / (host_ctl_.cfl * grid_.h));
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor(m)));
}

template <int D>
void Solver<D>::migrate(bool scheduled) {
  using S = ParticleStorage<D>;
  if (recut_ && scheduled) apply_recut();
  mem::synchronize(exec_.device);
  const int R = comm_->size(), me = comm_->rank(), ax = decomp_.axis;
  int a = 0, b = 0;
  stencil_reach(settings_.schemes.shape, a, b);
  double vmax = 0;
  std::uint64_t past = 0;  // points frozen inside the domain: they left this rank's grid, not the case's
  std::vector<std::uint64_t> layers(static_cast<std::size_t>(global_.cells[ax]), 0);  // points per cell layer
  for (auto& body : bodies_) {
    const Index n = body->size();
    const std::size_t C = body->bytes_per_particle() / sizeof(Real);
    std::vector<Real> block = body->save_state();
    auto at = [&](int col, Index p) { return block[static_cast<std::size_t>(col) * n + p]; };
    std::vector<std::vector<Real>> out(static_cast<std::size_t>(R));
    std::vector<Index> stay;
    stay.reserve(static_cast<std::size_t>(n));
    for (Index p = 0; p < n; ++p) {
      if (at(S::kColVolume0, p) < 0) {  // frozen where it left this rank's grid
        const double c = std::floor((at(S::kColX + ax, p) - global_.origin[ax]) / global_.h);
        if (c - a >= 0 && c + b <= global_.n[ax] - 1) ++past;
        stay.push_back(p);
        continue;
      }
      double v2 = 0;
      for (int d = 0; d < D; ++d) v2 += at(S::kColV + d, p) * at(S::kColV + d, p);
      vmax = std::max(vmax, std::sqrt(v2));
      const int cell = domain_cell(global_, ax, at(S::kColX + ax, p));
      ++layers[static_cast<std::size_t>(cell)];
      const int dest = decomp_.owner_of_cell(cell);
      if (dest == me) {
        stay.push_back(p);
        continue;
      }
      auto& o = out[static_cast<std::size_t>(dest)];
      for (std::size_t c = 0; c < C; ++c) o.push_back(block[c * n + p]);
    }
    std::vector<char> send;
    std::vector<std::size_t> counts(static_cast<std::size_t>(R), 0);
    for (int r = 0; r < R; ++r) {
      const auto& o = out[static_cast<std::size_t>(r)];
      counts[static_cast<std::size_t>(r)] = o.size() * sizeof(Real);
      send.insert(send.end(), reinterpret_cast<const char*>(o.data()),
                  reinterpret_cast<const char*>(o.data() + o.size()));
    }
    std::vector<char> recv;
    comm_->all_to_all(send, counts, recv);
    const std::size_t arrived = C > 0 ? recv.size() / (C * sizeof(Real)) : 0;
    if (arrived == 0 && stay.size() == static_cast<std::size_t>(n)) continue;  // nothing moved
    // The points that stay, in their order, then the arrivals in the senders' rank order.
    const std::size_t m = stay.size() + arrived;
    std::vector<Real> next(C * m);
    std::vector<Real> in(arrived * C);
    if (!recv.empty()) std::memcpy(in.data(), recv.data(), recv.size());
    for (std::size_t c = 0; c < C; ++c) {
      Real* dst = next.data() + c * m;
      for (std::size_t j = 0; j < stay.size(); ++j) dst[j] = block[c * n + stay[j]];
      for (std::size_t k = 0; k < arrived; ++k) dst[stay.size() + k] = in[k * C + c];
    }
    body->replace_state(next, static_cast<Index>(m));
  }
  vmax_ = comm_->max(vmax);
  past = comm_->sum(past);
  ++migrations_;
  if (past > 0) {
    std::ostringstream m;
    m << past << " point(s) moved more than " << kSlackCells
      << " cells past the box of the rank that held them between two migrations of points (a chunk of at most "
      << migration_limit_ << " steps, from the fastest point of the last migration, " << vmax_
      << " m/s, and gravity) at t = " << time()
      << " s: the flow accelerated faster than the migration interval assumed. Run on fewer ranks, or with a "
         "smaller deltaT (maxCo)";
    host_ctl_.failure |= kFailHalo;
    throw RunFailure(m.str());
  }
  migration_limit_ = migration_steps();
  next_migration_ = steps_done() + migration_limit_;
  // Load balance: the points per rank from the global histogram; cut anew above the ratio.
  comm_->sum(layers.data(), static_cast<int>(layers.size()));
  std::uint64_t most = 0, all = 0;
  for (int r = 0; r < R; ++r) {
    std::uint64_t held = 0;
    for (int c = decomp_.cuts[static_cast<std::size_t>(r)]; c < decomp_.cuts[static_cast<std::size_t>(r) + 1]; ++c)
      held += layers[static_cast<std::size_t>(c)];
    most = std::max(most, held);
    all += held;
  }
  if (all > 0 && static_cast<double>(most) * R > kRebalanceRatio * static_cast<double>(all)) {
    Decomposition<D> next = cut_slabs<D>(global_, layers, ax, R, me, a, b, decomp_.slack);
    if (next.cuts != decomp_.cuts) recut_ = std::move(next);
  }
}

template <int D>
void Solver<D>::gather_snapshot(Snapshot& s) {
  comm_->sum(s.energy.term, kEnergyTerms);
  for (BodySnapshot& b : s.bodies) {
    std::vector<std::int64_t> ids = comm_->gather_vector(b.id, 0);
    std::vector<Real> pos = comm_->gather_vector(b.position, 0);
    std::vector<std::uint8_t> lost = comm_->gather_vector(b.lost, 0);
    std::vector<std::vector<Real>> values;
    for (FieldData& f : b.fields) values.push_back(comm_->gather_vector(f.values, 0));
    if (!root()) {
      b.n = 0;
      b.id.clear();
      b.position.clear();
      b.lost.clear();
      for (FieldData& f : b.fields) f.values.clear();
      continue;
    }
    // In the order of the ids: the output of a decomposed run does not depend on which
    // rank held which point.
    const std::size_t n = ids.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return ids[i] < ids[j]; });
    b.n = static_cast<Index>(n);
    b.id.resize(n);
    b.position.resize(3 * n);
    b.lost.resize(lost.empty() ? 0 : n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = order[k];
      b.id[k] = ids[i];
      for (int d = 0; d < 3; ++d) b.position[3 * k + d] = pos[3 * i + d];
      if (!lost.empty()) b.lost[k] = lost[i];
    }
    for (std::size_t f = 0; f < b.fields.size(); ++f) {
      const int comps = b.fields[f].components;
      auto& v = b.fields[f].values;
      v.resize(static_cast<std::size_t>(comps) * n);
      for (std::size_t k = 0; k < n; ++k)
        for (int c = 0; c < comps; ++c) v[comps * k + c] = values[f][comps * order[k] + c];
    }
  }
  if (s.has_grid) gather_grid(s);
}

template <int D>
void Solver<D>::gather_grid(Snapshot& s) {
  // Each rank's owned node layers (along the cut axis; every node along the others), in
  // its local order, placed into the global grid by the root.
  const int ax = decomp_.axis;
  int lo = 0, hi = 0;
  decomp_.owned_local(lo, hi);
  auto in_owned = [&](const GridGeometry<D>& g, int olo, int ohi, Index f) {
    const Index i = (f / g.stride(ax)) % g.n[ax];
    return i >= olo && i < ohi;
  };
  for (FieldData& fd : s.grid.fields) {
    std::vector<Real> mine;
    const Index nn = grid_.num_nodes();
    for (Index f = 0; f < nn; ++f)
      if (in_owned(grid_, lo, hi, f))
        for (int c = 0; c < fd.components; ++c) mine.push_back(fd.values[static_cast<std::size_t>(fd.components * f + c)]);
    std::vector<std::size_t> counts;
    std::vector<Real> all = comm_->gather_vector(mine, 0, &counts);
    if (!root()) {
      fd.values.clear();
      continue;
    }
    const Index gn = global_.num_nodes();
    fd.values.assign(static_cast<std::size_t>(gn * fd.components), 0.0);
    std::size_t k = 0;
    for (int r = 0; r < comm_->size(); ++r) {
      const GridGeometry<D>& g = decomp_.local[static_cast<std::size_t>(r)];
      const int olo = decomp_.owned[static_cast<std::size_t>(r)] - g.offset[ax];
      const int ohi = decomp_.owned[static_cast<std::size_t>(r) + 1] - g.offset[ax];
      for (Index f = 0; f < g.num_nodes(); ++f) {
        if (!in_owned(g, olo, ohi, f)) continue;
        int idx[D];
        g.unflat(f, idx);
        for (int d = 0; d < D; ++d) idx[d] += g.offset[d];
        const Index gf = global_.flat(idx);
        for (int c = 0; c < fd.components; ++c) fd.values[static_cast<std::size_t>(fd.components * gf + c)] = all[k++];
      }
    }
  }
  if (root())
    for (int d = 0; d < D; ++d) {
      s.grid.n[d] = global_.n[d];
      s.grid.origin[d] = global_.origin[d];
    }
}

template <int D>
void Solver<D>::reduce_checkpoint_clock(Checkpoint& ck) {
  // The clock's per-rank counts summed: the lost points and the energy ledger; its speed the largest.
  StepControl c{};
  std::memcpy(&c, ck.clock.data(), sizeof c);
  c.lost = comm_->sum(static_cast<std::uint64_t>(c.lost));
  comm_->sum(c.energy, kEnergyTerms);
  // The signal speed each rank's flush measured (the next step's dt takes the largest).
  comm_->max(c.max_speed, 2);
  std::memcpy(ck.clock.data(), &c, sizeof c);
}

template void Solver<2>::set_local_grid();
template void Solver<3>::set_local_grid();
template void Solver<2>::adopt(Decomposition<2>);
template void Solver<3>::adopt(Decomposition<3>);
template void Solver<2>::apply_recut();
template void Solver<3>::apply_recut();
template void Solver<2>::decompose_case();
template void Solver<3>::decompose_case();
template void Solver<2>::check_rank_memory(const std::vector<std::array<std::vector<std::uint64_t>, 2>>&) const;
template void Solver<3>::check_rank_memory(const std::vector<std::array<std::vector<std::uint64_t>, 3>>&) const;
template void Solver<2>::report_decomposition();
template void Solver<3>::report_decomposition();
template std::vector<Real> Solver<2>::keep_own(const std::vector<Real>&, Index, Index&) const;
template std::vector<Real> Solver<3>::keep_own(const std::vector<Real>&, Index, Index&) const;
template void Solver<2>::exchange_before_grid(int, unsigned);
template void Solver<3>::exchange_before_grid(int, unsigned);
template void Solver<2>::halo_sum(int, unsigned);
template void Solver<3>::halo_sum(int, unsigned);
template void Solver<2>::agree_chunk(std::int64_t&, double&);
template void Solver<3>::agree_chunk(std::int64_t&, double&);
template int Solver<2>::agree_signal();
template int Solver<3>::agree_signal();
template void Solver<2>::check_health_ranks();
template void Solver<3>::check_health_ranks();
template void Solver<2>::reduce_clock();
template void Solver<3>::reduce_clock();
template std::int64_t Solver<2>::migration_steps() const;
template std::int64_t Solver<3>::migration_steps() const;
template void Solver<2>::migrate(bool);
template void Solver<3>::migrate(bool);
template void Solver<2>::gather_snapshot(Snapshot&);
template void Solver<3>::gather_snapshot(Snapshot&);
template void Solver<2>::gather_grid(Snapshot&);
template void Solver<3>::gather_grid(Snapshot&);
template void Solver<2>::reduce_checkpoint_clock(Checkpoint&);
template void Solver<3>::reduce_checkpoint_clock(Checkpoint&);

}  // namespace scree
