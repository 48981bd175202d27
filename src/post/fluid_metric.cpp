#include "post/fluid_metric.h"

#include "mesh/error.h"
#include "mesh/point_graph.h"
#include "post/wall_series.h"
#include "sizing/gradation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

namespace vesselmesh::post {
namespace {

// The integral over the mesh's cells of h^-3, each cell's as the mean of its corners' (a
// count of points up to a constant).
double count_integral(const TetMesh& mesh, const std::vector<Tet>& tets, const std::vector<double>& sizes) {
  double sum = 0.0;
  for (const Tet& t : tets) {
    double density = 0.0;
    for (int v : t) density += std::pow(sizes[v], -3.0);
    sum += std::abs(mesh::tet_volume6(mesh, t)) / 6.0 * density / 4.0;
  }
  return sum;
}

}  // namespace

FluidSizes fluid_error_sizes(const std::string& flow_directory, const std::vector<double>& times, double growth,
                             const sizing::ErrorMetricOptions& options, const Reporter& reporter) {
  const WallSeries series = read_wall_series(flow_directory, "fluid");
  if (series.frames.empty())
    throw InputError(fmt::format("{}: the flow saved no fluid frame (its case's output.fluid_every)", flow_directory));
  FluidSizes out;
  std::vector<std::vector<double>> fields;
  for_bounded_frames(series, times, read_fluid_frame, fluid_at_time, [&](const FluidField& f, bool first) {
    if (first) {
      out.mesh = f.mesh;
    } else if (f.mesh.points.size() != out.mesh.points.size() || f.mesh.tets != out.mesh.tets ||
               f.mesh.prisms != out.mesh.prisms) {
      throw InputError(fmt::format("{}: the fluid at t = {} s is not the mesh of t = {} s: the flow's frames must "
                                   "share one mesh",
                                   flow_directory, f.time, out.times.front()));
    }
    out.times.push_back(f.time);
    append_components(fields, f.velocity);
  });
  const double to_mm = series.length_scale / 1e-3;
  for (Vec3& p : out.mesh.points) p *= to_mm;
  reporter.info(fmt::format("the velocity's interpolation error in the flow's volume ({} points) at {} saved time{}, "
                            "from {:.4g} to {:.4g} s",
                            out.mesh.num_points(), out.times.size(), out.times.size() == 1 ? "" : "s",
                            out.times.front(), out.times.back()));
  const mesh::PointGraph graph = mesh::point_graph(out.mesh.num_points(), out.mesh.tets, out.mesh.prisms);
  out.sizes = sizing::volume_error_sizes(out.mesh.points, graph, fields, options, reporter);
  fields.clear();
  // The flow mesh's own sizes: each point's mean edge length.
  std::vector<double> own(out.mesh.points.size(), 0.0);
  for (int v = 0; v < out.mesh.num_points(); ++v) {
    for (int k = graph.start[v]; k < graph.start[v + 1]; ++k)
      own[v] += (out.mesh.points[graph.next[k]] - out.mesh.points[v]).norm();
    if (graph.degree(v) > 0) own[v] /= graph.degree(v);
  }
  const std::vector<Tet> tets = mesh::all_tetrahedra(out.mesh);
  const double wanted = count_integral(out.mesh, tets, own);
  const auto rescale = [&] {
    const double factor = std::cbrt(count_integral(out.mesh, tets, out.sizes) / wanted);
    for (double& h : out.sizes) h *= factor;
    out.scale *= factor;
  };
  rescale();
  const int lowered = sizing::grade_sizes(out.mesh.points, graph, out.sizes, growth);
  rescale();
  sizing::grade_sizes(out.mesh.points, graph, out.sizes, growth);  // graded last: the count a little over
  const auto [low, high] = std::minmax_element(out.sizes.begin(), out.sizes.end());
  reporter.info(fmt::format("the flow's interior sizes: {:.3g} to {:.3g} mm ({} of {} points lowered by the grading)",
                            *low, *high, lowered, out.sizes.size()));
  return out;
}

FluidSizeField::FluidSizeField(FluidSizes sizes) : sizes_(std::move(sizes)), locator_(sizes_.mesh) {
  VM_CHECK(sizes_.sizes.size() == sizes_.mesh.points.size(), "FluidSizeField: one size per point");
}

double FluidSizeField::at(const Vec3& x) const {
  const std::optional<TetLocator::Hit> hit = locator_.locate(x);
  if (!hit) return 0.0;
  const Tet& t = locator_.tets()[hit->tet];
  double h = 0.0;
  for (int k = 0; k < 4; ++k) h += std::max(hit->weights[k], 0.0) * sizes_.sizes[t[k]];
  double sum = 0.0;
  for (double w : hit->weights) sum += std::max(w, 0.0);
  return sum > 0.0 ? h / sum : 0.0;
}

std::function<double(const Vec3&)> size_function(FluidSizes sizes) {
  auto field = std::make_shared<const FluidSizeField>(std::move(sizes));
  return [field](const Vec3& x) { return field->at(x); };
}

}  // namespace vesselmesh::post
