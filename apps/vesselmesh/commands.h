// The subcommands of vesselmesh, one file each. Each registers itself on the app and returns
// the action main() runs when it was chosen.
#pragma once

#include "cli_support.h"

#include "analysis/curvature.h"
#include "analysis/open_ends.h"
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "remesh/adapt.h"
#include "sizing/size_field.h"
#include "io/surface.h"
#include "mesh/clean.h"
#include "mesh/statistics.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::cli {

struct Command {
  CLI::App* app;
  Action action;
};

Command add_info_command(CLI::App& parent);
Command add_curvature_command(CLI::App& parent);
Command add_centerline_command(CLI::App& parent);
Command add_size_command(CLI::App& parent);
Command add_remesh_command(CLI::App& parent);
Command add_volume_command(CLI::App& parent);
Command add_quality_command(CLI::App& parent);
Command add_simulate_command(CLI::App& parent);
Command add_wss_command(CLI::App& parent);
Command add_sample_command(CLI::App& parent);
Command add_study_command(CLI::App& parent);
Command add_synth_command(CLI::App& parent);
Command add_demo_command(CLI::App& parent);
Command add_windkessel_command(CLI::App& parent);
Command add_export_command(CLI::App& parent);
Command add_extend_command(CLI::App& parent);
Command add_adapt_command(CLI::App& parent);

// Reading, checking and describing a surface: what `info` does, reused by `demo`.
struct SurfaceCheckOptions {
  std::optional<std::string> units;
  std::string label_array;
  mesh::CleanOptions clean;
  analysis::OpenEndsOptions ends;
};

struct CheckedSurface {
  io::SurfaceFile file;  // the mesh in it is the repaired one
  mesh::CleanReport repairs;
  mesh::Statistics statistics;
  std::vector<analysis::OpenEnd> ends;
};

CheckedSurface check_surface(const std::string& path, const SurfaceCheckOptions& options,
                             const Reporter& reporter);

// The input surface of the stage commands (curvature, centerline, size, remesh): SURFACE,
// --units and --label-array; read, repaired and described as `info` does, without its
// self-intersection search.
struct SurfaceInput {
  std::string path, units, label_array;
};
void add_surface_input(CLI::App& app, SurfaceInput& input);
CheckedSurface read_surface_input(const SurfaceInput& input, const Reporter& reporter);

// Point data `metric`: per point its six entries xx, xy, xz, yy, yz, zz.
Field metric_field(const std::vector<Sym3>& metric);
Json describe(const CheckedSurface& surface);
std::string describe_as_text(const CheckedSurface& surface);
// The repaired surface with the input's point and cell data carried along.
void write_repaired(const std::string& path, const CheckedSurface& surface);

// The point-data arrays of the curvature contract: k1, k2, mean_curvature, gauss_curvature,
// dir1, dir2, normal.
std::vector<Field> curvature_fields(const analysis::CurvatureField& curvature);

// Centerlines as VTP polylines (point data radius, cell data branch), and the distance map
// as the surface with point data distance and radius.
void write_centerlines(const std::string& path, const centerline::Centerlines& centerlines);
void write_distance_map(const std::string& path, const TriMesh& surface, const centerline::Centerlines& centerlines);

// Size-field options shared by `size` and `remesh`, and what sizing computes on the way.
struct SizingArgs {
  std::string kind;
  sizing::SizingOptions options;
  std::string flow;                 // the flow kind: the `simulate` folder whose WSS it adapts to
  std::vector<double> flow_times;   // s; empty: the last period's saved frames, or the last frame
  double error_norm = 2.0;          // the L^p norm of the WSS's interpolation error made least
};
void add_sizing_options(CLI::App& app, SizingArgs& args, bool size_required = true);

struct SizedSurface {
  std::optional<analysis::CurvatureField> curvature;
  std::optional<centerline::Centerlines> centerlines;
  std::optional<centerline::DistanceMap> distance;
  std::optional<std::vector<Sym3>> flow_metric;  // the flow kind's error metric on the surface's points
  std::vector<double> flow_times;                 // s: the saved times it bounds
  sizing::SizeField field;
};
SizedSurface size_surface(const CheckedSurface& surface, const SizingArgs& args, const Reporter& reporter);
// Point data `size`, `metric` (xx, xy, xz, yy, yz, zz) and, with a distance map, `radius`.
std::vector<Field> size_fields(const SizedSurface& sized);
Json size_json(const sizing::SizeField& field);

// A remeshed surface: point data metric (what it was adapted to), cell data quality (in that
// metric) and tag (labels); and the figures of `vesselmesh remesh --json`.
void write_remeshed(const std::string& path, const remesh::RemeshResult& result);
Json remesh_json(const remesh::RemeshStats& stats);

}  // namespace vesselmesh::cli
