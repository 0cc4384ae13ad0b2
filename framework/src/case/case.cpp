// Reading and validating a whole case (see case.hpp for the layout).
#include "scree/case/case.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "../porous/porous_media.hpp"
#include "scree/case/particle_generation.hpp"
#include "scree/output/snapshot.hpp"

namespace fs = std::filesystem;

namespace scree {

namespace {

/// An interval counted in steps (`control` names the setting that makes it so) must be a
/// whole number of at least 1: `writeInterval 0.4` with `writeControl timeStep` was
/// rounded to every step without a word.
void check_step_count(const Entry& e, const std::string& control, const std::string& in_seconds,
                      std::vector<InputError>& errors) {
  double v = 0;
  try {
    v = e.as_scalar();
  } catch (const InputError&) {
    return;  // the spec reports a value that is no number
  }
  if (v >= 1 && v == std::floor(v) && v < 9.2e18) return;
  errors.emplace_back(e.where(), e.key() + ": with " + control + " it counts steps: expected a whole number of "
                                 "steps, at least 1, found " + e.value_string() +
                                 " (for an interval in seconds use " + in_seconds + ")");
}

}  // namespace

const CoreSpecs& CoreSpecs::get() {
  static const CoreSpecs specs = [] {
    CoreSpecs s;
    // ---- system/controlDict ----
    auto c = std::make_shared<ParamSpec>("controlDict", "time control, output and plugins (system/controlDict)");
    c->word("application", "the solver (informational)").default_value("scree");
    c->scalar("startTime", "s", "start time of a run from the case's initial state (0)").default_value(0.0).range(0, 0);
    // Restart (case/checkpoint.hpp): OpenFOAM's startFrom; `scree --restart` is latestTime.
    c->word("startFrom", "startTime: a run starts from the case's initial state; latestTime: it continues "
                         "from the newest checkpoint in checkpoints/ (from startTime when there is none)")
        .choices({"startTime", "latestTime"})
        .default_value("startTime");
    c->integer("checkpointInterval", "a checkpoint (the whole state, for a restart) at every this many write "
                                     "times, at endTime and when a signal stops the run (0: none)")
        .default_value(1.0)
        .non_negative();
    c->integer("checkpointKeep", "the newest checkpoints kept in checkpoints/ (older ones are removed)")
        .default_value(2.0)
        .range(1, 1e9);
    c->scalar("endTime", "s", "end time").positive();
    c->scalar("deltaT", "s", "time step (the first step when adjustTimeStep is on)").positive();
    c->boolean("adjustTimeStep", "adapt the time step to the CFL condition with maxCo").default_value("no");
    c->scalar("maxCo", "-", "CFL number for adjustTimeStep: dt = maxCo h / max(c + |v|)")
        .default_value(0.5)
        .range(0, 1)
        .open_min();
    c->scalar("maxDeltaT", "s", "largest time step with adjustTimeStep (default: deltaT)").optional().positive();
    c->word("writeControl", "when to write: timeStep (every writeInterval steps), runTime or "
                            "adjustableRunTime (every writeInterval seconds of simulated time)")
        .choices({"timeStep", "runTime", "adjustableRunTime"})
        .default_value("adjustableRunTime");
    c->scalar("writeInterval", "s or steps", "interval between writes (see writeControl)").positive();
    c->word_list("libs", "extra plugin libraries to load, e.g. (\"libmyMaterial.so\")").optional();
    c->dict("writers", "output writers: name { type vtk; ... }").optional();
    c->dict("functions", "function objects: name { type runOut; ... }").optional();
    c->integer("progressInterval", "steps between progress reports (0: automatic, about 2 per second)")
        .default_value(0.0)
        .non_negative();
    // Health: a run gone wrong stops non-zero with a diagnosis instead of writing garbage
    // (step_control.hpp; non-finite positions, velocities and stresses always stop it).
    c->scalar("stopCo", "-",
              "with a fixed deltaT, a step whose Courant number dt (c + |v|)_max / h exceeds this stops the "
              "run as unstable (the explicit scheme's limit is about 1; adjustTimeStep follows c + |v|)")
        .default_value(2.0)
        .positive();
    c->scalar("maxLostFraction", "-",
              "the run stops when more than this fraction of the particles has left the grid (1: never)")
        .default_value(0.1)
        .range(0, 1);
    c->allow_keys({"FoamFile"});
    c->check([spec = c.get()](const Dictionary& d, std::vector<InputError>& errors) {
      const ParamReader r(*spec, d);
      // The largest step: deltaT, or with adjustTimeStep maxDeltaT (which defaults to
      // deltaT). A step the clock cannot add at endTime ran forever without a word.
      const bool adaptive = r.boolean("adjustTimeStep");
      const char* key = adaptive && d.has("maxDeltaT") ? "maxDeltaT" : "deltaT";
      std::string problem = TimeControl::step_problem(r.scalar("startTime"), r.scalar("endTime"), r.scalar(key));
      if (!problem.empty()) {
        if (adaptive && !d.has("maxDeltaT"))
          problem += "; with adjustTimeStep, deltaT is also the largest step unless maxDeltaT is given";
        errors.emplace_back(d.at(key).where(), std::string(key) + ": " + problem);
      }
      // writeInterval 0.4 with writeControl timeStep was rounded to "every step".
      if (r.word("writeControl") == "timeStep")
        check_step_count(d.at("writeInterval"), "writeControl timeStep", "writeControl runTime or adjustableRunTime",
                         errors);
    });
    s.control = c;

    // ---- system/mpmSchemes ----
    auto m = std::make_shared<ParamSpec>("mpmSchemes", "MPM algorithm choices (system/mpmSchemes)");
    m->word("updateScheme", "USF: stress from the velocity mapped at the start of the step (the paper's); "
                            "USL: stress from the updated grid velocity (one fused particle pass per step); "
                            "MUSL: USL with the velocity re-mapped from the updated particles")
        .choices({"USF", "USL", "MUSL"})
        .default_value("USF");
    m->word("shapeFunction", "linear: the paper's tent functions; gimp: uGIMP; bspline2: quadratic B-spline "
                             "(the last two remove cell-crossing noise; a case with two-phase bodies: linear or gimp)")
        .choices({"linear", "gimp", "bspline2"})
        .default_value("linear");
    m->word("transfer", "particle velocity update: FLIP (blended with PIC by picRate or picFraction) or APIC")
        .choices({"FLIP", "APIC"})
        .default_value("FLIP");
    m->scalar("picFraction", "-", "PIC share of the FLIP/PIC blend per step (0: pure FLIP, the paper's eq. 10); "
                                 "its damping rate picFraction/dt doubles when the step is halved")
        .default_value(0.0)
        .range(0, 1);
    m->scalar("picRate", "1/s",
              "PIC share of the FLIP/PIC blend per unit time: each step takes 1 - exp(-picRate dt) of PIC, so "
              "that the blend damps the velocity fluctuations it removes at the same rate whatever the time "
              "step (instead of picFraction; 0: none)")
        .default_value(0.0)
        .non_negative();
    auto damp = std::make_shared<ParamSpec>("damping", "local non-viscous damping (Cundall)");
    damp->word("type", "damping model").choices({"local", "none"}).default_value("local");
    damp->scalar("coefficient", "-", "fraction of the unbalanced nodal force removed against the motion")
        .range(0, 1);
    damp->scalar("startTime", "s", "damping acts from this time").default_value(0.0);
    damp->scalar("endTime", "s", "damping acts until this time (e.g. the end of a consolidation stage)")
        .default_value(1e300);
    m->dict("damping", "optional local damping, e.g. during a consolidation stage").sub_spec(damp).optional();
    // Particles sorted by cell keep a warp's stencils together (its P2G adds combine before
    // the atomics) and the gathers in cache. A particle crosses a 1 mm cell in ~100 steps at
    // 1 m/s and dt = 1e-5 s, and neighbours move together; a sort costs about two passes
    // over the particle data and ends a chunk of steps: every 200 steps by default.
    m->integer("sortInterval", "re-sort particles by cell every this many steps (0: never; the reference "
                               "kernels never sort)")
        .default_value(200.0)
        .non_negative();
    m->scalar("massTolerance", "-", "nodes lighter than this fraction of the lightest particle are not accelerated (0.1 keeps "
                                     "USL with linear shape functions from blowing up where points cross cells, at "
                                     "the price of those nodes' share of the forces; gimp is the cure)")
        .default_value(1e-6)
        .range(0, 1);
    m->scalar("maxVolumeRatio", "-",
              "largest volume of a material point as a multiple of its initial one, det F (default: no "
              "limit); beyond it F is scaled isotropically. For phaseTransition 1000/(1 + e0) stops a point at "
              "the kinetic theory's smallest solid fraction (1e-3), so that the few points a flow stretches "
              "thousands of times do not set the time step of the whole run (cases/flume/README.md)")
        .optional()
        .range(1, 1e12);
    m->allow_keys({"FoamFile"});
    m->check([spec = m.get()](const Dictionary& d, std::vector<InputError>& errors) {
      const ParamReader r(*spec, d);  // the spec's own defaults
      if (d.has("picFraction") && d.has("picRate") && r.scalar("picFraction") > 0 && r.scalar("picRate") > 0)
        errors.emplace_back(d.at("picRate").where(),
                            "picRate: give picFraction (PIC share per step) or picRate (per second), not both: "
                            "picFraction is set at " +
                                d.at("picFraction").where().str());
      if (r.word("transfer") == "APIC" && r.word("shapeFunction") == "linear")
        errors.emplace_back(d.has("transfer") ? d.at("transfer").where() : d.where(),
                            "transfer APIC needs shapeFunction gimp or bspline2: with linear shape functions "
                            "its affine velocity (sum v_I grad N_I) amplifies round-off after cell crossings");
    });
    s.schemes = m;

    // ---- system/gridDict ----
    auto g = std::make_shared<ParamSpec>("gridDict", "background grid (system/gridDict)");
    g->integer("dimension", "2 (plane strain) or 3").range(2, 3);
    g->vector("lower", "m", "lower corner of the domain").size(-1);
    g->vector("upper", "m", "upper corner of the domain").size(-1);
    g->scalar("cellSize", "m", "cell size h (square/cubic cells)").positive();
    g->integer("ghostLayers", "node layers added outside the domain for the stencils")
        .default_value(2.0)
        .range(1, 8);
    g->allow_keys({"FoamFile"});
    g->check([](const Dictionary& d, std::vector<InputError>& errors) {
      const auto lo = d.at("lower").as_scalar_list(), hi = d.at("upper").as_scalar_list();
      for (std::size_t i = 0; i < lo.size() && i < hi.size(); ++i)
        if (!(hi[i] > lo[i]))
          errors.emplace_back(d.at("upper").where(), "upper: each component must exceed lower's (component " +
                                                         std::to_string(i) + ")");
    });
    s.grid = g;

    // ---- constant/g ----
    auto gr = std::make_shared<ParamSpec>("g", "gravitational acceleration (constant/g)");
    gr->vector("value", "m/s^2", "gravity vector, e.g. (0 -9.81)").size(-1);
    gr->any("dimensions", "OpenFOAM dimension set (ignored)").optional();
    gr->allow_keys({"FoamFile"});
    s.gravity = gr;

    // ---- a body in constant/bodies ----
    auto b = std::make_shared<ParamSpec>("body", "a set of particles with one material (constant/bodies)");
    b->word("material", "name of a material in constant/materialProperties");
    auto region = std::make_shared<ParamSpec>("region", "where the particles are");
    region
        ->word("type",
               "2D: rectangle (lower, upper), polygon (points); 3D: box (lower, upper), cylinder (p1, p2, radius: "
               "the axis from p1 to p2, as OpenFOAM's cylinderToCell), sphere (centre, radius), extrudedPolygon "
               "(points in the plane of the two axes after `axis` in cyclic order: axis z (x y), x (y z), y (z x); "
               "extruded over `range`), stl (file: a closed triangulated surface, ASCII or binary STL, relative to "
               "the case)")
        .choices({"rectangle", "box", "polygon", "cylinder", "sphere", "extrudedPolygon", "stl"});
    region->vector("lower", "m", "lower corner (rectangle, box)").size(-1).optional();
    region->vector("upper", "m", "upper corner (rectangle, box)").size(-1).optional();
    region->list("points", "vertices ((a0 b0) (a1 b1) ...), in order (polygon: (x y); extrudedPolygon: see axis)")
        .optional();
    region->vector("p1", "m", "start of the axis (cylinder)").size(3).optional();
    region->vector("p2", "m", "end of the axis (cylinder)").size(3).optional();
    region->vector("centre", "m", "centre (sphere)").size(3).optional();
    region->scalar("radius", "m", "radius (cylinder, sphere)").positive().optional();
    region->word("axis", "direction of extrusion (extrudedPolygon); the points are in the two axes after it")
        .choices({"x", "y", "z"})
        .default_value("z");
    region->scalar_list("range", "m", "(min max) along axis (extrudedPolygon)").optional();
    region->word("file",
                 "STL file relative to the case, e.g. \"constant/triSurface/terrain.stl\" (stl): a closed surface "
                 "(every edge shared by two triangles) of triangles with non-zero area, ASCII or binary; the "
                 "particles are the sub-cell centres inside it")
        .optional();
    region->check([](const Dictionary& d, std::vector<InputError>& errors) {
      const std::string t = d.get_word("type");
      // The keys of each type; any other is an error (a cylinder's `lower` would be ignored).
      static const std::vector<std::pair<std::string, std::vector<std::string>>> keys = {
          {"rectangle", {"lower", "upper"}},   {"box", {"lower", "upper"}},
          {"polygon", {"points"}},             {"cylinder", {"p1", "p2", "radius"}},
          {"sphere", {"centre", "radius"}},    {"extrudedPolygon", {"points", "axis", "range"}},
          {"stl", {"file"}}};
      std::vector<std::string> own;
      for (const auto& [type, k] : keys)
        if (type == t) own = k;
      std::string list;
      for (const auto& k : own) list += (list.empty() ? "" : ", ") + k;
      for (const auto& k : own)
        if (k != "axis" && !d.has(k))
          errors.emplace_back(d.where(), "region of type " + t + " needs " + k + " (it takes " + list + ")");
      for (const Entry& e : d.entries())
        if (e.key() != "type" && e.key()[0] != '_' && std::find(own.begin(), own.end(), e.key()) == own.end())
          errors.emplace_back(e.where(), e.key() + ": not a key of a region of type " + t + "; it takes " + list);
      if (t == "cylinder" && d.has("p1") && d.has("p2") && d.at("p1").as_scalar_list() == d.at("p2").as_scalar_list())
        errors.emplace_back(d.at("p2").where(), "p2: equals p1, so the cylinder has no axis; expected p2 != p1 (the "
                                                "axis runs from p1 to p2)");
      if (t == "extrudedPolygon" && d.has("range")) {
        const auto r = d.at("range").as_scalar_list();
        if (r.size() != 2)
          errors.emplace_back(d.at("range").where(), "range: expected (min max), found " + d.at("range").value_string());
        else if (!(r[0] < r[1]))
          errors.emplace_back(d.at("range").where(), "range: expected (min max) with min < max, found " +
                                                         d.at("range").value_string());
      }
    });
    b->dict("region", "the region filled with particles").sub_spec(region);
    auto clip = std::make_shared<ParamSpec>("clip", "a box the region is cut to");
    clip->vector("lower", "m", "lower corner").size(-1);
    clip->vector("upper", "m", "upper corner").size(-1);
    clip->check([](const Dictionary& d, std::vector<InputError>& errors) {
      const auto lo = d.at("lower").as_scalar_list(), hi = d.at("upper").as_scalar_list();
      for (std::size_t i = 0; i < lo.size() && i < hi.size(); ++i)
        if (!(hi[i] > lo[i]))
          errors.emplace_back(d.at("upper").where(), "upper: each component must exceed lower's (component " +
                                                         std::to_string(i) + ")");
    });
    b->dict("clip",
            "particles only where the region and this box { lower (..); upper (..); } both hold, e.g. a quarter "
            "cylinder beside two symmetry planes")
        .sub_spec(clip)
        .optional();
    b->integer("particlesPerCell", "particles per cell along each axis (2: 4 per cell in 2D)")
        .default_value(2.0)
        .range(1, 8);
    b->vector("velocity", "m/s", "initial velocity").size(-1).optional();
    b->scalar_list("angularVelocity", "rad/s",
                   "initial rigid rotation: (omega_z) in 2D (counter-clockwise positive), (wx wy wz) in 3D")
        .optional();
    b->vector("rotationCentre", "m", "centre of angularVelocity (default: the body's centroid)").size(-1).optional();
    auto init = std::make_shared<ParamSpec>("initialStress", "initial stress");
    init->word("type",
               "none; geostatic: sigma_v = -|g| int rho dz over the material above the point (`overburden`), "
               "sigma_h = K0 sigma_v, tension positive; uniform: `stress`. A geostatic state whose surface is not "
               "level (a slope, a mound) is in vertical equilibrium column by column but not in horizontal "
               "equilibrium: K0 sigma_v does not vanish on an inclined face. A damped gravity stage settles it "
               "(mpmSchemes damping { type local; startTime; endTime; }) before the loading of interest")
        .choices({"none", "geostatic", "uniform"});
    init->scalar_list("stress", "Pa", "uniform initial stress (xx yy zz xy yz zx), tension positive").optional();
    init->check([](const Dictionary& d, std::vector<InputError>& errors) {
      if (d.has("surface") && d.has("overburden") && d.get_word("overburden") == "all")
        errors.emplace_back(d.at("surface").where(),
                            "surface: a given level replaces the overburden of the material above, so it does not go "
                            "with `overburden all`; expected either surface (one level for the body) or overburden "
                            "all (the material above each point), not both");
      if (d.get_word("type") == "uniform") {
        if (!d.has("stress"))
          errors.emplace_back(d.where(), "initialStress of type uniform needs stress (xx yy zz xy yz zx)");
        else if (d.at("stress").as_scalar_list().size() != 6)
          errors.emplace_back(d.at("stress").where(), "stress: expected 6 components (xx yy zz xy yz zx)");
      }
    });
    init->scalar("K0", "-", "lateral earth pressure coefficient (geostatic)").default_value(0.5).non_negative();
    init->word("overburden",
               "geostatic: what loads a point. all: the material above it in its own column, of every body, each "
               "with its own density (a two-phase body: its mixture's, (1 - n0) rho_s + n0 S_l rho_l), so a slope "
               "drawn as one polygon or stl, or layers of bodies, start with the weight above each point; needs "
               "gravity along one axis of the grid. body: the depth below one level for the whole body, its "
               "highest point (plus half a point spacing), with the body's own density, measured along g in any "
               "direction (one level per body; a slope's toe then carries the crest's depth). Under all, a body "
               "put on the ground (a footing, a plate) loads it from the start; to apply it as a load at t = 0, "
               "give the ground overburden body. Pore water above the ground surface (a water table above it, "
               "ponding) is not counted: no body of water loads the free surface in the initial state")
        .choices({"all", "body"})
        .default_value("all");
    init->scalar("surface", "m",
                 "geostatic: elevation of a level free surface along -g, one for the whole body in 2D and 3D: with "
                 "g along -y, sigma_yy = -int_y^surface rho g dz = -rho g (surface - y) for one density, "
                 "sigma_xx = sigma_zz = K0 sigma_yy; given, it replaces the overburden (overburden body with this "
                 "level)")
        .optional();
    b->dict("initialStress", "initial stress (default none)").sub_spec(init).optional();
    b->dict("twoPhase", "a porous body with a pore liquid (the two-phase formulation, porous/two_phase.hpp)")
        .sub_spec(two_phase_spec())
        .optional();
    b->boolean("allowOverlap", "yes: this body may share space with other bodies (particles of one inside the "
                               "other's region, doubling the mass there); no: an overlap is an error")
        .default_value("no");
    s.body = b;
    return s;
  }();
  return specs;
}

bool names_an_object(const Entry& e) { return e.key() != "FoamFile" && !e.key().empty() && e.key()[0] != '_'; }

std::vector<const Entry*> plugin_entries(const Dictionary& d) {
  std::vector<const Entry*> out;
  for (const Entry& e : d.entries())
    if (e.is_dict() && names_an_object(e)) out.push_back(&e);
  return out;
}

const PluginEntry& plugin_of(const Registry& reg, PluginKind kind, const Dictionary& d) {
  const Entry& type = d.at("type");
  return reg.get(kind, type.as_word(), type.where());
}

std::vector<const Entry*> Case::group_entries(const char* group) const {
  const Entry* g = control_.find(group);
  return g && g->is_dict() ? plugin_entries(g->dict()) : std::vector<const Entry*>{};
}

namespace {

/// Read a case file; a parse error, or a required file that is missing, is recorded and
/// an empty dictionary returned whose name is marked, so that neither its contents nor
/// what other files refer to in it are checked: the cause is reported once, without a
/// cascade of "missing" or "not defined" errors. An optional file that is absent is an
/// empty dictionary (its defaults apply).
constexpr const char* kUnreadable = "<unreadable>";
Dictionary read_or_record(const fs::path& dir, const std::string& rel, std::vector<InputError>& errors,
                          bool required = true) {
  const fs::path p = dir / rel;
  std::error_code ec;
  if (!fs::exists(p, ec)) {
    if (!required) return Dictionary(rel, SourceLocation{std::make_shared<std::string>(rel), 0, 0});
    errors.emplace_back(SourceLocation{std::make_shared<std::string>(rel), 0, 0},
                        "missing case file (expected " + p.string() + ")");
    return Dictionary(kUnreadable, SourceLocation{std::make_shared<std::string>(rel), 0, 0});
  }
  try {
    return Dictionary::read_file(p, rel);
  } catch (const InputError& e) {
    errors.push_back(e);
  } catch (const InputErrors& e) {
    for (auto& x : e.errors()) errors.push_back(x);
  }
  return Dictionary(kUnreadable, SourceLocation{std::make_shared<std::string>(rel), 0, 0});
}

bool readable(const Dictionary& d) { return d.name() != kUnreadable; }

/// Validate each `name { type X; ... }` entry of `d` against the spec of plugin X.
void validate_plugin_entries(const Dictionary& d, PluginKind kind, const Registry& reg,
                             std::vector<InputError>& errors, int dim,
                             const std::vector<std::string>& extra_keys = {}) {
  for (const Entry& e : d.entries()) {
    if (!names_an_object(e)) continue;
    if (!e.is_dict()) {
      errors.emplace_back(e.where(), "'" + e.key() + "': expected a dictionary { type ...; ... }, found " +
                                         e.value_string());
      continue;
    }
    const Dictionary& sub = e.dict();
    const Entry* type = sub.find("type");
    if (!type) {
      errors.emplace_back(sub.where(), "'" + sub.name() + "': missing entry 'type' (the " +
                                           std::string(to_string(kind)) + " to use)");
      continue;
    }
    try {
      const PluginEntry& pe = reg.get(kind, type->as_word(), type->where());
      if (extra_keys.empty()) {
        validate(*pe.spec, sub, errors, dim);
      } else {
        ParamSpec s = *pe.spec;
        s.allow_keys(extra_keys);
        validate(s, sub, errors, dim);
      }
    } catch (const InputError& err) {
      errors.push_back(err);
    }
  }
}

}  // namespace

Case Case::read(const fs::path& dir, PluginRuntime& rt) {
  Case c;
  c.dir_ = dir;
  std::vector<InputError> errors;
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(SourceLocation{std::make_shared<std::string>(dir.string()), 0, 0},
                     "not a case directory (it must contain system/ and constant/)");

  c.control_ = read_or_record(dir, "system/controlDict", errors);
  c.schemes_ = read_or_record(dir, "system/mpmSchemes", errors, false);
  c.grid_ = read_or_record(dir, "system/gridDict", errors);
  c.gravity_ = read_or_record(dir, "constant/g", errors);
  c.materials_ = read_or_record(dir, "constant/materialProperties", errors);
  c.bodies_ = read_or_record(dir, "constant/bodies", errors);
  c.boundaries_ = read_or_record(dir, "constant/boundaryConditions", errors, false);

  // Plugins named by the case come first: their specs are needed below.
  try {
    rt.load_libs(c.control_, dir);
  } catch (const InputError& e) {
    errors.push_back(e);
  }

  const CoreSpecs& cs = CoreSpecs::get();
  bool dimension_known = false;
  if (const Entry* d = c.grid_.find("dimension")) {
    try {
      c.dimension_ = static_cast<int>(d->as_integer());
      dimension_known = c.dimension_ == 2 || c.dimension_ == 3;
    } catch (const InputError&) {
    }
  }
  // Without a valid dimension (gridDict unreadable, or its dimension wrong, which is
  // reported there), vectors are not checked for their number of components: a 3D case
  // would otherwise get an error for every vector of every file.
  const int dim = dimension_known ? c.dimension_ : 0;
  if (readable(c.control_)) validate(*cs.control, c.control_, errors, dim);
  if (readable(c.schemes_)) validate(*cs.schemes, c.schemes_, errors, dim);
  if (readable(c.grid_)) validate(*cs.grid, c.grid_, errors, dim);
  if (readable(c.gravity_)) validate(*cs.gravity, c.gravity_, errors, dim);

  const Registry& reg = rt.registry();
  validate_plugin_entries(c.materials_, PluginKind::material, reg, errors, dim);
  validate_plugin_entries(c.boundaries_, PluginKind::boundaryCondition, reg, errors, dim);
  if (const Entry* w = c.control_.find("writers"); w && w->is_dict())
    validate_plugin_entries(w->dict(), PluginKind::writer, reg, errors, dim);
  if (const Entry* f = c.control_.find("functions"); f && f->is_dict()) {
    const std::size_t before = errors.size();
    validate_plugin_entries(f->dict(), PluginKind::functionObject, reg, errors, dim);
    // executeInterval counts steps with executeControl timeStep, as writeInterval does.
    if (errors.size() == before)
      for (const Entry& e : f->dict().entries()) {
        if (!e.is_dict() || !names_an_object(e)) continue;
        const Entry* control = e.dict().find("executeControl");
        const Entry* interval = e.dict().find("executeInterval");
        if (control && interval && control->as_word() == "timeStep")
          check_step_count(*interval, "executeControl timeStep", "executeControl runTime", errors);
      }
  }

  // `fields (...)` of writers and function objects: every name must be a field some body
  // of this case will have (the standard ones or its material's), so that a typo is an
  // error here, with its line, rather than a warning at the first write. Not when the
  // materials or bodies did not read (an include that cannot be opened, say): their fields
  // are then unknown, and that file's error is the one to report.
  if (readable(c.materials_) && readable(c.bodies_)) {
    std::vector<std::string> known;
    for (const FieldInfo& f : standard_particle_fields()) known.push_back(f.name);
    for (const Entry& e : c.materials_.entries()) {
      if (!e.is_dict() || !names_an_object(e) || !e.dict().has("type")) continue;
      try {
        if (const PluginEntry* pe = reg.find(PluginKind::material, e.dict().get_word("type")))
          for (const FieldInfo& f : pe->output_fields) known.push_back(f.name);
      } catch (const InputError&) {
      }
    }
    for (const Entry& e : c.bodies_.entries())
      if (e.is_dict() && e.dict().has("twoPhase")) {
        for (const FieldInfo& f : two_phase_fields()) known.push_back(f.name);
        break;
      }
    known.push_back("all");
    for (const char* group : {"writers", "functions"}) {
      const Entry* g = c.control_.find(group);
      if (!g || !g->is_dict()) continue;
      for (const Entry& e : g->dict().entries()) {
        if (!e.is_dict()) continue;
        const Entry* f = e.dict().find("fields");
        if (!f) continue;
        try {
          for (const Item& it : f->single_item().list()) {
            if (std::find(known.begin(), known.end(), it.text()) != known.end()) continue;
            std::string msg = "fields: no body of this case has a field '" + it.text() + "'";
            const std::string near = nearest_name(it.text(), known);
            if (!near.empty()) msg += "; did you mean '" + near + "'?";
            msg += " Valid: ";
            for (std::size_t i = 0; i + 1 < known.size(); ++i) msg += (i ? ", " : "") + known[i];
            errors.emplace_back(it.where(), msg);
          }
        } catch (const InputError&) {
        }
      }
    }
  }

  // Bodies: the core spec, and the material must exist. A material whose own entry is
  // wrong (reported above) is still defined; when materialProperties is missing or could
  // not be read, that is the one error (no "material 'soil' is not defined" besides).
  std::vector<std::string> materials;
  for (const Entry& e : c.materials_.entries())
    if (names_an_object(e)) materials.push_back(e.key());
  int nbodies = 0;
  for (const Entry& e : c.bodies_.entries()) {
    if (!names_an_object(e)) continue;
    if (!e.is_dict()) {
      errors.emplace_back(e.where(), "'" + e.key() + "': expected a body dictionary { material ...; region {...} }");
      continue;
    }
    ++nbodies;
    const Dictionary& b = e.dict();
    validate(*cs.body, b, errors, dim);
    // A region type of the other dimension, here where a cylinder's 3-component p1 in a 2D
    // case would otherwise be the only complaint (check_bodies says the same of a valid dict).
    if (const Entry* r = b.find("region"); dim && r && r->is_dict())
      if (const Entry* t = r->dict().find("type")) {
        try {
          const std::string why = region_dimension_mismatch(t->as_word(), dim);
          if (!why.empty()) errors.emplace_back(t->where(), why);
        } catch (const InputError&) {  // not a word: the spec has said so
        }
      }
    // A two-phase body's retention and permeability models: their plugins' specs.
    if (const Entry* tp = b.find("twoPhase"); tp && tp->is_dict())
      for (const auto& [key, kind] : {std::pair{"retention", PluginKind::retention},
                                      std::pair{"permeability", PluginKind::permeability}}) {
        const Entry* m = tp->dict().find(key);
        if (!m || !m->is_dict()) continue;
        try {
          const Entry& t = m->dict().at("type");
          validate(*reg.get(kind, t.as_word(), t.where()).spec, m->dict(), errors, dim);
        } catch (const InputError& err) {
          errors.push_back(err);
        }
      }
    if (const Entry* m = b.find("material"); m && readable(c.materials_)) {
      try {
        const std::string name = m->as_word();
        if (std::find(materials.begin(), materials.end(), name) == materials.end()) {
          std::string msg = "material: '" + name + "' is not defined in constant/materialProperties";
          const std::string near = nearest_name(name, materials);
          if (!near.empty()) msg += "; did you mean '" + near + "'?";
          if (materials.empty()) {
            msg += " (it defines no material)";
          } else {
            msg += "; defined: ";
            for (std::size_t i = 0; i < materials.size(); ++i) msg += (i ? ", " : "") + materials[i];
          }
          errors.emplace_back(m->where(), msg);
        }
      } catch (const InputError& err) {
        errors.push_back(err);
      }
    }
  }
  if (nbodies == 0 && readable(c.bodies_))
    errors.emplace_back(c.bodies_.where(), "constant/bodies defines no body (name { material ...; region {...} })");

  if (!errors.empty()) {
    // Report in file order (files in the order read, then line and column).
    std::vector<std::string> order;
    for (const auto& e : errors) {
      const std::string f = e.where().file ? *e.where().file : "";
      if (std::find(order.begin(), order.end(), f) == order.end()) order.push_back(f);
    }
    std::stable_sort(errors.begin(), errors.end(), [&](const InputError& a, const InputError& b) {
      const auto fa = std::find(order.begin(), order.end(), a.where().file ? *a.where().file : "");
      const auto fb = std::find(order.begin(), order.end(), b.where().file ? *b.where().file : "");
      if (fa != fb) return fa < fb;
      if (a.where().line != b.where().line) return a.where().line < b.where().line;
      return a.where().column < b.where().column;
    });
    throw InputErrors(std::move(errors));
  }
  c.settings_ = CaseSettings::read(c);
  return c;
}

}  // namespace scree
