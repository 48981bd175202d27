#include "mesh/clean.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/statistics.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::mesh {
namespace {

TriMesh small_sphere() { return synth::sphere({.radius = 2.0, .resolution = 0.5}); }

int count_zero_area(const TriMesh& m) {
  int n = 0;
  for (int t = 0; t < m.num_triangles(); ++t) n += triangle_area(m, t) < 1e-14;
  return n;
}

TEST(Clean, CleanSurfaceIsLeftAsItIs) {
  TriMesh m = small_sphere();
  const TriMesh before = m;
  const CleanReport report = clean(m);
  EXPECT_EQ(report.total_repairs(), 0);
  for (const auto& [kind, count] : report.defects) EXPECT_EQ(count, 0) << kind;
  EXPECT_EQ(m.points, before.points);
  EXPECT_EQ(m.triangles, before.triangles);
  EXPECT_TRUE(report.notes.empty());
  EXPECT_EQ(report.input_components, 1);
}

TEST(Clean, InwardSurfaceIsTurnedOutward) {
  TriMesh m = small_sphere();
  for (Triangle& f : m.triangles) std::swap(f[1], f[2]);
  EXPECT_LT(signed_volume(m), 0.0);
  const CleanReport report = clean(m);
  EXPECT_EQ(report.defects.at("inward_components"), 1);
  EXPECT_EQ(report.repairs.at("flipped_triangles"), m.num_triangles());
  EXPECT_EQ(report.defects.at("inconsistent_orientation"), 0);
  // An inscribed polyhedron of edge h = R/4 holds a little less than 4/3 pi R^3 (about 2 %).
  const double exact = 4.0 / 3.0 * std::numbers::pi * 8.0;
  EXPECT_LT(signed_volume(m), exact);
  EXPECT_GT(signed_volume(m), 0.97 * exact);
}

TEST(Clean, OpenInwardPipeIsTurnedOutward) {
  TriMesh m = synth::cylinder({.radius = 3.0, .length = 10.0, .resolution = 0.5});
  for (Triangle& f : m.triangles) std::swap(f[1], f[2]);
  const CleanReport report = clean(m);
  EXPECT_EQ(report.defects.at("inward_components"), 1);
  EXPECT_GT(signed_volume(m), 0.0);
}

TEST(Clean, SingleFlippedTriangleIsMadeConsistent) {
  TriMesh m = small_sphere();
  const TriMesh reference = m;
  std::swap(m.triangles[7][1], m.triangles[7][2]);
  const CleanReport report = clean(m);
  EXPECT_EQ(report.defects.at("inconsistent_orientation"), 1);
  EXPECT_EQ(report.repairs.at("flipped_triangles"), 1);
  EXPECT_EQ(m.triangles, reference.triangles);
}

TEST(Clean, NearDuplicatePointsAreMergedAndTheSeamCloses) {
  TriMesh m = small_sphere();
  // Detach triangle 0 from its neighbours by giving it its own, slightly moved copies of
  // its corners, as an exporter with round-off would.
  for (int& v : m.triangles[0]) {
    m.points.push_back(m.points[v] + Vec3(1e-9, -1e-9, 0.0));
    v = m.num_points() - 1;
  }
  const int points_before = m.num_points();
  const CleanReport report = clean(m);
  EXPECT_EQ(report.defects.at("near_duplicate_points"), 3);
  EXPECT_EQ(report.repairs.at("merged_points"), 3);
  EXPECT_EQ(m.num_points(), points_before - 3);
  EXPECT_TRUE(statistics(m).closed);
  EXPECT_EQ(report.input_components, 1);
}

TEST(Clean, ShortRealEdgesAreNotMerged) {
  // A real edge of 4e-4 of its neighbours' length (as in marching-cubes surfaces) stays.
  TriMesh m = small_sphere();
  const EdgeMap edges = build_edge_map(m);
  const auto [a, b] = edges.edges[0];
  m.points[b] = m.points[a] + 4e-4 * (m.points[b] - m.points[a]);
  const CleanReport report = clean(m, {.find_self_intersections = false});
  EXPECT_EQ(report.defects.at("near_duplicate_points"), 0);
}

TEST(Clean, DegenerateAndDuplicateTrianglesAreRemoved) {
  TriMesh m = small_sphere();
  const int n = m.num_triangles();
  m.triangles.push_back({3, 3, 5});                                                          // repeated corner
  m.triangles.push_back({m.triangles[4][1], m.triangles[4][2], m.triangles[4][0]});           // same, rotated
  m.triangles.push_back({m.triangles[9][0], m.triangles[9][2], m.triangles[9][1]});           // same, reversed
  const CleanReport report = clean(m);
  EXPECT_EQ(report.defects.at("degenerate_triangles"), 1);
  EXPECT_EQ(report.defects.at("duplicate_triangles"), 2);
  EXPECT_EQ(m.num_triangles(), n);
  EXPECT_TRUE(statistics(m).closed);
  EXPECT_EQ(report.triangle_origin.size(), static_cast<size_t>(n));
}

TEST(Clean, NonManifoldEdgeIsAnErrorThatSaysWhere) {
  TriMesh m = small_sphere();
  const EdgeMap edges = build_edge_map(m);
  const auto [a, b] = edges.edges[0];
  m.points.push_back(Vec3(10, 10, 10));
  m.triangles.push_back({a, b, m.num_points() - 1});  // a fin on an edge already shared by two
  try {
    clean(m);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("non-manifold edge"), std::string::npos) << message;
    EXPECT_NE(message.find("3 triangles"), std::string::npos) << message;
  }
}

TEST(Clean, NonManifoldVertexIsSplitAndTheSmallerComponentReported) {
  // Two tetrahedra touching at one point (a bow-tie vertex); the second is larger.
  TriMesh m = test::tetrahedron();  // its point 0 is (1, 1, 1)
  const double size = 1.5;
  const TriMesh b = test::tetrahedron(Vec3(1, 1, 1) - size * Vec3(-1, -1, 1), size);  // its point 3 is (1, 1, 1)
  ASSERT_TRUE(b.points[3].isApprox(m.points[0]));
  for (int v = 0; v < 3; ++v) m.points.push_back(b.points[v]);
  for (Triangle f : b.triangles) {
    for (int& v : f) v = v == 3 ? 0 : v + 4;
    m.triangles.push_back(f);
  }
  const CleanReport report = clean(m);
  EXPECT_EQ(report.defects.at("non_manifold_vertices"), 1);
  EXPECT_EQ(report.repairs.at("split_vertices"), 1);
  EXPECT_EQ(report.input_components, 2);
  EXPECT_EQ(report.defects.at("extra_components"), 1);
  EXPECT_EQ(m.num_triangles(), 4);
  EXPECT_TRUE(statistics(m).closed);
  EXPECT_GT(signed_volume(m), 0.0);
}

TEST(Clean, KeepsEveryComponentWhenAsked) {
  TriMesh m = test::tetrahedron();
  const TriMesh b = test::tetrahedron(Vec3(5, 0, 0));
  for (const Triangle& f : b.triangles) m.triangles.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
  m.points.insert(m.points.end(), b.points.begin(), b.points.end());
  TriMesh all = m;
  clean(all, {.keep_largest_component = false});
  EXPECT_EQ(all.num_triangles(), 8);
  const CleanReport report = clean(m);
  EXPECT_EQ(m.num_triangles(), 4);
  EXPECT_EQ(report.repairs.at("removed_components"), 1);
  EXPECT_EQ(report.repairs.at("removed_component_triangles"), 4);
  EXPECT_EQ(report.repairs.at("removed_unreferenced_points"), 4);
}

TEST(Clean, ZeroAreaTriangleIsMendedByAnEdgeFlip) {
  // Split edge a-b at its midpoint m on one side and close the crack with the collinear
  // triangle (a, b, m): a manifold, closed surface with one zero-area triangle.
  TriMesh s = small_sphere();
  const EdgeMap edges = build_edge_map(s);
  const int e = 10;
  const int t1 = edges.triangles_of(e)[0];
  Triangle f = s.triangles[t1];
  int i = 0;
  while (!(std::minmax(f[i], f[(i + 1) % 3]) == std::minmax(edges.edges[e][0], edges.edges[e][1]))) ++i;
  const int a = f[i], b = f[(i + 1) % 3], c = f[(i + 2) % 3];
  const int mid = s.num_points();
  s.points.push_back(0.5 * (s.points[a] + s.points[b]));
  s.triangles[t1] = {a, mid, c};
  s.triangles.push_back({mid, b, c});
  s.triangles.push_back({a, b, mid});
  ASSERT_EQ(count_zero_area(s), 1);
  const double volume_before = signed_volume(s);
  const CleanReport report = clean(s);
  EXPECT_EQ(report.defects.at("zero_area_triangles"), 1);
  EXPECT_EQ(report.repairs.at("flipped_zero_area_edges"), 1);
  EXPECT_EQ(count_zero_area(s), 0);
  EXPECT_TRUE(statistics(s).closed);
  EXPECT_NEAR(signed_volume(s), volume_before, 1e-9 * volume_before);
}

TEST(Clean, ZeroAreaTriangleOnTheBoundaryIsRemoved) {
  TriMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(1, 1, 0)};
  m.triangles = {{0, 1, 3}, {1, 2, 3}, {0, 2, 1}};  // the last is collinear, on the boundary
  const CleanReport report = clean(m, {.orient_outward = false});
  EXPECT_EQ(report.repairs.at("removed_zero_area_triangles"), 1);
  EXPECT_EQ(m.num_triangles(), 2);
}

TEST(Clean, NonFiniteCoordinatesAreAnError) {
  TriMesh m = test::tetrahedron();
  m.points[2].y() = std::nan("");
  EXPECT_THROW(clean(m), InputError);
  m.points[2].y() = INFINITY;
  EXPECT_THROW(clean(m), InputError);
}

TEST(Clean, EmptyOrAllDegenerateSurfaceIsAnError) {
  TriMesh empty;
  EXPECT_THROW(clean(empty), InputError);
  TriMesh flat;
  flat.points = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  flat.triangles = {{0, 1, 1}, {0, 0, 1}};
  EXPECT_THROW(clean(flat), InputError);
}

TEST(Clean, IndexOutOfRangeIsAnError) {
  TriMesh m = test::tetrahedron();
  m.triangles[1][2] = 17;
  EXPECT_THROW(clean(m), InputError);
}

TEST(Clean, NonOrientableSurfaceIsAnError) {
  // A Moebius strip: a band of quads whose ends are glued with a half twist.
  TriMesh m;
  const int n = 24;
  for (int i = 0; i < n; ++i) {
    const double u = 2 * std::numbers::pi * i / n;
    for (double w : {-0.3, 0.3})
      m.points.emplace_back((1 + w * std::cos(u / 2)) * std::cos(u), (1 + w * std::cos(u / 2)) * std::sin(u),
                            w * std::sin(u / 2));
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 1;
    const bool last = i == n - 1;
    const int c = last ? 1 : 2 * (i + 1), d = last ? 0 : 2 * (i + 1) + 1;  // the twist swaps sides
    m.triangles.push_back({a, c, b});
    m.triangles.push_back({b, c, d});
  }
  try {
    clean(m);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not orientable"), std::string::npos) << e.what();
  }
}

TEST(Clean, SelfIntersectionsAreFoundAndReported) {
  TriMesh m = small_sphere();
  int top = 0;
  for (int v = 0; v < m.num_points(); ++v)
    if (m.points[v].z() > m.points[top].z()) top = v;
  m.points[top] = Vec3(0.0, 0.0, -3.0);  // pushed through the opposite side
  const CleanReport report = clean(m);
  EXPECT_GT(report.defects.at("self_intersections"), 0);
  EXPECT_EQ(report.self_intersections.size(), static_cast<size_t>(report.defects.at("self_intersections")));
  TriMesh clean_sphere = small_sphere();
  EXPECT_EQ(clean(clean_sphere).defects.at("self_intersections"), 0);
}

TEST(Clean, IsDeterministic) {
  TriMesh a = synth::sphere({.radius = 3.0, .resolution = 0.4, .jitter = 0.3, .seed = 7});
  for (Triangle& f : a.triangles) std::swap(f[0], f[1]);
  TriMesh b = a;
  clean(a);
  clean(b);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(Clean, LabelsFollowTheirTriangles) {
  TriMesh m = synth::cylinder({.radius = 2.0, .length = 4.0, .resolution = 0.5, .capped = true});
  m.triangles.push_back(m.triangles[0]);  // a duplicate, removed
  m.labels.push_back(99);
  for (Triangle& f : m.triangles) std::swap(f[1], f[2]);  // and everything inward
  clean(m);
  ASSERT_EQ(m.labels.size(), m.triangles.size());
  EXPECT_EQ(std::count(m.labels.begin(), m.labels.end(), 99), 0);
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Vec3 n = triangle_area_vector(m, t).normalized();
    if (m.labels[t] == 2) {
      EXPECT_NEAR(n.z(), -1.0, 1e-9);
    }
    if (m.labels[t] == 3) {
      EXPECT_NEAR(n.z(), 1.0, 1e-9);
    }
  }
}

}  // namespace
}  // namespace vesselmesh::mesh
