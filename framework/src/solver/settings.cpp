// CaseSettings::read (see settings.hpp): every core key through its spec, defaults applied
// by ParamReader from the one place they are written, CoreSpecs (case.cpp).
#include "scree/solver/settings.hpp"

#include "scree/params/spec.hpp"
#include "scree/solver/case.hpp"

namespace scree {
namespace {

ControlSettings read_control(const ParamSpec& spec, const Dictionary& d) {
  const ParamReader r(spec, d);
  ControlSettings c;
  TimeSettings& t = c.time;
  t.start_time = r.scalar("startTime");
  t.end_time = r.scalar("endTime");
  t.delta_t = r.scalar("deltaT");
  t.adjust_time_step = r.boolean("adjustTimeStep");
  t.max_co = r.scalar("maxCo");
  t.max_delta_t = r.has("maxDeltaT") ? r.scalar("maxDeltaT") : t.delta_t;
  c.write_control = r.word("writeControl") == "timeStep" ? WriteControl::timeStep : WriteControl::runTime;
  c.write_interval = r.scalar("writeInterval");
  c.progress_interval = r.integer("progressInterval");
  return c;
}

SchemeSettings read_schemes(const ParamSpec& spec, const Dictionary& d) {
  const ParamReader r(spec, d);
  SchemeSettings s;
  const std::string scheme = r.word("updateScheme");
  s.update_scheme = scheme == "USL" ? UpdateScheme::USL : (scheme == "MUSL" ? UpdateScheme::MUSL : UpdateScheme::USF);
  const std::string shape = r.word("shapeFunction");
  s.shape = shape == "gimp" ? ShapeKind::gimp : (shape == "bspline2" ? ShapeKind::bspline2 : ShapeKind::linear);
  s.transfer = r.word("transfer") == "APIC" ? Transfer::apic : Transfer::flip;
  s.pic_fraction = r.scalar("picFraction");
  if (r.has("maxVolumeRatio")) s.max_volume_ratio = r.scalar("maxVolumeRatio");
  if (r.has("damping")) {
    const ParamReader dr(*spec.find("damping")->sub(), r.entry("damping").dict());
    if (dr.word("type") == "local") {
      s.damping.coefficient = dr.scalar("coefficient");
      s.damping.start_time = dr.scalar("startTime");
      s.damping.end_time = dr.scalar("endTime");
    }
  }
  s.sort_interval = r.integer("sortInterval");
  s.mass_tolerance = r.scalar("massTolerance");
  return s;
}

GridSettings read_grid(const ParamSpec& spec, const Dictionary& d) {
  const ParamReader r(spec, d);
  GridSettings g;
  g.dimension = static_cast<int>(r.integer("dimension"));
  g.lower = r.scalars("lower");
  g.upper = r.scalars("upper");
  g.cell_size = r.scalar("cellSize");
  g.ghost_layers = static_cast<int>(r.integer("ghostLayers"));
  return g;
}

}  // namespace

BodySettings BodySettings::read(const Dictionary& body) {
  const ParamReader r(*CoreSpecs::get().body, body);
  BodySettings b;
  b.material = r.word("material");
  b.particles_per_cell = static_cast<int>(r.integer("particlesPerCell"));
  return b;
}

CaseSettings CaseSettings::read(const Case& c) {
  const CoreSpecs& cs = CoreSpecs::get();
  CaseSettings s;
  s.control = read_control(*cs.control, c.control());
  s.schemes = read_schemes(*cs.schemes, c.schemes());
  s.grid = read_grid(*cs.grid, c.grid());
  s.gravity = ParamReader(*cs.gravity, c.gravity()).scalars("value");
  return s;
}

}  // namespace scree
