// Wall shear stress on the wall of a volume mesh, from a velocity field.
//
// The wall: the boundary triangles of the chosen tags as a surface of its own (points numbered
// anew, `volume_point` leads back), each triangle with the tetrahedron it bounds.
// t = mu (grad u + grad u^T) n and tau = t - (t.n) n (the seed paper's equations 1-2; the
// pressure's part of sigma n is normal and drops out), with n the wall normal pointing into the
// fluid, so that tau points along the flow next to the wall. Two ways to the gradient at a wall
// point:
// - quadratic (the default): a weighted least-squares quadratic through the point's value and
//   the velocities at the points within two edges of it in the volume mesh (its 2-ring), its
//   gradient at the point; n the area-weighted mean of its triangles' normals. Exact for a
//   quadratic field (Poiseuille), second order on smooth ones, and it reads the layers below
//   the first, where the P1 gradient of a first-layer cell is the gradient half a layer in
//   (first order: h / 2R too low on Poiseuille). A point whose 2-ring does not fix a quadratic
//   (fewer than 9 well-spread points) takes the face value.
// - face: per wall triangle, the P1 (constant) gradient of the tetrahedron it bounds with the
//   triangle's normal; per point the area-weighted mean of its triangles' values.
// The map from velocity to stress is linear: `WallShearOperator` builds it once for a mesh and
// applies it at every step.
#pragma once

#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"

#include <array>
#include <string>
#include <vector>

namespace vesselmesh::post {

// The wall: its triangles (outward; labels their tag), each point's volume point, each triangle's
// tetrahedron (mesh::boundary_part).
using WallSurface = mesh::BoundaryPart;

// `tetrahedra`: the mesh's cells as tetrahedra (mesh::all_tetrahedra). Throws InputError when a
// wall triangle bounds no tetrahedron.
inline WallSurface extract_wall(const TetMesh& mesh, const std::vector<Tet>& tetrahedra, const std::vector<int>& tags) {
  return mesh::boundary_part(mesh, tetrahedra, tags);
}

enum class WssMethod { quadratic, face };

// "quadratic" / "face"; parse throws InputError naming the choices.
const char* to_string(WssMethod method);
WssMethod parse_wss_method(const std::string& text);

// `points`: the volume mesh's points (metres, for stresses in Pa); `tetrahedra`: its cells as
// tetrahedra. Keeps no reference to its arguments.
class WallShearOperator {
 public:
  WallShearOperator(const WallSurface& wall, const std::vector<Tet>& tetrahedra, const std::vector<Vec3>& points,
                    WssMethod method = WssMethod::quadratic);

  // Per wall point, in Pa. `velocity`: m/s per volume point; `viscosity`: Pa s.
  std::vector<Vec3> apply(const std::vector<Vec3>& velocity, double viscosity) const;

  WssMethod method() const { return method_; }
  // Wall points that took the face value because their 2-ring does not fix a quadratic.
  int face_fallbacks() const { return fallbacks_; }
  // Whether wall point `v` takes the face value (the face method, or a fallback).
  bool by_face(int v) const {
    return method_ == WssMethod::face || offset_.empty() || offset_[v] == offset_[v + 1];
  }

 private:
  struct Face {
    std::array<int, 4> tet;        // volume points
    std::array<Vec3, 4> gradient;  // of the tetrahedron's barycentric coordinates
    Vec3 normal;                   // into the fluid
    double area;
  };
  WssMethod method_;
  int fallbacks_ = 0;
  std::vector<int> volume_point_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Face> faces_;
  // Quadratic: per wall point, its stencil [offset_[v], offset_[v + 1]) of volume points and
  // weights (grad u = sum_j (u_j - u_v) weight_j^T) and its normal; an empty stencil: face value.
  std::vector<int> offset_;
  std::vector<int> stencil_point_;
  std::vector<Vec3> stencil_weight_;
  std::vector<Vec3> normal_;
};

// One application of a fresh operator.
std::vector<Vec3> wall_shear_stress(const WallSurface& wall, const std::vector<Tet>& tetrahedra,
                                    const std::vector<Vec3>& points, const std::vector<Vec3>& velocity,
                                    double viscosity, WssMethod method = WssMethod::quadratic);

}  // namespace vesselmesh::post
