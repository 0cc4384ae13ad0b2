// Reading an element-test program from a dictionary (OpenFOAM syntax), validated against
// a ParamSpec so that typos and out-of-range values are reported with file:line.
//
//   material { type phaseTransition; ... }           // any registered material
//   initialStress
//   {
//       type            K0;        // K0 | isotropic  (stresses compression positive)
//       verticalStress  500;       // [Pa] sigma_v (K0)
//       K0              0.5;       // [-] sigma_h/sigma_v (K0)
//       // pressure     100e3;     // [Pa] (isotropic)
//   }
//   loading
//   {
//       type            undrainedSimpleShear;  // see element_driver.hpp
//       segments                               // rate history, in file order
//       {
//           start { duration 0.5;  rate 10; }          // constant rate
//           ramp  { duration 19.5; acceleration 50; }  // rate continues from 10
//       }
//       timeStep        1e-4;      // [s]  (or: increments N;)
//       outputInterval  0.02;      // [s]  (default: duration/500)
//       // outputPerDecade 50;     // or log-spaced rows in time (rates from rest)
//       control         constantCellPressure;  // drainedTriaxial: | constantMeanStress
//       spin            yes;       // simple shear: rotate the stress with the spin
//   }
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "element_driver.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/params/spec.hpp"

namespace scree::element {

inline std::shared_ptr<ParamSpec> segment_spec() {
  auto s = std::make_shared<ParamSpec>("segment", "one piece of the rate history: rate(t) = rate + acceleration t");
  s->scalar("duration", "s", "length of the segment").positive();
  s->scalar("rate", "1/s",
            "rate at the start of the segment (shear rate; axial or volumetric strain rate, compression positive); "
            "default: the end rate of the previous segment (0 for the first)")
      .optional();
  s->scalar("acceleration", "1/s^2", "rate of change of the rate").default_value(0.0);
  return s;
}

inline std::shared_ptr<ParamSpec> initial_stress_spec() {
  auto s = std::make_shared<ParamSpec>("initialStress", "initial stress (compression positive)");
  s->word("type", "K0 (vertical stress and lateral ratio) or isotropic").choices({"K0", "isotropic"});
  s->scalar("verticalStress", "Pa", "sigma_v (type K0)").non_negative().optional();
  s->scalar("K0", "-", "lateral stress ratio sigma_h/sigma_v (type K0)").non_negative().default_value(0.5);
  s->scalar("pressure", "Pa", "p (type isotropic)").non_negative().optional();
  s->check([](const Dictionary& d, std::vector<InputError>& errors) {
    const std::string t = d.get_word("type");
    if (t == "K0" && !d.has("verticalStress"))
      errors.emplace_back(d.at("type").where(), "initialStress: type K0 needs verticalStress [Pa]");
    if (t == "isotropic" && !d.has("pressure"))
      errors.emplace_back(d.at("type").where(), "initialStress: type isotropic needs pressure [Pa]");
  });
  return s;
}

inline std::shared_ptr<ParamSpec> loading_spec() {
  auto s = std::make_shared<ParamSpec>("loading", "the loading program");
  s->word("type", "the element test")
      .choices({"undrainedSimpleShear", "drainedSimpleShear", "drainedTriaxial", "undrainedTriaxial",
                "isotropicCompression", "drainedTrueTriaxial"});
  s->dict("segments", "rate history: sub-dictionaries { duration; rate; acceleration; } in file order")
      .each_entry(segment_spec());
  s->scalar("timeStep", "s", "time step of the increments").positive().optional();
  s->integer("increments", "number of increments over the whole program (instead of timeStep)")
      .min(1)
      .optional();
  s->scalar("outputInterval", "s", "time between output rows (default: duration/500)").positive().optional();
  s->scalar("outputPerDecade", "-", "log-spaced output instead: rows per decade of time from the first step")
      .positive()
      .optional();
  s->word("control", "drainedTriaxial: constantCellPressure or constantMeanStress")
      .choices({"constantCellPressure", "constantMeanStress"})
      .default_value("constantCellPressure");
  s->scalar("b", "-",
            "drainedTrueTriaxial: b = (sigma_2 - sigma_3)/(sigma_1 - sigma_3) held at constant p, sigma_1 = "
            "sigma_yy (axial), sigma_2 = sigma_zz, sigma_3 = sigma_xx; 0 triaxial compression, 1 extension")
      .range(0.0, 1.0)
      .default_value(0.0);
  s->boolean("spin", "simple shear: co-rotate the stress with the spin W dt (objective)").default_value("yes");
  s->scalar("newtonTolerance", "-", "relative tolerance of the stress conditions (mixed control)")
      .positive()
      .default_value(1e-10);
  s->check([](const Dictionary& d, std::vector<InputError>& errors) {
    if (d.has("timeStep") == d.has("increments"))
      errors.emplace_back(d.where(), "loading: give exactly one of timeStep [s] and increments");
    if (d.sub("segments").entries().empty())
      errors.emplace_back(d.at("segments").where(), "loading: segments needs at least one { duration ...; }");
  });
  return s;
}

/// The spec of a whole element-test dictionary (the material is validated by the registry).
inline ParamSpec element_spec() {
  ParamSpec s("scree-element", "element test of one material point");
  s.dict("material", "the material: { type <name>; parameters... } (see scree --list-plugins)");
  s.dict("initialStress", "initial stress").sub_spec(initial_stress_spec());
  s.dict("loading", "loading program").sub_spec(loading_spec());
  return s;
}

/// Read a validated dictionary into a Program.
inline Program read_program(const Dictionary& d) {
  Program P;
  const Dictionary& is = d.sub("initialStress");
  {
    auto spec = initial_stress_spec();
    ParamReader r(*spec, is);
    if (r.word("type") == "K0") {
      const Real sv = r.scalar("verticalStress"), k0 = r.scalar("K0");
      P.sigma0 = Sym3{{-k0 * sv, -sv, -k0 * sv, 0, 0, 0}};
    } else {
      const Real p = r.scalar("pressure");
      P.sigma0 = Sym3{{-p, -p, -p, 0, 0, 0}};
    }
  }
  const Dictionary& ld = d.sub("loading");
  auto spec = loading_spec();
  ParamReader r(*spec, ld);
  const std::string t = r.word("type");
  if (t == "undrainedSimpleShear") P.loading = Loading::undrainedSimpleShear;
  if (t == "drainedSimpleShear") P.loading = Loading::drainedSimpleShear;
  if (t == "drainedTriaxial") P.loading = Loading::drainedTriaxial;
  if (t == "undrainedTriaxial") P.loading = Loading::undrainedTriaxial;
  if (t == "isotropicCompression") P.loading = Loading::isotropicCompression;
  if (t == "drainedTrueTriaxial") P.loading = Loading::drainedTrueTriaxial;
  P.b = r.scalar("b");
  P.control = r.word("control") == "constantMeanStress" ? TriaxialControl::constantMeanStress
                                                        : TriaxialControl::constantCellPressure;
  auto sspec = segment_spec();
  for (const Entry& e : ld.sub("segments").entries()) {
    ParamReader sr(*sspec, e.dict());
    Segment sg;
    sg.duration = sr.scalar("duration");
    sg.rate_given = sr.has("rate");
    sg.rate = sg.rate_given ? sr.scalar("rate") : 0;
    sg.acceleration = sr.scalar("acceleration");
    P.segments.push_back(sg);
  }
  const Real T = P.duration();
  P.dt = r.has("timeStep") ? r.scalar("timeStep") : T / static_cast<Real>(r.integer("increments"));
  P.output_interval = r.has("outputInterval") ? r.scalar("outputInterval") : T / 500;
  P.output_per_decade = r.has("outputPerDecade") ? r.scalar("outputPerDecade") : 0;
  P.spin = r.boolean("spin");
  P.newton_tolerance = r.scalar("newtonTolerance");
  return P;
}

}  // namespace scree::element
