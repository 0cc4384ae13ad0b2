// Particle generation (see particle_generation.hpp).
#include "scree/solver/particle_generation.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "scree/solver/case.hpp"

namespace scree {
namespace {

/// Even-odd rule point-in-polygon test.
bool inside_polygon(const std::vector<std::array<Real, 2>>& poly, Real x, Real y) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]) in = !in;
  }
  return in;
}

}  // namespace

template <int D>
GeneratedParticles<D> generate_particles(const Dictionary& body, const GridGeometry<D>& g, Real density,
                                         const Vec<D>& gravity) {
  GeneratedParticles<D> out;
  const Dictionary& region = body.sub("region");
  const std::string type = region.get_word("type");
  const int n = BodySettings::read(body).particles_per_cell;

  // Bounding box of the region and the inside test.
  Vec<D> lo, hi;
  std::vector<std::array<Real, 2>> poly;
  if (type == "polygon") {
    if (D != 2) throw InputError(region.at("type").where(), "polygon regions are 2D only; use box in 3D");
    const Entry& pts = region.at("points");
    const Item& list = pts.single_item();
    for (const Item& p : list.list) {
      if (p.kind != Item::Kind::list || p.list.size() != 2 || p.list[0].kind != Item::Kind::number ||
          p.list[1].kind != Item::Kind::number)
        throw InputError(p.where, "points: each vertex must be (x y), found " + p.to_string());
      poly.push_back({p.list[0].number, p.list[1].number});
    }
    if (poly.size() < 3) throw InputError(pts.where(), "points: a polygon needs at least 3 vertices");
    for (int d = 0; d < D; ++d) {
      lo[d] = 1e300;
      hi[d] = -1e300;
    }
    for (auto& p : poly)
      for (int d = 0; d < 2; ++d) {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
  } else {
    if ((type == "rectangle" && D != 2) || (type == "box" && D != 3))
      throw InputError(region.at("type").where(),
                       "region type " + type + " does not fit a " + std::to_string(D) + "D case (use " +
                           (D == 2 ? "rectangle" : "box") + ")");
    const auto l = region.at("lower").as_scalar_list(), u = region.at("upper").as_scalar_list();
    for (int d = 0; d < D; ++d) {
      lo[d] = l[d];
      hi[d] = u[d];
    }
  }
  auto inside = [&](const Vec<D>& x) {
    if (!poly.empty()) return inside_polygon(poly, x[0], x[1]);
    for (int d = 0; d < D; ++d)
      if (x[d] < lo[d] || x[d] > hi[d]) return false;
    return true;
  };

  // Cells of the background lattice overlapping the bounding box.
  const Real h = g.h, sub = h / n;
  int c0[D], c1[D];
  for (int d = 0; d < D; ++d) {
    c0[d] = static_cast<int>(std::floor((lo[d] - g.origin[d]) / h + 1e-9));
    c1[d] = static_cast<int>(std::ceil((hi[d] - g.origin[d]) / h - 1e-9));
  }
  Real vol = 1;
  for (int d = 0; d < D; ++d) vol *= sub;
  // Iterate sub-cell centres.
  long long counts[D], total = 1;
  for (int d = 0; d < D; ++d) {
    counts[d] = static_cast<long long>(c1[d] - c0[d]) * n;
    total *= std::max(0LL, counts[d]);
  }
  for (long long k = 0; k < total; ++k) {
    long long r = k;
    Vec<D> x;
    for (int d = 0; d < D; ++d) {
      const long long i = r % counts[d];
      r /= counts[d];
      x[d] = g.origin[d] + c0[d] * h + (static_cast<Real>(i) + Real(0.5)) * sub;
    }
    if (!inside(x)) continue;
    out.x.push_back(x);
    out.volume.push_back(vol);
  }
  if (out.x.empty())
    throw InputError(region.where(), "region '" + region.name() + "' contains no particle position (is it "
                                     "smaller than a cell, or outside the grid?)");
  for (auto& x : out.x)
    for (int d = 0; d < D; ++d)
      if (x[d] < g.lower[d] || x[d] > g.upper[d])
        throw InputError(region.where(), "region '" + region.name() + "' extends outside the domain of "
                                         "system/gridDict (lower/upper)");

  // Initial velocity.
  Vec<D> v0 = Vec<D>::zero();
  if (const Entry* e = body.find("velocity")) {
    const auto v = e->as_scalar_list();
    for (int d = 0; d < D; ++d) v0[d] = v[d];
  }
  out.v.assign(out.x.size(), v0);
  if (const Entry* e = body.find("angularVelocity")) {
    const auto w = e->as_scalar_list();
    if (static_cast<int>(w.size()) != (D == 2 ? 1 : 3))
      throw InputError(e->where(), std::string("angularVelocity: expected ") +
                                       (D == 2 ? "(omega_z): one component in 2D" : "(wx wy wz) in 3D") +
                                       ", found " + e->value_string());
    Vec<D> c = Vec<D>::zero();
    if (const Entry* ce = body.find("rotationCentre")) {
      const auto cc = ce->as_scalar_list();
      for (int d = 0; d < D; ++d) c[d] = cc[d];
    } else {
      for (auto& x : out.x) c += x;
      c *= Real(1) / static_cast<Real>(out.x.size());
    }
    // Omega (skew) with Omega r = w x r.
    Mat<D> W = Mat<D>::zero();
    if constexpr (D == 2) {
      W.a[0][1] = -w[0];
      W.a[1][0] = w[0];
    } else {
      W.a[0][1] = -w[2];
      W.a[1][0] = w[2];
      W.a[0][2] = w[1];
      W.a[2][0] = -w[1];
      W.a[1][2] = -w[0];
      W.a[2][1] = w[0];
    }
    for (std::size_t p = 0; p < out.x.size(); ++p) out.v[p] += W * (out.x[p] - c);
    out.velocity_gradient = W;
  }

  // Initial stress.
  out.sigma.assign(out.x.size(), Sym3::zero());
  if (const Entry* e = body.find("initialStress"); e && e->dict().get_word("type") == "uniform") {
    const auto v = e->dict().at("stress").as_scalar_list();
    out.sigma.assign(out.x.size(), Sym3{{v[0], v[1], v[2], v[3], v[4], v[5]}});
  }
  if (const Entry* e = body.find("initialStress"); e && e->dict().get_word("type") == "geostatic") {
    const Dictionary& s = e->dict();
    const Real K0 = ParamReader(*CoreSpecs::get().body->find("initialStress")->sub(), s).scalar("K0");
    const Real gn = norm(gravity);
    if (gn > 0) {
      Vec<D> up = gravity * (-1 / gn);  // unit vector against gravity
      Real surface = -1e300;
      if (s.has("surface")) {
        surface = s.get_scalar("surface");
      } else {
        for (auto& x : out.x) surface = std::max(surface, dot(x, up));
        surface += Real(0.5) * sub;  // the top particle sits half a spacing below the surface
      }
      for (std::size_t p = 0; p < out.x.size(); ++p) {
        const Real depth = std::max(Real(0), surface - dot(out.x[p], up));
        const Real sv = -density * gn * depth, sh = K0 * sv;
        // sigma = sh I + (sv - sh) up (x) up ; out-of-plane (2D) = sh.
        Sym3 sig{{sh, sh, sh, 0, 0, 0}};
        Real u3[3] = {0, 0, 0};
        for (int d = 0; d < D; ++d) u3[d] = up[d];
        sig[0] += (sv - sh) * u3[0] * u3[0];
        sig[1] += (sv - sh) * u3[1] * u3[1];
        sig[2] += (sv - sh) * u3[2] * u3[2];
        sig[3] += (sv - sh) * u3[0] * u3[1];
        sig[4] += (sv - sh) * u3[1] * u3[2];
        sig[5] += (sv - sh) * u3[2] * u3[0];
        out.sigma[p] = sig;
      }
    }
  }
  return out;
}

template GeneratedParticles<2> generate_particles<2>(const Dictionary&, const GridGeometry<2>&, Real,
                                                     const Vec<2>&);
template GeneratedParticles<3> generate_particles<3>(const Dictionary&, const GridGeometry<3>&, Real,
                                                     const Vec<3>&);

}  // namespace scree
