#include "mesh/tetmesh.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <numbers>

namespace vesselmesh::mesh {

std::array<Tet, 3> split_prism(const Prism& p) {
  // Vertical edge i joins bottom p[i] to top p[i + 3]. Lifting the bottom triangle to the top
  // one edge at a time in the order (i, j, k) gives the tetrahedra (b_i b_j b_k t_i),
  // (t_i b_j b_k t_j), (t_i t_j b_k t_k), and cuts the side between edges i and j along
  // (t_i, b_j). The least-index rule picks that diagonal where it passes through the side's
  // least vertex, i.e. edge i goes first when min(b_j, t_i) < min(b_i, t_j). The rule never
  // asks for a cycle (Dompierre et al.), so the order exists.
  auto before = [&](int i, int j) { return std::min(p[j], p[i + 3]) < std::min(p[i], p[j + 3]); };
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return i != j && before(i, j); });
  VM_CHECK(before(order[0], order[1]) && before(order[1], order[2]) && before(order[0], order[2]),
           "split_prism: the prism's vertices are not distinct");
  const auto [i, j, k] = order;
  std::array<Tet, 3> tets = {Tet{p[i], p[j], p[k], p[i + 3]}, Tet{p[i + 3], p[j], p[k], p[j + 3]},
                             Tet{p[i + 3], p[j + 3], p[k], p[k + 3]}};
  // Orientation from the reference prism (bottom (0,0,0), (0,1,0), (1,0,0) facing -z, top at
  // z = 1), so that an inverted real prism shows as negative tetrahedra instead of being mended.
  static const Vec3 reference[6] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}};
  auto local = [&](int v) { return reference[std::find(p.begin(), p.end(), v) - p.begin()]; };
  for (Tet& t : tets)
    if (tet_volume6(local(t[0]), local(t[1]), local(t[2]), local(t[3])) < 0) std::swap(t[0], t[1]);
  return tets;
}

namespace {

// The unit normals of the faces opposite each corner, all outward or all inward (so the angles
// between them do not depend on the orientation); zero for a degenerate face.
std::array<Vec3, 4> unit_face_normals(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 p[4] = {a, b, c, d};
  std::array<Vec3, 4> n;
  static const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (int f = 0; f < 4; ++f) {
    n[f] = (p[face[f][1]] - p[face[f][0]]).cross(p[face[f][2]] - p[face[f][0]]);
    const double len = n[f].norm();
    if (len > 0) n[f] /= len;
  }
  return n;
}

}  // namespace

std::array<double, 6> dihedral_angles(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const std::array<Vec3, 4> n = unit_face_normals(a, b, c, d);
  // The edge between corners (i, j) is shared by the faces opposite the other two corners.
  static const int edge_faces[6][2] = {{2, 3}, {1, 3}, {1, 2}, {0, 3}, {0, 2}, {0, 1}};
  std::array<double, 6> angles{};
  for (int e = 0; e < 6; ++e) {
    const double cosine = std::clamp(-n[edge_faces[e][0]].dot(n[edge_faces[e][1]]), -1.0, 1.0);
    angles[e] = std::acos(cosine);
  }
  return angles;
}

double least_dihedral_angle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const std::array<Vec3, 4> n = unit_face_normals(a, b, c, d);
  // The angle between faces f and g is acos(-n_f . n_g): the least has the largest cosine.
  double largest = -1.0;
  for (int f = 0; f < 4; ++f)
    for (int g = f + 1; g < 4; ++g) largest = std::max(largest, -n[f].dot(n[g]));
  return std::acos(std::clamp(largest, -1.0, 1.0));
}

double scaled_jacobian(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double volume6 = tet_volume6(a, b, c, d);
  const Vec3 p[4] = {a, b, c, d};
  double largest = 0.0;
  for (int i = 0; i < 4; ++i) {
    double product = 1.0;
    for (int j = 0; j < 4; ++j)
      if (j != i) product *= (p[j] - p[i]).norm();
    largest = std::max(largest, product);
  }
  return largest > 0 ? std::numbers::sqrt2 * volume6 / largest : 0.0;
}

std::string unnamed_tag(int tag) { return "tag_" + std::to_string(tag); }

std::map<int, std::string> boundary_tag_names(const TetMesh& m) {
  std::map<int, std::string> names = m.tag_names;
  for (int tag : m.boundary_tags)
    if (!names.count(tag)) names[tag] = unnamed_tag(tag);
  return names;
}

Triangle canonical_rotation(const Triangle& f) {
  Triangle out = f;
  std::rotate(out.begin(), std::min_element(out.begin(), out.end()), out.end());
  return out;
}

std::vector<Triangle> tet_boundary(const std::vector<Tet>& tets, int* nonmanifold) {
  // Every face, outward (the right-hand normal points away from the opposite corner), keyed by
  // its sorted corners; a face seen twice is interior.
  struct Face {
    std::array<int, 3> key;
    Triangle oriented;
  };
  std::vector<Face> faces;
  faces.reserve(4 * tets.size());
  for (const Tet& t : tets) {
    const Triangle sides[4] = {{t[1], t[2], t[3]}, {t[0], t[3], t[2]}, {t[0], t[1], t[3]}, {t[0], t[2], t[1]}};
    for (const Triangle& f : sides) {
      std::array<int, 3> key = f;
      std::sort(key.begin(), key.end());
      faces.push_back({key, f});
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& x, const Face& y) { return x.key < y.key; });
  std::vector<Triangle> out;
  int many = 0;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) out.push_back(canonical_rotation(faces[i].oriented));
    if (j - i > 2) ++many;
    i = j;
  }
  if (nonmanifold) *nonmanifold = many;
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Tet> all_tetrahedra(const TetMesh& m) {
  std::vector<Tet> all = m.tets;
  all.reserve(m.tets.size() + 3 * m.prisms.size());
  for (const Prism& p : m.prisms)
    for (const Tet& t : split_prism(p)) all.push_back(t);
  return all;
}

BoundaryClosure boundary_closure(const TetMesh& m, const std::vector<Tet>& all) {
  BoundaryClosure out;
  const std::vector<Triangle> faces = tet_boundary(all, &out.nonmanifold);
  std::vector<Triangle> boundary;
  boundary.reserve(m.boundary.size());
  for (const Triangle& f : m.boundary) boundary.push_back(canonical_rotation(f));
  std::sort(boundary.begin(), boundary.end());
  std::vector<Triangle> difference;
  std::set_difference(faces.begin(), faces.end(), boundary.begin(), boundary.end(), std::back_inserter(difference));
  out.open_faces = static_cast<int>(difference.size());
  difference.clear();
  std::set_difference(boundary.begin(), boundary.end(), faces.begin(), faces.end(), std::back_inserter(difference));
  out.stray_triangles = static_cast<int>(difference.size());
  return out;
}

BoundaryPart boundary_part(const TetMesh& mesh, const std::vector<Tet>& tetrahedra, const std::vector<int>& tags) {
  BoundaryPart wall;
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
  for (size_t e = 0; e < tetrahedra.size(); ++e) {
    int on = 0;  // corners on the part: a face of it needs three
    for (int v : tetrahedra[e]) on += renumber[v] >= 0;
    if (on < 3) continue;
    for (const auto& face : kFaces) {
      std::array<int, 3> key = {tetrahedra[e][face[0]], tetrahedra[e][face[1]], tetrahedra[e][face[2]]};
      std::sort(key.begin(), key.end());
      const auto it = face_of.find(key);
      if (it != face_of.end()) wall.tet[it->second] = static_cast<int>(e);
    }
  }
  for (size_t f = 0; f < wall.tet.size(); ++f)
    if (wall.tet[f] < 0) {
      const Vec3& p = wall.mesh.points[wall.mesh.triangles[f][0]];
      throw InputError(fmt::format("boundary triangle {} (at ({:.4g}, {:.4g}, {:.4g})) bounds no cell of the mesh", f,
                                   p.x(), p.y(), p.z()));
    }
  return wall;
}

}  // namespace vesselmesh::mesh
