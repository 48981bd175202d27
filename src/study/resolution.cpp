#include "study/resolution.h"

#include "study/envelope.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vesselmesh::study {
namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// The mean of the values whose sites lie within `reach` of x, or the nearest site's value when
// none does (NaN values left out).
double mean_near(const std::vector<Vec3>& sites, const std::vector<double>& values, const Vec3& x, double reach) {
  double sum = 0.0, nearest = std::numeric_limits<double>::infinity(), nearest_value = kNone;
  int count = 0;
  for (size_t i = 0; i < sites.size(); ++i) {
    if (std::isnan(values[i])) continue;
    const double d = (sites[i] - x).squaredNorm();
    if (d <= reach * reach) {
      sum += values[i];
      ++count;
    }
    if (d < nearest) {
      nearest = d;
      nearest_value = values[i];
    }
  }
  return count > 0 ? sum / count : nearest_value;
}

}  // namespace

std::vector<double> first_heights(const TetMesh& volume) {
  int wall_tag = -1;
  for (const auto& [tag, name] : volume.tag_names)
    if (name == "wall") wall_tag = tag;
  const size_t n = volume.points.size();
  std::vector<Vec3> normal(n, Vec3::Zero());
  std::vector<char> on_boundary(n, 0);
  for (size_t t = 0; t < volume.boundary.size(); ++t) {
    const Triangle& f = volume.boundary[t];
    for (int v : f) on_boundary[v] = 1;
    if (volume.boundary_tags[t] != wall_tag) continue;
    const Vec3 a = (volume.points[f[1]] - volume.points[f[0]]).cross(volume.points[f[2]] - volume.points[f[0]]);
    for (int v : f) normal[v] += a;
  }
  std::vector<double> height(n, kNone), along(n, -1.0);  // along: the chosen edge's |cosine| to n
  const auto edge = [&](int a, int b) {
    if (on_boundary[b] || normal[a].squaredNorm() == 0.0) return;
    const Vec3 e = volume.points[b] - volume.points[a];
    const double h = std::abs(e.dot(normal[a].normalized())), cosine = h / e.norm();
    if (cosine > along[a]) along[a] = cosine, height[a] = h;
  };
  const auto cell = [&](const auto& c) {
    for (size_t i = 0; i < c.size(); ++i)
      for (size_t j = 0; j < c.size(); ++j)
        if (i != j) edge(c[i], c[j]);
  };
  for (const Tet& t : volume.tets) cell(t);
  for (const Prism& p : volume.prisms) cell(p);
  return height;
}

std::vector<PlaceResolution> measure_resolution(const TriMesh& wall, const TetMesh& volume,
                                                const std::vector<Place>& places, const ResolutionOptions& options) {
  // The sites and values of the three measures.
  std::vector<Vec3> triangle_sites(wall.triangles.size());
  std::vector<double> triangle_sizes(wall.triangles.size());
  for (size_t t = 0; t < wall.triangles.size(); ++t) {
    const Triangle& f = wall.triangles[t];
    triangle_sites[t] = (wall.points[f[0]] + wall.points[f[1]] + wall.points[f[2]]) / 3.0;
    triangle_sizes[t] = triangle_size(wall.points[f[0]], wall.points[f[1]], wall.points[f[2]]);
  }
  const std::vector<double> heights = first_heights(volume);
  std::vector<Vec3> cell_sites(volume.tets.size() + volume.prisms.size());
  std::vector<double> cell_edges(cell_sites.size());
  const auto describe = [&](const auto& c, size_t at) {
    Vec3 centre = Vec3::Zero();
    double sum = 0.0;
    int edges = 0;
    for (size_t i = 0; i < c.size(); ++i) {
      centre += volume.points[c[i]];
      for (size_t j = i + 1; j < c.size(); ++j, ++edges) sum += (volume.points[c[j]] - volume.points[c[i]]).norm();
    }
    cell_sites[at] = centre / static_cast<double>(c.size());
    cell_edges[at] = sum / edges;  // a prism's diagonals too: it stands for its three tetrahedra
  };
  tbb::parallel_for(size_t{0}, volume.tets.size(), [&](size_t t) { describe(volume.tets[t], t); });
  tbb::parallel_for(size_t{0}, volume.prisms.size(),
                    [&](size_t p) { describe(volume.prisms[p], volume.tets.size() + p); });

  std::vector<PlaceResolution> out(places.size());
  for (size_t k = 0; k < places.size(); ++k) {
    const Place& place = places[k];
    const size_t n = place.positions.size();
    PlaceResolution& r = out[k];
    r.surface.assign(n, kNone);
    r.first_height.assign(n, kNone);
    r.interior.assign(n, kNone);
    tbb::parallel_for(size_t{0}, n, [&](size_t i) {
      const Vec3& x = place.positions[i];
      const double radius = place.radius[i];
      r.surface[i] = mean_near(triangle_sites, triangle_sizes, x, options.reach * radius);
      r.first_height[i] = mean_near(volume.points, heights, x, options.reach * radius);
      r.interior[i] = mean_near(cell_sites, cell_edges, x + options.depth * radius * place.inward[i],
                                options.depth_reach * radius);
    });
  }
  return out;
}

double mean_of(const std::vector<double>& values) {
  double sum = 0.0;
  int count = 0;
  for (double v : values)
    if (!std::isnan(v)) {
      sum += v;
      ++count;
    }
  return count > 0 ? sum / count : kNone;
}

double least_ratio(const std::vector<double>& coarse, const std::vector<double>& fine) {
  double least = kNone;
  for (size_t i = 0; i < std::min(coarse.size(), fine.size()); ++i) {
    if (!(fine[i] > 0.0) || std::isnan(coarse[i])) continue;
    const double ratio = coarse[i] / fine[i];
    if (std::isnan(least) || ratio < least) least = ratio;
  }
  return least;
}

}  // namespace vesselmesh::study
