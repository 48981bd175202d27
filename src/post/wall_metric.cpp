#include "post/wall_metric.h"

#include "analysis/normals.h"
#include "mesh/error.h"
#include "post/wall_series.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::post {

WallMetric wall_error_metric(const std::string& flow_directory, const std::vector<double>& times,
                             const sizing::ErrorMetricOptions& options, const Reporter& reporter) {
  const WallSeries series = read_wall_series(flow_directory);
  if (series.frames.empty())
    throw InputError(fmt::format("{}: the flow saved no wall frame", flow_directory));
  WallMetric out;
  std::vector<std::vector<double>> fields;
  for_bounded_frames(series, times, read_wall_frame, wall_at_time, [&](const WallField& f, bool first) {
    if (first) {
      out.wall = f.mesh;
    } else if (f.mesh.points.size() != out.wall.points.size() || f.mesh.triangles != out.wall.triangles) {
      throw InputError(fmt::format(
          "{}: the wall at t = {} s is not the mesh of t = {} s: the flow's frames must share one wall",
          flow_directory, f.time, out.times.front()));
    }
    out.times.push_back(f.time);
    append_components(fields, f.wss);
  });
  const double to_mm = series.length_scale / 1e-3;
  for (Vec3& p : out.wall.points) p *= to_mm;
  reporter.info(fmt::format(
      "the WSS's interpolation error on the flow's wall ({} points) at {} saved time{}, from "
      "{:.4g} to {:.4g} s",
      out.wall.num_points(), out.times.size(), out.times.size() == 1 ? "" : "s", out.times.front(),
      out.times.back()));
  const std::vector<Vec3> normals = analysis::vertex_normals(out.wall);
  out.metric = sizing::error_metric(out.wall, fields, normals, options, reporter);
  return out;
}

}  // namespace vesselmesh::post
