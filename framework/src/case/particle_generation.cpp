// Particle generation (see particle_generation.hpp).
#include "scree/case/particle_generation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "scree/case/case.hpp"
#include "scree/case/overburden.hpp"
#include "scree/geometry/shapes.hpp"
#include "scree/geometry/tri_surface.hpp"

namespace scree {
namespace {

std::string point_text(const Real* x, int dim) {
  std::string s = "(";
  char buf[32];
  for (int d = 0; d < dim; ++d) {
    std::snprintf(buf, sizeof buf, "%s%g", d ? " " : "", x[d]);
    s += buf;
  }
  return s + ")";
}

/// A body's region read from its validated dictionary: rectangle/box or polygon (2D), and
/// in 3D cylinder, sphere, extrudedPolygon or stl (geometry/shapes.hpp, tri_surface.hpp),
/// cut to the body's `clip` box if it has one.
template <int D>
struct Shape {
  enum class Kind { box, polygon, cylinder, sphere, extruded, stl };
  Kind kind = Kind::box;
  const Dictionary* dict = nullptr;  ///< the region { } dictionary
  Vec<D> lo, hi;                     ///< bounding box (of the clipped region)
  std::vector<std::array<Real, 2>> poly;
  geometry::Cylinder cylinder;
  geometry::Sphere sphere;
  geometry::ExtrudedPolygon extruded;
  std::shared_ptr<const geometry::TriSurface> surface;
  bool clipped = false;
  Vec<D> clip_lo, clip_hi;

  bool contains(const Vec<D>& x) const {
    if (clipped)
      for (int d = 0; d < D; ++d)
        if (x[d] < clip_lo[d] || x[d] > clip_hi[d]) return false;
    if (kind == Kind::polygon) return geometry::inside_polygon(poly, x[0], x[1]);
    if (kind == Kind::box) {
      for (int d = 0; d < D; ++d)
        if (x[d] < lo[d] || x[d] > hi[d]) return false;
      return true;
    }
    if constexpr (D == 3) {  // the 3D shapes (a 2D region is a rectangle or a polygon)
      switch (kind) {
        case Kind::cylinder: return cylinder.contains(x);
        case Kind::sphere: return sphere.contains(x);
        case Kind::extruded: return extruded.contains(x);
        case Kind::stl: return surface->contains(x);
        default: return false;
      }
    }
    return false;
  }

  /// The region's exact volume (area in 2D), clip aside; < 0 for none known.
  double measure() const {
    switch (kind) {
      case Kind::polygon: return geometry::polygon_area(poly);
      case Kind::cylinder: return cylinder.volume();
      case Kind::sphere: return sphere.volume();
      case Kind::extruded: return extruded.volume();
      case Kind::stl: return surface->volume();
      default: return -1;
    }
  }
};

std::vector<std::array<Real, 2>> read_points(const Entry& pts, const std::string& what) {
  std::vector<std::array<Real, 2>> poly;
  const Item& list = pts.single_item();
  for (const Item& p : list.list()) {
    if (p.kind() != Item::Kind::list || p.list().size() != 2 || p.list()[0].kind() != Item::Kind::number ||
        p.list()[1].kind() != Item::Kind::number)
      throw InputError(p.where(), "points: each vertex must be " + what + ", found " + p.to_string());
    poly.push_back({p.list()[0].number(), p.list()[1].number()});
  }
  if (poly.size() < 3)
    throw InputError(pts.where(), "points: a polygon needs at least 3 vertices, found " + std::to_string(poly.size()));
  return poly;
}

geometry::Point3 point3(const Dictionary& d, const char* key) {
  const auto v = d.at(key).as_scalar_list();
  return {{v.at(0), v.at(1), v.at(2)}};
}

/// Throws InputError for a region that does not fit the case: a 2D type (rectangle,
/// polygon) in 3D or a 3D one in 2D, a polygon with fewer than 3 vertices, an STL file that
/// cannot be read or is not closed, a clip box that misses the region.
template <int D>
Shape<D> read_shape(const Dictionary& body, const std::filesystem::path& case_dir) {
  const Dictionary& region = body.sub("region");
  Shape<D> s;
  s.dict = &region;
  const std::string type = region.get_word("type");
  if (const std::string why = region_dimension_mismatch(type, D); !why.empty())
    throw InputError(region.at("type").where(), why);
  Real lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  auto take = [&](const geometry::Box3& b) {
    for (int d = 0; d < 3; ++d) lo[d] = b.lo[d], hi[d] = b.hi[d];
  };
  if (type == "polygon") {
    s.kind = Shape<D>::Kind::polygon;
    s.poly = read_points(region.at("points"), "(x y)");
    for (int d = 0; d < D; ++d) {
      lo[d] = 1e300;
      hi[d] = -1e300;
    }
    for (auto& p : s.poly)
      for (int d = 0; d < 2; ++d) {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
  } else if (type == "rectangle" || type == "box") {
    const auto l = region.at("lower").as_scalar_list(), u = region.at("upper").as_scalar_list();
    for (int d = 0; d < D; ++d) {
      lo[d] = l[d];
      hi[d] = u[d];
    }
  } else if (type == "cylinder") {
    s.kind = Shape<D>::Kind::cylinder;
    s.cylinder = {point3(region, "p1"), point3(region, "p2"), region.get_scalar("radius")};
    take(s.cylinder.bounds());
  } else if (type == "sphere") {
    s.kind = Shape<D>::Kind::sphere;
    s.sphere = {point3(region, "centre"), region.get_scalar("radius")};
    take(s.sphere.bounds());
  } else if (type == "extrudedPolygon") {
    s.kind = Shape<D>::Kind::extruded;
    const std::string axis = ParamReader(*CoreSpecs::get().body->find("region")->sub(), region).word("axis");
    s.extruded.axis = axis == "x" ? 0 : axis == "y" ? 1 : 2;
    static const char* kPlane[3] = {"(y z)", "(z x)", "(x y)"};
    for (const auto& p : read_points(region.at("points"), kPlane[s.extruded.axis])) s.extruded.points.push_back(p);
    const auto r = region.at("range").as_scalar_list();
    s.extruded.min = r.at(0);
    s.extruded.max = r.at(1);
    take(s.extruded.bounds());
  } else if (type == "stl") {
    s.kind = Shape<D>::Kind::stl;
    const Entry& f = region.at("file");
    const std::string rel = f.as_word();
    const std::filesystem::path path = std::filesystem::path(rel).is_absolute() ? std::filesystem::path(rel)
                                                                                 : case_dir / rel;
    s.surface = geometry::TriSurface::load(path, rel, f.where());
    take(s.surface->bounds());
  }
  for (int d = 0; d < D; ++d) {
    s.lo[d] = lo[d];
    s.hi[d] = hi[d];
  }

  if (const Entry* c = body.find("clip")) {
    const Dictionary& cd = c->dict();
    const auto l = cd.at("lower").as_scalar_list(), u = cd.at("upper").as_scalar_list();
    s.clipped = true;
    bool misses = false;
    for (int d = 0; d < D; ++d) {
      s.clip_lo[d] = l[d];
      s.clip_hi[d] = u[d];
      s.lo[d] = std::max(s.lo[d], s.clip_lo[d]);
      s.hi[d] = std::min(s.hi[d], s.clip_hi[d]);
      misses = misses || s.hi[d] < s.lo[d];
    }
    if (misses)
      throw InputError(cd.where(), "clip: the box " + point_text(&s.clip_lo[0], D) + " .. " +
                                       point_text(&s.clip_hi[0], D) + " does not meet the region, whose bounds are " +
                                       point_text(lo, D) + " .. " + point_text(hi, D) +
                                       ", so the body would be empty; expected a clip box that overlaps the region");
  }
  return s;
}

/// Calls f(x) for every particle position of `shape`: the centres of the n^D sub-cells
/// of the background cells that lie inside the region.
template <int D, class F>
void for_each_position(const Shape<D>& shape, const GridGeometry<D>& g, int n, F&& f) {
  // Cells of the background lattice overlapping the bounding box.
  const Real h = g.h, sub = h / n;
  int c0[D], c1[D];
  for (int d = 0; d < D; ++d) {
    c0[d] = static_cast<int>(std::floor((shape.lo[d] - g.origin[d]) / h + 1e-9));
    c1[d] = static_cast<int>(std::ceil((shape.hi[d] - g.origin[d]) / h - 1e-9));
  }
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
    if (shape.contains(x)) f(x);
  }
}

template <int D>
bool outside_domain(const Vec<D>& x, const GridGeometry<D>& g) {
  for (int d = 0; d < D; ++d)
    if (x[d] < g.lower[d] || x[d] > g.upper[d]) return true;
  return false;
}

/// The errors of a region with no particle position, or with one outside the domain
/// (`outside` is the first such position).
template <int D>
InputError empty_region(const Dictionary& region, int n) {
  return InputError(region.where(), "region: no particle position lies inside it (particles sit at the centres of the " +
                                        std::to_string(n) + " x " + std::to_string(n) +
                                        (D == 3 ? " x " + std::to_string(n) : std::string()) +
                                        " sub-cells of each grid cell); expected a region at least one sub-cell wide "
                                        "inside the domain of system/gridDict");
}

template <int D>
InputError region_outside(const Dictionary& region, const Vec<D>& outside, const GridGeometry<D>& g) {
  Real lo[D], hi[D], x[D];
  for (int d = 0; d < D; ++d) lo[d] = g.lower[d], hi[d] = g.upper[d], x[d] = outside[d];
  return InputError(region.where(), "region: extends outside the domain of system/gridDict: a particle at " +
                                        point_text(x, D) + " lies beyond lower " + point_text(lo, D) + " / upper " +
                                        point_text(hi, D) + "; expected a region inside the domain");
}

/// angularVelocity with the other dimension's components: (omega_z) in 3D, (wx wy wz) in 2D.
template <int D>
InputError angular_velocity_error(const Entry& e) {
  return InputError(e.where(), std::string("angularVelocity: expected ") +
                                   (D == 2 ? "(omega_z): one component in 2D" : "(wx wy wz) in 3D") + ", found " +
                                   e.value_string());
}

}  // namespace

std::string region_dimension_mismatch(const std::string& type, int dimension) {
  static const char* kTypes[] = {"rectangle", "polygon", "box", "cylinder", "sphere", "extrudedPolygon", "stl"};
  if (std::find(std::begin(kTypes), std::end(kTypes), type) == std::end(kTypes)) return {};  // the spec's to say
  const bool two_d = type == "rectangle" || type == "polygon";
  if (two_d == (dimension == 2)) return {};
  return "type: region type " + type + " does not fit a " + std::to_string(dimension) + "D case; expected " +
         (dimension == 2 ? "rectangle or polygon in 2D (box, cylinder, sphere, extrudedPolygon and stl are 3D)"
                         : "box, cylinder, sphere, extrudedPolygon or stl in 3D (rectangle and polygon are 2D; a 2D "
                           "section extruded across the width is an extrudedPolygon)");
}

bool takes_overburden(const Dictionary& body) {
  const Entry* e = body.find("initialStress");
  if (!e || !e->is_dict() || e->dict().get_word("type") != "geostatic" || e->dict().has("surface")) return false;
  return ParamReader(*CoreSpecs::get().body->find("initialStress")->sub(), e->dict()).word("overburden") == "all";
}

template <int D>
GeneratedParticles<D> generate_particles(const Dictionary& body, const GridGeometry<D>& g, Real density,
                                         const Vec<D>& gravity, const std::filesystem::path& case_dir,
                                         const PointFilter<D>& keep, const Overburden<D>* overburden,
                                         const std::function<Real(Real)>& profile) {
  GeneratedParticles<D> out;
  const Dictionary& region = body.sub("region");
  const int n = BodySettings::read(body).particles_per_cell;
  const Shape<D> shape = read_shape<D>(body, case_dir);
  const Real sub = g.h / n;
  Real vol = 1;
  for (int d = 0; d < D; ++d) vol *= sub;
  out.point_volume = vol;
  // What depends on every point of the body, kept or not: the first point outside the
  // domain, the centroid (a rotation's default centre), the highest and lowest points (the
  // geostatic surface, its density table's range) and the body's own columns of material
  // (its overburden when no other body's is given), each summed or compared in the
  // generation order.
  const Real gn = norm(gravity);
  const Vec<D> up = gn > 0 ? gravity * (-1 / gn) : Vec<D>::zero();  // unit vector against gravity
  const Entry* stress_entry = body.find("initialStress");
  const bool geostatic = stress_entry && stress_entry->dict().get_word("type") == "geostatic" && gn > 0;
  const ParamSpec& stress_spec = *CoreSpecs::get().body->find("initialStress")->sub();
  // The overburden of the material above each point (`overburden all`, the default), unless a
  // level is asked for (`overburden body`, or a `surface`).
  const bool columns = geostatic && takes_overburden(body);
  if (columns) {
    const Dictionary& s = stress_entry->dict();
    if (gravity_axis(gravity) < 0)
      throw InputError(s.has("overburden") ? s.at("overburden").where() : s.where(),
                       "overburden all: the columns of the material above a point need gravity along one axis of "
                       "the grid, and constant/g is " + point_text(&gravity[0], D) +
                           "; expected gravity along one axis, or `overburden body;` (the depth below the body's "
                           "highest point, measured along g) or a `surface` level");
  }
  std::optional<Overburden<D>> own;  // the body alone, when the caller gives no overburden
  if (columns && !overburden) {
    own.emplace(gravity);
    own->begin_body(sub, g.origin, DensityProfile{density, profile});
  }
  Vec<D> sum = Vec<D>::zero();
  Real top = -1e300, bottom = 1e300;
  bool outside = false;
  Vec<D> first_outside = Vec<D>::zero();
  std::uint64_t total = 0;
  for_each_position(shape, g, n, [&](const Vec<D>& x) {
    if (!outside && outside_domain(x, g)) {
      outside = true;
      first_outside = x;
    }
    sum += x;
    top = std::max(top, dot(x, up));
    bottom = std::min(bottom, dot(x, up));
    if (own) own->add_point(x);
    if (!keep || keep(x)) {
      out.x.push_back(x);
      out.volume.push_back(vol);
      if (keep) out.index.push_back(static_cast<std::int64_t>(total));
    }
    ++total;
  });
  out.total = total;
  if (total == 0) throw empty_region<D>(region, n);
  if (outside) throw region_outside(region, first_outside, g);

  // Initial velocity.
  Vec<D> v0 = Vec<D>::zero();
  if (const Entry* e = body.find("velocity")) {
    const auto v = e->as_scalar_list();
    for (int d = 0; d < D; ++d) v0[d] = v[d];
  }
  out.v.assign(out.x.size(), v0);
  if (const Entry* e = body.find("angularVelocity")) {
    const auto w = e->as_scalar_list();
    if (static_cast<int>(w.size()) != (D == 2 ? 1 : 3)) throw angular_velocity_error<D>(*e);
    Vec<D> c = Vec<D>::zero();
    if (const Entry* ce = body.find("rotationCentre")) {
      const auto cc = ce->as_scalar_list();
      for (int d = 0; d < D; ++d) c[d] = cc[d];
    } else {
      c = sum * (Real(1) / static_cast<Real>(total));
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
  if (geostatic) {
    const Dictionary& s = stress_entry->dict();
    const Real K0 = ParamReader(stress_spec, s).scalar("K0");
    if (own) own->end_body();
    const Overburden<D>* columns_of = overburden ? overburden : own ? &*own : nullptr;
    // One level for the body: the given surface, or its top particle plus half a spacing
    // (the top particle stands for the sub-cell about it).
    const Real surface = s.has("surface") ? s.get_scalar("surface") : top + Real(0.5) * sub;
    // A two-phase body's mixture density varies with the elevation: its integral below the level.
    DensityIntegral level_rho;
    if (!columns && profile)
      level_rho = DensityIntegral(DensityProfile{density, profile}, bottom - sub, std::max(surface, top) + sub);
    for (std::size_t p = 0; p < out.x.size(); ++p) {
      Real sv;  // [Pa], compression negative
      if (columns) {
        sv = columns_of->vertical_stress(out.x[p]);
      } else if (profile) {
        sv = -gn * level_rho.between(dot(out.x[p], up), surface);
      } else {
        const Real depth = std::max(Real(0), surface - dot(out.x[p], up));
        sv = -density * gn * depth;
      }
      const Real sh = K0 * sv;
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
  return out;
}

template <int D>
double estimate_particle_count(const Dictionary& body, Real cell_size, int particles_per_cell,
                               const std::filesystem::path& case_dir) {
  Shape<D> shape;
  try {
    shape = read_shape<D>(body, case_dir);
  } catch (const InputError&) {
    return 0;
  }
  // The region's volume: exact for each shape (the shoelace formula for a polygon, the
  // divergence theorem for a surface). Cut by a clip box, the share of the clipped bounds
  // inside the region, counted on a lattice of 32 midpoints per axis (the region's own test).
  double box = 1;
  for (int d = 0; d < D; ++d) box *= std::max(0.0, static_cast<double>(shape.hi[d] - shape.lo[d]));
  double measure = shape.measure();
  if (measure < 0) measure = box;
  if (shape.clipped && box > 0) {
    constexpr int kSamples = 32;
    long long in = 0, total = 1;
    for (int d = 0; d < D; ++d) total *= kSamples;
    for (long long k = 0; k < total; ++k) {
      long long r = k;
      Vec<D> x;
      for (int d = 0; d < D; ++d) {
        x[d] = shape.lo[d] + (static_cast<Real>(r % kSamples) + Real(0.5)) * (shape.hi[d] - shape.lo[d]) / kSamples;
        r /= kSamples;
      }
      in += shape.contains(x);
    }
    measure = box * static_cast<double>(in) / static_cast<double>(total);
  }
  return measure * std::pow(particles_per_cell / static_cast<double>(cell_size), D);
}

template <int D>
void check_bodies(const Dictionary& bodies, const GridGeometry<D>& g, std::vector<InputError>& errors,
                  const std::filesystem::path& case_dir) {
  struct Placed {
    std::string name;
    Shape<D> shape;
    int n = 0;
    bool allow_overlap = false;
  };
  std::vector<Placed> placed;
  const ParamSpec& spec = *CoreSpecs::get().body;
  for (const Entry* e : plugin_entries(bodies)) {
    const Dictionary& body = e->dict();
    // What generate_particles reads besides the region, and the spec does not size.
    if (const Entry* w = body.find("angularVelocity"); w && static_cast<int>(w->as_scalar_list().size()) != (D == 2 ? 1 : 3))
      errors.push_back(angular_velocity_error<D>(*w));
    try {
      const Dictionary& region = body.sub("region");
      Placed p{e->key(), read_shape<D>(body, case_dir), BodySettings::read(body).particles_per_cell,
               ParamReader(spec, body).boolean("allowOverlap")};
      bool any = false, outside = false;
      for_each_position(p.shape, g, p.n, [&](const Vec<D>& x) {
        any = true;
        if (!outside && outside_domain(x, g)) {
          outside = true;
          errors.push_back(region_outside(region, x, g));
        }
      });
      if (!any) errors.push_back(empty_region<D>(region, p.n));
      if (any && !outside) placed.push_back(std::move(p));
    } catch (const InputError& err) {
      errors.push_back(err);
    }
  }

  // Two bodies in one place: each point of the one inside the other's region doubles
  // the mass there. Checked both ways (a small region inside a large one, and points of
  // a coarse body that fall inside a polygon).
  for (std::size_t a = 0; a < placed.size(); ++a)
    for (std::size_t b = a + 1; b < placed.size(); ++b) {
      const Placed& A = placed[a];
      const Placed& B = placed[b];
      if (A.allow_overlap || B.allow_overlap) continue;
      long long a_in_b = 0, b_in_a = 0, b_total = 0;
      for_each_position(A.shape, g, A.n, [&](const Vec<D>& x) { a_in_b += B.shape.contains(x); });
      for_each_position(B.shape, g, B.n, [&](const Vec<D>& x) {
        ++b_total;
        b_in_a += A.shape.contains(x);
      });
      if (a_in_b == 0 && b_in_a == 0) continue;
      std::string msg = "region: body '" + B.name + "' overlaps body '" + A.name + "' (region at " +
                        A.shape.dict->where().str() + "): ";
      if (b_in_a > 0)
        msg += std::to_string(b_in_a) + " of its " + std::to_string(b_total) + " particles lie inside the region of '" +
               A.name + "'";
      if (a_in_b > 0)
        msg += std::string(b_in_a > 0 ? ", and " : "") + std::to_string(a_in_b) + " particles of '" + A.name +
               "' lie inside its region";
      msg += "; expected bodies in separate places (two bodies in one place double the mass there). If they are "
             "meant to share space, set allowOverlap yes in one of them";
      errors.emplace_back(B.shape.dict->where(), msg);
    }
}

template <int D>
void for_each_particle_position(const Dictionary& body, const GridGeometry<D>& g,
                                const std::function<void(const Vec<D>&)>& f, const std::filesystem::path& case_dir) {
  for_each_position(read_shape<D>(body, case_dir), g, BodySettings::read(body).particles_per_cell, f);
}

template GeneratedParticles<2> generate_particles<2>(const Dictionary&, const GridGeometry<2>&, Real,
                                                     const Vec<2>&, const std::filesystem::path&,
                                                     const PointFilter<2>&, const Overburden<2>*,
                                                     const std::function<Real(Real)>&);
template GeneratedParticles<3> generate_particles<3>(const Dictionary&, const GridGeometry<3>&, Real,
                                                     const Vec<3>&, const std::filesystem::path&,
                                                     const PointFilter<3>&, const Overburden<3>*,
                                                     const std::function<Real(Real)>&);
template void for_each_particle_position<2>(const Dictionary&, const GridGeometry<2>&,
                                            const std::function<void(const Vec<2>&)>&, const std::filesystem::path&);
template void for_each_particle_position<3>(const Dictionary&, const GridGeometry<3>&,
                                            const std::function<void(const Vec<3>&)>&, const std::filesystem::path&);
template double estimate_particle_count<2>(const Dictionary&, Real, int, const std::filesystem::path&);
template double estimate_particle_count<3>(const Dictionary&, Real, int, const std::filesystem::path&);
template void check_bodies<2>(const Dictionary&, const GridGeometry<2>&, std::vector<InputError>&,
                              const std::filesystem::path&);
template void check_bodies<3>(const Dictionary&, const GridGeometry<3>&, std::vector<InputError>&,
                              const std::filesystem::path&);

}  // namespace scree
