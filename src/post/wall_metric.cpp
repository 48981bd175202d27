#include "post/wall_metric.h"

#include "analysis/normals.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/locator.h"
#include "post/wall_series.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace vesselmesh::post {

namespace {

// Each wall frame the metrics bound (for_bounded_frames), checked to be of the first's mesh, handed
// to `use`; `out_wall` the wall in mm, `out_times` the frames' times.
template <typename Use>
void each_bounded_wall(const WallSeries& series, const std::string& flow_directory, const std::vector<double>& times,
                       TriMesh& out_wall, std::vector<double>& out_times, Use use) {
  if (series.frames.empty())
    throw InputError(fmt::format("{}: the flow saved no wall frame", flow_directory));
  for_bounded_frames(series, times, read_wall_frame, wall_at_time, [&](const WallField& f, bool first) {
    if (first) {
      out_wall = f.mesh;
    } else if (f.mesh.points.size() != out_wall.points.size() || f.mesh.triangles != out_wall.triangles) {
      throw InputError(fmt::format(
          "{}: the wall at t = {} s is not the mesh of t = {} s: the flow's frames must share one wall",
          flow_directory, f.time, out_times.front()));
    }
    out_times.push_back(f.time);
    use(f);
  });
  const double to_mm = series.length_scale / 1e-3;
  for (Vec3& p : out_wall.points) p *= to_mm;
}

}  // namespace

WallMetric wall_error_metric(const std::string& flow_directory, const std::vector<double>& times,
                             const sizing::ErrorMetricOptions& options, const Reporter& reporter) {
  const WallSeries series = read_wall_series(flow_directory);
  WallMetric out;
  std::vector<std::vector<double>> fields;
  each_bounded_wall(series, flow_directory, times, out.wall, out.times,
                    [&](const WallField& f) { append_components(fields, f.wss); });
  reporter.info(fmt::format(
      "the WSS's interpolation error on the flow's wall ({} points) at {} saved time{}, from "
      "{:.4g} to {:.4g} s",
      out.wall.num_points(), out.times.size(), out.times.size() == 1 ? "" : "s", out.times.front(),
      out.times.back()));
  const std::vector<Vec3> normals = analysis::vertex_normals(out.wall);
  out.metric = sizing::error_metric(out.wall, fields, normals, options, reporter);
  return out;
}

WallHeights first_layer_heights(const std::string& flow_directory, const std::vector<double>& times, double y_plus,
                                Fluid fluid, const Reporter& reporter) {
  if (!(y_plus > 0.0 && std::isfinite(y_plus)))
    throw OptionError(fmt::format("a first layer's y+ of {}: give a positive number (1 is the usual)", y_plus));
  const WallSeries series = read_wall_series(flow_directory);
  if (!(fluid.density > 0.0 && fluid.viscosity > 0.0)) fluid = {series.density, series.viscosity};
  if (!(fluid.density > 0.0 && fluid.viscosity > 0.0))
    throw InputError(fmt::format("{}/summary.json names no fluid (density, viscosity), nor a case file that still "
                                 "reads: run its simulate again",
                                 flow_directory));
  WallHeights out;
  out.y_plus = y_plus;
  std::vector<double> largest;  // Pa: each point's largest |WSS| over the frames
  each_bounded_wall(series, flow_directory, times, out.wall, out.times, [&](const WallField& f) {
    largest.resize(f.wss.size(), 0.0);
    for (size_t v = 0; v < f.wss.size(); ++v) largest[v] = std::max(largest[v], f.wss[v].norm());
  });
  // y+ = y u_tau / nu with u_tau = sqrt(|tau| / rho): y = y+ mu / sqrt(rho |tau|), in metres, then mm.
  constexpr double kLeastStress = 1e-12;  // Pa: a point without shear asks for no height
  out.heights.resize(largest.size());
  for (size_t v = 0; v < largest.size(); ++v)
    out.heights[v] = y_plus * fluid.viscosity / std::sqrt(fluid.density * std::max(largest[v], kLeastStress)) / 1e-3;
  const auto least = std::min_element(out.heights.begin(), out.heights.end());
  reporter.info(fmt::format("the first layer's height for y+ = {:g} from the flow's largest wall shear at {} saved "
                            "time{}: {:.4g} mm at the least, near {}",
                            y_plus, out.times.size(), out.times.size() == 1 ? "" : "s", *least,
                            mesh::format_point(out.wall.points[static_cast<size_t>(least - out.heights.begin())])));
  return out;
}

std::function<double(const Vec3&)> height_function(WallHeights heights) {
  struct Field {
    WallHeights h;
    mesh::SurfaceLocator locator;
    explicit Field(WallHeights given) : h(std::move(given)), locator(h.wall) {}
  };
  const auto field = std::make_shared<const Field>(std::move(heights));
  return [field](const Vec3& x) {
    const mesh::SurfaceLocator::Hit hit = field->locator.closest(x);
    return mesh::linear_on_triangle(field->h.wall, hit.triangle, hit.point, field->h.heights);
  };
}

}  // namespace vesselmesh::post
