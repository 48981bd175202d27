// Volume mesh data: the tetrahedra (and, on request, the prisms of a boundary layer) of a
// lumen, with its boundary triangles tagged by name for the solver.
//
// Tetrahedra have positive volume: (b - a) x (c - a) . (d - a) > 0. Prisms (a, b, c, a', b', c')
// have their first triangle on the wall, oriented outward (away from a', b', c'), and a' above a;
// this is VTK's wedge order. Boundary triangles are oriented outward (right-hand rule).
// Tags: `boundary_tags[i]` names boundary triangle i through `tag_names` (`wall`, `inlet`,
// `outlet_1`, ...); the fluid has one volume tag. Per cell, `layer` is the boundary-layer
// level counted from the wall (1 .. N) or 0 in the interior, and `column` the wall triangle
// the layer cell stands on (-1 in the interior); both empty when unknown (a mesh read back
// from a foreign file).
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace vesselmesh {

using Tet = std::array<int, 4>;
using Prism = std::array<int, 6>;

struct TetMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  std::vector<Prism> prisms;  // empty unless the layer keeps its prisms
  std::vector<int> tet_layer, tet_column;
  std::vector<int> prism_layer, prism_column;
  std::vector<Triangle> boundary;
  std::vector<int> boundary_tags;
  std::map<int, std::string> tag_names;
  int volume_tag = 1;
  std::string volume_name = "fluid";

  int num_points() const { return static_cast<int>(points.size()); }
  int num_tets() const { return static_cast<int>(tets.size()); }
  int num_prisms() const { return static_cast<int>(prisms.size()); }
  int num_cells() const { return num_tets() + num_prisms(); }
  bool has_layers() const { return !tet_layer.empty() || !prism_layer.empty(); }
};

namespace mesh {

// Six times the signed volume of tetrahedron (a, b, c, d).
inline double tet_volume6(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}
inline double tet_volume6(const TetMesh& m, const Tet& t) {
  return tet_volume6(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
}

// The three tetrahedra of prism (a, b, c, a', b', c') (TetMesh order): each quadrilateral side
// is cut along the diagonal through its vertex of least global index, so that two prisms
// sharing a side cut it alike (Dompierre, Labbe, Vallet, Camarero, "How to subdivide pyramids,
// prisms and hexahedra into tetrahedra", IMR 1999). Oriented positively for a valid prism.
std::array<Tet, 3> split_prism(const Prism& p);

// The gradients of the four barycentric (P1 shape) functions of tetrahedron (a, b, c, d), and
// six times its signed volume in `volume6`; the gradients are meaningless when it is 0.
inline std::array<Vec3, 4> barycentric_gradients(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                                 double& volume6) {
  const Vec3 d1 = b - a, d2 = c - a, d3 = d - a;
  volume6 = d1.cross(d2).dot(d3);
  // Rows of the inverse Jacobian are the gradients of the functions of b, c and d.
  const Vec3 g1 = d2.cross(d3) / volume6, g2 = d3.cross(d1) / volume6, g3 = d1.cross(d2) / volume6;
  return {-(g1 + g2 + g3), g1, g2, g3};
}

// The six dihedral angles of a tetrahedron, in radians.
std::array<double, 6> dihedral_angles(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// The least of them (one arc cosine instead of six).
double least_dihedral_angle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The scaled Jacobian of a tetrahedron: its signed volume divided by the largest product of
// the three edge lengths at a corner, times sqrt(2); 1 for the regular tetrahedron, <= 0 when
// inverted or flat.
double scaled_jacobian(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The name of a boundary tag that has none: "tag_<tag>" (every reader and the solver use it).
std::string unnamed_tag(int tag);
// Every boundary tag's name: `tag_names`, with unnamed_tag() for the tags it lacks.
std::map<int, std::string> boundary_tag_names(const TetMesh& m);

// A triangle's corners rotated so that the least comes first (its orientation kept): one
// spelling per oriented triangle, for comparing faces.
Triangle canonical_rotation(const Triangle& f);

// The boundary faces of a set of tetrahedra: faces used by one tetrahedron, oriented outward,
// in canonical rotation, sorted. Faces used by more than two tetrahedra are counted in `nonmanifold`.
std::vector<Triangle> tet_boundary(const std::vector<Tet>& tets, int* nonmanifold = nullptr);

// The same prism with both triangles reversed: TetMesh's order (the first triangle facing away
// from the second) to Gmsh's and Medit's (facing it), and back.
inline Prism flipped_prism(const Prism& p) { return {p[0], p[2], p[1], p[3], p[5], p[4]}; }

// The boundary triangles with one of `tags`, as a surface of their own (`mesh`: its points
// renumbered in the order the triangles first use them, labels the tags), each point's point in
// the volume (`volume_point`) and each triangle's tetrahedron (`tet`, an index into `tetrahedra`:
// the mesh's cells as tetrahedra, all_tetrahedra). Throws InputError when a triangle bounds none.
struct BoundaryPart {
  TriMesh mesh;
  std::vector<int> volume_point;
  std::vector<int> tet;
};
BoundaryPart boundary_part(const TetMesh& mesh, const std::vector<Tet>& tetrahedra, const std::vector<int>& tags);

// Every cell as tetrahedra: the tetrahedra, then each prism's three (split_prism).
std::vector<Tet> all_tetrahedra(const TetMesh& m);

// How the tagged boundary triangles compare with the faces used by one cell (`all`: the
// cells as tetrahedra): faces no triangle tags, triangles that are no such face (or face the
// wrong way), and faces shared by more than two cells.
struct BoundaryClosure {
  int open_faces = 0, stray_triangles = 0, nonmanifold = 0;
  bool closed() const { return open_faces == 0 && stray_triangles == 0 && nonmanifold == 0; }
};
BoundaryClosure boundary_closure(const TetMesh& m, const std::vector<Tet>& all);

}  // namespace mesh
}  // namespace vesselmesh
