#include "mesh/self_intersections.h"

#include "mesh/error.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>

namespace vesselmesh::mesh {

std::vector<std::pair<int, int>> self_intersecting_pairs(const TriMesh& mesh) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
  using Face = SurfaceMesh::Face_index;
  using Vertex = SurfaceMesh::Vertex_index;

  SurfaceMesh sm;
  sm.reserve(mesh.points.size(), mesh.triangles.size() * 3 / 2, mesh.triangles.size());
  std::vector<Vertex> vertices;
  vertices.reserve(mesh.points.size());
  for (const Vec3& p : mesh.points) vertices.push_back(sm.add_vertex({p.x(), p.y(), p.z()}));
  std::vector<int> triangle_of_face;  // Surface_mesh face index -> our triangle index
  triangle_of_face.reserve(mesh.triangles.size());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Triangle& f = mesh.triangles[t];
    const Face face = sm.add_face(vertices[f[0]], vertices[f[1]], vertices[f[2]]);
    VM_CHECK(face != SurfaceMesh::null_face(),
             "self-intersection test needs a manifold, oriented surface: clean it first");
    triangle_of_face.push_back(t);
  }
  std::vector<std::pair<Face, Face>> faces;
  CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(faces));
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(faces.size());
  for (const auto& [f, g] : faces) {
    const int s = triangle_of_face[static_cast<size_t>(f)];
    const int t = triangle_of_face[static_cast<size_t>(g)];
    pairs.emplace_back(std::min(s, t), std::max(s, t));
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace vesselmesh::mesh
