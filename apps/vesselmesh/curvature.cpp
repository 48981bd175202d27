// vesselmesh curvature: per-point curvature tensor, principal curvatures and directions.
#include "commands.h"

#include "analysis/curvature.h"
#include "io/surface.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>

namespace vesselmesh::cli {
namespace {

Json quantiles(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  auto at = [&](double q) { return values.empty() ? 0.0 : values[static_cast<size_t>(q * (values.size() - 1))]; };
  return {{"min", round_to(at(0.0))}, {"p05", round_to(at(0.05))}, {"median", round_to(at(0.5))},
          {"p95", round_to(at(0.95))}, {"max", round_to(at(1.0))}};
}

}  // namespace

std::vector<Field> curvature_fields(const analysis::CurvatureField& c) {
  std::vector<double> mean(c.size()), gauss(c.size());
  for (int v = 0; v < c.size(); ++v) mean[v] = c.mean(v), gauss[v] = c.gauss(v);
  return {Field::scalar("k1", c.k1),           Field::scalar("k2", c.k2),
          Field::scalar("mean_curvature", mean), Field::scalar("gauss_curvature", gauss),
          Field::vector("dir1", c.dir1),        Field::vector("dir2", c.dir2),
          Field::vector("normal", c.normal)};
}

Command add_curvature_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "curvature",
      "Principal curvatures and directions per point (Rusinkiewicz 2004, with second-order fitted normals); "
      "writes a VTP with point data k1, k2 (k1 <= k2), mean_curvature, gauss_curvature, dir1, dir2, normal, in 1/mm. "
      "Positive where the outward surface is convex: on a pipe of radius R, k2 = 1/R around it and k1 = 0 along it");
  struct Options {
    SurfaceInput surface;
    std::string output, normals = "fit";
    int smooth = 0;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  add_surface_input(*app, o->surface);
  app->add_option("-o,--output", o->output, "Output .vtp (the repaired surface in mm with the curvature arrays)")
      ->required();
  app->add_option("--smooth", o->smooth, "Passes of area-weighted smoothing of the curvature tensor (default 0)")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--normals", o->normals,
                  "Vertex normals: fit (local quadric, second order; default), max (Max 1999, the paper's), angle, area")
      ->check(CLI::IsMember({"fit", "max", "angle", "area"}));
  add_common_options(*app, o->common);
  return {app, [o] {
            if (io::surface_format(o->output) != io::SurfaceFormat::vtp)
              throw OptionError(fmt::format("{}: the curvature is written as VTP point data: use a .vtp name", o->output));
            TerminalReporter reporter(o->common.quiet);
            const CheckedSurface surface = read_surface_input(o->surface, reporter);
            const std::map<std::string, analysis::NormalMethod> methods = {
                {"fit", analysis::NormalMethod::quadric_fit}, {"max", analysis::NormalMethod::max},
                {"angle", analysis::NormalMethod::angle}, {"area", analysis::NormalMethod::area}};
            const auto start = std::chrono::steady_clock::now();
            const analysis::CurvatureField c = analysis::curvature(
                surface.file.mesh, {.normals = methods.at(o->normals), .smoothing_passes = o->smooth}, reporter);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            io::write_vtp(o->output, surface.file.mesh, curvature_fields(c));
            std::vector<double> mean(c.size()), gauss(c.size());
            for (int v = 0; v < c.size(); ++v) mean[v] = c.mean(v), gauss[v] = c.gauss(v);
            if (o->common.json) {
              print_json({{"input", o->surface.path},
                          {"output", o->output},
                          {"units", "mm"},
                          {"curvature_units", "1/mm"},
                          {"points", surface.file.mesh.num_points()},
                          {"triangles", surface.file.mesh.num_triangles()},
                          {"normals", o->normals},
                          {"smoothing_passes", o->smooth},
                          {"k1", quantiles(c.k1)},
                          {"k2", quantiles(c.k2)},
                          {"mean_curvature", quantiles(mean)},
                          {"gauss_curvature", quantiles(gauss)},
                          {"repairs", surface.repairs.repairs},
                          {"seconds", round_to(seconds, 4)}});
            } else {
              std::sort(mean.begin(), mean.end());
              reporter.info(fmt::format("wrote k1, k2, mean_curvature, gauss_curvature, dir1, dir2, normal (1/mm) "
                                        "for {} points to {}; median mean curvature {:.4g} /mm ({:.3f} s)",
                                        c.size(), o->output, mean[mean.size() / 2], seconds));
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
