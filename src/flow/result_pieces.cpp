#include "flow/result_pieces.h"

#include "mesh/error.h"

namespace vesselmesh::flow {

WallPiece whole_wall(const TetMesh& mesh, const std::vector<int>& wall_tags, const FlowCase& fc) {
  WallPiece w;
  const std::vector<Tet> all = mesh::all_tetrahedra(mesh);
  w.surface = post::extract_wall(mesh, all, wall_tags);
  std::vector<Vec3> si(mesh.points.size());
  for (size_t i = 0; i < si.size(); ++i) si[i] = mesh.points[i] * fc.length_scale;
  w.shear.emplace(w.surface, all, si, post::parse_wss_method(fc.wss_method));
  w.mesh = w.surface.mesh;
  w.surface_point.resize(w.mesh.num_points());
  for (int v = 0; v < w.mesh.num_points(); ++v) w.surface_point[v] = v;
  w.mesh_point = w.surface.volume_point;
  w.owned_points = w.mesh.num_points();
  w.owned_fallbacks = w.shear->face_fallbacks();
  return w;
}

WallPiece distributed_wall(const MeshPart& part, const std::vector<int>& wall_tags, const FlowCase& fc) {
  WallPiece w;
  TetMesh band;
  band.points = part.points;
  band.boundary = part.wall.triangles;
  band.boundary_tags = part.wall.tags;
  w.surface = post::extract_wall(band, part.wall.cells, wall_tags);
  std::vector<Vec3> si(part.points.size());
  for (size_t i = 0; i < si.size(); ++i) si[i] = part.points[i] * fc.length_scale;
  w.shear.emplace(w.surface, part.wall.cells, si, post::parse_wss_method(fc.wss_method));
  // extract_wall keeps the triangles' order: the written ones, their points numbered anew.
  std::vector<int> at(w.surface.mesh.num_points(), -1);
  for (size_t f = 0; f < part.wall.triangles.size(); ++f) {
    if (!part.wall.written[f]) continue;
    Triangle tri = w.surface.mesh.triangles[f];
    for (int& v : tri) {
      if (at[v] < 0) {
        at[v] = w.mesh.num_points();
        w.mesh.points.push_back(w.surface.mesh.points[v]);
        w.surface_point.push_back(v);
        w.mesh_point.push_back(part.mesh_point[w.surface.volume_point[v]]);
      }
      v = at[v];
    }
    w.mesh.triangles.push_back(tri);
    w.mesh.labels.push_back(part.wall.tags[f]);
  }
  for (int v = 0; v < w.surface.mesh.num_points(); ++v)
    if (w.surface.volume_point[v] < part.owned) {
      ++w.owned_points;
      if (w.shear->by_face(v)) ++w.owned_fallbacks;
    }
  return w;
}

FluidPiece own_fluid_piece(const MeshPart& part) {
  FluidPiece piece;
  piece.mesh.tag_names = part.tag_names;
  std::vector<int> at(part.points.size(), -1);
  for (const Tet& t4 : part.tets) {
    int least = t4[0];
    for (int a : t4)
      if (part.local_global[a] < part.local_global[least]) least = a;
    if (least >= part.owned) continue;  // another process's
    Tet cell = t4;
    for (int& a : cell) {
      if (at[a] < 0) {
        at[a] = static_cast<int>(piece.local.size());
        piece.local.push_back(a);
        piece.mesh.points.push_back(part.points[a]);
      }
      a = at[a];
    }
    piece.mesh.tets.push_back(cell);
  }
  return piece;
}

}  // namespace vesselmesh::flow
