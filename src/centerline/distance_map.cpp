#include "centerline/distance_map.h"

#include "analysis/open_ends.h"
#include "centerline/voronoi.h"
#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/locator.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vesselmesh::centerline {

DistanceMap distance_map(const TriMesh& surface, const Centerlines& centerlines) {
  std::vector<std::array<Vec3, 2>> segments;
  std::vector<std::array<double, 2>> radii;
  for (const Branch& b : centerlines.branches)
    for (size_t i = 0; i + 1 < b.points.size(); ++i) {
      segments.push_back({b.points[i], b.points[i + 1]});
      radii.push_back({b.radius[i], b.radius[i + 1]});
    }
  VM_CHECK(!segments.empty(), "a distance map needs centerline segments");
  const mesh::SegmentLocator locator(segments);
  DistanceMap map;
  map.distance.resize(surface.points.size());
  map.radius.resize(surface.points.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, surface.num_points(), 1024), [&](const tbb::blocked_range<int>& range) {
    for (int v = range.begin(); v < range.end(); ++v) {
      const mesh::SegmentLocator::Hit hit = locator.closest(surface.points[v]);
      map.distance[v] = hit.distance;
      map.radius[v] = (1.0 - hit.t) * radii[hit.segment][0] + hit.t * radii[hit.segment][1];
    }
  });
  return map;
}

std::vector<double> pole_radius(const TriMesh& surface, const Reporter& reporter) {
  const mesh::InsideTest inside(analysis::fan_capped(surface, analysis::open_ends(surface)));
  std::vector<double> radius = internal_voronoi(surface, inside, reporter).pole_radius;
  std::vector<double> found;
  for (double r : radius)
    if (r > 0.0) found.push_back(r);
  if (found.empty()) throw InputError("no Voronoi vertex lies inside the surface: is it a closed lumen?");
  std::nth_element(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(found.size() / 2), found.end());
  const double median = found[found.size() / 2];
  for (double& r : radius)
    if (!(r > 0.0)) r = median;
  // A point's pole ball is the vessel's only where its Voronoi cell reaches the medial axis;
  // many stop short (measured on the VMTK aorta: median 4.2 mm against the distance map's 5.5,
  // 18 % apart across an edge). The largest over two rings of triangles, then five passes of
  // averaging over one, agree with the distance map (median 5.7, 5th percentile 4.16 against
  // 4.15, 1.2 % across an edge against 0.7 %).
  const mesh::VertexTriangles around = mesh::build_vertex_triangles(surface);
  auto pass = [&](bool largest) {
    std::vector<double> next(radius.size());
    for (int v = 0; v < surface.num_points(); ++v) {
      double sum = 0.0, most = radius[v];
      int count = 0;
      for (int t : around.of(v))
        for (int w : surface.triangles[t]) sum += radius[w], most = std::max(most, radius[w]), ++count;
      next[v] = largest ? most : count > 0 ? sum / count : radius[v];
    }
    radius = std::move(next);
  };
  for (int k = 0; k < 2; ++k) pass(true);
  for (int k = 0; k < 5; ++k) pass(false);
  return radius;
}

}  // namespace vesselmesh::centerline
