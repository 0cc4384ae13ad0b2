// A straightforward scalar explicit MPM, written for one comparison (docs/performance.md): how
// far is Scree's CPU backend (one source with the CUDA kernels, structure of arrays, OpenMP,
// phase flags, plugins) from the loop a person would write by hand for one problem?
//
// Plane strain, USL (P2G of mass, momentum and force; grid update; G2P with FLIP and the
// stress update from the new velocities), linear shape functions, one thread, particles
// as an array of structs, the grid as an array of node structs. The material is the same
// header Scree compiles (M::update), so the difference measured is the framework's. The
// problem is scree-bench's block: a 1 m square of 4 particles per cell resting on a fixed
// floor against a slip wall on the left, geostatic initial stress (K0 = 0.5).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "scree/core/tensor.hpp"
#include "scree/material/material.hpp"

namespace scree::bench {

template <class M>
class ScalarMpm {
 public:
  struct Particle {
    double x[2], v[2], F[4], mass, vol0;
    Sym3 sigma;
    typename M::State state;
  };
  struct Node {
    double m, p[2], f[2], v[2], vn[2];
  };

  /// The block of scree-bench (write_block_case): cells per side, the time step.
  ScalarMpm(const typename M::Params& mp, int cells, double dt) : mp_(mp), dt_(dt) {
    h_ = 1.0 / cells;
    ghost_ = 2;
    nx_ = static_cast<int>(std::ceil(1.5 / h_ - 1e-9)) + 1 + 2 * ghost_;
    ny_ = static_cast<int>(std::ceil(1.2 / h_ - 1e-9)) + 1 + 2 * ghost_;
    ox_ = -ghost_ * h_;
    oy_ = -ghost_ * h_;
    nodes_.resize(static_cast<std::size_t>(nx_) * ny_);
    const double rho = M::density(mp), sub = h_ / 2, top = 1.0, g = 9.81;
    for (int j = 0; j < 2 * cells; ++j)
      for (int i = 0; i < 2 * cells; ++i) {
        Particle p{};
        p.x[0] = (i + 0.5) * sub;
        p.x[1] = (j + 0.5) * sub;
        p.F[0] = p.F[3] = 1;
        p.vol0 = sub * sub;
        p.mass = rho * p.vol0;
        const double depth = top - p.x[1], sv = -rho * g * depth, sh = 0.5 * sv;
        p.sigma = Sym3{{sh, sv, sh, 0, 0, 0}};
        p.state = M::initial_state(mp, p.sigma);
        parts_.push_back(p);
      }
  }

  std::size_t size() const { return parts_.size(); }
  const std::vector<Particle>& particles() const { return parts_; }

  void step() {
    for (Node& n : nodes_) n = Node{};
    // P2G: mass, momentum, internal and gravity force
    for (const Particle& p : parts_) {
      int bx, by;
      double wx[2], wy[2], dwx[2], dwy[2];
      weights(p, bx, by, wx, wy, dwx, dwy);
      const double J = p.F[0] * p.F[3] - p.F[1] * p.F[2], vol = p.vol0 * J;
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          Node& n = nodes_[static_cast<std::size_t>(by + b) * nx_ + bx + a];
          const double N = wx[a] * wy[b], gx = dwx[a] * wy[b], gy = wx[a] * dwy[b];
          n.m += N * p.mass;
          n.p[0] += N * p.mass * p.v[0];
          n.p[1] += N * p.mass * p.v[1];
          n.f[0] += -vol * (p.sigma[0] * gx + p.sigma[3] * gy);
          n.f[1] += -vol * (p.sigma[3] * gx + p.sigma[1] * gy) - N * p.mass * 9.81;
        }
    }
    // grid: velocities, integration, walls (fixed floor y <= 0, slip wall x <= 0)
    for (int j = 0; j < ny_; ++j)
      for (int i = 0; i < nx_; ++i) {
        Node& n = nodes_[static_cast<std::size_t>(j) * nx_ + i];
        if (n.m <= 0) continue;
        for (int d = 0; d < 2; ++d) {
          n.v[d] = n.p[d] / n.m;
          n.vn[d] = n.v[d] + dt_ * n.f[d] / n.m;
        }
        if (j <= ghost_) n.v[0] = n.v[1] = n.vn[0] = n.vn[1] = 0;
        if (i <= ghost_) n.v[0] = n.vn[0] = 0;
      }
    // G2P: FLIP velocity, position, velocity gradient, F and the stress update
    for (Particle& p : parts_) {
      int bx, by;
      double wx[2], wy[2], dwx[2], dwy[2];
      weights(p, bx, by, wx, wy, dwx, dwy);
      double dv[2] = {0, 0}, vp[2] = {0, 0}, L[4] = {0, 0, 0, 0};
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          const Node& n = nodes_[static_cast<std::size_t>(by + b) * nx_ + bx + a];
          const double N = wx[a] * wy[b], gx = dwx[a] * wy[b], gy = wx[a] * dwy[b];
          for (int d = 0; d < 2; ++d) {
            vp[d] += N * n.vn[d];
            dv[d] += N * (n.vn[d] - n.v[d]);
          }
          L[0] += n.vn[0] * gx;
          L[1] += n.vn[0] * gy;
          L[2] += n.vn[1] * gx;
          L[3] += n.vn[1] * gy;
        }
      for (int d = 0; d < 2; ++d) {
        p.v[d] += dv[d];
        p.x[d] += dt_ * vp[d];
      }
      const double F0 = p.F[0], F1 = p.F[1], F2 = p.F[2], F3 = p.F[3];
      p.F[0] = F0 + dt_ * (L[0] * F0 + L[1] * F2);
      p.F[1] = F1 + dt_ * (L[0] * F1 + L[1] * F3);
      p.F[2] = F2 + dt_ * (L[2] * F0 + L[3] * F2);
      p.F[3] = F3 + dt_ * (L[2] * F1 + L[3] * F3);
      StrainIncrement inc;
      inc.deps = Sym3{{L[0] * dt_, L[3] * dt_, 0, 0.5 * (L[1] + L[2]) * dt_, 0, 0}};
      inc.spin = Spin3{0.5 * (L[1] - L[2]) * dt_, 0, 0};
      inc.dt = dt_;
      inc.J = p.F[0] * p.F[3] - p.F[1] * p.F[2];
      p.sigma = corotate(p.sigma, inc.spin);
      M::update(mp_, p.state, p.sigma, inc);
    }
  }

 private:
  void weights(const Particle& p, int& bx, int& by, double* wx, double* wy, double* dwx, double* dwy) const {
    const double gx = (p.x[0] - ox_) / h_, gy = (p.x[1] - oy_) / h_;
    bx = std::clamp(static_cast<int>(std::floor(gx)), 0, nx_ - 2);
    by = std::clamp(static_cast<int>(std::floor(gy)), 0, ny_ - 2);
    const double rx = gx - bx, ry = gy - by;
    wx[0] = 1 - rx;
    wx[1] = rx;
    wy[0] = 1 - ry;
    wy[1] = ry;
    dwx[0] = -1 / h_;
    dwx[1] = 1 / h_;
    dwy[0] = -1 / h_;
    dwy[1] = 1 / h_;
  }

  typename M::Params mp_;
  double dt_, h_, ox_, oy_;
  int nx_, ny_, ghost_;
  std::vector<Particle> parts_;
  std::vector<Node> nodes_;
};

}  // namespace scree::bench
