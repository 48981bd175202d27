// Sparse linear systems of the flow solver, solved by PETSc behind this small header (PETSc's
// headers stay in linear_solver.cpp).
//
// The unknowns are interleaved per node: `block_size` values a node, the last one the
// pressure (u, v, w, p for the flow). With PETSc's `fieldsplit` preconditioner the two fields
// are named `u` (the first block_size - 1 components) and `p`, so options address them as
// `-fieldsplit_u_...` and `-fieldsplit_p_...`.
// Options are PETSc's command-line options as one string; each solver starts from its
// defaults and then applies the caller's string, whose values win.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::flow {

// Compressed rows with sorted (global) column indices, of points (nodes): a matrix with
// `block_size` unknowns a point holds a block_size x block_size block at every entry (rows
// block_size x rows, interleaved per point; a right-hand side or solution too). On several MPI
// processes each holds its own consecutive rows: `first_row` .. first_row + rows of
// `global_rows` (the whole matrix on one process: first_row 0, global_rows = rows), and reads
// the solution at its `ghost_rows` too (rows other processes own: the points of its cells that it
// does not own). `values` of a matrix follow the pattern's order: per row, per component row
// i < block_size, per column, per component column j.
struct SparsePattern {
  int rows = 0;
  int first_row = 0;
  int global_rows = 0;  // 0: rows
  std::vector<int> row_start;  // rows + 1 offsets
  std::vector<int> columns;
  std::vector<int> ghost_rows;  // global rows, in the order the solution holds them after its own
  int nonzeros() const { return static_cast<int>(columns.size()); }
  int total_rows() const { return global_rows > 0 ? global_rows : rows; }
};

struct SolveStats {
  int iterations = 0;
  double residual_norm = 0.0;  // the preconditioned residual PETSc's test looks at
  bool converged = false;
  std::string reason;  // PETSc's converged reason, e.g. CONVERGED_RTOL or DIVERGED_ITS
  bool preconditioner_built = true;  // false: the previous solve's preconditioner served
  // The Krylov method said converged but the true residual is far above the tolerance
  // (LinearSolver::set_residual_check): converged is false, and reason says so.
  bool true_residual_missed = false;
};

// The Schur complement of every default split below is preconditioned by a matrix the flow
// assembles (`user`: MatrixValues::schur_own; its pressure block plus a weighted pressure Laplacian
// on the element stencil, NavierStokes's assembly) where PETSc's selfp multiplied
// A11 - A10 diag(A00)^-1 A01 out over two rings of points at every preconditioner build: at 420k
// unknowns 832 MB against 1021 and 1.24 s a step against 1.15 (9/8/4/4/3 iterations against 7/6/3/3/3),
// the Stokes start 11 s against 15; the carotid bifurcation's steady solve at Re 300 110 s against
// 198 and 900 MB against 1293 (1050 linear iterations against 1419; bench/flow_scaling.sh,
// bench/steady_vessels.sh). A caller's `-pc_fieldsplit_schur_precondition selfp` has PETSc's again.
// That matrix's preconditioner, in every split: one cycle of hypre's BoomerAMG, HMIS coarsening,
// ext+i interpolation, strong threshold 0.6, aggressive coarsening on its first level (a hierarchy
// of less memory, as many iterations and faster; at 1.4 M unknowns a time step took 4.81 s against
// 6.69, the Stokes start 73 s against 107, 3172 MB against 3420; bench/flow_scaling.sh).
// It smooths by one Gauss-Seidel sweep forward on the way down and one backward on the way up (hypre's
// l1 variants: Gauss-Seidel within a process, l1-scaled Jacobi across processes, which converges
// however the points are split), where PETSc's default, a symmetric sweep each way (for CG), costs
// twice the smoothing; neither GMRES on the right nor FGMRES needs a symmetric preconditioner.
// - Time steps: the default's sweeps were about a third of a step's solve
//   (hypre_BoomerAMGRelaxHybridGaussSeidel_core, 28 % of the run's samples in perf on the anastomosis
//   study's level 2); iterations within 5 % (on 3 processes too), 0.88-0.89 of the solve time on the
//   FDA nozzle and the pipe, 0.99 on the anastomosis's curvature mesh (bench/time_steps.sh, PIPE=1,
//   two rounds), 0.76-0.83 on the study's level 2 (0.9 M unknowns, 10 steps); the reduced study from
//   nothing 2420 s against 2864. Tried there too: a V(0,1) cycle (23 % more iterations), P_max 4
//   truncation, aggressive coarsening on two levels, a strong threshold of 0.7: none faster.
// - Steady Newton (issue 48): first held back, as it stalled Newton's iterations on the bifurcation aneurysm
//   of Cli.SteadyNewtonSettlesOnABifurcationAneurysm (6000 triangles, Re 300: 24 iterations against 20, the
//   line search shortening eight steps at half the inflow, the residual creeping from 1.8e-2 to 1.1e-2; with
//   the default's sweeps the same stall, one iteration shorter); since a stalling stage moves on
//   (NavierStokes::kStalledSteps) 18 iterations and 1010 linear (the default's 17 and 1044). On the FDA
//   nozzle at Re 500: 296k unknowns (bench/fda_nozzle.sh's mesh 23 0.91, one process) 69.7 s against 81.4
//   (810 linear iterations against 844; 83.9 against 95.2 s on a busier day); the jet's core refined
//   (JET=0.35, 744k unknowns, 2 processes) 335 s against 466 (3050 against 3390: the default's ILU factors
//   failed at the full inflow's first Newton iteration, these converged there in 951 iterations);
//   bench/steady_vessels.sh at Re 300, one process: the carotid bifurcation 54.9 s against 59.3 (909
//   linear iterations against 892), the bifurcation aneurysm 204 s against 216 (2458 against 2519). Tried
//   there too (the nozzle's two meshes): GMRES restarted after 100 (the jet: 4436 iterations, 444 s: the
//   ILU factors failed again), LGMRES and BiCGStab(l) (their estimated residuals miss the true one, 18-32
//   times the tolerance), SOR sweeps instead of ILU (2177 iterations, none failed, each dearer: 373 s),
//   hypre's AMG or AIR on the velocity block (as many iterations as SOR or more, each over four times dearer).
inline std::string schur_amg_options() {
  return std::string("-fieldsplit_p_ksp_type preonly -fieldsplit_p_pc_type hypre -fieldsplit_p_pc_hypre_type boomeramg "
                     "-fieldsplit_p_pc_hypre_boomeramg_coarsen_type HMIS -fieldsplit_p_pc_hypre_boomeramg_interp_type "
                     "ext+i -fieldsplit_p_pc_hypre_boomeramg_strong_threshold 0.6 "
                     "-fieldsplit_p_pc_hypre_boomeramg_agg_nl 1") +
         " -fieldsplit_p_pc_hypre_boomeramg_relax_type_down l1-Gauss-Seidel "
         "-fieldsplit_p_pc_hypre_boomeramg_relax_type_up backward-l1-Gauss-Seidel";
}

// Steady solves: GMRES (preconditioned on the right: the residual it tests is the system's) with
// a Schur-complement field split, the velocity block by block-Jacobi ILU(0) (where its factors are
// unstable, the steady solve checks the true residual and goes on with SOR sweeps instead:
// LinearSolver::set_residual_check, sweep_velocity_blocks), the Schur complement by one AMG cycle
// (schur_amg_options). Its tolerance is relative to the initial residual, which
// a steady iteration's initial guess (the iterate) makes the steady equations' residual there: each
// solve cuts it 1000-fold (an inexact Newton's forcing term of 1e-3; the Stokes solve from rest
// 1e6-fold, NavierStokes::solve_steady), so that the iterations converge in the residual itself.
// (Relative to the right-hand side, as before, a solve near convergence stopped at once: the
// residual stalled at the tolerance, 9e-7 on the 180-degree bend of the Newton test, while the
// change fell below 1e-8; now 2e-9 there, 578 linear iterations for Newton's 15 against 497.)
// (Inline, as the other option strings: the program has them without opening PETSc's module,
// modules/petsc_module.h.)
// GMRES's classical Gram-Schmidt refined where it loses orthogonality (PETSc's refine_ifneeded): over
// its long cycles (up to 200 vectors) it did, and broke down on the carotid bifurcation at Re 300
// (bench/steady_vessels.sh, 294k unknowns: DIVERGED_BREAKDOWN after 200 iterations at its last
// stage's first Newton iteration, the direct solver then taking 686 s for the whole solve; refined,
// 107 iterations there, 14 Newton iterations and 905 linear in 71 s).
inline std::string saddle_point_options() {
  return "-ksp_type gmres -ksp_pc_side right -ksp_rtol 1e-3 -ksp_converged_use_initial_residual_norm "
         "-ksp_max_it 1000 -ksp_gmres_restart 200 -ksp_gmres_cgs_refinement_type refine_ifneeded "
         "-pc_type fieldsplit -pc_fieldsplit_type schur -pc_fieldsplit_schur_fact_type full "
         "-pc_fieldsplit_schur_precondition user "
         "-fieldsplit_u_ksp_type preonly -fieldsplit_u_pc_type bjacobi -fieldsplit_u_sub_pc_type ilu " +
         schur_amg_options();
}
// Time steps, whose mass term makes the velocity block diagonally strong: the same Schur field
// split, its velocity block by point-block Jacobi (the inverse of each point's 3 x 3 diagonal block:
// local to each process, nothing to sweep), which takes about twice SOR's iterations at a fraction
// of their cost. On the 420k-unknown pipe (bench/flow_scaling.sh's, dt 1 ms, 18 steps, the
// preconditioner reused) the solve took 0.16 s a step against SOR's 0.24 (2-4 iterations against
// 4-7 once settled); at dt 10 ms (CFL 36) 0.44-1.6 s against 0.56-2.0 s, at 50 ms (CFL 180) as long.
// SOR's sweeps replaced ILU of the whole system (6.4-7.4 s a step per million unknowns, iterations
// growing with the mesh) before. FGMRES restarts after 10 iterations (a time step settles at under
// 10; its two vectors an iteration are held up to the restart: 626 MB peak at 420k against 699 with
// 30); GMRES preconditioned on the right keeps one an iteration but applies the preconditioner once
// more at the end of each solve.
// The tolerance, 1e-6 of ||b||, is not slack to cut: the steps' linear errors add up over a run. The
// anastomosis study's curvature mesh (110k unknowns, 242 steps of 5 ms, WSS at t = 1.21 s, the wall's
// points; issue 48): at 1e-5 the WSS moved by 7.6e-4 of its mean in RMS (5.6e-3 at the most, OSI by up
// to 0.057) for 17 iterations a step against 24, at 1e-4 by 4.0e-3 (1.7e-2) for 10.5, where 1 and 2
// processes at 1e-6 differ by 4.4e-5 (4.3e-4): the differences the study reports are a few percent.
// What bounds the iterations as the CFL number grows (issue 48; one process, 55 settled steps of
// the anastomosis study's curvature mesh, 126k unknowns, CFL 44, 17.2 a step; 15 of a coarse FDA
// nozzle at Re 500, 296k, CFL 52, 41.3): the velocity block solved to 1e-5 by GMRES still takes
// 10.7 and 27.7, so on the nozzle the Schur complement's approximation does; scaling its
// convective weight (the tau_M (u.grad N)^2 in the momentum diagonal D) by 0.3 or 3, or adding the
// Galerkin convection's |u.grad N| to D, moves neither by more than 1.3; two AMG cycles on S_p
// neither; PETSc's LSC, which ignores the stabilization's pressure block, does not converge; a
// pressure convection-diffusion product S_p^-1 F_p D_p^-1 (F_p the velocity block's trace / 3 on
// the pressure's points, natural boundaries) took 48.4 on the anastomosis and failed on the
// nozzle's Stokes start. The velocity block matters where the Schur side does not: SOR sweeps
// instead of point-block Jacobi take 9.5 and 24.6, but their sweeps cost more (0.38 s a step
// against 0.27 on the anastomosis); ILU with the factorization's upper part: README's figures.
// Tried on the velocity block: a line-block Jacobi (each chain of strongly coupled points, as across
// the layer, solved at once): 6-13 % fewer iterations, each dearer (1.15 of the solve time on the
// study's level 2); hypre's AMG (HMIS, ext+i, one-way l1 Gauss-Seidel) and its AIR (approximate
// ideal restriction, made for advection: restriction_type 1, direct interpolation), rebuilt at
// each step: a third fewer iterations on the anastomosis's curvature mesh (16.6 and 16.1 against
// 24.9, 15 steps) at 6.9 and 4.9 times the solve time (bench/time_steps.sh); AIR's Stokes start
// did not converge on the nozzle.
// Tried after (bench/time_steps.sh's two cases, one process, the same binary; iterations a settled step and
// solve seconds, the default 18.2 / 0.23-0.29 on the anastomosis and 45.0 / 1.36-1.42 on the nozzle):
// - a Cahouet-Chabard Schur approximation, S^-1 ~ (L / m)^-1 + kappa M_p^-1 (the weighted Laplacian of the
//   mass term alone plus a lumped pressure mass weighted by nu + tau_C + tau_M |u|^2 / 3, added through a
//   composite preconditioner; the Fourier symbol of a gradient mode's Schur complement under grad-div):
//   25.5 and 91.7; the additive mass term beside the default's Laplacian 22.7 and 75.7; none better at
//   any weight tried (0.3, 1, 3): the default's Laplacian weighted by the whole momentum diagonal is the best;
// - PETSc's selfp (B diag(A)^-1 B^T, two rings): 27.2 and 97.9;
// - SOR on the velocity block: 12.0 and 28.9 iterations at 1.6-1.8 times the solve time; its forward
//   sweep only 14.6 and 31.1 (1.3-1.5 times); with the factorization's upper part 13.9 and 29.4 (1.1-1.4);
// - the factorization's upper or lower part with point-block Jacobi: 21.2 / 20.7 and 40.7 / 40.7 (the
//   nozzle's solve 0.81-0.90 of the default's, the anastomosis's 1.2-1.3: not taken);
// - the velocity block's preconditioner rebuilt at every step while the Schur complement's AMG is kept:
//   17.2 and 43.3, no faster; everything rebuilt at every step: 15.3 and 39.9 (what reuse costs: 3-5
//   iterations a step, cheaper than AMG's set-up);
// - FGMRES restarted after 30 or 60: 18.1 / 17.7 and 45.7 / 43.7: the restart does not limit it.
// On the envelope levels the iterations grow with the mesh (the reduced anastomosis study with the flow kind, 2
// processes, mean over 237 steps: 13.8 at 113k unknowns, 16.3 at 433k, 21.2 at 971k, 31.2 at 2.42 M; the
// largest CFL number 21, 40, 44, 52), where the pipe's hold. Level 2 (971k) restarted from its checkpoint at
// t = 1.21 s through the next systole (40 steps, one process): the default 25.6 a step (2.35 s of solve);
// FGMRES restarted after 40: 24.9, no faster; the velocity block solved to 1e-5 (GMRES, SOR): 0.6 times
// the default's iterations over the first 14 steps (both sides of the split limit it about equally there);
// a least-squares commutator with the stabilization's block (S^-1 ~ P^-1 (C - A10 D^-1 A00 D^-1 A01) P^-1,
// P the user's matrix by one AMG cycle, D = diag(A00) scaled to match P on a smooth vector; a shell
// preconditioner, code not kept) on the anastomosis's curvature mesh: 182 iterations at the first step
// against 51, the second not converged in 1000 (at D's scale 0.24, 0.5 and 1: the commutator unadjusted at
// the no-slip walls, which hold the whole lumen, is known to fail there).
inline std::string time_step_options() {
  return "-ksp_type fgmres -ksp_rtol 1e-6 -ksp_max_it 1000 -ksp_gmres_restart 10 "
         "-pc_type fieldsplit -pc_fieldsplit_type schur -pc_fieldsplit_schur_fact_type full "
         "-pc_fieldsplit_schur_precondition user "
         "-fieldsplit_u_ksp_type preonly -fieldsplit_u_pc_type pbjacobi " +
         schur_amg_options();
}
// The Stokes start of an unsteady run (a solver of its own, gone before the time steps): no mass
// term, so its velocity block by SOR (PETSc's: local to each process under MPI; point-block Jacobi
// would take many times the iterations on the viscous block), with GMRES on the right, whose one
// vector an iteration (FGMRES: two) matters over its 71 iterations at 420k unknowns (105 MB less
// peak memory) and whose one more application of the preconditioner does not; restarted after 30.
inline std::string stokes_start_options() {
  std::string options = time_step_options();
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"-ksp_type fgmres", "-ksp_type gmres -ksp_pc_side right"},
                                 {"-ksp_gmres_restart 10", "-ksp_gmres_restart 30"},
                                 {"-fieldsplit_u_pc_type pbjacobi", "-fieldsplit_u_pc_type sor"}})
    options.replace(options.find(from), from.size(), to);
  return options;
}

// A process's matrix values between LinearSolver::begin_assembly() and end_assembly(), in
// PETSc's own arrays, in one of two layouts (entry_place finds an entry in either).
// - One matrix (`split` false): per row of unknowns its entries in the columns of the points this
//   process owns (`own`) and in the others' (`other`), each part in the pattern's order, row after
//   row (on one process `other` is empty).
// - A field split (`split` true: block_size > 1 and PETSc's fieldsplit preconditioner): the
//   matrix held as four blocks, field F 0 the first block_size - 1 components of every point, 1 the
//   last, block [F][G] the rows of field F in the columns of field G, each in its own and others'
//   parts (`split_own`, `split_other`) as above: the preconditioner works on the blocks themselves,
//   where a field split of one matrix copies them out (the matrix twice, 266 MB at 420k unknowns).
//   Block [0][0] (velocity in velocity) is BAIJ, a (block_size - 1)^2 block per pattern entry stored
//   by columns, its column index kept once a block (164 -> 115 MB at 420k unknowns; PETSc's SOR and
//   ILU then work point block by point block: the same iterations, the time steps' solve 11 % faster);
//   the others AIJ.
// - The Schur complement's preconditioning matrix (`schur_own`, `schur_other`; under a field split
//   whose options say `-pc_fieldsplit_schur_precondition user`, null otherwise): one value per entry
//   of the point pattern, laid out as block [1][1]. The caller adds there its approximation of
//   -A10 diag(A00)^-1 A01 (the flow: a weighted pressure Laplacian on the pattern's own stencil, where
//   PETSc's selfp multiplies it out over two rings of points); end_assembly adds block [1][1] to it.
//   Left at zero, the pressure block alone preconditions the Schur complement.
struct MatrixValues {
  double* own = nullptr;
  double* other = nullptr;
  bool split = false;
  double* split_own[2][2] = {};
  double* split_other[2][2] = {};
  double* schur_own = nullptr;
  double* schur_other = nullptr;
};

// Where point a's component row i holds its entries at one column point: the first
// block_size - 1 components (from `first`, `stride` apart: 1 in AIJ rows, block_size - 1 in the
// field split's velocity block, whose BAIJ blocks are stored by columns) and the last (`last`);
// at[j] is component j's. `own`: the column
// point is this process's; `before`: the column points of that kind (own or other) in the rows
// before a; `count`: in a's row; `place`: the column point's position among them in a's row.
// `schur`: the Schur complement's preconditioning matrix at (a, column point), for the last row
// when the assembly has one (MatrixValues::schur_own), null otherwise.
struct EntryPlace {
  double* first;
  double* last;
  double* schur = nullptr;
  int stride = 1;
  int components = 0;  // block_size - 1: the components from `first`
  double& operator[](int j) const { return j < components ? first[stride * j] : *last; }
};
// A field split's (MatrixValues::split) entries of all of point a's rows at one column point, the
// layout entry_place reads them from: the velocity block's c x c (c = block_size - 1, BAIJ, by
// columns), the velocity rows' entries in the pressure column (a row every `count`), the pressure
// row's in the velocity columns (c together), the pressure block's and the Schur complement's
// preconditioning matrix's (null without one). The assembly adds a cell's point pair through it.
struct SplitPairPlace {
  double* velocity;
  double* gradient;
  int count;
  double* divergence;
  double* pressure;
  double* schur;
};
inline SplitPairPlace split_pair_place(const MatrixValues& m, int block_size, bool own, int before, int count,
                                       int place) {
  const int c = block_size - 1, at = before + place;
  double* const* const rows = own ? m.split_own[0] : m.split_other[0];
  double* const* const last = own ? m.split_own[1] : m.split_other[1];
  double* const schur = own ? m.schur_own : m.schur_other;
  return {rows[0] + c * c * at, rows[1] + c * before + place, count, last[0] + c * at, last[1] + at,
          schur ? schur + at : nullptr};
}
inline EntryPlace entry_place(const MatrixValues& m, int block_size, bool own, int before, int count, int i,
                              int place) {
  if (!m.split) {
    double* const v = (own ? m.own : m.other) + block_size * (block_size * before + i * count + place);
    return {v, v + block_size - 1, nullptr, 1, block_size - 1};
  }
  const int c = block_size - 1;
  const SplitPairPlace pair = split_pair_place(m, block_size, own, before, count, place);
  if (i < c) return {pair.velocity + i, pair.gradient + i * count, nullptr, c, c};
  return {pair.divergence, pair.pressure, pair.schur, 1, c};
}

class LinearSolver {
 public:
  // Throws OptionError when PETSc refuses an option (naming it), InternalError otherwise.
  LinearSolver(SparsePattern pattern, int block_size, const std::string& defaults, const std::string& options);
  ~LinearSolver();
  LinearSolver(const LinearSolver&) = delete;
  LinearSolver& operator=(const LinearSolver&) = delete;

  // The pattern's sizes and row offsets (its columns were handed to PETSc's matrix, not kept twice).
  const SparsePattern& pattern() const;

  // Solves A x = b for the matrix with `values` (this process's rows, in the pattern's order)
  // and `rhs` (this process's rows); `x` holds this process's rows then its ghost rows: the
  // initial guess on entry (its own rows), the solution on return (its own rows and ghosts).
  SolveStats solve(const std::vector<double>& values, const std::vector<double>& rhs, std::vector<double>& x);

  // The same without a copy of the matrix: begin_assembly() gives PETSc's own arrays of the
  // matrix's values, zeroed (the matrix is held once), end_assembly() hands them back,
  // solve_assembled() solves with them.
  MatrixValues begin_assembly();
  void end_assembly();
  SolveStats solve_assembled(const std::vector<double>& rhs, std::vector<double>& x);
  // The same system by a direct solve (MUMPS's LU, in parallel under MPI; its factorization kept
  // for the next such solve, whose symbolic part it reuses): the fallback for a steady system the
  // iterative solver did not converge on. Its memory grows faster than the unknowns (fill-in):
  // for systems up to a few hundred thousand.
  SolveStats solve_assembled_direct(const std::vector<double>& rhs, std::vector<double>& x);

  // ||A x - b|| / ||b|| (2-norms over every process's rows; ||A x - b|| when b is 0) for the
  // assembled matrix, `rhs` and `x` (its own rows; ghosts ignored): a nonlinear iteration's
  // residual when the matrix and right-hand side were assembled at the iterate x.
  double relative_residual(const std::vector<double>& rhs, const std::vector<double>& x);

  // An iterative solve stops once ||A x - b|| is under `relative` x ||b|| too (0, the default: only
  // the options' tolerances): a nonlinear iteration whose tolerance is relative to the residual it
  // starts from then does nothing once that residual is small enough.
  void set_residual_floor(double relative);
  // solve_assembled measures the true residual ||b - A x|| of a solve the Krylov method says
  // converged (two products with A more a solve) and calls it not converged when that is over
  // kTrueResidualSlack times the tolerance (its reason says so); off by default.
  void set_residual_check(bool on);
  static constexpr double kTrueResidualSlack = 10.0;
  // The velocity block of a field split preconditioned block by block (block Jacobi) by ILU: each
  // block by SOR sweeps from the next solve on, which cannot be unstable as ILU's factors can
  // (Newton's velocity block on the FDA nozzle at Re 500: GMRES's recurrence said 4e-10 where the
  // true residual was 21, 1.7e7 times ||b||, and Newton's steps went nowhere; with the sweeps 11
  // Newton iterations to 7.7e-6 in 61 s on 186k unknowns, where Picard's crawled to 2.5e-4 in 42
  // and 310 s). Where ILU holds it is the faster (the bifurcation aneurysm of
  // bench/steady_vessels.sh at Re 300: 178 s against 339). Returns whether any block changed (on
  // every process: collective); false before the first solve, which sets the blocks up.
  bool sweep_velocity_blocks();
  // The next iterative solves' relative tolerance is the options' times `factor` (1: as given).
  void scale_tolerance(double factor);

  // A low-rank term: the operator becomes A + sum_k c_k u_k u_k^T (resistive ends coupled
  // implicitly: u_k an end's area vectors at its points, c_k its resistance over the density, so
  // that the end's pressure is c_k times its flux u_k^T x in the same solve). The columns u_k (this
  // process's rows, interleaved as the right-hand side) are set once, their coefficients before
  // each solve (0 leaves a column out). The preconditioner stays A's (PETSc's Krylov method applies
  // the whole operator, a matrix-free product: a rank-K term costs it about K more iterations,
  // however large c_k); solve_assembled_direct's LU of A is iterated on the whole operator too
  // (GMRES, K + 1 iterations), and relative_residual measures it.
  void set_low_rank_columns(const std::vector<std::vector<double>>& columns);
  void set_low_rank_coefficients(const std::vector<double>& coefficients);

  // Keep the preconditioner from one solve to the next while it still serves (a time step's
  // matrix changes little from the step before, and building ILU or AMG costs more than the few
  // extra iterations): it is built anew when the solve before took more than the fewest iterations
  // a solve has taken with it plus kReuseSlack (about what building it costs), and a solve that
  // reuses it is capped at twice that count, then repeated with a new one. (Against the building
  // solve's count, as before, a preconditioner built in a run's first, hardest steps served on while
  // its iterations doubled: on a bifurcation aneurysm at Re 300, 81k unknowns, 300 steps of 1 ms, 25
  // a step on average and 0.140 s a solve, where one built every step took 14 and 0.103 s. Allowing
  // a quarter more than the fewest too, as before, let a preconditioner of a fast-changing flow
  // serve while it cost more than building one, and its capped solves that failed were thrown away:
  // on the FDA nozzle at Re 500 (296k unknowns, CFL ~50, 12 steps of 5 ms from the Stokes flow) 66.5
  // iterations a step (at most 149) and 2.45-2.80 s a solve against 54.0 (89) and 1.89-2.29 s now
  // (built every step: 46.1 and 1.72 s); on the anastomosis study's curvature mesh (121k unknowns,
  // CFL 13-30) 28.4 (43) and 0.43-0.46 s against 26.5 (32) and 0.39-0.43 s; on the pipe of
  // bench/flow_scaling.sh (86k unknowns, CFL ~5) the same iterations and time (0.094 s built every step).)
  // The answer meets the same tolerance either way. Off by default.
  void reuse_preconditioner(bool on);
  // Each iterative solve starts from the least-residual combination of the caller's initial guess
  // and the last `count` solutions (Fischer's projection for successive right-hand sides, CMAME
  // 1998; here the matrix changes too, so A times each is taken anew: count + 1 products with A
  // and about (count + 1)^2 dot products a solve, 2 count + 2 vectors kept), where the guess's
  // residual is over kProjectAbove times the tolerance and the combination halves it at least;
  // 0, the default: the caller's guess as it is. The tolerance is the same; what it saves is the
  // iterations that only found again what the last steps knew. Measured (bench/time_steps.sh, one
  // process): on the anastomosis study's curvature mesh (121k unknowns, pulsatile, CFL up to 30)
  // the time steps' extrapolation left 4e-3 of ||b||, the combination of it and 4 solutions
  // 1-5e-4: 16.8 iterations a step against 25.0, 0.72 of the solve time; over a cycle and 0.21 s
  // (242 steps) 13.8 against 22.1, and the WSS 4x closer to a run at -ksp_rtol 1e-9 (7.3e-5 of its
  // mean RMS against 3.1e-4). Not taken on the FDA nozzle's developing jet (CFL 50: it cut 0.2-0.4
  // of ||b|| by a third; the same iterations, 2 % more time) nor on the benchmark pipe's settling
  // flow (guesses within 1000 times the tolerance). Forgets the solutions kept.
  void keep_solutions(int count);
  // The kept solutions dropped (another history starts: a state restored).
  void forget_solutions();
  static constexpr double kProjectAbove = 1000.0;  // times the tolerance: the least residual a guess is projected from
  // The next solve builds its preconditioner (the system's kind changed, e.g. after a Stokes
  // solve).
  void rebuild_preconditioner();
  static constexpr int kReuseSlack = 4;

  // The Krylov method and preconditioner PETSc settled on, e.g. "gmres + fieldsplit".
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vesselmesh::flow
