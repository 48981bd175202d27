// Incompressible Navier-Stokes on a tetrahedral mesh: P1-P1 finite elements with residual-based
// stabilization (SUPG/PSPG and LSIC), BDF2 in time (BDF1 on the first step; of variable step
// where the steps' length changes, set_time_step), a semi-implicit
// Oseen linearization (the advecting velocity extrapolated from the last two steps, optional
// Picard iterations) and one PETSc solve per step; a steady solve by Picard iterations from
// Stokes.
//
// Input: a TetMesh with tagged boundary triangles (mesh units; scaled to SI by the case's
// length unit) and a FlowCase whose conditions name every tag. Works in SI: velocity in m/s,
// pressure in Pa (the unknown is p / density).
// Stabilization (Tezduyar & Osawa 2000; Bazilevs et al. 2007): per element the metric
// G = sum_a grad(phi_a) grad(phi_a)^T, tau_M = (4/dt^2 + u.G.u + C_I nu^2 G:G)^(-1/2) with
// C_I = 36, tau_C = 1 / (tau_M tr G); thin boundary-layer tetrahedra get a small tau across the
// layer from G itself. Convection uses the element's mean advecting velocity. (The element's
// system: flow/stabilized_cell.h, four cells at a time.)
// Boundaries: `wall` no-slip; `velocity` a profile normal to the end (parabolic in the
// distance from the end's centroid, plug, or Womersley's from the waveform's Fourier series, with
// the radius of a disc of the end's area) scaled so that its discrete flux is the flow;
// `traction` the do-nothing condition nu du/dn - p n / rho = 0 with backflow stabilization
// (beta/2 |min(u.n, 0)| u, Moghadam et al. 2011); `resistance` a traction -R Q n with the
// outflow Q of the last step. Dirichlet rows carry the diagonal the element matrices gave them.
// Without a traction or resistance boundary the pressure is fixed to 0 at one point.
// Inside, the points are renumbered (flow/mesh_part.h): under MPI split among the processes by
// PT-Scotch (balanced in points, few shared), each process's in reverse Cuthill-McKee order; a
// process holds only its part of the mesh (its cells: those with a point it owns, and their
// points), and after a solve receives only its ghost points' values. Every argument and result is
// in the mesh's numbering.
// Under MPI every process makes one and calls every member alike (they are collective); the
// whole flow (gathered_velocity(), gathered_pressure()) is on every process when asked for,
// gathered_state()'s fields on the first only (empty on the others): the names say what they cost
// under MPI; the distributed post-processing and the checkpoints use the local ones (local_velocity(),
// own_state()).
#pragma once

#include "flow/case.h"
#include "flow/linear_solver.h"
#include "flow/mesh_part.h"
#include "mesh/reporter.h"
#include "mesh/tetmesh.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace vesselmesh::flow {

struct BoundaryFlow {
  std::string tag;
  double flux = 0.0;           // m3/s through the boundary, positive out of the domain
  double mean_pressure = 0.0;  // Pa, area-weighted
  double area = 0.0;           // m2
  double capacitor_pressure = 0.0;  // Pa: an rcr end's P_c (0 for the others)
};

// What the time stepping needs to go on (a checkpoint): per mesh point the velocity at the last
// two steps (m/s) and the pressure over the density (m2/s2, as the solver holds it), the time
// (s) and the steps taken (the first step is BDF1), the next step's length and the last one's (s;
// 0: the case's dt).
struct FlowState {
  double time = 0.0;
  int steps = 0;
  double time_step = 0.0, last_time_step = 0.0;
  std::vector<Vec3> velocity, previous;
  std::vector<double> kinematic_pressure;
  std::vector<double> capacitor_pressure;  // per boundary of the case: an rcr end's P_c (Pa), else 0
  // The mesh points the fields are of, one per entry (own_state()); empty: every point, in the
  // mesh's order (gathered_state()).
  std::vector<int> points;
};

// How the points are shared among the MPI processes: per process its points (owned rows / 4),
// its ghost points (points of the cells it assembles that another process owns) and the
// processes it shares cells with.
struct PartitionReport {
  std::vector<int> owned_points, ghost_points, neighbours;
  int threads = 1;  // the assembly's threads in each process (FlowCase::threads)
};

struct StepReport {
  int step = 0;  // steps taken so far (0 before the first)
  double time = 0.0;
  double time_step = 0.0;  // s, the step's length (time steps)
  int linear_iterations = 0;  // all solves of the step
  int solves = 0;
  int preconditioners_built = 0;  // the step's solves that built their preconditioner (the others reused one)
  double max_cfl = 0.0;  // max |u| dt / h over the elements (h: the element's least height)
  double change = 0.0;   // relative velocity change of the last (Picard) iteration
  // Steady solves: the steady equations' relative residual at the answer, ||R(u)|| / ||b|| (the
  // system assembled at u, times u, less its right-hand side; 2-norms over the unknowns); -1 when
  // not computed (time steps).
  double residual = -1.0;
  double seconds = 0.0, assembly_seconds = 0.0, solve_seconds = 0.0;
  std::string solver_reason;
};

// One iteration of a steady solve (NavierStokes::steady_history): what it was ("Stokes", "Newton",
// "Newton on the convection", "Picard", "pseudo time step"; a step that raised the residual names
// the linearization that replaced it), the share of the inflow it solved for, the steady residual
// of the flow it started from (-1 for the first: none measured), the velocity's relative change it
// made and its linear iterations.
struct SteadyIteration {
  int iteration = 0;
  std::string method;
  double inflow = 1.0;
  double residual = -1.0;
  double change = 0.0;
  int linear_iterations = 0;
};

// A time step's BDF weights: du/dt at the new time ~ (current u^(n+1) - now u^n + before u^(n-1)) / dt,
// the convecting velocity extrapolated to it as convect_now u^n - convect_before u^(n-1). The first
// step BDF1 (1, 1, 0; u^n); then BDF2 of variable step, ratio w = dt_n / dt_(n-1): (1 + 2w) /
// (1 + w), 1 + w, w^2 / (1 + w); 1 + w, w (with w = 1: 3/2, 2, 1/2; 2, 1): exact for quadratics in
// time, the extrapolation for linear ones; zero-stable for w < 1 + sqrt 2.
struct BdfWeights {
  double current = 1.0, now = 1.0, before = 0.0;
  double convect_now = 1.0, convect_before = 0.0;
};
BdfWeights bdf_weights(bool first, double ratio);

class NavierStokes {
 public:
  // Checks the case's tags against the mesh's (check_tags) and builds everything a step needs,
  // from this process's part of the mesh (distribute_mesh), or from the whole mesh (the first
  // process's; the others' are not read: it distributes it).
  NavierStokes(MeshPart part, const FlowCase& flow_case, const Reporter& reporter = silent_reporter());
  NavierStokes(const TetMesh& mesh, const FlowCase& flow_case, const Reporter& reporter = silent_reporter());
  ~NavierStokes();

  // One time step (unsteady cases), of time_step(). A diverging step is a ComputationError naming
  // the step and the likely cause (CFL, backflow).
  StepReport step();
  // The next step's length (s): the case's dt until set. Where it differs from the last step's,
  // the step is BDF2 of variable step (bdf_weights). OptionError for a length that is not positive
  // and finite.
  void set_time_step(double dt);
  double time_step() const;
  // The steady flow by the case's steady_method: Newton's (the default, last below), or Picard
  // iterations from Stokes until the relative change is below the case's tolerance, or pseudo time steps.
  // With the case's pseudo_transient: from Stokes, backward-Euler pseudo time steps, the first
  // at a CFL number of kPseudoCflStart, the next ones longer while the change per unit pseudo
  // time falls (by its fall, within [1.2, 2] a step), shorter (at most 2x) when it rises
  // (switched evolution relaxation); once a step changes the flow by less than the tolerance,
  // a Picard iteration (no time term) confirms it. The steady answer is the same; the pseudo
  // steps damp the iteration (not a flow that is itself unsteady).
  // With the case's newton: the inflow taken up in stages (kInflowStages: Dirichlet velocities a
  // quarter, a half, then all of the case's), each stage from the flow extrapolated from the last
  // two (a secant; zero flow at zero inflow before the first), to a change under kStageTolerance (or
  // until its Newton steps stall: kStalledSteps) but the last; the Stokes flow at the first stage, then
  // Newton's iterations: on the Galerkin convection (its full Jacobian, the stabilization in Picard's
  // form) and, after a whole step, on the stabilization's terms too (their derivatives through the
  // advecting velocity, the parameters tau_m and tau_c included: the exact Jacobian), each step cut back
  // (halved down to kLeastStep) until the steady residual falls (Armijo's test, the residual evaluated
  // by an assembly at the trial flow); where none does, the iteration again with the linearization
  // below (Newton's on the convection, then Picard's).
  // The iteration has settled when Newton's whole step is under the tolerance at the whole inflow.
  // A steady solve that does not settle in the case's steady_iterations is a ComputationError that
  // names the method, where the residual went, and what to try next (another method, running in time).
  StepReport solve_steady();
  // The last steady solve's iterations, one an iteration (also after it failed).
  const std::vector<SteadyIteration>& steady_history() const;
  static constexpr double kPseudoCflStart = 5.0;
  static constexpr double kLeastStep = 1.0 / 16.0;
  // Newton's stages of the inflow (the Reynolds number), each to a change under kStageTolerance
  // but the last.
  static constexpr std::array<double, 3> kInflowStages = {0.25, 0.5, 1.0};
  static constexpr double kStageTolerance = 1e-2;
  // A stage below the whole inflow whose Newton steps stall moves on too (kStalledSteps steps in a row
  // cut back, each taking off less than kStallFall of the steady residual).
  static constexpr int kStalledSteps = 2;
  static constexpr double kStallFall = 0.1;
  // A steady iteration's linear system the iterative solver does not converge on (its true
  // residual checked: an answer whose true residual missed, or a failed solve, is solved again with
  // SOR sweeps on the velocity blocks first, LinearSolver::sweep_velocity_blocks) is solved directly (MUMPS) up to
  // this many unknowns (its memory grows faster than they do), said in a warning; larger ones are a
  // ComputationError as before.
  static constexpr int kDirectFallbackUnknowns = 300000;
  // An unsteady run's start from the Stokes flow of the conditions at the current time (one
  // linear solve, no advection; stabilized with the time steps' tau_M, so that its discrete
  // continuity equation is theirs): the developed flow a pipe would take seconds of time steps to
  // reach. The next step() is the first (BDF1).
  StepReport start_from_stokes();

  // Starts the time stepping from this velocity (m/s per point) at this time (s).
  void set_state(const std::vector<Vec3>& velocity, double time);
  // The whole state (its fields on the first process), and the stepping resumed from one: whole
  // (`points` empty) or by mesh point, holding at least this process's local points
  // (local_points()); InputError when its sizes do not fit or a local point is missing.
  FlowState gathered_state() const;
  void restore(const FlowState& state);
  // The mesh numbers of this process's points (its own, then its ghosts).
  const std::vector<int>& local_points() const;
  // The state of this process's own points (`points` their mesh numbers; nothing gathered).
  FlowState own_state() const;

  double time() const;
  int steps() const;
  int dofs() const;
  // The whole flow per mesh point (m/s, Pa), on every process: under MPI gathered when first asked
  // for after a solve (every process must ask alike; the whole mesh's fields on each, 32 bytes a point).
  const std::vector<Vec3>& gathered_velocity() const;
  const std::vector<double>& gathered_pressure() const;
  // This process's flow per point of its part (MeshPart's local numbering: owned, then ghosts),
  // m/s and Pa; nothing gathered.
  const std::vector<Vec3>& local_velocity() const;
  std::vector<double> local_pressure() const;
  std::vector<BoundaryFlow> boundary_flows() const;
  std::string solver_description() const;
  PartitionReport partition() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vesselmesh::flow
