#include "centerline/distance_map.h"

#include "mesh/error.h"
#include "mesh/locator.h"

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

}  // namespace vesselmesh::centerline
