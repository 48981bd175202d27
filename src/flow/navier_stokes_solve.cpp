// NavierStokes: the linear solver made and its fallbacks, the time step, the steady driver
// (Picard, pseudo time steps, Newton's staged inflow) and the Stokes start.
#include "flow/navier_stokes_impl.h"

#include <functional>

namespace vesselmesh::flow {

void NavierStokes::Impl::make_solver() {
  if (solver) return;
  const std::string defaults =
      fc.steady ? saddle_point_options() : stokes_start ? stokes_start_options() : time_step_options();
  solver = std::make_unique<LinearSolver>(point_pattern(), kBlock, defaults, fc.petsc_options);
  solver->reuse_preconditioner(!fc.steady && fc.reuse_preconditioner);
  if (!fc.steady && !stokes_start) solver->keep_solutions(fc.kept_solutions);
  // The resistive ends' columns: per end, at each of its points this process owns, the area
  // vector of its triangles there (a third of each's area times its outward normal) in the free
  // velocity rows, so that a column times the flow is the end's outflow (fluxes()).
  if (!resistive.empty()) {
    std::vector<std::vector<double>> columns;
    for (int k : resistive) {
      std::vector<double> column(kBlock * owned, 0.0);
      for (const BoundaryFace& f : boundaries[k].faces)
        for (int a = 0; a < 3; ++a)
          if (owns(f.v[a]))
            for (int i = 0; i < 3; ++i)
              if (!fixed[kBlock * f.v[a] + i]) column[kBlock * f.v[a] + i] += f.area / 3.0 * f.normal[i];
      columns.push_back(std::move(column));
    }
    solver->set_low_rank_columns(columns);
  }
  // A steady iteration's solve cuts the residual it starts from 1000-fold (saddle_point_options),
  // and does nothing once that residual is a hundredth of the change tolerance (of ||b||): the
  // last iterations cost nothing more, as they did when the tolerance was relative to ||b||.
  if (fc.steady) solver->set_residual_floor(1e-2 * fc.steady_tolerance);
  solver->set_residual_check(fc.steady);
}

void NavierStokes::Impl::solve_system(StepReport& report, const std::string& where, bool direct_fallback,
                                      const std::vector<Vec3>* guess, const std::vector<double>* pressure_guess) {
  const auto initial_guess = [&] { x = state_rows(guess ? *guess : u, pressure_guess ? *pressure_guess : p); };
  initial_guess();
  const auto start = Clock::now();
  // Once a steady solve has needed the direct solver, the next ones go to it at once (the
  // iterative one would spend its 1000 iterations again).
  SolveStats stats =
      direct_fallback && direct_now ? solver->solve_assembled_direct(rhs, x) : solver->solve_assembled(rhs, x);
  // A solve made again after one that failed, the warning saying why and how; the iterations of
  // both counted.
  const auto again = [&](const char* failed, const char* how, bool direct) {
    reporter->warning(fmt::format("{}: the iterative solver {} ({} after {} iterations): {}", where, failed, stats.reason,
                                  stats.iterations, how));
    const int iterative = stats.iterations;
    initial_guess();
    stats = direct ? solver->solve_assembled_direct(rhs, x) : solver->solve_assembled(rhs, x);
    stats.iterations += iterative;
  };
  // An answer whose true residual missed, or a steady solve that failed (unstable ILU factors of the
  // velocity block: on the FDA nozzle's 1.0M-unknown mesh GMRES broke down after 200 iterations at
  // half the inflow): again with SOR sweeps there, as the iterations after it
  // (LinearSolver::sweep_velocity_blocks).
  if ((stats.true_residual_missed || (!stats.converged && direct_fallback)) && solver->sweep_velocity_blocks())
    again(stats.true_residual_missed ? "missed the answer" : "did not converge",
          "the velocity block's ILU factors may be unstable here; solved again with SOR sweeps instead of them, and "
          "so the steady iterations after it", false);
  if (!stats.converged && direct_fallback && !direct_now &&
      kBlock * total_points <= NavierStokes::kDirectFallbackUnknowns) {
    direct_now = true;
    again("did not converge", "solved directly (MUMPS's LU) instead, and so the steady iterations after it; the "
          "steady preconditioner is weak where convection dominates", true);
  }
  report.solve_seconds += seconds_since(start);
  report.linear_iterations += stats.iterations;
  report.solves += 1;
  report.preconditioners_built += stats.preconditioner_built ? 1 : 0;
  report.solver_reason = stats.reason;
  if (!stats.converged)
    throw ComputationError(fmt::format("{}: the linear solver did not converge ({} after {} iterations); the mesh "
                                       "or the time step may be too coarse, or pass other [solver] petsc_options",
                                       where, stats.reason, stats.iterations));
}

void NavierStokes::Impl::check_finite(const StepReport& report) const {
  bool finite = true;
  for (const Vec3& v : u) finite = finite && v.allFinite();
  if (!parallel::any_process(!finite)) return;
  throw ComputationError(fmt::format("step {} (t = {:.6g} s) diverged: the velocity is no longer finite; the CFL "
                                     "number was {:.3g} (above ~1 the semi-implicit scheme may blow up: take a "
                                     "smaller dt), or flow entering through a traction boundary (backflow) grew",
                                     report.step, report.time, report.max_cfl));
}

BdfWeights bdf_weights(bool first, double ratio) {
  if (first) return {};
  const double w = ratio;
  return {(1.0 + 2.0 * w) / (1.0 + w), 1.0 + w, w * w / (1.0 + w), 1.0 + w, w};
}

StepReport NavierStokes::step() {
  Impl& s = *impl_;
  VM_CHECK(!s.fc.steady, "step() on a steady case");
  const auto start = Clock::now();
  StepReport report;
  report.step = s.step_count + 1;
  const double dt = time_step();
  const double t_next = s.t + dt;
  const bool first = s.step_count == 0;
  const BdfWeights bdf = bdf_weights(first, dt / (s.dt_last > 0.0 ? s.dt_last : s.fc.dt));
  const double alpha0 = bdf.current;
  std::vector<Vec3> history(s.n()), advect(s.n());
  for (int a = 0; a < s.n(); ++a) {  // the first step's weights take u^n alone
    history[a] = Vec3(bdf.now * s.u[a] - bdf.before * s.u_old[a]) / dt;
    advect[a] = Vec3(bdf.convect_now * s.u[a] - bdf.convect_before * s.u_old[a]);
  }
  // The pressure's initial guess extrapolated as the velocity's once p^(n-1) is a step's (from
  // rest the first step's pressure is the start's spike): with the kept solutions
  // (LinearSolver::keep_solutions) 17.6 iterations a step against 18.9 from p^n on the anastomosis
  // study's curvature mesh (40 steps through systole).
  std::vector<double> next_p = s.p;
  if (s.step_count >= 2)
    for (int a = 0; a < s.n(); ++a) next_p[a] = bdf.convect_now * s.p[a] - bdf.convect_before * s.p_old[a];
  s.update_resistance(dt);
  s.set_dirichlet(t_next);
  report.time = t_next;
  report.time_step = dt;

  std::vector<Vec3> next = s.u;
  for (int iteration = 0; iteration <= s.fc.picard; ++iteration) {
    const auto assembly = Clock::now();
    s.assemble(advect, history, alpha0 / dt, dt);
    report.assembly_seconds += seconds_since(assembly);
    if (iteration == 0) report.max_cfl = s.assembled_cfl();  // at the extrapolated velocity, as the step convects
    // From the velocity extrapolated to the new time (the convecting one: 2 u^n - u^(n-1) after the
    // first step), whose residual is O(dt^2) where the last step's is O(dt); a Picard iteration
    // from the last one's flow.
    s.solve_system(report, fmt::format("step {} (t = {:.6g} s)", report.step, t_next), false, &advect, &next_p);
    report.change = s.take_solution(next, next_p);
    advect = next;
  }
  s.u_old = std::move(s.u);
  s.u = std::move(next);
  s.p_old = std::move(s.p);
  s.p = std::move(next_p);
  s.settle_capacitors();
  s.t = t_next;
  s.step_count += 1;
  s.dt_last = dt;
  s.published = false;
  report.seconds = seconds_since(start);
  s.check_finite(report);
  return report;
}

std::string NavierStokes::Impl::not_settled(double change) const {
  // What was tried, in the user's words, and the other methods to try next (running in time the last resort).
  const std::string tried =
      fc.newton ? fmt::format("Newton's method (the inflow in stages of {:g}, {:g} and {:g}, each step cut back until the "
                              "residual fell)",
                              kInflowStages[0], kInflowStages[1], kInflowStages[2])
      : fc.pseudo_transient ? std::string("pseudo time steps (their length grown as the flow settled)")
                            : std::string("Picard's iterations");
  std::vector<std::string> next;
  if (!fc.newton) next.push_back("time.steady_method = \"newton\"");
  if (!fc.pseudo_transient) next.push_back("time.steady_method = \"pseudo-transient\"");
  double first = -1.0, least = -1.0, last = -1.0;
  for (const SteadyIteration& k : steady_history)
    if (k.residual >= 0.0) {
      if (first < 0.0) first = k.residual;
      least = least < 0.0 ? k.residual : std::min(least, k.residual);
      last = k.residual;
    }
  const std::string residuals =
      last >= 0.0 ? fmt::format("; its residual went from {:.3g} to {:.3g} (least {:.3g})", first, last, least) : "";
  return fmt::format("the steady solve by {} did not settle in {} iterations (last relative change {:.3g} > {:.3g}{}): "
                     "the flow may be unsteady at this Reynolds number; try {}run the case in time (time.steady = "
                     "false, to an end that washes out the start), or raise time.steady_iterations (summary.json's "
                     "steady_history holds every iteration)",
                     tried, fc.steady_iterations, change, fc.steady_tolerance, residuals,
                     next.empty() ? std::string() : fmt::format("{}, ", fmt::join(next, " or ")));
}

void NavierStokes::Impl::start_next_stage(size_t stage, std::vector<Vec3>& stage_u, std::vector<double>& stage_p) {
  // A secant through this stage's flow and the last one's (from rest, zero flow at zero inflow,
  // for the first), taken to the next stage's inflow.
  const auto& stages = NavierStokes::kInflowStages;
  const double before = stage > 0 ? stages[stage - 1] : 0.0, now = stages[stage];
  const double factor = (stages[stage + 1] - now) / (now - before);
  for (int a = 0; a < n(); ++a) {
    const Vec3 was = u[a];
    const double was_p = p[a];
    u[a] += factor * (was - stage_u[a]);
    p[a] += factor * (was_p - stage_p[a]);
    stage_u[a] = was;
    stage_p[a] = was_p;
  }
  x = state_rows(u, p);
}

namespace {

// The pseudo time steps' length (steady_method = "pseudo-transient"): `dt`, 0 for a Picard iteration.
struct PseudoSteps {
  double dt = 0.0, last_rate = 0.0, resume = 0.0;
  // After an iteration (a step of `dt`, or a Picard iteration) that changed the flow by `change`:
  // `confirm` (a step settled it): a Picard iteration next, to confirm, the step kept to resume; after
  // Stokes or a Picard iteration that did not confirm, the step before it, or one at kPseudoCflStart
  // (cfl_per_second(): the largest CFL number of a step of 1 s, which cfl() is linear in); otherwise
  // the change per unit pseudo time measures the steady residual: the step lengthened by the rate's
  // fall (at least 1.2x while it falls, at most 2x), shortened (at most 2x) when it rises.
  void next(bool confirm, double change, const std::function<double()>& cfl_per_second) {
    const double used = dt;
    if (confirm) {
      resume = dt;
      dt = 0.0;
    } else if (dt == 0.0) {
      const double per_second = resume > 0.0 ? 0.0 : cfl_per_second();
      dt = resume > 0.0 ? resume : per_second > 0.0 ? NavierStokes::kPseudoCflStart / per_second : 0.0;
    } else {
      const double rate = change / used;
      if (last_rate > 0.0)
        dt *= rate <= last_rate ? std::clamp(last_rate / rate, 1.2, 2.0) : std::max(0.5, last_rate / rate);
    }
    last_rate = used > 0.0 ? change / used : 0.0;
  }
};

}  // namespace

StepReport NavierStokes::solve_steady() {
  Impl& s = *impl_;
  const auto start = Clock::now();
  StepReport report;
  // Newton's iterations (fc.newton) go up the inflow in stages (NavierStokes::kInflowStages): each
  // stage's flow, to a loose change, extrapolated to the next one's start (below: the residual
  // there 0.06-0.2 instead of the 0.5 of the last stage's flow with the new inflow).
  size_t stage = s.fc.newton ? 0 : kInflowStages.size() - 1;
  s.steady_history.clear();
  int linear_before = 0;  // the linear iterations before this iteration's (report's are the solve's)
  const auto set_inflow = [&] {
    s.set_dirichlet(0.0);
    for (size_t row = 0; row < s.dirichlet.size(); ++row)
      if (s.fixed[row]) s.dirichlet[row] *= kInflowStages[stage];
  };
  set_inflow();
  std::vector<Vec3> advect(s.n(), Vec3::Zero()), none(s.n(), Vec3::Zero());
  std::vector<Vec3> stage_u(s.n(), Vec3::Zero());  // the last stage's flow (rest before the first)
  std::vector<double> stage_p(s.n(), 0.0);
  int stalled = 0;  // this stage's iterations in a row whose cut-back step took off under kStallFall of the residual
  // Pseudo time steps (pseudo_transient): their length, 0 for a Picard iteration (the first
  // iteration the Stokes solve either way). known: the iterate's steady residual, where a line search measured it.
  PseudoSteps pseudo;
  double& pseudo_dt = pseudo.dt;
  double known = -1.0;
  bool settled = false;
  using Linearization = Impl::Linearization;
  Linearization level = Linearization::picard;  // the Stokes solve, then Newton's (fc.newton) or Picard's
  s.direct_now = false;
  for (int iteration = 0; iteration < s.fc.steady_iterations; ++iteration) {
    s.update_resistance(0.0);
    const auto assembly = Clock::now();
    std::vector<Vec3> history = none;
    if (pseudo_dt > 0.0)
      for (int a = 0; a < s.n(); ++a) history[a] = s.u[a] / pseudo_dt;
    const double residual = iteration > 0 ? s.residual_and_assemble(advect, history, pseudo_dt, level, known) : -1.0;
    if (iteration == 0) s.assemble(advect, history, 0.0, 0.0, level);
    report.assembly_seconds += seconds_since(assembly);
    const auto name = [](Linearization l) {
      return l == Linearization::full         ? "Newton iteration"
             : l == Linearization::convection ? "Newton iteration on the convection"
                                              : "Picard iteration";
    };
    const std::string what = pseudo_dt > 0.0 ? "pseudo time step" : name(level);
    // The Stokes solve from rest 1000 times tighter than the iterations after it (to 1e-6 of ||b||
    // by default): a loose start costs more in the Picard iterations it adds (measured: 260 linear
    // iterations against 175 on a 117k-unknown pipe, 114 when the solves stopped at 1e-6 of ||b|| and
    // the residual with them).
    s.solver->scale_tolerance(iteration == 0 ? 1e-3 : 1.0);
    s.solve_system(report, fmt::format("steady {} {}", what, iteration + 1), /*direct_fallback=*/true);
    // Newton's step cut back until the residual falls; where none does (far from the answer,
    // where the linearization misleads), the iteration again from the same flow with the
    // linearization below (Newton's on the convection alone, then Picard's), from which the next
    // iteration goes up again after a whole step.
    double lambda = 1.0;
    double reached = -1.0;  // the steady residual of the state taken, where the line search measured it
    std::string taken;
    if (level != Linearization::picard) {
      lambda = s.line_search(residual, report, reached);
      while (lambda == 0.0) {
        taken += ", its step raised the residual";
        level = level == Linearization::full ? Linearization::convection : Linearization::picard;
        const auto again = Clock::now();
        s.assemble(advect, history, 0.0, 0.0, level);
        report.assembly_seconds += seconds_since(again);
        s.solve_system(report, fmt::format("steady {} {} (again)", name(level), iteration + 1), true);
        lambda = level == Linearization::picard ? 1.0 : s.line_search(residual, report, reached);
        taken += fmt::format(": a {} instead", name(level));
      }
      if (lambda < 1.0) taken += fmt::format(", its step times {:g}", lambda);
    }
    report.change = s.take_solution(s.u, s.p);
    known = reached;  // the state taken is the line search's last trial
    s.published = false;
    report.step = iteration + 1;
    s.check_finite(report);
    s.reporter->info(fmt::format("steady iteration {} ({}{}{}{}): {}velocity change {:.3e}, {} linear iterations",
                                 iteration + 1, what,
                                 stage + 1 < kInflowStages.size()
                                     ? fmt::format(" at {:g} of the inflow", kInflowStages[stage])
                                     : "",
                                 taken,
                                 pseudo_dt > 0.0 ? fmt::format(", CFL {:.3g}", s.cfl(advect, pseudo_dt)) : "",
                                 residual >= 0.0 ? fmt::format("residual before it {:.3e}, ", residual) : "",
                                 report.change, report.linear_iterations));
    s.steady_history.push_back({iteration + 1, iteration == 0 ? std::string("Stokes") : what + taken,
                                kInflowStages[stage], residual, report.change,
                                report.linear_iterations - linear_before});
    linear_before = report.linear_iterations;
    advect = s.u;
    // Newton's iterations (fc.newton) from the first after the Stokes solve, on the convection;
    // after a whole step, with the stabilization's terms too (near the answer superlinear: 9, 99
    // and 1040-fold on the bend of the tests, where the convection's alone converged linearly, 0.7
    // a step on a carotid bifurcation at Re 300).
    if (s.fc.newton && lambda == 1.0)
      level = level == Linearization::picard ? Linearization::convection : Linearization::full;
    // Settled when the step (Newton's whole step where it was cut back) is under the tolerance; a
    // stage below the whole inflow when it is under kStageTolerance: the next stage from its flow.
    // A stage whose Newton steps stall (kStalledSteps cut back in a row, each taking off less than
    // kStallFall of the residual) has done what it can for the next one: the next stage from its flow.
    const double step_change = report.change / (lambda > 0.0 ? lambda : 1.0);
    const bool stalling = s.fc.newton && lambda < 1.0 && residual > 0.0 && reached >= 0.0 &&
                          reached > (1.0 - kStallFall) * residual;
    stalled = stalling ? stalled + 1 : 0;
    if (stage + 1 < kInflowStages.size() && iteration > 0 &&
        (step_change < kStageTolerance || stalled >= kStalledSteps)) {
      s.start_next_stage(stage, stage_u, stage_p);
      known = -1.0;
      advect = s.u;
      ++stage;
      stalled = 0;
      set_inflow();
      continue;
    }
    // (Or when the residual Newton's step reached is under the tolerance: no iteration to confirm it.)
    const bool small = stage + 1 == kInflowStages.size() &&
                       (step_change < s.fc.steady_tolerance || (reached >= 0.0 && reached < s.fc.steady_tolerance));
    if (!s.fc.pseudo_transient) {
      if (iteration > 0 && small) {
        settled = true;
        break;
      }
      continue;
    }
    if (iteration > 0 && pseudo_dt == 0.0 && small) {  // a Picard iteration confirmed it
      settled = true;
      break;
    }
    pseudo.next(iteration > 0 && pseudo_dt > 0.0 && small, report.change, [&] { return s.cfl(advect, 1.0); });
  }
  if (!settled) throw ComputationError(s.not_settled(report.change));
  // The answer's residual: the steady system assembled at it once more (Picard's form).
  s.update_resistance(0.0);
  const auto assembly = Clock::now();
  s.assemble(s.u, none, 0.0, 0.0);
  report.assembly_seconds += seconds_since(assembly);
  report.residual = s.solver->relative_residual(s.rhs, s.x);
  s.settle_capacitors();  // P_d + R_d Q at the answer
  s.reporter->info(fmt::format("steady residual {:.3e} (relative: ||A(u) u - b|| / ||b||) after {} iterations",
                               report.residual, report.step));
  report.seconds = seconds_since(start);
  return report;
}

StepReport NavierStokes::start_from_stokes() {
  Impl& s = *impl_;
  const auto start = Clock::now();
  StepReport report;
  s.update_resistance(0.0);
  s.set_dirichlet(s.t);
  const std::vector<Vec3> none(s.n(), Vec3::Zero());
  const auto assembly = Clock::now();
  s.solver.reset();
  s.stokes_start = true;
  // With the time steps' stabilization parameter (tau_M's 4/dt^2 term; no mass term): the
  // viscous limit's tau_M, 20 times theirs on a 0.48 mm pipe at dt 1 ms, relaxed the continuity
  // equation's PSPG part so differently that the first step had to project the flow anew, its
  // pressure a spike (inlet 30.3 Pa, then 2.4, 11.4 against 11.4 settled) and its solves 13-23
  // iterations; now 11.39, 11.34, 11.36 and 11-16.
  s.assemble(none, none, 0.0, s.fc.dt);
  s.stokes_start = false;
  report.assembly_seconds = seconds_since(assembly);
  s.solve_system(report, fmt::format("the Stokes start (t = {:.6g} s)", s.t));
  // The time steps' system has a mass term: a new solver for it, made once this one is gone (its
  // preconditioner and the Stokes solve's Krylov vectors: 250 MB of the peak at 420k unknowns).
  s.solver.reset();
  report.change = s.take_solution(s.u, s.p);
  s.published = false;
  s.u_old = s.u;
  s.step_count = 0;
  report.time = s.t;
  report.seconds = seconds_since(start);
  s.check_finite(report);
  return report;
}

}  // namespace vesselmesh::flow
