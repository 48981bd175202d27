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
  // The frames, read one at a time: a cycle's frames of a large wall do not all fit at once.
  const std::vector<const WallFrame*> saved = times.empty() ? last_period_frames(series) : std::vector<const WallFrame*>{};
  const size_t count = times.empty() ? saved.size() : times.size();
  std::vector<std::vector<double>> fields;
  for (size_t i = 0; i < count; ++i) {
    const WallField f = times.empty() ? read_wall_frame(*saved[i]) : wall_at_time(series, times[i]);
    if (i == 0) {
      out.wall = f.mesh;
    } else if (f.mesh.points.size() != out.wall.points.size() ||
               f.mesh.triangles != out.wall.triangles) {
      throw InputError(fmt::format(
          "{}: the wall at t = {} s is not the mesh of t = {} s: the flow's frames must share "
          "one wall",
          flow_directory, f.time, out.times.front()));
    }
    out.times.push_back(f.time);
    for (int c = 0; c < 3; ++c) {
      std::vector<double>& component = fields.emplace_back(f.wss.size());
      for (size_t v = 0; v < f.wss.size(); ++v) component[v] = f.wss[v][c];
    }
  }
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
