#include "mesh/connectivity.h"

#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace vesselmesh::mesh {
namespace {

TEST(Connectivity, TetrahedronHasSixManifoldEdgesAndNoBoundary) {
  const TriMesh m = test::tetrahedron();
  const EdgeMap edges = build_edge_map(m);
  ASSERT_EQ(edges.num_edges(), 6);
  for (int e = 0; e < edges.num_edges(); ++e) {
    EXPECT_EQ(edges.valence(e), 2);
    EXPECT_LT(edges.edges[e][0], edges.edges[e][1]);
  }
  // Every triangle's edges connect its own corners.
  for (int t = 0; t < m.num_triangles(); ++t)
    for (int i = 0; i < 3; ++i) {
      const auto [a, b] = edges.edges[edges.triangle_edges[t][i]];
      const auto [lo, hi] = std::minmax(m.triangles[t][i], m.triangles[t][(i + 1) % 3]);
      EXPECT_EQ(a, lo);
      EXPECT_EQ(b, hi);
    }
  EXPECT_TRUE(boundary_loops(m, edges).empty());
}

TEST(Connectivity, OpenCylinderHasTwoLoopsFollowingTheTriangles) {
  const TriMesh m = synth::cylinder({.radius = 2.0, .length = 5.0, .resolution = 0.5});
  const EdgeMap edges = build_edge_map(m);
  const auto loops = boundary_loops(m, edges);
  ASSERT_EQ(loops.size(), 2u);
  const int around = static_cast<int>(loops[0].size());
  EXPECT_EQ(loops[1].size(), loops[0].size());
  EXPECT_GE(around, 8);
  // Each consecutive pair a -> b is an edge that some triangle runs in the same direction.
  for (const auto& loop : loops)
    for (size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      bool found = false;
      for (const Triangle& f : m.triangles)
        for (int c = 0; c < 3; ++c) found |= f[c] == a && f[(c + 1) % 3] == b;
      EXPECT_TRUE(found) << "loop edge " << a << " -> " << b;
    }
}

TEST(Connectivity, VertexTrianglesListsEachIncidence) {
  const TriMesh m = test::tetrahedron();
  const VertexTriangles vt = build_vertex_triangles(m);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(vt.of(v).size(), 3u);
  EXPECT_EQ(std::vector<int>(vt.of(1).begin(), vt.of(1).end()), (std::vector<int>{0, 1, 3}));
}

TEST(Connectivity, ComponentsAreNumberedByLowestTriangle) {
  TriMesh m = test::tetrahedron(Vec3(10, 0, 0));
  const TriMesh b = test::tetrahedron();
  for (const Triangle& f : b.triangles) m.triangles.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
  m.points.insert(m.points.end(), b.points.begin(), b.points.end());
  int count = 0;
  const auto component = triangle_components(m, build_edge_map(m), &count);
  EXPECT_EQ(count, 2);
  EXPECT_EQ(component, (std::vector<int>{0, 0, 0, 0, 1, 1, 1, 1}));
}

TEST(Connectivity, BoundaryWithTwoOutgoingEdgesIsAnError) {
  // Two triangles touching only at point 0: the boundary passes through it twice.
  TriMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_THROW(boundary_loops(m, build_edge_map(m)), InputError);
}

}  // namespace
}  // namespace vesselmesh::mesh
