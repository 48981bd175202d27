#include "mesh/locator.h"

#include "mesh/error.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>

namespace vesselmesh::mesh {
namespace {

// The inside test shoots rays: its predicates must be exact. Closest points need no exact
// predicate, and an exact one costs dearly: a query on the surface itself (Gmsh's size callback,
// the remesher's projections) is as close to two triangles sharing an edge, a tie that a filtered
// kernel settles in rational arithmetic (measured: a fifth of a Gmsh remesh in GMP). So the AABB
// trees use plain doubles, as CGAL's AABB documentation advises for speed.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using FastKernel = CGAL::Simple_cartesian<double>;

template <typename P = Point>
P to_cgal(const Vec3& p) {
  return {p.x(), p.y(), p.z()};
}
template <typename P>
Vec3 from_cgal(const P& p) {
  return {p.x(), p.y(), p.z()};
}

}  // namespace

struct SurfaceLocator::Impl {
  using Triangles = std::vector<FastKernel::Triangle_3>;
  using Primitive = CGAL::AABB_triangle_primitive<FastKernel, Triangles::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<FastKernel, Primitive>>;
  Triangles triangles;
  Tree tree;
};

SurfaceLocator::SurfaceLocator(const TriMesh& mesh) : impl_(std::make_unique<Impl>()) {
  VM_CHECK(!mesh.triangles.empty(), "a surface locator needs triangles");
  impl_->triangles.reserve(mesh.triangles.size());
  for (const Triangle& f : mesh.triangles)
    impl_->triangles.emplace_back(to_cgal<FastKernel::Point_3>(mesh.points[f[0]]),
                                  to_cgal<FastKernel::Point_3>(mesh.points[f[1]]),
                                  to_cgal<FastKernel::Point_3>(mesh.points[f[2]]));
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

SurfaceLocator::~SurfaceLocator() = default;
SurfaceLocator::SurfaceLocator(SurfaceLocator&&) noexcept = default;
SurfaceLocator& SurfaceLocator::operator=(SurfaceLocator&&) noexcept = default;

SurfaceLocator::Hit SurfaceLocator::closest(const Vec3& p) const {
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(to_cgal<FastKernel::Point_3>(p));
  Hit hit;
  hit.point = from_cgal(point);
  hit.triangle = static_cast<int>(primitive - impl_->triangles.begin());
  hit.distance = (hit.point - p).norm();
  return hit;
}

struct InsideTest::Impl {
  using SurfaceMesh = CGAL::Surface_mesh<Point>;
  SurfaceMesh mesh;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>> side;
};

InsideTest::InsideTest(const TriMesh& closed_mesh) : impl_(std::make_unique<Impl>()) {
  std::vector<Impl::SurfaceMesh::Vertex_index> vertices;
  vertices.reserve(closed_mesh.points.size());
  for (const Vec3& p : closed_mesh.points) vertices.push_back(impl_->mesh.add_vertex(to_cgal(p)));
  for (const Triangle& f : closed_mesh.triangles) {
    // Side_of_triangle_mesh only needs the triangles; a face that does not fit the halfedge
    // structure (a cap fan meeting a pinched loop) is added as its own copy.
    if (impl_->mesh.add_face(vertices[f[0]], vertices[f[1]], vertices[f[2]]) == Impl::SurfaceMesh::null_face()) {
      const auto a = impl_->mesh.add_vertex(to_cgal(closed_mesh.points[f[0]]));
      const auto b = impl_->mesh.add_vertex(to_cgal(closed_mesh.points[f[1]]));
      const auto c = impl_->mesh.add_vertex(to_cgal(closed_mesh.points[f[2]]));
      impl_->mesh.add_face(a, b, c);
    }
  }
  impl_->side = std::make_unique<CGAL::Side_of_triangle_mesh<Impl::SurfaceMesh, Kernel>>(impl_->mesh);
  (void)(*impl_->side)(Point(0, 0, 0));  // builds the tree now, before any concurrent query
}

InsideTest::~InsideTest() = default;

bool InsideTest::inside(const Vec3& p) const { return (*impl_->side)(to_cgal(p)) == CGAL::ON_BOUNDED_SIDE; }

struct SegmentLocator::Impl {
  using Segments = std::vector<FastKernel::Segment_3>;
  using Primitive = CGAL::AABB_segment_primitive<FastKernel, Segments::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<FastKernel, Primitive>>;
  Segments segments;
  Tree tree;
};

SegmentLocator::SegmentLocator(const std::vector<std::array<Vec3, 2>>& segments) : impl_(std::make_unique<Impl>()) {
  VM_CHECK(!segments.empty(), "a segment locator needs segments");
  for (const auto& s : segments)
    impl_->segments.emplace_back(to_cgal<FastKernel::Point_3>(s[0]), to_cgal<FastKernel::Point_3>(s[1]));
  impl_->tree.insert(impl_->segments.begin(), impl_->segments.end());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

SegmentLocator::~SegmentLocator() = default;

SegmentLocator::Hit SegmentLocator::closest(const Vec3& p) const {
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(to_cgal<FastKernel::Point_3>(p));
  Hit hit;
  hit.point = from_cgal(point);
  hit.segment = static_cast<int>(primitive - impl_->segments.begin());
  const Vec3 a = from_cgal(primitive->source()), b = from_cgal(primitive->target());
  const double l2 = (b - a).squaredNorm();
  hit.t = l2 > 0.0 ? std::clamp((hit.point - a).dot(b - a) / l2, 0.0, 1.0) : 0.0;
  hit.distance = (hit.point - p).norm();
  return hit;
}

}  // namespace vesselmesh::mesh
