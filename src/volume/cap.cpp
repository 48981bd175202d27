#include "volume/cap.h"

#include "mesh/error.h"
#include "mesh/geometry.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/format.h>

#include <map>

namespace vesselmesh::volume {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<Kernel>;
using Fb = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
using Point2 = Kernel::Point_2;
}  // namespace

Cap triangulate_cap(const std::vector<Vec3>& loop, const Vec3& normal) {
  const int m = static_cast<int>(loop.size());
  if (m < 3) throw InputError(fmt::format("an end's loop has {} points: a cap needs 3 or more", m));
  Vec3 center = Vec3::Zero();
  double perimeter = 0.0;
  for (int i = 0; i < m; ++i) center += loop[i], perimeter += (loop[(i + 1) % m] - loop[i]).norm();
  center /= m;
  const Vec3 w = normal.normalized();
  const Vec3 u = w.unitOrthogonal(), v = w.cross(u);  // u x v = w: counter-clockwise in (u, v) faces w

  Cdt cdt;
  std::map<Cdt::Vertex_handle, int> index;
  std::vector<Cdt::Vertex_handle> handles(m);
  for (int i = 0; i < m; ++i) {
    const Vec3 d = loop[i] - center;
    handles[i] = cdt.insert(Point2(d.dot(u), d.dot(v)));
    index.emplace(handles[i], i);
  }
  for (int i = 0; i < m; ++i) cdt.insert_constraint(handles[i], handles[(i + 1) % m]);
  if (static_cast<int>(cdt.number_of_vertices()) != m || static_cast<int>(index.size()) != m)
    throw InputError(fmt::format("the end loop around {} crosses or touches itself seen along its normal; "
                                 "cut the end flat (normal to the vessel) and remesh",
                                 mesh::format_point(center)));
  const double size = 1.2 * perimeter / m;
  CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria> mesher(cdt, Criteria(0.125, size));
  mesher.refine_mesh();

  Cap cap;
  // Plane height: the loop's mean (the points lie in it when the end is flat).
  for (auto vh = cdt.finite_vertices_begin(); vh != cdt.finite_vertices_end(); ++vh) {
    if (index.count(vh)) continue;
    index.emplace(vh, m + static_cast<int>(cap.points.size()));
    cap.points.push_back(center + vh->point().x() * u + vh->point().y() * v);
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    cap.triangles.push_back({index.at(f->vertex(0)), index.at(f->vertex(1)), index.at(f->vertex(2))});
  }
  return cap;
}

}  // namespace vesselmesh::volume
