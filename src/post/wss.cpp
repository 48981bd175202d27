#include "post/wss.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace vesselmesh::post {

WallSurface extract_wall(const TetMesh& mesh, const std::vector<Tet>& tetrahedra, const std::vector<int>& tags) {
  WallSurface wall;
  std::map<std::array<int, 3>, int> face_of;  // sorted corners -> wall triangle
  std::vector<int> renumber(mesh.points.size(), -1);
  for (size_t f = 0; f < mesh.boundary.size(); ++f) {
    if (std::find(tags.begin(), tags.end(), mesh.boundary_tags[f]) == tags.end()) continue;
    Triangle tri = mesh.boundary[f];
    std::array<int, 3> key = tri;
    std::sort(key.begin(), key.end());
    face_of[key] = static_cast<int>(wall.mesh.triangles.size());
    for (int& v : tri) {
      if (renumber[v] < 0) {
        renumber[v] = static_cast<int>(wall.mesh.points.size());
        wall.mesh.points.push_back(mesh.points[v]);
        wall.volume_point.push_back(v);
      }
      v = renumber[v];
    }
    wall.mesh.triangles.push_back(tri);
    wall.mesh.labels.push_back(mesh.boundary_tags[f]);
  }
  wall.tet.assign(wall.mesh.triangles.size(), -1);
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (size_t e = 0; e < tetrahedra.size(); ++e)
    for (const auto& face : kFaces) {
      std::array<int, 3> key = {tetrahedra[e][face[0]], tetrahedra[e][face[1]], tetrahedra[e][face[2]]};
      std::sort(key.begin(), key.end());
      const auto it = face_of.find(key);
      if (it != face_of.end()) wall.tet[it->second] = static_cast<int>(e);
    }
  for (size_t f = 0; f < wall.tet.size(); ++f)
    if (wall.tet[f] < 0) {
      const Vec3& p = wall.mesh.points[wall.mesh.triangles[f][0]];
      throw InputError(fmt::format("wall triangle {} (at ({:.4g}, {:.4g}, {:.4g})) bounds no cell of the mesh", f,
                                   p.x(), p.y(), p.z()));
    }
  return wall;
}

std::vector<Vec3> wall_shear_stress(const WallSurface& wall, const std::vector<Tet>& tetrahedra,
                                    const std::vector<Vec3>& points, const std::vector<Vec3>& velocity,
                                    double viscosity) {
  std::vector<Vec3> sum(wall.mesh.points.size(), Vec3::Zero());
  std::vector<double> weight(wall.mesh.points.size(), 0.0);
  for (size_t f = 0; f < wall.mesh.triangles.size(); ++f) {
    const Triangle& tri = wall.mesh.triangles[f];
    const Vec3& a = points[wall.volume_point[tri[0]]];
    const Vec3 area2 = (points[wall.volume_point[tri[1]]] - a).cross(points[wall.volume_point[tri[2]]] - a);
    const double area = 0.5 * area2.norm();
    if (!(area > 0.0)) continue;
    const Vec3 n = -area2.normalized();  // into the fluid
    const Tet& t = tetrahedra[wall.tet[f]];
    double v6 = 0.0;
    const std::array<Vec3, 4> g = mesh::barycentric_gradients(points[t[0]], points[t[1]], points[t[2]], points[t[3]], v6);
    Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();  // grad(i, j) = d u_i / d x_j
    for (int k = 0; k < 4; ++k) grad += velocity[t[k]] * g[k].transpose();
    const Vec3 traction = viscosity * (grad + grad.transpose()) * n;
    const Vec3 tau = traction - traction.dot(n) * n;
    for (int v : tri) {
      sum[v] += area * tau;
      weight[v] += area;
    }
  }
  for (size_t v = 0; v < sum.size(); ++v)
    if (weight[v] > 0.0) sum[v] /= weight[v];
  return sum;
}

}  // namespace vesselmesh::post
