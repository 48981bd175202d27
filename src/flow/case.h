// The flow case: a TOML file naming the mesh, the fluid, the time stepping, one condition per
// boundary tag and the solver's PETSc options. The keys below are a contract (tests, examples
// and users' scripts rely on them):
//
//   mesh = "volume.msh"        # from `vesselmesh volume`; relative to the case file
//   length_unit = "mm"         # the mesh's unit; the solver works in SI
//   [fluid]    density = 1060.0 (kg/m3), viscosity = 0.0035 (Pa s)
//   [time]     steady = false; dt (s); end (s) or cycles with period (s); save_every (steps);
//              period may come with end too: the wall shear stress indices cover the last period
//              cfl_target = C (optional; where only the settled or periodic flow is wanted, not
//              its history: the steps' length chosen for a largest CFL number of about C, dt the
//              first's; next_time_step below)
//   [[boundary]] tag = "inlet"; type = "velocity" | "traction" | "resistance" | "rcr" | "wall";
//              profile = "parabolic" | "plug" | "womersley"; flow = 5.0 (mL/s) or waveform = "inlet.csv"
//              (time s, flow mL/s, repeated with its period); scale = -1.0 (multiplies the flow:
//              an outlet given the inlet's waveform); resistance = R (Pa s/m3)
//              type = "rcr": proximal_resistance, distal_resistance (Pa s/m3), capacitance (m3/Pa),
//              distal_pressure (Pa, default 0), initial_pressure (Pa, default distal_pressure)
//   [solver]   petsc_options = "..." (PETSc's options, applied after the defaults)
// Added keys: [boundary] harmonics (womersley: the waveform's Fourier harmonics kept, default
// 20); [time] picard (extra Oseen iterations per step, default 0), steady_tolerance
// (1e-6), steady_iterations (50), steady_method = "newton" | "picard" | "pseudo-transient"
// (the default Newton's iterations from Stokes up the inflow in stages; Picard iterations from
// Stokes; or pseudo time steps whose length grows as the flow settles; NavierStokes::solve_steady:
// on a bifurcation aneurysm at Re 300 Picard's stalled at a residual of 3e-4 after 50 iterations,
// Newton's settled in 14), initial = "rest" | "stokes" (an unsteady run starts at rest,
// or from the Stokes flow of the conditions at t = 0); [boundary] backflow (the traction boundaries' backflow
// stabilization coefficient, default 1); [solver] reuse_preconditioner = true | false (time steps
// keep the linear solver's preconditioner while it serves, LinearSolver::reuse_preconditioner;
// default true), kept_solutions = N (time steps' solves start from the least-residual combination
// of their guess and the last N solutions, LinearSolver::keep_solutions; default 4, 0: the
// extrapolated guess alone), threads = N (the assembly's threads in each process; default 0: the machine's
// cores on one process, one under MPI; the result is the same whatever N); [output] wss_method = "quadratic" | "face" (how the
// wall shear stress is taken from the velocity, post/wss.h; default quadratic), checkpoint_every
// = N (unsteady runs: a checkpoint, flow/checkpoint.h, every N steps, default save_every; 0:
// only at the last step and when SIGTERM or SIGINT stops the run), fluid_every = N (steps between
// saved fluid volumes, fluid_*.vtu, a multiple of save_every; default save_every; 0: the last step
// only — the wall, wall_*.vtp, is saved every save_every steps whatever it is: a fine mesh's
// volume files are what fills a disk), statistics_from = T (s; unsteady runs: the time mean of the
// velocity and the pressure and the RMS of the velocity's fluctuation from T to the end, per point,
// in statistics.vtu, flow/statistics.h; default none); [boundary] perturbation = I (velocity
// boundaries of unsteady cases: a disturbance added to the profile, each component's RMS over time
// I times the local speed, its net flow removed; flow/inflow_perturbation.h; default 0, none);
// [stabilization] tau_c_factor = f (tau_C times f: the LSIC term's weight; default 1, 0: none),
// tau_m_time = C_t (tau_M's time term C_t / dt^2; default 4, Bazilevs et al. 2007; 0: tau_M as a steady
// flow's): flow/stabilized_cell.h; for measuring what the stabilization does (issue 47), not for tuning a
// study's flows.
// A positive flow enters the domain, a negative one leaves it.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::flow {

// A flow rate in time, repeated with `period` (the samples' span). Samples that close the period
// (the last value the first's, within 1e-9 of the largest) are joined by the periodic cubic
// spline through them: its rate of change, which an inlet's pressure follows, continuous, where
// straight lines between samples 10 ms apart made the anastomosis study's inlet pressure jump
// +-9 Pa from one 5 ms step to the next (of about 50 at peak flow). Others, linear between samples
// (the period's end a jump in any case).
class Waveform {
 public:
  Waveform() = default;
  Waveform(std::vector<double> times, std::vector<double> values);
  static Waveform constant(double value);
  // A CSV of `time, value` rows (a header line and # comments allowed); InputError naming the
  // file and line for anything else.
  static Waveform read_csv(const std::string& path);
  double operator()(double t) const;
  Waveform scaled(double factor) const;
  double period() const { return times_.size() < 2 ? 0.0 : times_.back() - times_.front(); }
  int samples() const { return static_cast<int>(times_.size()); }
  bool smooth() const { return !curvature_.empty(); }  // the periodic spline, not straight lines

 private:
  std::vector<double> times_, values_;
  std::vector<double> curvature_;  // the spline's second derivative at each sample (empty: linear)
};

enum class BoundaryType { velocity, traction, resistance, rcr, wall };
enum class Profile { parabolic, plug, womersley };

struct BoundaryCondition {
  std::string tag;
  BoundaryType type = BoundaryType::wall;
  Profile profile = Profile::parabolic;
  Waveform flow;             // mL/s, positive into the domain (velocity)
  std::string waveform_file;  // where `flow` came from, if a file
  double resistance = 0.0;    // Pa s / m3 (resistance)
  // rcr (three-element Windkessel): the end's pressure is proximal_resistance x its outflow plus
  // the capacitor's pressure P_c, with capacitance dP_c/dt = outflow - (P_c - distal_pressure) /
  // distal_resistance; P_c starts at initial_pressure (default distal_pressure).
  double proximal_resistance = 0.0, distal_resistance = 0.0;  // Pa s / m3
  double capacitance = 0.0;                                   // m3 / Pa
  double distal_pressure = 0.0;                               // Pa
  std::optional<double> initial_pressure;                     // Pa
  int harmonics = 20;         // womersley: Fourier harmonics of the waveform kept
  double perturbation = 0.0;  // velocity: the inflow's disturbance, each component's RMS over the local
                              // speed (flow/inflow_perturbation.h; 0: none)
};

struct FlowCase {
  std::string path;  // the case file
  std::string mesh;  // resolved against the case file's folder
  std::string length_unit = "mm";
  double length_scale = 1e-3;  // metres per mesh unit
  double density = 1060.0, viscosity = 0.0035;
  bool steady = false;
  double dt = 1e-3, end = 1.0;
  double period = 0.0;  // s; 0 when not given. The hemodynamic indices cover the last period.
  double cfl_target = 0.0;  // [time] cfl_target: > 0, the steps' length follows the CFL number
  int save_every = 10;
  int picard = 0;
  double steady_tolerance = 1e-6;
  int steady_iterations = 50;
  bool stokes_start = false;  // [time] initial = "stokes"
  bool pseudo_transient = false;  // [time] steady_method = "pseudo-transient"
  bool newton = true;             // [time] steady_method = "newton" (the default)
  std::string steady_method = "newton";  // as the case gives it
  double backflow = 1.0;
  std::vector<BoundaryCondition> boundaries;
  std::string petsc_options;
  double tau_c_factor = 1.0;  // [stabilization]: tau_C times this (flow/stabilized_cell.h)
  double tau_m_time = 4.0;    // [stabilization]: C_t, tau_M's time term C_t / dt^2
  bool reuse_preconditioner = true;  // [solver]: time steps keep the preconditioner while it serves
  int kept_solutions = 4;  // [solver]: time steps start from the last N solutions' best (LinearSolver::keep_solutions)
  int threads = 0;  // [solver]: the assembly's threads a process; 0: the cores on one process, 1 under MPI
  std::string wss_method = "quadratic";  // post::parse_wss_method
  int checkpoint_every = 10;             // [output]: steps (default save_every); 0: at the end, on a signal
  int fluid_every = 10;                  // [output]: steps between fluid volumes (default save_every); 0: the last
  double statistics_from = -1.0;         // [output]: s, the time statistics' start; < 0: none
};

std::string to_string(BoundaryType type);
// Whether the boundary's condition is a traction (traction, resistance, rcr: the pressure level is
// set there, and flow entering through it is stabilized).
inline bool is_natural(BoundaryType type) {
  return type == BoundaryType::traction || type == BoundaryType::resistance || type == BoundaryType::rcr;
}

// Reads and checks a case file; every mistake is an InputError naming the file, the key and
// what is accepted. The mesh is not read here.
FlowCase read_case(const std::string& path);
// The same from TOML text (`path` names it in messages and resolves the relative paths).
FlowCase parse_case(const std::string& text, const std::string& path);

// Where the case aims at a CFL number (FlowCase::cfl_target): the next step's length (s) from this
// step's (`dt`) and its largest CFL number, dt x target / max_cfl, grown at most kTimeStepGrowth
// times and shrunk at most kTimeStepShrink times a step (BDF2 of variable step is zero-stable for
// ratios under 1 + sqrt 2; a flow at rest, max_cfl 0, grows by the most).
inline constexpr double kTimeStepGrowth = 1.25, kTimeStepShrink = 4.0;
double next_time_step(double dt, double max_cfl, double target);
// The length of the step from `time` that does not step past `end`: `dt`, all that is left when
// that is at most dt, half of it when it is under 2 dt (no sliver of a last step, none longer
// than asked).
double landing_time_step(double dt, double time, double end);

// The case with its time step divided by `divisor` (> 1) and its step counts (save_every,
// checkpoint_every, fluid_every) multiplied by it, so that it saves at the same times: a time-step
// convergence check (the study's); a CFL target divided too (steps chosen by it then as many times
// shorter). OptionError for a divisor < 1 or a steady case.
void divide_time_step(FlowCase& c, int divisor);
// The case run to `end` (s) instead of its [time] end: with a restart, a finished run extended (its
// hemodynamic indices then over the new last period); the study's start-up check. OptionError for
// an end that is not positive or a steady case.
void set_end(FlowCase& c, double end);

// Checks the case's tags against the mesh's: a tag of the case absent from the mesh, or a tag
// of the mesh without a condition, is an InputError listing both sets.
void check_tags(const FlowCase& flow_case, const std::vector<std::string>& mesh_tags);

}  // namespace vesselmesh::flow
