// vesselmesh simulate: unsteady (or steady) incompressible flow on a tagged volume mesh
// (flow/simulate.h).
#include "commands.h"

#include "flow/case.h"
#include "parallel/processes.h"
#include "flow/simulate.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>


namespace vesselmesh::cli {
namespace {

struct Options {
  std::string case_file, output, petsc_options, mesh;
  int time_step_divisor = 1;
  double end = std::numeric_limits<double>::quiet_NaN();  // s; NaN: the case's
  bool restart = false;
  CommonOptions common;
};

// One process's run (under mpirun every process runs it; the first speaks).
int run(const Options& options, bool first) {
  TerminalReporter reporter(options.common.quiet || !first);
  flow::FlowCase fc = flow::read_case(options.case_file);
  if (!options.mesh.empty()) fc.mesh = options.mesh;
  if (options.time_step_divisor > 1) flow::divide_time_step(fc, options.time_step_divisor);
  if (!std::isnan(options.end)) flow::set_end(fc, options.end);
  const flow::SimulationSummary s =
      flow::simulate(fc, options.output, options.petsc_options, reporter, options.restart);
  if (s.status == "stopped") return 128 + s.signal;
  if (!first) return 0;
  if (fc.steady)
    reporter.info(fmt::format("{} in {} iterations, {} dofs, {} linear iterations, {:.1f} s in all ({:.1f} s set-up); "
                              "results in {}",
                              s.status, s.steps, s.dofs, s.linear_iterations, s.seconds, s.setup_seconds,
                              options.output));
  else
    reporter.info(fmt::format(
        "{} {} steps, {} dofs, {} linear iterations; set-up (reading, distributing) {:.2f} s, initial state {:.2f} s, "
        "first step {:.3g} s, then {:.3g} s a step over {} settled steps ({:.3g} s a step per million unknowns); "
        "{:.1f} s in all; results in {}",
        s.status, s.steps, s.dofs, s.linear_iterations, s.setup_seconds, s.initial_seconds, s.first_step_seconds,
        s.settled_step_seconds, s.settled_steps, s.per_million_dofs(s.settled_step_seconds),
        s.seconds, options.output));
  if (options.common.json)
    print_json(Json{{"status", s.status},
                    {"points", s.points},
                    {"tetrahedra", s.tetrahedra},
                    {"dofs", s.dofs},
                    {"ranks", s.ranks},
                    {"steps", s.steps},
                    {"saved", s.saved},
                    {"linear_iterations", s.linear_iterations},
                    {"seconds", round_to(s.seconds, 4)},
                    {"seconds_per_step", round_to(s.seconds_per_step, 4)},
                    {"setup_seconds", round_to(s.setup_seconds, 4)},
                    {"initial_state_seconds", round_to(s.initial_seconds, 4)},
                    {"first_step_seconds", round_to(s.first_step_seconds, 4)},
                    {"settled_steps", s.settled_steps},
                    {"settled_step_seconds", round_to(s.settled_step_seconds, 4)},
                    {"length_scale_m", s.length_scale},
                    {"solver", s.solver},
                    {"peak_memory_mb", s.peak_memory_mb},
                    {"library_memory_mb", s.library_memory_mb},
                    {"peak_own_memory_mb", s.own_memory_mb},
                    {"output", options.output}});
  return 0;
}

}  // namespace

Command add_simulate_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "simulate",
      "Incompressible Navier-Stokes flow (stabilized P1-P1 finite elements, BDF2, PETSc) on a volume mesh from "
      "'vesselmesh volume', as a TOML case file describes it (mesh, length_unit, [fluid], [time], one [[boundary]] "
      "per mesh tag: velocity | traction | resistance | rcr | wall, [solver] petsc_options; see examples/). Writes "
      "DIR/fluid.pvd (velocity m/s, pressure Pa), DIR/wall.pvd (wss, wss_magnitude in Pa), DIR/log.csv and "
      "DIR/summary.json; with [output] statistics_from = T, DIR/statistics.vtu (the time means of the velocity and "
      "the pressure from T to the end, and the RMS of the velocity's fluctuation). The mesh's unit is scaled to SI "
      "(the scale is logged and written). An unsteady run "
      "writes DIR/checkpoint.bin every [output] checkpoint_every steps (default save_every), at its end and when "
      "SIGTERM or SIGINT stops it (after the step under way; exit code 128 + the signal); --restart goes on from "
      "it. Under 'mpirun -np K' the first process reads the mesh and sends each its part (PT-Scotch); each solves "
      "its rows and writes its pieces of the results (DIR/pieces/, joined by .pvtu / .pvtp files in the .pvd)");
  auto o = std::make_shared<Options>();
  app->add_option("CASE", o->case_file, "Case file (.toml)")->required()->check(CLI::ExistingFile);
  app->add_option("-o,--output", o->output, "Output folder (created if absent)")->required();
  app->add_option("--mesh", o->mesh,
                  "Volume mesh (.msh or .vtu) to run the case on instead of the case's `mesh` (a path as given "
                  "here, not relative to the case file)")
      ->check(CLI::ExistingFile);
  app->add_option("--time-step-divisor", o->time_step_divisor,
                  "Run the case at its time step divided by K, saving at the same times (save_every, checkpoint_every "
                  "and fluid_every times K): a time-step convergence check")
      ->check(CLI::PositiveNumber);
  app->add_option("--end", o->end,
                  "Run to this time (s) instead of the case's [time] end; with --restart, a finished run goes on to "
                  "it (e.g. one period more, to see how periodic the flow has become)");
  app->add_option("--petsc-options", o->petsc_options,
                  "PETSc options applied after the case's [solver] petsc_options, e.g. \"-ksp_monitor\"");
  app->add_flag("--restart", o->restart,
               "Go on from DIR/checkpoint.bin (the same mesh and time step; a later [time] end extends the run, its "
               "hemodynamic indices then over the new last period), as if the run had not stopped");
  add_common_options(*app, o->common);
  return {app, [o] {
            const bool first = parallel::process_rank() == 0;  // under mpirun, the first process speaks
            if (parallel::process_count() == 1) return run(*o, first);
            // Under mpirun an input, option or computation error is raised on every process alike
            // (the mesh's, from the first): the first tells it, then the others end with its code
            // once it says it has (mpirun ends every process once one has ended with an error: the
            // first's message raced with it, lost on a loaded machine after half a second's wait);
            // 10 s at most, not a collective wait, which an error raised on some processes alone
            // would hang. Any other failure may be on one process while the others wait on it: it
            // is told with the process's rank and every process ends at once.
            const auto alike = [&](const std::exception& e, int code) {
              if (first) fmt::print(stderr, "vesselmesh simulate: error: {}\n", e.what());
              parallel::error_told_together(10.0);
              return code;
            };
            try {
              return run(*o, first);
            } catch (const InputError& e) {
              return alike(e, 2);
            } catch (const OptionError& e) {
              return alike(e, 2);
            } catch (const ComputationError& e) {
              return alike(e, 1);
            } catch (const std::exception& e) {
              fmt::print(stderr, "vesselmesh simulate: internal error on process {} of {}: {}\n", parallel::process_rank(),
                         parallel::process_count(), e.what());
              parallel::abort_all(1);
            }
          }};
}

}  // namespace vesselmesh::cli
