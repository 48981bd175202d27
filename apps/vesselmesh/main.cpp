// vesselmesh: vessel surfaces to simulation-ready meshes and wall shear stress.
#include "cli_support.h"
#include "commands.h"

#include <fmt/format.h>

#ifndef VESSELMESH_VERSION
#define VESSELMESH_VERSION "0.0.0"
#endif

int main(int argc, char** argv) {
  using namespace vesselmesh::cli;
  CLI::App app("vesselmesh " VESSELMESH_VERSION
               ": vessel lumen surfaces (STL, VTP, ...) to curvature- and radius-adapted surface meshes, "
               "boundary-layer volume meshes, flow and wall shear stress.\n"
               "Lengths are in mm unless a command says otherwise. Licensed GPL-3.0-or-later.",
               "vesselmesh");
  app.set_version_flag("--version", VESSELMESH_VERSION);
  app.require_subcommand(1);
  app.fallthrough();
  const std::vector<Command> commands = {add_info_command(app), add_curvature_command(app), add_centerline_command(app), add_size_command(app),
                                         add_remesh_command(app),
                                         add_volume_command(app), add_adapt_command(app), add_quality_command(app), add_simulate_command(app), add_wss_command(app), add_sample_command(app), add_study_command(app), add_windkessel_command(app), add_export_command(app), add_extend_command(app),
                                         add_synth_command(app),
                                         add_demo_command(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Under mpirun every process parses the same command line: the first tells what is wrong.
    if (launch_rank() == 0)
      fmt::print(stderr, "vesselmesh: error: {}\nRun 'vesselmesh --help' or 'vesselmesh COMMAND --help'.\n", e.what());
    return 2;
  }
  for (const Command& command : commands)
    if (command.app->parsed()) return run_action(command.action, command.app->get_name());
  return 2;
}
