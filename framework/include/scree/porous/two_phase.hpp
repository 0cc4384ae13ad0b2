// The two-phase formulation: saturated or unsaturated soil as one set of material points
// carrying the solid skeleton and the pore liquid, with a velocity field for each phase
// (the single-point, two-velocity formulation of Anura3D and of the rainfall-infiltration
// MPM we implement: a_s, a_l, n, S_l, rho_s, rho_l). The pore air is at atmospheric
// pressure (p_a = 0).
//
// The solid skeleton is an ordinary body of the case's material: its kernels (mpm/
// particle_pass.hpp) move the points with the solid velocity v_s, update F and the
// effective stress sigma' (tension positive), and scatter the solid mass m_s = (1 - n0)
// rho_s V0, its momentum and the force -V sigma' grad N + N m_s g. The pore liquid adds two
// passes over the same points and its own grid fields; nothing of it runs in a
// single-phase case.
//
// Equations (SI, p_w compression positive, sigma tension positive, chi = S_l):
//   effective stress (Bishop, chi = S_l):   sigma = sigma' - S_l p_w I
//   mixture momentum:   M_s a_s + M_lm a_l = F_mix
//       F_mix = -sum V (sigma' - S_l p_w I) grad N + sum N (m_s + m_lm) g
//   liquid momentum (per unit volume of liquid, Darcy drag):
//       M_l a_l = F_l - Q (v_l - v_s),  F_l = sum V p_w grad N + sum N rho_l V g,
//       Q = sum N V n S_l mu_l / (kappa k_I),  k_I = sum N V k_rel / sum N V
//     (k_I the arithmetic mean over the node's points, as a finite-volume Richards solver
//     takes between its cells, Celia et al. 1990; a sum of the points' resistances,
//     sum N V n S mu / (kappa k_rel), is their harmonic mean: one dry point behind a
//     wetting front then holds the water back, and a dry surface takes in almost no rain)
//     (steady state: n S_l (v_l - v_s) = -(kappa k_rel / mu_l)(grad p_w - rho_l g), Darcy)
//   liquid mass balance, incompressible grains, liquid bulk modulus K_l:
//       (n S_l / K_l + n dS_l/dp_w) dp_w/dt = -(S_l div v_s + div q),  q = n S_l (v_l - v_s)
//   porosity from the solid volumetric strain: n = 1 - (1 - n0) / J, J = det F.
// The drag is integrated implicitly per node (TwoPhaseGridUpdate): its explicit limit,
// dt < 2 k / (n g) with k the hydraulic conductivity (4e-8 s at k = 1e-7 m/s, and smaller
// as k_rel -> 0), no longer constrains the step, which the acoustic limit alone sets.
//
// The formulation in its headers, each included here:
//   liquid_fields.hpp        the pore liquid's columns on the points, its constants and its
//                            nodal fields (LiquidFields)
//   free_surface.hpp         the surface nodes, the seepage through the surface (closed, open,
//                            the rain's correction) and the walls' share in its normal
//   hydraulic_condition.hpp  what the hydraulic conditions (rainfall, ponding, seepageFace,
//                            porePressure) give the formulation: HydraulicCondition
//   pore_pass.hpp            the pore passes' parameters and base (PorePassParams, PorePass)
//   pore_gather.hpp          the gather at x^k: liquid G2P, pore pressure per cell
//                            (PoreRate, CellPressure, PorePressure)
//   pore_scatter.hpp         both phases' P2G at x^{k+1} (MixtureScatter, SurfaceScatter)
//   grid_update.hpp          the grid update with the implicit drag (TwoPhaseGridUpdate) and
//                            the liquid that entered through the surface (SurfaceInflow)
// The stencil loop they share with the solid's pass is mpm/stencil.hpp; PorousMedia
// (src/porous/porous_media.hpp) runs them.
#pragma once

#include "scree/porous/free_surface.hpp"
#include "scree/porous/grid_update.hpp"
#include "scree/porous/hydraulic_condition.hpp"
#include "scree/porous/hydraulic_model.hpp"
#include "scree/porous/liquid_fields.hpp"
#include "scree/porous/pore_gather.hpp"
#include "scree/porous/pore_pass.hpp"
#include "scree/porous/pore_scatter.hpp"
