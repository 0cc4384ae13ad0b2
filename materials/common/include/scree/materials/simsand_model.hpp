// SIMSAND-type critical-state frictional model (Feng, Liang, Yin & Hu 2025, IJNAMG, section
// 3.2, eqs. 12-18): the whole model, for the materials that use it (simsand, the frictional
// half of phaseTransition) and for code built on the SDK. It lives in four headers, each
// usable on its own:
//   simsand_params.hpp      the constants: Params, Vars, Constants, make_params(), the
//                           evaluation policies (Production and the test references)
//   simsand_formulas.hpp    the model's formulas, one per function, each with its equation:
//                           elasticity (eq. 13), yield function and hardening (eq. 14),
//                           dilatancy (eq. 15), critical state (eq. 16), interlocking
//                           (eqs. 17-18), the Lode dependence, the elastoplastic rate, the
//                           initial state, the wave speed and the elastic energy
//   simsand_substeps.hpp    the pieces of the stress integration: drift correction, elastic
//                           path and yield crossing, apex and separation, Heun substeps and
//                           their error, implicit returns of stiff remainders
//   simsand_integrator.hpp  the stress update integrate() in stages, and integrate_elastic()
// The dictionary entries and their reader: simsand_spec.hpp (host only).
// materials/simsand/README.md lists the parameters and every decision.
#pragma once

#include "scree/materials/simsand_formulas.hpp"
#include "scree/materials/simsand_integrator.hpp"
#include "scree/materials/simsand_params.hpp"
#include "scree/materials/simsand_substeps.hpp"
