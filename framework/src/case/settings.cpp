// CaseSettings::read (see settings.hpp): every core key through its spec, defaults applied
// by ParamReader from the one place they are written, CoreSpecs (case.cpp).
#include "scree/case/settings.hpp"

#include "scree/case/case.hpp"
#include "scree/params/spec.hpp"

namespace scree {
namespace {

ControlSettings read_control(const ParamSpec& spec, const Dictionary& d) {
  const ParamReader r(spec, d);
  const double delta_t = r.scalar("deltaT");
  return ControlSettings{
      .time = {.start_time = r.scalar("startTime"),
               .end_time = r.scalar("endTime"),
               .delta_t = delta_t,
               .adjust_time_step = r.boolean("adjustTimeStep"),
               .max_co = r.scalar("maxCo"),
               .max_delta_t = r.has("maxDeltaT") ? r.scalar("maxDeltaT") : delta_t,
               .stop_co = r.scalar("stopCo")},
      .write_control = r.word("writeControl") == "timeStep" ? WriteControl::timeStep : WriteControl::runTime,
      .write_interval = r.scalar("writeInterval"),
      .progress_interval = r.integer("progressInterval"),
      .max_lost_fraction = r.scalar("maxLostFraction"),
      .start_from_latest = r.word("startFrom") == "latestTime",
      .checkpoint_interval = r.integer("checkpointInterval"),
      .checkpoint_keep = r.integer("checkpointKeep")};
}

/// damping { type local; coefficient ...; } (none: no damping)
DampingSettings read_damping(const ParamSpec& spec, const Dictionary& d) {
  const ParamReader r(spec, d);
  if (r.word("type") != "local") return {};
  return {.coefficient = r.scalar("coefficient"), .start_time = r.scalar("startTime"), .end_time = r.scalar("endTime")};
}

SchemeSettings read_schemes(const ParamSpec& spec, const Dictionary& d) {
  const ParamReader r(spec, d);
  const std::string scheme = r.word("updateScheme"), shape = r.word("shapeFunction");
  return SchemeSettings{
      .update_scheme = scheme == "USL" ? UpdateScheme::USL : (scheme == "MUSL" ? UpdateScheme::MUSL : UpdateScheme::USF),
      .shape = shape == "gimp" ? ShapeKind::gimp : (shape == "bspline2" ? ShapeKind::bspline2 : ShapeKind::linear),
      .transfer = r.word("transfer") == "APIC" ? Transfer::apic : Transfer::flip,
      .pic_fraction = r.scalar("picFraction"),
      .pic_rate = r.scalar("picRate"),
      .max_volume_ratio = r.has("maxVolumeRatio") ? r.scalar("maxVolumeRatio") : kNoVolumeLimit,
      .damping = r.has("damping") ? read_damping(*spec.find("damping")->sub(), r.entry("damping").dict())
                                  : DampingSettings{},
      .sort_interval = r.integer("sortInterval"),
      .mass_tolerance = r.scalar("massTolerance")};
}

GridSettings read_grid(const ParamSpec& spec, const Dictionary& d) {
  const ParamReader r(spec, d);
  return GridSettings{.dimension = static_cast<int>(r.integer("dimension")),
                      .lower = r.scalars("lower"),
                      .upper = r.scalars("upper"),
                      .cell_size = r.scalar("cellSize"),
                      .ghost_layers = static_cast<int>(r.integer("ghostLayers"))};
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
