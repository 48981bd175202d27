#include "study/envelope.h"

#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/locator.h"
#include "sizing/gradation.h"
#include "sizing/metric.h"
#include "sizing/size_field.h"
#include "study/wall_difference.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <memory>
#include <cmath>
#include <limits>

namespace vesselmesh::study {

double triangle_size(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double twice_area = (b - a).cross(c - a).norm();
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  if (!(longest > 0.0)) return 0.0;
  return 2.0 / std::sqrt(3.0) * twice_area / longest;  // the shortest altitude: 2 A / the longest side
}

std::vector<double> achieved_sizes(const TriMesh& mesh) {
  std::vector<double> sum(mesh.points.size(), 0.0);
  std::vector<int> count(mesh.points.size(), 0);
  for (const Triangle& f : mesh.triangles) {
    const double s = triangle_size(mesh.points[f[0]], mesh.points[f[1]], mesh.points[f[2]]);
    for (int v : f) {
      sum[v] += s;
      ++count[v];
    }
  }
  for (size_t v = 0; v < sum.size(); ++v) sum[v] = count[v] > 0 ? sum[v] / count[v] : 0.0;
  return sum;
}

std::vector<double> field_on(const TriMesh& input, const TriMesh& mesh, const std::vector<double>& values) {
  const mesh::SurfaceLocator on_mesh(mesh);
  std::vector<double> there(input.points.size());
  tbb::parallel_for(size_t{0}, input.points.size(), [&](size_t v) {
    const mesh::SurfaceLocator::Hit hit = on_mesh.closest(input.points[v]);
    there[v] = vesselmesh::mesh::linear_on_triangle(mesh, hit.triangle, hit.point, values);
  });
  return there;
}

std::vector<double> sizes_on(const TriMesh& input, const TriMesh& mesh) {
  return field_on(input, mesh, achieved_sizes(mesh));
}

double envelope_interior_factor(const TriMesh& input, const std::vector<const TriMesh*>& meshes,
                                const std::vector<double>& factors, const std::vector<double>& envelope) {
  VM_CHECK(meshes.size() == factors.size() && envelope.size() == input.points.size(),
           "envelope_interior_factor: a factor per mesh, a size per input point");
  std::vector<double> finest(input.points.size(), std::numeric_limits<double>::infinity());
  for (size_t m = 0; m < meshes.size(); ++m) {
    const std::vector<double> there = field_on(input, *meshes[m], volume::area_equivalent_sizes(*meshes[m]));
    for (size_t v = 0; v < finest.size(); ++v) finest[v] = std::min(finest[v], factors[m] * there[v]);
  }
  std::vector<double> ratio;
  for (size_t v = 0; v < finest.size(); ++v)
    if (envelope[v] > 0.0 && std::isfinite(finest[v])) ratio.push_back(finest[v] / envelope[v]);
  if (ratio.empty()) return 1.0;
  const size_t k = ratio.size() / 10;
  std::nth_element(ratio.begin(), ratio.begin() + static_cast<long>(k), ratio.end());
  return ratio[k];
}

std::vector<double> envelope_sizes(const TriMesh& input, const std::vector<const TriMesh*>& meshes,
                                   double gradation) {
  if (meshes.empty()) throw InputError("envelope sizes: no compared mesh to take the sizes of");
  std::vector<double> size(input.points.size(), std::numeric_limits<double>::infinity());
  const mesh::SurfaceLocator on_input(input);
  for (const TriMesh* m : meshes) {
    const std::vector<double> there = sizes_on(input, *m);
    for (size_t v = 0; v < size.size(); ++v) size[v] = std::min(size[v], there[v]);
    // A finer point of the mesh inside an input triangle lowers that triangle's corners: an input
    // coarser than the mesh does not hide its small sizes.
    const std::vector<double> achieved = achieved_sizes(*m);
    std::vector<int> triangle_of(m->points.size(), -1);
    tbb::parallel_for(size_t{0}, m->points.size(), [&](size_t p) {
      if (achieved[p] > 0.0) triangle_of[p] = on_input.closest(m->points[p]).triangle;
    });
    for (size_t p = 0; p < triangle_of.size(); ++p)
      if (triangle_of[p] >= 0)
        for (int v : input.triangles[triangle_of[p]]) size[v] = std::min(size[v], achieved[p]);
  }
  for (size_t v = 0; v < size.size(); ++v)
    VM_CHECK(std::isfinite(size[v]) && size[v] > 0.0, "envelope size of input point " + std::to_string(v));
  sizing::grade_sizes(input, size, gradation);
  return size;
}

std::vector<double> calibrated_sizes(const TriMesh& input, const std::vector<double>& asked,
                                     const std::vector<double>& target, const TriMesh& made, double gradation) {
  VM_CHECK(asked.size() == input.points.size() && target.size() == input.points.size(),
           "calibrated_sizes: one size per input point");
  const std::vector<double> achieved = sizes_on(input, made);
  std::vector<double> next(asked.size());
  for (size_t v = 0; v < next.size(); ++v)
    next[v] = achieved[v] > 0.0 ? asked[v] * std::clamp(target[v] / achieved[v], 2.0 / 3.0, 1.5) : asked[v];
  sizing::grade_sizes(input, next, gradation);
  return next;
}

remesh::RemeshResult remesh_level(const TriMesh& input, const std::vector<double>& target,
                                  const remesh::RemeshOptions& options, double& predicted, const Reporter& reporter) {
  const auto metric_of = [](const std::vector<double>& sizes) {
    std::vector<Sym3> metric(sizes.size());
    for (size_t v = 0; v < metric.size(); ++v) metric[v] = sizing::isotropic_metric(sizes[v]);
    return metric;
  };
  const std::vector<Sym3> asked = metric_of(target);
  predicted = sizing::predicted_triangles(input, asked);
  reporter.info(fmt::format("study: the level's sizes predict about {:.0f} triangles", predicted));
  const remesh::RemeshResult first = remesh::adapt(input, asked, options, reporter);
  std::vector<double> sizes = calibrated_sizes(input, target, target, first.mesh);
  remesh::RemeshResult made = remesh::adapt(input, metric_of(sizes), options, reporter);
  const double count = static_cast<double>(made.mesh.num_triangles());
  if (count < (1.0 - kLevelCountShortfall) * predicted) {
    reporter.info(fmt::format("study: the level made {:.0f} triangles, {:.1f} % short: its sizes times {:.3f}", count,
                              100.0 * (1.0 - count / predicted), std::sqrt(count / predicted)));
    for (double& s : sizes) s *= std::sqrt(count / predicted);
    made = remesh::adapt(input, metric_of(sizes), options, reporter);
  }
  return made;
}

double envelope_level_scale(double factor, int level, int levels) {
  return kEnvelopeMargin * std::pow(factor, levels >= 3 ? level - 1 : level);
}

LevelLayers level_layers(int layers, double scale) {
  LevelLayers out;
  if (layers <= 0) return out;
  const double wanted = layers * scale;  // thickness / the first height asked for
  out.layers = std::max(layers, static_cast<int>(std::floor(wanted + 1e-9)));
  // 1 + g + ... + g^(n-1) = wanted, with g >= 1 (the sum is n at g = 1, <= wanted).
  const auto sum = [&](double g) {
    double s = 0.0, power = 1.0;
    for (int k = 0; k < out.layers; ++k, power *= g) s += power;
    return s;
  };
  double low = 1.0, high = 2.0;
  while (sum(high) < wanted) high *= 2.0;
  for (int i = 0; i < 100 && high - low > 1e-14; ++i) (sum(0.5 * (low + high)) < wanted ? low : high) = 0.5 * (low + high);
  out.growth = sum(low) >= wanted - 1e-12 ? low : high;
  if (out.growth > kMostLayerGrowth + 1e-9) out = {static_cast<int>(std::ceil(wanted - 1e-9)), 1.0};
  return out;
}

volume::InteriorSizeOptions level_interior(const volume::InteriorSizeOptions& compared, double factor,
                                           double scale, const std::function<double(const Vec3&)>& flow) {
  volume::InteriorSizeOptions o = compared;
  o.factor = factor;
  o.gradation = std::pow(compared.gradation, 1.0 / scale);
  o.core_fraction = compared.core_fraction / scale;
  if (flow) {  // the field is factor x min(..., flow / (scale x factor)): the flow kinds' sizes / scale
    o.flow = [flow, divisor = scale * factor](const Vec3& x) { return flow(x) / divisor; };
    o.flow_keeps_core = true;
  }
  return o;
}

std::function<double(const Vec3&)> least_flow_interior(std::vector<post::FluidSizes> sizes,
                                                       const std::vector<double>& factors) {
  VM_CHECK(sizes.size() == factors.size(), "least_flow_interior: a factor per flow");
  std::vector<std::shared_ptr<const post::FluidSizeField>> fields;
  for (post::FluidSizes& s : sizes) fields.push_back(std::make_shared<const post::FluidSizeField>(std::move(s)));
  return [fields, factors](const Vec3& x) {
    double least = 0.0;
    for (size_t k = 0; k < fields.size(); ++k)
      if (const double h = factors[k] * fields[k]->at(x); h > 0.0) least = least > 0.0 ? std::min(least, h) : h;
    return least;
  };
}

std::function<double(const Vec3&)> level_first_height(const std::vector<post::WallHeights>& flows, double scale) {
  if (flows.empty()) return nullptr;
  std::vector<std::function<double(const Vec3&)>> heights;
  for (const post::WallHeights& h : flows) heights.push_back(post::height_function(h));
  return [heights, scale](const Vec3& x) {
    double least = std::numeric_limits<double>::infinity();
    for (const auto& h : heights) least = std::min(least, h(x));
    return least / scale;
  };
}

}  // namespace vesselmesh::study
