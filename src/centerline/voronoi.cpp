#include "centerline/voronoi.h"

#include "mesh/error.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/property_map.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

namespace vesselmesh::centerline {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CellBase = CGAL::Triangulation_cell_base_with_info_3<int, Kernel>;  // our node index, or -1
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>;  // a surface point's index
using Tds = CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;
using Point = Kernel::Point_3;

}  // namespace

VoronoiGraph internal_voronoi(const TriMesh& surface, const mesh::InsideTest& inside, const Reporter& reporter) {
  const std::string task = "building the Voronoi diagram";
  reporter.progress(task, 0.0);
  std::vector<std::pair<Point, int>> points;
  points.reserve(surface.points.size());
  for (int i = 0; i < surface.num_points(); ++i) {
    const Vec3& p = surface.points[i];
    points.emplace_back(Point(p.x(), p.y(), p.z()), i);
  }
  // A fixed insertion order (CGAL's default range insertion shuffles with a random generator).
  CGAL::hilbert_sort(points.begin(), points.end(),
                     CGAL::Spatial_sort_traits_adapter_3<Kernel, CGAL::First_of_pair_property_map<std::pair<Point, int>>>());
  Delaunay delaunay;
  Delaunay::Vertex_handle hint;
  for (const auto& [p, i] : points) {
    hint = delaunay.insert(p, hint);
    hint->info() = i;  // a point given twice keeps its last index
  }
  reporter.progress(task, 0.4);

  // Circumcentres in cell order; which of them lie inside is asked in parallel (the queries
  // are independent and the answers land in their own slots: the same for any thread count).
  std::vector<Vec3> centers;
  std::vector<double> radii;
  centers.reserve(delaunay.number_of_finite_cells());
  for (auto cell = delaunay.finite_cells_begin(); cell != delaunay.finite_cells_end(); ++cell) {
    const Point c = CGAL::circumcenter(cell->vertex(0)->point(), cell->vertex(1)->point(), cell->vertex(2)->point(),
                                       cell->vertex(3)->point());
    centers.emplace_back(c.x(), c.y(), c.z());
    radii.push_back(std::sqrt(CGAL::squared_distance(c, cell->vertex(0)->point())));
  }
  reporter.progress(task, 0.5);
  std::vector<char> keep(centers.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, centers.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) keep[i] = centers[i].allFinite() && inside.inside(centers[i]);
  });
  reporter.progress(task, 0.9);
  VoronoiGraph graph;
  size_t index = 0;
  for (auto cell = delaunay.finite_cells_begin(); cell != delaunay.finite_cells_end(); ++cell, ++index) {
    cell->info() = -1;
    if (!keep[index]) continue;
    cell->info() = graph.size();
    graph.centers.push_back(centers[index]);
    graph.radius.push_back(radii[index]);
  }
  // Each surface point's inner pole: the largest inside ball its cells' circumspheres give.
  graph.pole_radius.assign(surface.points.size(), 0.0);
  index = 0;
  for (auto cell = delaunay.finite_cells_begin(); cell != delaunay.finite_cells_end(); ++cell, ++index) {
    if (!keep[index]) continue;
    for (int i = 0; i < 4; ++i) {
      double& pole = graph.pole_radius[cell->vertex(i)->info()];
      pole = std::max(pole, radii[index]);
    }
  }
  for (auto cell = delaunay.all_cells_begin(); cell != delaunay.all_cells_end(); ++cell)
    if (delaunay.is_infinite(cell)) cell->info() = -1;
  // Adjacency through shared faces, in cell order.
  graph.offsets.assign(1, 0);
  for (auto cell = delaunay.finite_cells_begin(); cell != delaunay.finite_cells_end(); ++cell) {
    if (cell->info() < 0) continue;
    for (int i = 0; i < 4; ++i) {
      const int other = cell->neighbor(i)->info();
      if (other >= 0) graph.neighbours.push_back(other);
    }
    graph.offsets.push_back(static_cast<int>(graph.neighbours.size()));
  }
  VM_CHECK(graph.offsets.size() == graph.centers.size() + 1, "one adjacency list per internal Voronoi vertex");
  reporter.progress(task, 1.0);
  return graph;
}

}  // namespace vesselmesh::centerline
