#include "synth/plane_cut.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>

namespace vesselmesh::synth {

TriMesh cut_by_plane(const TriMesh& input, const CutPlane& plane, double snap,
                     const std::function<Vec3(const Vec3&)>& move_onto_plane) {
  TriMesh mesh = input;
  const int np = mesh.num_points();
  constexpr double kFar = -std::numeric_limits<double>::infinity();  // out of reach: kept
  std::vector<double> side(np, kFar);
  for (int v = 0; v < np; ++v) {
    const Vec3 d = mesh.points[v] - plane.point;
    const double s = d.dot(plane.normal);
    if ((d - s * plane.normal).norm() > plane.reach) continue;
    if (std::abs(s) < snap) {
      mesh.points[v] = move_onto_plane(mesh.points[v]);
      side[v] = 0.0;
    } else {
      side[v] = s;
    }
  }
  std::map<std::pair<int, int>, int> crossing;  // edge -> new point on the plane
  auto cross_point = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto found = crossing.find(key);
    if (found != crossing.end()) return found->second;
    const double t = side[a] / (side[a] - side[b]);
    const int index = mesh.num_points();
    mesh.points.push_back(mesh.points[a] + t * (mesh.points[b] - mesh.points[a]));
    crossing.emplace(key, index);
    return index;
  };
  TriMesh out;
  for (int t = 0; t < input.num_triangles(); ++t) {
    const Triangle& f = input.triangles[t];
    int beyond = 0, within = 0;
    for (int v : f) beyond += side[v] > 0.0, within += side[v] < 0.0;
    if (beyond == 0) {
      out.triangles.push_back(f);
    } else if (within > 0) {
      for (int v : f)
        if (side[v] == kFar)
          throw OptionError(fmt::format("cannot cut the end at ({:.4g}, {:.4g}, {:.4g}): another part of the "
                                        "surface comes too close to it",
                                        plane.point.x(), plane.point.y(), plane.point.z()));
      std::vector<int> polygon;  // the triangle clipped to the kept side
      for (int i = 0; i < 3; ++i) {
        const int a = f[i], b = f[(i + 1) % 3];
        if (side[a] <= 0.0) polygon.push_back(a);
        if ((side[a] < 0.0 && side[b] > 0.0) || (side[a] > 0.0 && side[b] < 0.0)) polygon.push_back(cross_point(a, b));
      }
      if (polygon.size() == 3) {
        out.triangles.push_back({polygon[0], polygon[1], polygon[2]});
      } else if (polygon.size() == 4) {  // split along the shorter diagonal
        const double d02 = (mesh.points[polygon[0]] - mesh.points[polygon[2]]).squaredNorm();
        const double d13 = (mesh.points[polygon[1]] - mesh.points[polygon[3]]).squaredNorm();
        if (d02 <= d13) {
          out.triangles.push_back({polygon[0], polygon[1], polygon[2]});
          out.triangles.push_back({polygon[0], polygon[2], polygon[3]});
        } else {
          out.triangles.push_back({polygon[0], polygon[1], polygon[3]});
          out.triangles.push_back({polygon[1], polygon[2], polygon[3]});
        }
      }
    }
    if (input.has_labels()) out.labels.resize(out.triangles.size(), input.labels[t]);
  }
  // Keep only the points still used, in order.
  std::vector<int> remap(mesh.points.size(), -1);
  for (const Triangle& f : out.triangles)
    for (int v : f) remap[v] = 0;
  for (size_t v = 0; v < mesh.points.size(); ++v)
    if (remap[v] == 0) remap[v] = out.num_points(), out.points.push_back(mesh.points[v]);
  for (Triangle& f : out.triangles)
    for (int& v : f) v = remap[v];
  return out;
}

}  // namespace vesselmesh::synth
