// vesselmesh simulate: unsteady (or steady) incompressible flow on a tagged volume mesh
// (flow/simulate.h).
#include "commands.h"

#include "flow/case.h"
#include "flow/linear_solver.h"
#include "flow/simulate.h"

#include <fmt/format.h>

namespace vesselmesh::cli {

Command add_simulate_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "simulate",
      "Incompressible Navier-Stokes flow (stabilized P1-P1 finite elements, BDF2, PETSc) on a volume mesh from "
      "'vesselmesh volume', as a TOML case file describes it (mesh, length_unit, [fluid], [time], one [[boundary]] "
      "per mesh tag: velocity | traction | resistance | rcr | wall, [solver] petsc_options; see examples/). Writes "
      "DIR/fluid.pvd (velocity m/s, pressure Pa), DIR/wall.pvd (wss, wss_magnitude in Pa), DIR/log.csv and "
      "DIR/summary.json. The mesh's unit is scaled to SI (the scale is logged and written). An unsteady run "
      "writes DIR/checkpoint.bin every [output] checkpoint_every steps (default save_every), at its end and when "
      "SIGTERM or SIGINT stops it (after the step under way; exit code 128 + the signal); --restart goes on from "
      "it. Under 'mpirun -np K' the rows are shared among the K processes");
  struct Options {
    std::string case_file, output, petsc_options, mesh;
    bool restart = false;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("CASE", o->case_file, "Case file (.toml)")->required()->check(CLI::ExistingFile);
  app->add_option("-o,--output", o->output, "Output folder (created if absent)")->required();
  app->add_option("--mesh", o->mesh,
                  "Volume mesh (.msh or .vtu) to run the case on instead of the case's `mesh` (a path as given "
                  "here, not relative to the case file)")
      ->check(CLI::ExistingFile);
  app->add_option("--petsc-options", o->petsc_options,
                  "PETSc options applied after the case's [solver] petsc_options, e.g. \"-ksp_monitor\"");
  app->add_flag("--restart", o->restart,
               "Go on from DIR/checkpoint.bin (the same mesh and time step; a later [time] end extends the run), as "
               "if the run had not stopped");
  add_common_options(*app, o->common);
  return {app, [o] {
            const bool first = flow::process_rank() == 0;  // under mpirun, the first process speaks
            TerminalReporter reporter(o->common.quiet || !first);
            flow::FlowCase fc = flow::read_case(o->case_file);
            if (!o->mesh.empty()) fc.mesh = o->mesh;
            const flow::SimulationSummary s = flow::simulate(fc, o->output, o->petsc_options, reporter, o->restart);
            if (s.status == "stopped") return 128 + s.signal;
            if (!first) return 0;
            reporter.info(fmt::format("{} {} steps, {} dofs, {} linear iterations, {:.3g} s per step, {:.1f} s in all; "
                                      "results in {}",
                                      s.status, s.steps, s.dofs, s.linear_iterations, s.seconds_per_step, s.seconds,
                                      o->output));
            if (o->common.json)
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
                              {"length_scale_m", s.length_scale},
                              {"solver", s.solver},
                              {"peak_memory_mb", s.peak_memory_mb},
                              {"output", o->output}});
            return 0;
          }};
}

}  // namespace vesselmesh::cli
