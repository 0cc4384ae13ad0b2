// scree-richards: a 1D Richards-equation solver, the independent reference for Scree's
// unsaturated (solid + liquid) infiltration cases. Standard C++ only; no libscree.
//
// Units are SI throughout, and the signs are these:
//   z    [m]     elevation, upward, 0 at the base of the column, L at the surface
//   h    [m]     pressure head, negative in suction; pore pressure p_w = rho_w g h [Pa]
//   s    [Pa]    suction s = -p_w (positive when unsaturated)
//   S    [-]     degree of saturation; water content theta = n S (n the porosity)
//   K    [m/s]   hydraulic conductivity K(h) = K_sat k_rel(h)
//   q    [m/s]   Darcy flux, POSITIVE UPWARD: q = -K (dh/dz + 1)
//   infiltration rate, outflow rate [m/s] are positive DOWNWARD (into the surface, out
//   through the base); cumulative amounts and storage are depths of water [m].
//
// Equation (the mixed form of Celia, Bouloutas & Zarba 1990, in 1D with z upward):
//   dW/dt = d/dz [ K(h) (dh/dz + 1) ],   W(h) = theta(h) + S_s S(h) h
// W is the water per unit volume at the reference density when the liquid has a
// linearised compressibility rho_w(p) = rho_w0 (1 + p_w/K_l): theta rho_w/rho_w0 =
// n S (1 + rho_w g h/K_l) = theta + S_s S h with S_s = n rho_w g/K_l [1/m]. Its time
// derivative is d(theta)/dt + S_s S dh/dt + S_s h dS/dt: the usual storage term S_s S dh/dt
// plus S_s h dS/dt, which is smaller than d(theta)/dt by the factor |S_s h|/n (1e-5 per
// metre of head for water). Keeping W as the conserved quantity makes the scheme exactly
// mass conservative with or without compressibility.
// With a deformable skeleton (Soil::E_oed > 0, oedometric, Bishop chi = S) W also holds the
// skeleton's volume change: W = S (n0 - eps) + S_s S h per unit reference volume, with
// eps = (dsigma - (S p_w - S_0 p_w0))/E_oed (richards1d.cpp, "Skeleton storage").
#pragma once

#include <filesystem>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include "scree/core/constants.hpp"

namespace scree::richards1d {

// ---------------------------------------------------------------------------------------
// Soil: retention S(h) and relative permeability k_rel(h)
// ---------------------------------------------------------------------------------------
enum class Retention { vanGenuchten, gardner };

struct Soil {
  Retention retention = Retention::vanGenuchten;
  double porosity = 0;   // n [-]
  double K_sat = 0;      // saturated hydraulic conductivity [m/s]
  double S_min = 0;      // residual saturation [-]
  double S_max = 1;      // saturation at zero suction [-]
  // van Genuchten (1980) in the form S = S_min + (S_max - S_min) [1 + (s/p0)^(1/(1-lambda))]^(-lambda)
  double p0 = 0;         // [Pa] air-entry-like pressure; alpha_vG = rho_w g / p0 [1/m]
  double lambda = 0;     // [-]  = m of van Genuchten; n_vG = 1/(1 - lambda)
  // Gardner (1958) exponential model: S_e = k_rel = exp(alpha h) for h < 0
  double alpha = 0;      // [1/m]
  double rho_w = 1000;   // [kg/m^3]
  double g = 9.81;       // [m/s^2]
  double kr_min = 1e-12; // floor on k_rel [-]
  double S_s = 0;        // specific storage [1/m]
  // Deformable skeleton (oedometric, small strain; richards1d.cpp "Skeleton storage"):
  double E_oed = 0;        // oedometric modulus [Pa]; 0: rigid skeleton (the classic Richards equation)
  bool water_load = true;  // E_oed > 0: the weight of the water gained or lost loads the skeleton
  bool deformable() const { return E_oed > 0; }

  double n_vg() const { return 1.0 / (1.0 - lambda); }
  double saturation(double h) const;            // S(h) [-]
  double dS_dh(double h) const;                 // [1/m]
  double effective_saturation(double h) const;  // S_e = (S - S_min)/(S_max - S_min) [-]
  double k_rel(double h) const;                 // [-], >= kr_min
  double k_rel_of_Se(double Se) const;          // the same as a function of S_e (no floor)
  double conductivity(double h) const { return K_sat * k_rel(h); }  // [m/s]
  double water_content(double h) const { return porosity * saturation(h); }
  double stored_water(double h) const;          // W(h) [-] (rigid skeleton)
  double capacity(double h) const;              // dW/dh [1/m] (rigid skeleton)
  /// Deformable skeleton: the stored water per unit reference volume at head h and
  /// compressive volumetric strain eps (richards1d.cpp, "Skeleton storage"), and its
  /// derivative in h at fixed total stress [1/m].
  double stored_water(double h, double eps) const;
  double capacity(double h, double eps) const;
  /// The saturation at which K_sat k_rel(S) = q (0 < q < K_sat): the unit-gradient state.
  double saturation_for_flux(double q) const;
};

// ---------------------------------------------------------------------------------------
// Problem settings
// ---------------------------------------------------------------------------------------
enum class TopCondition { head, flux };
enum class BottomCondition { head, noFlux, freeDrainage };
enum class InitialCondition { hydrostatic, uniform, steadyFlux };
enum class ConductivityMean { arithmetic, geometric };

struct Settings {
  double height = 0;  // column height L [m]
  int cells = 0;      // cells of the uniform grid; nodes at z_i = i L/cells, i = 0..cells
  Soil soil;

  InitialCondition initial = InitialCondition::hydrostatic;
  double water_table = 0;    // hydrostatic: h = water_table - z [m]
  double initial_head = 0;   // uniform: h [m]
  double initial_flux = 0;   // steadyFlux: steady infiltration rate q_A [m/s] above the base head

  TopCondition top = TopCondition::flux;
  double top_head = 0;       // head: h(L) [m]
  double top_flux = 0;       // flux: infiltration rate [m/s], downward positive
  double ponding_head = 0;   // flux: the head the surface holds while ponded [m]

  BottomCondition bottom = BottomCondition::head;
  double bottom_head = 0;    // head: h(0) [m]

  ConductivityMean mean = ConductivityMean::arithmetic;

  double end_time = 0;          // [s]
  double dt_initial = 1e-3;     // [s]
  double dt_min = 1e-9;         // [s] a step that fails below this stops the run
  double dt_max = kUnbounded;  // [s]
  double picard_tolerance = 1e-8;  // converged when max |delta h| < this [m]
  int picard_max_iterations = 30;
  int fast_iterations = 3;      // converged in <= this: dt *= dt_grow
  int slow_iterations = 8;      // converged in >= this: dt *= dt_shrink
  double dt_grow = 1.25, dt_shrink = 0.7, dt_cut = 0.5;  // dt_cut after a failed step
  double time_tolerance = 1e-6; // [m] bound on the estimated local time error of h; 0: off

  std::vector<double> profile_times;  // [s] rows of profiles.csv
  double history_interval = 0;        // [s] rows of surface.csv, front.csv; 0: every step
};

// ---------------------------------------------------------------------------------------
// Config files: "key value;" per line, // or # comments, `include "other.conf"`
// ---------------------------------------------------------------------------------------
/// A user error in a config: what() lists every problem found, one per line, each as
/// "file:line: key 'name': message".
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Reads a config file; `overrides` are "key=value" (the command line's --set), applied last.
/// Warnings (keys that the chosen options ignore) go to `warnings` when given.
Settings read_config(const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                     std::vector<std::string>* warnings = nullptr);
/// The same from text; `name` stands for the file name in messages, includes are relative
/// to the current directory.
Settings parse_config(const std::string& text, const std::string& name,
                      const std::vector<std::string>& overrides = {},
                      std::vector<std::string>* warnings = nullptr);
/// Every key with its unit, default and meaning (for --help).
void print_config_keys(std::ostream& os);

// ---------------------------------------------------------------------------------------
// The solver
// ---------------------------------------------------------------------------------------
/// Water balance since t = 0, depths of water [m] per unit area.
struct Balance {
  double applied = 0;   // prescribed surface flux integrated over time (flux top)
  double inflow = 0;    // infiltration through the surface (downward positive)
  double outflow = 0;   // outflow through the base (downward positive)
  double runoff = 0;    // applied - infiltrated while ponded (flux top)
  double storage0 = 0;  // integral of W dz at t = 0
  double storage = 0;   // integral of W dz now
  /// (inflow - outflow) - (storage - storage0): zero for an exactly conservative scheme.
  double error() const { return (inflow - outflow) - (storage - storage0); }
};

struct Counters {
  long steps = 0;             // accepted steps
  long rejected = 0;          // Picard failures (step cut and repeated)
  long error_rejected = 0;    // steps repeated shorter for the time-error bound
  long iterations = 0;        // Picard iterations over accepted and rejected attempts
  long switches = 0;          // top condition switches flux <-> ponded
  long max_iterations = 0;    // the most iterations an accepted step took
};

/// The column: node-centred finite differences (a finite-volume balance on each node's
/// cell, half cells at the ends), backward Euler, modified Picard iteration of Celia et al.
/// (1990) on the mixed form, one tridiagonal solve per iteration. The step adapts to the
/// Picard iteration count and to an estimate of the local time error (Column::step).
class Column {
 public:
  explicit Column(Settings s);

  /// Replaces the head profile (one value per node) as the state at t = 0, e.g. an analytic
  /// initial condition; resets the clock and the balance.
  void set_initial_head(std::vector<double> h);

  /// One accepted step, never past `t_limit`. Throws std::runtime_error when the Picard
  /// iteration fails even at dt_min.
  void step(double t_limit);
  /// Steps until time() == t_end.
  void advance_to(double t_end);

  double time() const { return t_; }
  double dt_next() const { return dt_; }
  const Settings& settings() const { return s_; }
  const std::vector<double>& z() const { return z_; }
  const std::vector<double>& head() const { return h_; }
  std::vector<double> saturation() const;
  const std::vector<double>& initial_saturation() const { return S0_; }
  /// Deformable skeleton: the compressive volumetric strain since t = 0 and the change of
  /// the total vertical stress [Pa] (compression positive) at the nodes now; zeros when rigid.
  const std::vector<double>& strain() const { return eps_; }
  const std::vector<double>& stress_change() const { return dsig_; }
  /// The stored water per unit reference volume at the nodes now (theta + S_s S h, and the
  /// skeleton's share when deformable) [-].
  const std::vector<double>& stored() const { return W_; }
  bool ponded() const { return ponded_; }
  const Balance& balance() const { return bal_; }
  const Counters& counters() const { return cnt_; }
  /// Rates of the last accepted step [m/s], downward positive.
  double infiltration_rate() const { return q_in_; }
  double outflow_rate() const { return q_out_; }

  /// Wetting-front elevation [m], the definition of front.csv's z_front: where S crosses
  /// the midpoint between the initial saturation and the surface saturation now,
  /// front_elevation(z, S, S_0, T) with T(z) = S(L, t).
  double front_elevation() const;
  /// The same with the steady state of the boundary conditions as the target, T = S_inf(z)
  /// (front.csv's z_front_steady); NaN when there is none (steady_state()).
  double front_elevation_steady() const;
  /// The steady saturation profile the column tends to (empty when there is none).
  const std::vector<double>& steady_saturation() const { return S_inf_; }

 private:
  bool picard(double dt, int& iterations);
  double surface_flux_under_head(double dt) const;
  void account(double dt);
  double dz() const { return s_.height / s_.cells; }
  double cell(int i) const { return (i == 0 || i == s_.cells) ? 0.5 * dz() : dz(); }
  double interface_K(double Ka, double Kb) const;
  bool top_is_head() const { return s_.top == TopCondition::head || ponded_; }
  double storage() const;
  /// W_i for the head profile h (rigid: the local W(h_i); deformable: top down through the
  /// stress change, "Skeleton storage" in richards1d.cpp); fills W, and eps_, dsig_.
  void stored_water(const std::vector<double>& h, std::vector<double>& W);
  double capacity(int i) const;  // dW_i/dh_i at the current iterate (the Picard matrix)

  Settings s_;
  std::vector<double> W_;     // stored water of the current iterate / state
  std::vector<double> W0_;    // stored water at t = 0 (the reference of the stress change)
  std::vector<double> Sp0_;   // S p_w at t = 0 [Pa] (the reference of the effective stress)
  std::vector<double> eps_, dsig_;  // strain and stress change of W_'s evaluation
  std::vector<double> z_, h_, h_old_, W_old_, S0_, S_inf_;
  std::vector<double> rate_;  // (h^n - h^{n-1})/dt of the last step [m/s]
  bool rate_valid_ = false;   // false at the start and after a switch of the top condition

  std::vector<double> Kf_;   // interface conductivities of the last Picard iteration
  double Kbase_ = 0;         // free drainage: K(h_0) of the last iteration
  std::vector<double> a_, b_, c_, r_, delta_;  // tridiagonal system
  double t_ = 0, dt_ = 0;
  bool ponded_ = false;
  double q_in_ = 0, q_out_ = 0;
  Balance bal_;
  Counters cnt_;
};

/// The steady head profile under an infiltration rate q [m/s] (downward) above a base
/// head h(0) = h_base: dh/dz = q/K(h) - 1, integrated upward with RK4 (64 substeps a cell).
std::vector<double> steady_flux_profile(const Soil& soil, double q, double h_base,
                                        const std::vector<double>& z);

/// The steady head profile that the boundary conditions of `s` lead to, on the nodes z;
/// empty when there is none to compute: only a head base has one here. With a head top it
/// is the profile of steady_flux_profile whose surface head is the top head (shooting on q);
/// with a flux top, the profile under that flux, or, if that would raise the surface above
/// the ponding head, the ponded one (shooting again).
std::vector<double> steady_state(const Settings& s, const std::vector<double>& z);

/// The wetting front [m]: scanning down from the surface, the first elevation where
/// S(z) < (S_0(z) + T(z))/2, T the target saturation (linear between nodes). The scan stops
/// at the first node where T does not exceed S_0 (beyond round-off): the target wets nothing
/// from there down, and the front is at that node. z.back() when the surface itself has
/// not reached its midpoint; z[0] when every node has.
double front_elevation(const std::vector<double>& z, const std::vector<double>& S, const std::vector<double>& S0,
                       const std::vector<double>& T);

// ---------------------------------------------------------------------------------------
// A run: the column plus its CSV output
// ---------------------------------------------------------------------------------------
struct FrontPassage {
  double z = 0;            // [m]
  double t = -1;           // first time z_front <= z [s]; -1: not reached
  double t_steady = -1;    // the same for z_front_steady
};

struct RunSummary {
  Balance balance;
  Counters counters;
  double wall_seconds = 0;
  double end_time = 0;
  double front_final = 0;          // [m]
  double front_steady_final = 0;   // [m] (NaN without a steady state)
  /// At 3/4, 1/2 and 1/4 of the height and at dz, the top of the base cell ("arrival at
  /// the base"); checked after every step, linear in time within it.
  std::vector<FrontPassage> front_passages;
  double first_ponding_time = -1;  // -1: never ponded
};

/// Runs the settings to end_time, writing profiles.csv, surface.csv and front.csv in `out`
/// (created if missing). Progress and the summary go to `log` when given.
RunSummary run(const Settings& s, const std::filesystem::path& out, std::ostream* log = nullptr);

}  // namespace scree::richards1d
