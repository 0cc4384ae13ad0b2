// Solver<D>: what a run decomposed over several ranks adds (case/decomposition.hpp,
// comm/comm.hpp). Each rank holds the points in its box and a grid over the box with a
// halo; per step, after a particle-to-grid pass, neighbours exchange their partial sums on
// the nodes they share and each adds them in the ranks' order (halo_sum), and before the grid update that advances the clock
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
#include "scree/mpm/particle_storage.hpp"
#include "solver.hpp"

namespace scree {

template <int D>
void Solver<D>::decompose_case() {
  // The boxes from the positions generate_particles will make, in the whole grid's lattice,
  // counted alike on every rank (no reduction): one walk over every body per level of the
  // bisection tree.
  const std::vector<const Entry*> entries = case_.body_entries();
  auto walk = [&](const std::function<void(std::size_t, const int*)>& at) {
    for (std::size_t i = 0; i < entries.size(); ++i)
      for_each_particle_position<D>(
          entries[i]->dict(), global_,
          [&](const Vec<D>& x) {
            int c[D];
            for (int d = 0; d < D; ++d) c[d] = domain_cell(global_, d, x[d]);
            at(i, c);
          },
          case_.dir());
  };
  const CountBoxes<D> count = [&](const std::vector<CellBox<D>>& boxes, const std::function<int(const int*)>& which) {
    std::vector<LayerCounts<D>> h(boxes.size());
    for (std::size_t k = 0; k < boxes.size(); ++k)
      for (int d = 0; d < D; ++d) h[k][d].assign(static_cast<std::size_t>(boxes[k].hi[d] - boxes[k].lo[d]), 0);
    walk([&](std::size_t, const int* c) {
      const int k = which(c);
      if (k < 0) return;
      for (int d = 0; d < D; ++d) ++h[static_cast<std::size_t>(k)][d][static_cast<std::size_t>(c[d] - boxes[static_cast<std::size_t>(k)].lo[d])];
    });
    return h;
  };
  int a = 0, b = 0;
  stencil_reach(settings_.schemes.shape, a, b);
  try {
    decomp_ = bisect<D>(global_, comm_->size(), comm_->rank(), a, b, kSlackCells, count);
  } catch (const std::invalid_argument& e) {
    throw InputError(case_.grid().where(), std::string("system/gridDict: cellSize: ") + e.what());
  }
  // Each body's points in each rank's box: what the cuts counted for one body, one more
  // walk for several.
  const std::size_t R = static_cast<std::size_t>(comm_->size());
  std::vector<std::vector<std::uint64_t>> per_body(entries.size(), std::vector<std::uint64_t>(R, 0));
  std::vector<std::uint64_t> totals(entries.size(), 0);
  if (entries.size() == 1)
    per_body[0] = decomp_.counted;
  else
    walk([&](std::size_t i, const int* c) { ++per_body[i][static_cast<std::size_t>(decomp_.owner_of_cell(c))]; });
  for (std::size_t i = 0; i < entries.size(); ++i)
    for (auto n : per_body[i]) totals[i] += n;
  check_rank_memory(per_body, totals);
  set_local_grid();
}

template <int D>
void Solver<D>::check_rank_memory(const std::vector<std::vector<std::uint64_t>>& per_body,
                                  const std::vector<std::uint64_t>& totals) const {
  // What each rank's backend will hold once the points are cut into its box: its grid and
  // its points, the most of its share before the boxes move (kRebalanceRatio times the
  // mean) or what it starts with if more, at the bytes per node and point of the memory
  // estimate. The estimate before the run assumed equal shares; here the boxes are known,
  // and a box over empty space carries a large grid. Every rank knows every box; only the
  // free memory of each rank's backend is exchanged.
  const int R = comm_->size();
  const MemoryEstimate m = estimate_memory(case_, rt_.registry(), exec_.device, opt_.output, {R, 1});
  std::vector<double> grid_bytes(static_cast<std::size_t>(R)), point_bytes(static_cast<std::size_t>(R), 0.0);
  std::vector<std::uint64_t> points(static_cast<std::size_t>(R), 0);
  for (int r = 0; r < R; ++r) {
    const auto ru = static_cast<std::size_t>(r);
    grid_bytes[ru] = static_cast<double>(decomp_.local[ru].num_nodes()) * m.parts.at(0).backend_each;
    for (std::size_t i = 0; i < per_body.size(); ++i) {
      const std::uint64_t n = per_body[i][ru];
      points[ru] += n;
      const double most = std::max(static_cast<double>(n), kRebalanceRatio * static_cast<double>(totals[i]) / R);
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
      << (worst == comm_->rank() ? " (" + a.source + ")" : std::string()) << ": its box, cells "
      << decomp_.describe_box(worst) << ", holds " << decomp_.local[w].num_nodes() << " grid nodes ("
      << mem::format_bytes(grid_bytes[w]) << ") and " << points[w] << " points (" << mem::format_bytes(point_bytes[w])
      << ", allowing for " << kRebalanceRatio
      << " times the mean share before the boxes move). The boxes are cut for equal points, so a box over empty "
         "space holds a large grid: run on more ranks, narrow the domain to where the material goes, or coarsen "
         "cellSize; nothing was allocated";
  throw InputError(cell ? cell->where() : case_.grid().where(), msg.str());
}

template <int D>
void Solver<D>::report_decomposition() {
  std::ostringstream m;
  m << "Decomposed over " << comm_->size() << " ranks (" << comm_->describe()
    << (exec_.device == Device::cpu ? ""
        : halo_direct() ? "; the halo goes from GPU memory to GPU memory"
                        : "; GPU buffers are staged through the host")
    << "): boxes of cells";
  for (int r = 0; r < comm_->size(); ++r) m << (r ? ", " : " ") << decomp_.describe_box(r);
  std::uint64_t mine = 0;
  for (auto& bd : bodies_) mine += static_cast<std::uint64_t>(bd->size());
  std::vector<std::uint64_t> held(static_cast<std::size_t>(comm_->size()), 0);
  held[static_cast<std::size_t>(comm_->rank())] = mine;
  comm_->sum(held.data(), comm_->size());
  m << "; points per rank";
  for (auto h : held) m << " " << h;
  log_ << m.str() << std::endl;
}

template <int D>
void Solver<D>::set_local_grid() {
  // This rank's grid: its box with the halo, owning its box's nodes.
  static_cast<GridGeometry<D>&>(grid_) = decomp_.grid();
  for (int d = 0; d < D; ++d) grid_.cells[d] = grid_.n[d] - 1 - 2 * grid_.ghost;
  grid_.owned = decomp_.owned_local();
  allocate_grid();
  for (int d = 0; d < D; ++d) {  // the boundary conditions' faces are the whole domain's
    ctx_.domain_lower[static_cast<std::size_t>(d)] = global_.lower[d];
    ctx_.domain_upper[static_cast<std::size_t>(d)] = global_.upper[d];
  }
  ctx_.start_time = run_start_;
  // The boxes shared with each neighbour, in ascending rank order (halo_sum).
  halo_peers_.clear();
  halo_self_ = 0;
  for (int q : decomp_.neighbours) {
    NodeRange<D> shared;
    decomp_.overlap(q, shared);
    HaloPeer<D> p;
    for (int d = 0; d < D; ++d) {
      p.lo[d] = shared.lo[d];
      p.hi[d] = shared.hi[d];
    }
    p.size = p.nodes();
    p.offset = halo_peers_.empty() ? 0 : halo_peers_.back().offset + halo_peers_.back().size;
    halo_peers_.push_back(p);
    if (q < comm_->rank()) ++halo_self_;
  }
  halo_peers_dev_.resize(halo_peers_.size(), exec_.device);
  if (!halo_peers_.empty()) halo_peers_dev_.copy_from_host(halo_peers_);
  if (porous_) {
    porous_->set_grid(grid_);
    set_porous_halo();
  }
}

template <int D>
void Solver<D>::set_porous_halo() {
  typename PorousMedia<D>::Halo h;
  h.sum = [this](const HaloFields& f) { halo_exchange(f); };
  h.clear = [this](const HaloFields& f) {
    for (const HaloPeer<D>& p : halo_peers_) clear_box<D>(exec_, grid_, p, f);
  };
  h.owned = owned_nodes();
  porous_->set_halo(std::move(h));
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
  m << "rebalanced at t = " << time() << " s: boxes of cells";
  for (int r = 0; r < comm_->size(); ++r) m << (r ? ", " : " ") << decomp_.describe_box(r);
  log_ << m.str() << "\n";
}

template <int D>
std::vector<Real> Solver<D>::keep_own(const std::vector<Real>& block, Index n, Index& kept) const {
  using S = ParticleStorage<D>;
  const std::size_t C = n > 0 ? block.size() / static_cast<std::size_t>(n) : 0;
  std::vector<Index> own;
  for (Index p = 0; p < n; ++p) {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = block[static_cast<std::size_t>(S::kColX + d) * n + p];
    if (decomp_.owner(x, global_) == comm_->rank()) own.push_back(p);
  }
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
  HaloFields fields;
  const GridFields<D>& g = sets_[set];
  if (scattered & kScatterMassMomentum) {
    fields.add(g.mass);
    for (int d = 0; d < D; ++d) fields.add(g.momentum[d]);
  }
  if (scattered & (kScatterForce | kScatterMomentum))  // MUSL re-maps momentum into the force array
    for (int d = 0; d < D; ++d) fields.add(g.force[d]);
  halo_exchange(fields);
  // The sparse grid update visits only stamped tiles: the shared boxes may hold sums that
  // only a neighbour's points made.
  if (fields.count > 0 && policy_.sparse())
    for (const HaloPeer<D>& p : halo_peers_)
      stamp_box_tiles<D>(exec_, grid_, p, tile_stamps_[set].data(), tile_stamp(host_ctl_.step[parity()]));
}

template <int D>
void Solver<D>::halo_exchange(const HaloFields& fields) {
  const int count = static_cast<int>(halo_peers_.size());
  if (fields.count == 0 || count == 0) return;
  // Every neighbour at once: the boxes shared with each are packed side by side into one
  // block, exchanged with all in flight together and summed in the ranks' order
  // (ordered_sum). The block goes to MPI as it is where MPI can read the backend's memory
  // (the CPU backend; a CUDA-aware MPI), else through host buffers, one copy each way.
  const HaloPeer<D>& last = halo_peers_.back();
  const std::size_t total = static_cast<std::size_t>((last.offset + last.size) * fields.count);
  const bool direct = halo_direct();
  if (halo_buffer_.size() < total) halo_buffer_.resize(total, exec_.device);
  if (direct && halo_arrived_.size() < total) halo_arrived_.resize(total, exec_.device);
  if (!direct) {
    halo_send_.reserve(total);
    halo_recv_.reserve(total);
  }
  for (const HaloPeer<D>& p : halo_peers_) pack_box<D>(exec_, grid_, p, fields, halo_buffer_.data());
  mem::synchronize(exec_.device);
  if (!direct) mem::copy(halo_send_.data(), Device::cpu, halo_buffer_.data(), exec_.device, total * sizeof(Real));
  Real* const send = direct ? halo_buffer_.data() : halo_send_.data();
  Real* const recv = direct ? halo_arrived_.data() : halo_recv_.data();
  std::vector<Comm::Exchange> with(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const HaloPeer<D>& p = halo_peers_[static_cast<std::size_t>(i)];
    const std::size_t bytes = static_cast<std::size_t>(p.size * fields.count) * sizeof(Real);
    const Index at = p.offset * fields.count;
    with[static_cast<std::size_t>(i)] =
        Comm::Exchange{decomp_.neighbours[static_cast<std::size_t>(i)], send + at, bytes, recv + at, bytes};
  }
  comm_->exchange(with.data(), count);
  if (!direct) {
    mem::copy(halo_buffer_.data(), exec_.device, halo_recv_.data(), Device::cpu, total * sizeof(Real));
    mem::synchronize(exec_.device);  // the copy landed before the stream's kernel reads it
  }
  ordered_sum<D>(exec_, grid_, halo_peers_dev_.data(), halo_peers_.data(), count, halo_self_, fields,
                 direct ? halo_arrived_.data() : halo_buffer_.data());
}

template <int D>
bool Solver<D>::halo_direct() const {
  return exec_.device == Device::cpu || comm_->device_aware();
}

template <int D>
OwnedNodes<D> Solver<D>::owned_nodes() const {
  OwnedNodes<D> o;
  if (!decomposed()) return o;
  const NodeRange<D> own = decomp_.owned_local();
  o.all = false;
  for (int d = 0; d < D; ++d) {
    o.lo[d] = own.lo[d];
    o.hi[d] = own.hi[d];
  }
  return o;
}

template <int D>
std::vector<Real> Solver<D>::liquid_totals() const {
  std::vector<Real> t = porous_->totals();
  if (decomposed()) comm_->sum(t.data(), static_cast<int>(t.size()));
  return t;
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
  // The diagnosis reads the points after the pending G2P, whose pore-liquid gather sums
  // over the ranks: every rank applies it first.
  flush();
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
  const int R = comm_->size(), me = comm_->rank();
  int a = 0, b = 0;
  stencil_reach(settings_.schemes.shape, a, b);
  double vmax = 0;
  std::uint64_t past = 0;  // points frozen inside the domain: they left this rank's grid, not the case's
  std::uint64_t held = 0;  // the points this rank holds once they have migrated
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
        bool inside = true;
        for (int d = 0; d < D; ++d) {
          const double c = std::floor((at(S::kColX + d, p) - global_.origin[d]) / global_.h);
          inside = inside && c - a >= 0 && c + b <= global_.n[d] - 1;
        }
        if (inside) ++past;
        stay.push_back(p);
        continue;
      }
      double v2 = 0;
      int cell[D];
      for (int d = 0; d < D; ++d) {
        v2 += at(S::kColV + d, p) * at(S::kColV + d, p);
        cell[d] = domain_cell(global_, d, at(S::kColX + d, p));
      }
      vmax = std::max(vmax, std::sqrt(v2));
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
    held += stay.size() + arrived;
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
  // Load balance: cut anew when the rank holding the most holds more than the ratio of the
  // mean, from the points' histograms summed over the ranks (one reduction per level).
  std::vector<std::uint64_t> per_rank(static_cast<std::size_t>(R), 0);
  per_rank[static_cast<std::size_t>(me)] = held;
  comm_->sum(per_rank.data(), R);
  std::uint64_t most = 0, all = 0;
  for (auto h : per_rank) {
    most = std::max(most, h);
    all += h;
  }
  if (all == 0 || static_cast<double>(most) * R <= kRebalanceRatio * static_cast<double>(all)) return;
  // The cells of the points this rank holds (not frozen), read once from the positions for
  // every level of the tree.
  std::vector<int> cells;
  for (auto& body : bodies_) {
    const ParticleArrays<D>& pa = body->arrays();
    const std::size_t n = static_cast<std::size_t>(pa.n);
    if (n == 0) continue;
    std::vector<Real> col(n), vol(n);
    std::vector<int> mine(D * n);
    mem::copy(vol.data(), Device::cpu, pa.volume0, exec_.device, n * sizeof(Real));
    for (int d = 0; d < D; ++d) {
      mem::copy(col.data(), Device::cpu, pa.x[d], exec_.device, n * sizeof(Real));
      for (std::size_t p = 0; p < n; ++p) mine[D * p + static_cast<std::size_t>(d)] = domain_cell(global_, d, col[p]);
    }
    for (std::size_t p = 0; p < n; ++p)
      if (vol[p] >= 0) cells.insert(cells.end(), mine.begin() + static_cast<std::ptrdiff_t>(D * p), mine.begin() + static_cast<std::ptrdiff_t>(D * (p + 1)));
  }
  const CountBoxes<D> count = [&](const std::vector<CellBox<D>>& boxes, const std::function<int(const int*)>& which) {
    std::vector<std::size_t> start(boxes.size() + 1, 0);
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      start[k + 1] = start[k];
      for (int d = 0; d < D; ++d) start[k + 1] += static_cast<std::size_t>(boxes[k].hi[d] - boxes[k].lo[d]);
    }
    std::vector<std::uint64_t> flat(start.back(), 0);  // every box's layers along every axis, one reduction
    for (std::size_t q = 0; q < cells.size(); q += D) {
      const int* c = cells.data() + q;
      const int k = which(c);
      if (k < 0) continue;
      const CellBox<D>& bx = boxes[static_cast<std::size_t>(k)];
      std::size_t at = start[static_cast<std::size_t>(k)];
      for (int d = 0; d < D; ++d) {
        ++flat[at + static_cast<std::size_t>(c[d] - bx.lo[d])];
        at += static_cast<std::size_t>(bx.hi[d] - bx.lo[d]);
      }
    }
    comm_->sum(flat.data(), static_cast<int>(flat.size()));
    std::vector<LayerCounts<D>> h(boxes.size());
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      std::size_t at = start[k];
      for (int d = 0; d < D; ++d) {
        const std::size_t w = static_cast<std::size_t>(boxes[k].hi[d] - boxes[k].lo[d]);
        h[k][d].assign(flat.begin() + static_cast<std::ptrdiff_t>(at), flat.begin() + static_cast<std::ptrdiff_t>(at + w));
        at += w;
      }
    }
    return h;
  };
  Decomposition<D> next = bisect<D>(global_, R, me, a, b, decomp_.slack, count);
  if (!next.same_boxes(decomp_)) recut_ = std::move(next);
}

template <int D>
void Solver<D>::gather_snapshot(Snapshot& s) {
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
  // Each rank's owned nodes, in its local order, placed into the global grid by the root.
  auto in_owned = [](const GridGeometry<D>& g, const NodeRange<D>& own, Index f) {
    int idx[D];
    g.unflat(f, idx);
    for (int d = 0; d < D; ++d)
      if (idx[d] < own.lo[d] - g.offset[d] || idx[d] >= own.hi[d] - g.offset[d]) return false;
    return true;
  };
  const NodeRange<D>& mine_nodes = decomp_.owned[static_cast<std::size_t>(comm_->rank())];
  for (FieldData& fd : s.grid.fields) {
    std::vector<Real> mine;
    const Index nn = grid_.num_nodes();
    for (Index f = 0; f < nn; ++f)
      if (in_owned(grid_, mine_nodes, f))
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
      const NodeRange<D>& own = decomp_.owned[static_cast<std::size_t>(r)];
      for (Index f = 0; f < g.num_nodes(); ++f) {
        if (!in_owned(g, own, f)) continue;
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
  Real energy[kEnergyTerms];
  for (int t = 0; t < kEnergyTerms; ++t) energy[t] = c.energy.total(t);
  comm_->sum(energy, kEnergyTerms);
  for (int t = 0; t < kEnergyTerms; ++t) c.energy.set(t, energy[t]);
  // The signal speed each rank's flush measured (the next step's dt takes the largest).
  comm_->max(c.max_speed, 2);
  std::memcpy(ck.clock.data(), &c, sizeof c);
}

template void Solver<2>::set_local_grid();
template void Solver<3>::set_local_grid();
template void Solver<2>::set_porous_halo();
template void Solver<3>::set_porous_halo();
template void Solver<2>::adopt(Decomposition<2>);
template void Solver<3>::adopt(Decomposition<3>);
template void Solver<2>::apply_recut();
template void Solver<3>::apply_recut();
template void Solver<2>::decompose_case();
template void Solver<3>::decompose_case();
template void Solver<2>::check_rank_memory(const std::vector<std::vector<std::uint64_t>>&,
                                           const std::vector<std::uint64_t>&) const;
template void Solver<3>::check_rank_memory(const std::vector<std::vector<std::uint64_t>>&,
                                           const std::vector<std::uint64_t>&) const;
template void Solver<2>::report_decomposition();
template void Solver<3>::report_decomposition();
template std::vector<Real> Solver<2>::keep_own(const std::vector<Real>&, Index, Index&) const;
template std::vector<Real> Solver<3>::keep_own(const std::vector<Real>&, Index, Index&) const;
template void Solver<2>::exchange_before_grid(int, unsigned);
template void Solver<3>::exchange_before_grid(int, unsigned);
template void Solver<2>::halo_sum(int, unsigned);
template void Solver<3>::halo_sum(int, unsigned);
template void Solver<2>::halo_exchange(const HaloFields&);
template void Solver<3>::halo_exchange(const HaloFields&);
template bool Solver<2>::halo_direct() const;
template bool Solver<3>::halo_direct() const;
template OwnedNodes<2> Solver<2>::owned_nodes() const;
template OwnedNodes<3> Solver<3>::owned_nodes() const;
template std::vector<Real> Solver<2>::liquid_totals() const;
template std::vector<Real> Solver<3>::liquid_totals() const;
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
