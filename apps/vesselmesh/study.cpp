// vesselmesh study: the mesh-impact study on any vessel (study/study.h), with its report.
#include "commands.h"

#include "study/study.h"

#include <fmt/format.h>

#include <filesystem>

namespace vesselmesh::cli {

Command add_study_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "study",
      "The paper's experiment on any vessel, from a TOML study file (surface, flow case, triangles, [reference] "
      "levels/factor, [volume], [post] time, [[ring]], [[point]], [[end]]; see examples/ and src/study/study.h): the four "
      "surface meshes (uniform, distance, curvature, anisotropic) with the same triangle count, a refinement series "
      "whose finest level is the reference (by default the envelope series: each level finer than every compared mesh "
      "at every point, by 1.1 x factor^(k-1); [reference] kind = \"uniform\" for the seed's uniform meshes), their "
      "boundary-layer volume meshes, the flow case on each, and WSS on the rings, at the points and over the whole wall "
      "against the reference, with the reference's own uncertainty (grid convergence, half the time step). Writes "
      "DIR/report.md and DIR/report.html (Table 1, WSS along the rings, relative differences, pictures of the meshes "
      "and of WSS, timings, options), DIR/figures/ (SVG and PNG), DIR/study.json. Steps already made with the same "
      "inputs are reused: run it again to resume");
  struct Options {
    std::string study_file, output;
    int ranks = 0;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("STUDY", o->study_file, "Study file (.toml)")->required()->check(CLI::ExistingFile);
  app->add_option("-o,--output", o->output, "Output folder (created if absent)")->required();
  app->add_option("--ranks", o->ranks,
                  "Processes each flow runs on (the study file's `ranks`, default 1): more than 1 runs each flow as "
                  "'mpirun -np N vesselmesh simulate ...' (mpirun from PATH)")
      ->check(CLI::PositiveNumber);
  add_common_options(*app, o->common);
  return {app, [o] {
            TerminalReporter reporter(o->common.quiet);
            study::StudyConfig config = study::read_study(o->study_file);
            if (o->ranks > 0) config.ranks = o->ranks;
            config.program = std::filesystem::read_symlink("/proc/self/exe").string();
            const study::StudyResult r = study::run_study(config, o->output, reporter);
            reporter.info(fmt::format("study done: {} meshes, reference {}; report in {} and {}", r.meshes.size(),
                                      r.meshes[r.reference].name, r.report_html, r.report_markdown));
            if (o->common.json) {
              Json meshes = Json::array();
              for (const study::MeshRun& m : r.meshes) {
                Json rings = Json::array();
                for (const post::Ring& ring : m.rings)
                  rings.push_back({{"name", ring.name}, {"minimum_wss", round_to(ring.samples[ring.minimum].magnitude)}});
                meshes.push_back({{"name", m.name},
                                  {"series", m.series},
                                  {"surface_triangles", m.surface_triangles},
                                  {"tetrahedra", m.tetrahedra},
                                  {"reused", m.reused},
                                  {"rings", rings}});
              }
              print_json(Json{{"report_html", r.report_html},
                              {"report_markdown", r.report_markdown},
                              {"time_s", r.time},
                              {"reference", r.meshes[r.reference].name},
                              {"meshes", meshes}});
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
