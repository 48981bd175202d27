#include "flow/linear_solver.h"

#include "mesh/error.h"
#include "parallel/processes.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vesselmesh::flow {
namespace {

// The 1D Laplacian (2, -1) on n points: pattern and values.
SparsePattern laplacian_pattern(int n, std::vector<double>& values) {
  SparsePattern p;
  p.rows = n;
  p.row_start.push_back(0);
  for (int i = 0; i < n; ++i) {
    for (int j = std::max(0, i - 1); j <= std::min(n - 1, i + 1); ++j) {
      p.columns.push_back(j);
      values.push_back(i == j ? 2.0 : -1.0);
    }
    p.row_start.push_back(p.nonzeros());
  }
  return p;
}

// The 2D Laplacian (4, -1) on side x side points: pattern and values.
SparsePattern laplacian_2d_pattern(int side, std::vector<double>& values) {
  const int n = side * side;
  SparsePattern p;
  p.rows = n;
  p.row_start.push_back(0);
  for (int i = 0; i < n; ++i) {
    const int x = i % side;
    for (int j : {i - side, i - 1, i, i + 1, i + side}) {
      if (j < 0 || j >= n || (j == i - 1 && x == 0) || (j == i + 1 && x == side - 1)) continue;
      p.columns.push_back(j);
      values.push_back(j == i ? 4.0 : -1.0);
    }
    p.row_start.push_back(p.nonzeros());
  }
  return p;
}

TEST(LinearSolver, SolvesWithTheCallersOptions) {
  const int n = 200;
  std::vector<double> values;
  const SparsePattern pattern = laplacian_pattern(n, values);
  // x_i = sin(pi (i + 1) / (n + 1)) * ... : build b = A x for a known x.
  std::vector<double> exact(n), b(n, 0.0), x(n, 0.0);
  for (int i = 0; i < n; ++i) exact[i] = std::sin(0.1 * i) + 0.01 * i;
  for (int i = 0; i < n; ++i)
    for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k) b[i] += values[k] * exact[pattern.columns[k]];
  LinearSolver solver(pattern, 1, time_step_options(), "-ksp_type cg -pc_type jacobi -ksp_rtol 1e-12");
  const SolveStats stats = solver.solve(values, b, x);
  EXPECT_TRUE(stats.converged) << stats.reason;
  EXPECT_GT(stats.iterations, 0);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(x[i], exact[i], 1e-8);
  EXPECT_EQ(solver.description(), "cg + jacobi");

  // Too few iterations: not converged, and said so.
  LinearSolver short_of_breath(pattern, 1, saddle_point_options(), "-ksp_type cg -pc_type none -ksp_max_it 2");
  std::vector<double> y(n, 0.0);
  const SolveStats poor = short_of_breath.solve(values, b, y);
  EXPECT_FALSE(poor.converged);
  EXPECT_EQ(poor.reason, "DIVERGED_ITS");
}

// GMRES tests the residual its recurrence estimates. A preconditioner that is not one linear
// operator (here an inner Krylov solve of three iterations, as unstable factors are in effect)
// leaves the true residual of its answer far above that estimate: with the check on, such a solve
// did not converge, and its reason says by how much; off (the default), it is taken.
TEST(LinearSolver, ASolveWhoseTrueResidualMissesTheToleranceDidNotConverge) {
  const int n = 200;
  std::vector<double> values;
  const SparsePattern pattern = laplacian_pattern(n, values);
  std::vector<double> exact(n), b(n, 0.0);
  for (int i = 0; i < n; ++i) exact[i] = std::sin(0.1 * i) + 0.01 * i;
  for (int i = 0; i < n; ++i)
    for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k) b[i] += values[k] * exact[pattern.columns[k]];
  const std::string varying = "-ksp_type gmres -ksp_pc_side right -ksp_rtol 1e-8 -ksp_max_it 400 -pc_type ksp "
                              "-ksp_ksp_type gmres -ksp_ksp_max_it 3 -ksp_pc_type none";
  const auto error = [&](const std::vector<double>& x) {
    double worst = 0.0;
    for (int i = 0; i < n; ++i) worst = std::max(worst, std::abs(x[i] - exact[i]));
    return worst;
  };
  LinearSolver trusting(pattern, 1, saddle_point_options(), varying);
  std::vector<double> x(n, 0.0);
  const SolveStats taken = trusting.solve(values, b, x);
  ASSERT_TRUE(taken.converged) << taken.reason;  // by GMRES's own estimate
  EXPECT_GT(error(x), 1e-3);                      // but far from the answer

  LinearSolver checking(pattern, 1, saddle_point_options(), varying);
  checking.set_residual_check(true);
  std::vector<double> y(n, 0.0);
  const SolveStats refused = checking.solve(values, b, y);
  EXPECT_FALSE(refused.converged);
  EXPECT_NE(refused.reason.find("CONVERGED_RTOL by its own estimate"), std::string::npos) << refused.reason;
  EXPECT_NE(refused.reason.find("but its true residual is"), std::string::npos) << refused.reason;

  // A linear preconditioner: the check passes the same solve, and the answer is right.
  LinearSolver sound(pattern, 1, saddle_point_options(), "-ksp_type gmres -ksp_rtol 1e-10 -pc_type jacobi");
  sound.set_residual_check(true);
  std::vector<double> z(n, 0.0);
  const SolveStats good = sound.solve(values, b, z);
  EXPECT_TRUE(good.converged) << good.reason;
  EXPECT_LT(error(z), 1e-6);
}

TEST(LinearSolver, RefusedOptionsAreOptionErrors) {
  std::vector<double> values;
  const SparsePattern pattern = laplacian_pattern(10, values);
  EXPECT_THROW(LinearSolver(pattern, 1, time_step_options(), "-pc_type no_such_preconditioner"), OptionError);
}

TEST(LinearSolver, OneProcessHere) { EXPECT_EQ(parallel::process_count(), 1); }

// Solves (A + shift I) x = b for the known x of `exact` and checks the answer.
SolveStats solve_shifted(LinearSolver& solver, const SparsePattern& pattern, std::vector<double> values,
                         double shift, const std::vector<double>& exact) {
  const int n = pattern.rows;
  for (int i = 0; i < n; ++i)
    for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k)
      if (pattern.columns[k] == i) values[k] += shift;
  std::vector<double> b(n, 0.0), x(n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k) b[i] += values[k] * exact[pattern.columns[k]];
  const SolveStats stats = solver.solve(values, b, x);
  EXPECT_TRUE(stats.converged) << stats.reason;
  for (int i = 0; i < n; ++i) EXPECT_NEAR(x[i], exact[i], 1e-6 * (1.0 + std::abs(exact[i]))) << "shift " << shift;
  return stats;
}

TEST(LinearSolver, ReusesThePreconditionerWhileItServes) {
  // ILU(0) of the tridiagonal Laplacian is its exact LU: a fresh solve takes one iteration.
  const int n = 200;
  std::vector<double> values;
  const SparsePattern pattern = laplacian_pattern(n, values);
  std::vector<double> exact(n);
  for (int i = 0; i < n; ++i) exact[i] = std::cos(0.05 * i) + 0.002 * i;
  const std::string options = "-ksp_type gmres -pc_type ilu -ksp_rtol 1e-10";
  LinearSolver solver(pattern, 1, time_step_options(), options);
  solver.reuse_preconditioner(true);

  const SolveStats first = solve_shifted(solver, pattern, values, 0.0, exact);
  EXPECT_TRUE(first.preconditioner_built);
  EXPECT_EQ(first.iterations, 1);
  // A matrix a little different: the old factors still serve, in a few iterations.
  const SolveStats close = solve_shifted(solver, pattern, values, 1e-7, exact);
  EXPECT_FALSE(close.preconditioner_built);
  EXPECT_LE(close.iterations, 1 + LinearSolver::kReuseSlack);
  // Far from it (A's inverse spreads the shift over 0.02 x 4000): the capped solve (twice the
  // reuse limit) fails and is repeated with new factors; the iterations of both are counted.
  const SolveStats far = solve_shifted(solver, pattern, values, 0.02, exact);
  EXPECT_TRUE(far.preconditioner_built);
  const int limit = 1 + LinearSolver::kReuseSlack;
  EXPECT_EQ(far.iterations, 2 * limit + 1);
  // Between the limit and the cap (factors of A + 0.02 I for A + 0.025 I: 8 iterations): the
  // solve converges with the old factors, and the next one builds new ones.
  solver.rebuild_preconditioner();
  solve_shifted(solver, pattern, values, 0.02, exact);
  const SolveStats slow = solve_shifted(solver, pattern, values, 0.025, exact);
  EXPECT_FALSE(slow.preconditioner_built);
  EXPECT_GT(slow.iterations, limit);
  EXPECT_TRUE(solve_shifted(solver, pattern, values, 0.025, exact).preconditioner_built);
  // Asked to: the next solve builds.
  solver.rebuild_preconditioner();
  EXPECT_TRUE(solve_shifted(solver, pattern, values, 0.02, exact).preconditioner_built);

  // Off (the default): every solve builds.
  LinearSolver fresh(pattern, 1, time_step_options(), options);
  EXPECT_TRUE(solve_shifted(fresh, pattern, values, 0.0, exact).preconditioner_built);
  EXPECT_TRUE(solve_shifted(fresh, pattern, values, 1e-7, exact).preconditioner_built);
}

// Time steps' solves start from the least-residual combination of the caller's guess and the kept
// solutions (keep_solutions): steps whose answer is quadratic in the step (here with a matrix that
// changes from step to step, as a time step's does) lie in the span of the last three answers, so
// from the fourth step on the projection leaves only the kept answers' own errors (each within the
// tolerance; a few iterations), where the last answer as the guess takes about as many as the first
// (31, 26, 25, 25, 24, 24, 23, 22 against 31, 26, 21, 3, 2, 2, 1, 1); forgotten, the next solve
// iterates from its guess again.
// Every answer to the tolerance either way.
TEST(LinearSolver, KeptSolutionsMakeTheGuess) {
  const int side = 30, n = side * side;
  std::vector<double> laplacian;
  const SparsePattern pattern = laplacian_2d_pattern(side, laplacian);
  const auto answer = [&](int step) {  // quadratic in the step
    std::vector<double> x(n);
    for (int i = 0; i < n; ++i) {
      const double t = 0.1 * step;
      x[i] = std::sin(0.37 * i) + t * std::cos(0.11 * i) + t * t * 0.01 * (i % 7);
    }
    return x;
  };
  const auto run = [&](int kept, std::vector<int>& iterations) {
    LinearSolver solver(pattern, 1, time_step_options(), "-ksp_type gmres -pc_type jacobi -ksp_rtol 1e-8");
    solver.keep_solutions(kept);
    std::vector<double> x(n, 0.0);
    for (int step = 0; step < 8; ++step) {
      std::vector<double> values = laplacian;
      for (int i = 0; i < n; ++i)
        for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k)
          if (pattern.columns[k] == i) values[k] += 0.5 + 0.05 * step;  // the matrix changes too
      const std::vector<double> exact = answer(step);
      std::vector<double> b(n, 0.0);
      for (int i = 0; i < n; ++i)
        for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k)
          b[i] += values[k] * exact[pattern.columns[k]];
      const SolveStats stats = solver.solve(values, b, x);  // from the last answer
      EXPECT_TRUE(stats.converged) << stats.reason;
      for (int i = 0; i < n; ++i) EXPECT_NEAR(x[i], exact[i], 1e-6) << "step " << step << " kept " << kept;
      iterations.push_back(stats.iterations);
    }
    if (kept > 0) {  // another history: nothing kept
      solver.forget_solutions();
      std::vector<double> zero(n, 0.0);
      std::vector<double> values = laplacian;
      const std::vector<double> exact = answer(0);
      std::vector<double> b(n, 0.0);
      for (int i = 0; i < n; ++i)
        for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k)
          b[i] += values[k] * exact[pattern.columns[k]];
      iterations.push_back(solver.solve(values, b, zero).iterations);
    }
  };
  std::vector<int> plain, kept;
  run(0, plain);
  run(4, kept);
  for (int step = 3; step < 8; ++step) {
    EXPECT_GT(plain[step], 15) << "step " << step;
    EXPECT_LE(kept[step], 3) << "step " << step;
  }
  EXPECT_GT(kept.back(), 10);  // forgotten: from zero again
  std::printf("iterations a step, the last answer as the guess: %s; the kept solutions' best: %s\n",
              fmt::format("{}", fmt::join(plain, " ")).c_str(), fmt::format("{}", fmt::join(kept, " ")).c_str());
}

// The reuse limit follows the fewest iterations a solve has taken with the preconditioner, not its
// building solve's (a run's first steps, which build it, are its hardest): ILU(0) of the 2D
// Laplacian (not exact: the building solve from zero iterates), a solve from next to the answer
// takes fewer, then one from a thousandth off it more than the limit those set (within the cap,
// twice the limit): the solve after it builds anew (against the building solve's count it would have
// reused it).
TEST(LinearSolver, ReuseLimitFollowsTheFewestIterationsSinceTheBuild) {
  const int side = 30, n = side * side;
  std::vector<double> values;
  const SparsePattern pattern = laplacian_2d_pattern(side, values);
  std::vector<double> exact(n), b(n, 0.0);
  for (int i = 0; i < n; ++i) exact[i] = std::sin(0.37 * i) + 0.01 * i;
  for (int i = 0; i < n; ++i)
    for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k) b[i] += values[k] * exact[pattern.columns[k]];
  LinearSolver solver(pattern, 1, time_step_options(), "-ksp_type gmres -pc_type ilu -ksp_rtol 1e-10");
  solver.reuse_preconditioner(true);
  const auto solve = [&](double start) {  // from `start` times the answer (0: from zero)
    std::vector<double> x(n);
    for (int i = 0; i < n; ++i) x[i] = start * exact[i];
    const SolveStats stats = solver.solve(values, b, x);
    EXPECT_TRUE(stats.converged) << stats.reason;
    for (int i = 0; i < n; ++i) EXPECT_NEAR(x[i], exact[i], 1e-6);
    return stats;
  };
  const SolveStats built = solve(0.0), near = solve(1.0 - 1e-7), again = solve(1.0 - 1e-3), after = solve(0.0);
  EXPECT_TRUE(built.preconditioner_built);
  EXPECT_FALSE(near.preconditioner_built);
  EXPECT_FALSE(again.preconditioner_built);
  const int limit = near.iterations + LinearSolver::kReuseSlack;
  ASSERT_GT(again.iterations, limit);  // the case this test is about
  ASSERT_LE(again.iterations, built.iterations + LinearSolver::kReuseSlack);
  EXPECT_TRUE(after.preconditioner_built);
  std::printf("iterations: %d building, %d from next to the answer, %d from a thousandth off (limit %d), then built "
              "anew\n",
              built.iterations, near.iterations, again.iterations, limit);
}

// Points on a line, each with its neighbours and itself.
SparsePattern line_points(int n) {
  SparsePattern p;
  p.rows = n;
  p.row_start.push_back(0);
  for (int a = 0; a < n; ++a) {
    for (int b = std::max(0, a - 1); b <= std::min(n - 1, a + 1); ++b) p.columns.push_back(b);
    p.row_start.push_back(p.nonzeros());
  }
  return p;
}

// A saddle-point system of points on a line in 4 x 4 blocks (three velocity components and a
// pressure a point: a diagonally strong velocity block, a gradient and a divergence between
// neighbours, a stabilizing pressure Laplacian), in the pattern's order.
SparsePattern saddle_pattern(int n, std::vector<double>& values) {
  const SparsePattern p = line_points(n);
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < 4; ++i)
      for (int k = p.row_start[a]; k < p.row_start[a + 1]; ++k) {
        const int b = p.columns[k], d = b - a;
        for (int j = 0; j < 4; ++j) {
          double v = 0.0;
          if (i < 3 && j < 3) v = i == j ? (d == 0 ? 4.0 + i : -1.0) : (d == 0 ? 0.1 * (i + j) : 0.0);
          else if (i < 3) v = 0.5 * d * (i + 1);   // gradient
          else if (j < 3) v = 0.5 * d * (j + 1);   // divergence (minus the gradient's transpose)
          else v = 0.1 * (d == 0 ? 2.0 : -1.0);    // stabilization
          values.push_back(v);
        }
      }
  return p;
}

// A saddle point system's value (saddle_pattern's layout) at point a's component i, column point k
// (its position in the pattern), component j.
double saddle_value(const SparsePattern& p, const std::vector<double>& values, int a, int i, int k, int j) {
  const int degree = p.row_start[a + 1] - p.row_start[a];
  return values[16 * p.row_start[a] + 4 * degree * i + 4 * (k - p.row_start[a]) + j];
}

// A known solution of the saddle point system and its right-hand side.
void saddle_solution(const SparsePattern& p, const std::vector<double>& values, std::vector<double>& exact,
                     std::vector<double>& b) {
  const int n = p.rows;
  exact.resize(4 * n);
  b.assign(4 * n, 0.0);
  for (int r = 0; r < 4 * n; ++r) exact[r] = std::sin(0.37 * r) + (r % 4 == 3 ? 2.0 : 0.0);
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < 4; ++i)
      for (int k = p.row_start[a]; k < p.row_start[a + 1]; ++k)
        for (int j = 0; j < 4; ++j) b[4 * a + i] += saddle_value(p, values, a, i, k, j) * exact[4 * p.columns[k] + j];
}

// saddle_pattern's system on n points with saddle_solution's answer and right-hand side.
struct SaddleSystem {
  std::vector<double> values;
  SparsePattern pattern;
  std::vector<double> exact, b;
  explicit SaddleSystem(int n) : pattern(saddle_pattern(n, values)) { saddle_solution(pattern, values, exact, b); }
};

// The field split holds the matrix as its field blocks (MatrixValues::split) and translates the
// rows; the answer is the one matrix's (LU, no split) and the exact one.
TEST(LinearSolver, FieldSplitBlocksSolveAsTheOneMatrix) {
  const int n = 60;
  const SaddleSystem system(n);
  const auto& [values, pattern, exact, b] = system;
  LinearSolver split(pattern, 4, time_step_options(), "-ksp_rtol 1e-12");
  LinearSolver one(pattern, 4, time_step_options(), "-ksp_type gmres -pc_type lu");
  EXPECT_TRUE(split.begin_assembly().split);
  split.end_assembly();
  EXPECT_FALSE(one.begin_assembly().split);
  one.end_assembly();
  std::vector<double> x_split(4 * n, 0.0), x_one(4 * n, 0.0);
  const SolveStats s = split.solve(values, b, x_split);
  EXPECT_TRUE(s.converged) << s.reason;
  EXPECT_GT(s.iterations, 0);  // iterated, not factored
  EXPECT_TRUE(one.solve(values, b, x_one).converged);
  for (int r = 0; r < 4 * n; ++r) {
    EXPECT_NEAR(x_one[r], exact[r], 1e-10) << "row " << r;
    EXPECT_NEAR(x_split[r], exact[r], 1e-8) << "row " << r;
  }
  EXPECT_LT(split.relative_residual(b, x_split), 1e-10);
  // The direct solver on the blocks (copied into one matrix for MUMPS) agrees too.
  std::vector<double> x_direct(4 * n, 0.0);
  EXPECT_TRUE(split.solve_assembled_direct(b, x_direct).converged);
  for (int r = 0; r < 4 * n; ++r) EXPECT_NEAR(x_direct[r], exact[r], 1e-10) << "row " << r;
}

// The steady solver's velocity block, block-Jacobi ILU, turns to SOR sweeps when asked (after the
// first solve has set the blocks up; once); the same answer after it. Nothing to turn in the time
// steps' point-block Jacobi.
TEST(LinearSolver, VelocityBlocksTurnFromIluToSweeps) {
  const int n = 60;
  const SaddleSystem system(n);
  const auto& [values, pattern, exact, b] = system;
  const std::string options = "-pc_fieldsplit_schur_precondition selfp -ksp_rtol 1e-12";
  LinearSolver steady(pattern, 4, saddle_point_options(), options);
  EXPECT_FALSE(steady.sweep_velocity_blocks());  // nothing set up yet
  std::vector<double> x(4 * n, 0.0);
  const SolveStats factored = steady.solve(values, b, x);
  EXPECT_TRUE(factored.converged) << factored.reason;
  EXPECT_TRUE(steady.sweep_velocity_blocks());
  EXPECT_FALSE(steady.sweep_velocity_blocks());  // sweeps already
  std::vector<double> y(4 * n, 0.0);
  const SolveStats swept = steady.solve(values, b, y);
  EXPECT_TRUE(swept.converged) << swept.reason;
  EXPECT_TRUE(swept.preconditioner_built);
  for (int r = 0; r < 4 * n; ++r) {
    EXPECT_NEAR(x[r], exact[r], 1e-8) << "row " << r;
    EXPECT_NEAR(y[r], exact[r], 1e-8) << "row " << r;
  }
  LinearSolver step(pattern, 4, time_step_options(), options);
  std::vector<double> z(4 * n, 0.0);
  EXPECT_TRUE(step.solve(values, b, z).converged);
  EXPECT_FALSE(step.sweep_velocity_blocks());
}

namespace {

// A saddle point system of points on a line whose Schur complement A11 - A10 A00^-1 A01 lies on the
// pattern: a diagonal velocity block (`scale` (4 + i)), one-sided differences in the divergence A10
// and the gradient A01 (minus its transpose), a pressure Laplacian in A11; its value at point a's
// component i, point b's component j.
double diagonal_saddle(double scale, int a, int i, int b, int j) {
  const auto divergence = [](int at, int k, int c) { return (c + 1) * (k == at ? 1.0 : k == at + 1 ? -1.0 : 0.0); };
  if (i < 3 && j < 3) return a == b && i == j ? scale * (4.0 + i) : 0.0;
  if (i < 3) return -divergence(b, a, i);
  if (j < 3) return divergence(a, b, j);
  return 0.1 * (a == b ? 2.0 : -1.0);
}

// Assembles diagonal_saddle into `solver` (and, when `add_schur`, the Schur complement's own values into
// its preconditioning matrix: -A10 A00^-1 A01 at (a, c), over the velocity points next to both),
// solves it for a known solution from zero and checks the answer.
SolveStats solve_diagonal_saddle(LinearSolver& solver, const SparsePattern& pattern, double scale, bool add_schur) {
  const int n = pattern.rows;
  std::vector<double> values;
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < 4; ++i)
      for (int k = pattern.row_start[a]; k < pattern.row_start[a + 1]; ++k)
        for (int j = 0; j < 4; ++j) values.push_back(diagonal_saddle(scale, a, i, pattern.columns[k], j));
  std::vector<double> exact, b;
  saddle_solution(pattern, values, exact, b);
  const auto schur = [&](int a, int c) {
    double sum = 0.0;
    for (int k = std::max(0, std::max(a, c) - 1); k <= std::min(n - 1, std::min(a, c) + 1); ++k)
      for (int j = 0; j < 3; ++j)
        sum -= diagonal_saddle(scale, a, 3, k, j) * diagonal_saddle(scale, k, j, c, 3) / diagonal_saddle(scale, k, j, k, j);
    return sum;
  };
  const MatrixValues m = solver.begin_assembly();
  EXPECT_NE(m.schur_own, nullptr);
  for (int a = 0; a < n; ++a) {
    const int degree = pattern.row_start[a + 1] - pattern.row_start[a];
    for (int i = 0; i < 4; ++i)
      for (int k = pattern.row_start[a]; k < pattern.row_start[a + 1]; ++k) {
        const EntryPlace at = entry_place(m, 4, true, pattern.row_start[a], degree, i, k - pattern.row_start[a]);
        for (int j = 0; j < 4; ++j) at[j] = diagonal_saddle(scale, a, i, pattern.columns[k], j);
        EXPECT_EQ(at.schur != nullptr, i == 3);
        if (add_schur && at.schur) *at.schur = schur(a, pattern.columns[k]);
      }
  }
  solver.end_assembly();
  std::vector<double> x(4 * n, 0.0);
  const SolveStats stats = solver.solve_assembled(b, x);
  EXPECT_TRUE(stats.converged) << stats.reason;
  for (int r = 0; r < 4 * n; ++r) EXPECT_NEAR(x[r], exact[r], 1e-8) << "row " << r;
  return stats;
}

// Exact inner solves: LU of the velocity block and of the Schur complement's preconditioning matrix.
const std::string kExactSplit = "-ksp_rtol 1e-10 -fieldsplit_u_pc_type lu -fieldsplit_p_pc_type lu";

}  // namespace

// The caller's Schur preconditioning matrix (MatrixValues::schur_own, the flow's default: options
// with -pc_fieldsplit_schur_precondition user) preconditions the Schur complement: handed the
// complement itself, the split with exact inner solves is exact and converges at once; with nothing
// added (the pressure block alone) it iterates. PETSc's selfp makes its own (no array of ours).
TEST(LinearSolver, SchurPreconditioningMatrixOfTheCallersServes) {
  const SparsePattern pattern = line_points(80);
  LinearSolver selfp(pattern, 4, time_step_options(), kExactSplit + " -pc_fieldsplit_schur_precondition selfp");
  EXPECT_EQ(selfp.begin_assembly().schur_own, nullptr);
  selfp.end_assembly();
  const auto solve = [&](bool add_schur) {
    LinearSolver solver(pattern, 4, time_step_options(), kExactSplit);
    return solve_diagonal_saddle(solver, pattern, 1.0, add_schur).iterations;
  };
  const int with_schur = solve(true), pressure_block = solve(false);
  EXPECT_LE(with_schur, 2);
  EXPECT_GE(pressure_block, with_schur + 2);
  std::printf("iterations: %d with the Schur complement, %d with the pressure block alone\n", with_schur,
              pressure_block);
}

// Reuse keeps the preconditioners nested in the field split too (the velocity block's and the Schur
// complement's, whose matrices the assembly changed as well): the system's velocity block scaled by
// 1.3, the split's exact inner solves of the system before no longer are, and the solve iterates;
// once a rebuild is asked for, they are built for the new system and the split is exact again.
TEST(LinearSolver, ReuseKeepsTheFieldSplitsInnerPreconditioners) {
  const SparsePattern pattern = line_points(80);
  LinearSolver solver(pattern, 4, time_step_options(), kExactSplit);
  solver.reuse_preconditioner(true);
  const SolveStats first = solve_diagonal_saddle(solver, pattern, 1.0, true);
  EXPECT_TRUE(first.preconditioner_built);
  EXPECT_LE(first.iterations, 2);
  const SolveStats kept = solve_diagonal_saddle(solver, pattern, 1.3, true);
  EXPECT_FALSE(kept.preconditioner_built);
  EXPECT_GT(kept.iterations, 2);
  solver.rebuild_preconditioner();
  const SolveStats rebuilt = solve_diagonal_saddle(solver, pattern, 1.3, true);
  EXPECT_TRUE(rebuilt.preconditioner_built);
  EXPECT_LE(rebuilt.iterations, 2);
  std::printf("iterations: %d built, %d with the last system's inner solves, %d rebuilt\n", first.iterations,
              kept.iterations, rebuilt.iterations);
}

}  // namespace
}  // namespace vesselmesh::flow
