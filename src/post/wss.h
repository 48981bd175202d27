// Wall shear stress on the wall of a volume mesh, from a velocity field.
//
// The wall: the boundary triangles of the chosen tags as a surface of its own (points numbered
// anew, `volume_point` leads back), each triangle with the tetrahedron it bounds.
// Per wall triangle, from that tetrahedron's velocity gradient (P1: constant):
// t = mu (grad u + grad u^T) n and tau = t - (t.n) n (the seed paper's equations 1-2; the
// pressure's part of sigma n is normal and drops out), with n the wall normal pointing into the
// fluid, so that tau points along the flow next to the wall. Per wall point: the area-weighted
// mean of its triangles.
#pragma once

#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"

#include <vector>

namespace vesselmesh::post {

struct WallSurface {
  TriMesh mesh;                   // wall triangles, outward; labels: their tag
  std::vector<int> volume_point;  // per surface point, its point in the volume mesh
  std::vector<int> tet;           // per triangle, the tetrahedron (index into `tetrahedra`) it bounds
};

// `tetrahedra`: the mesh's cells as tetrahedra (mesh::all_tetrahedra). Throws InputError when a
// wall triangle bounds no tetrahedron.
WallSurface extract_wall(const TetMesh& mesh, const std::vector<Tet>& tetrahedra, const std::vector<int>& tags);

// Per wall point, in Pa. `points`: the volume mesh's points in metres; `velocity`: m/s per point;
// `viscosity`: Pa s.
std::vector<Vec3> wall_shear_stress(const WallSurface& wall, const std::vector<Tet>& tetrahedra,
                                    const std::vector<Vec3>& points, const std::vector<Vec3>& velocity,
                                    double viscosity);

}  // namespace vesselmesh::post
