#include "analysis/features.h"

#include "mesh/connectivity.h"
#include "synth/shapes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::analysis {
namespace {

// A unit cube, two triangles a face, outward: twelve 90-degree creases and eight corners.
TriMesh cube() {
  TriMesh m;
  for (int i = 0; i < 8; ++i) m.points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TEST(Features, CubeHasTwelveCreaseCurvesAndEightCorners) {
  const TriMesh m = cube();
  const Features f = detect_features(m);
  EXPECT_EQ(f.num_creases, 12);
  EXPECT_EQ(f.num_curves, 12);  // corners end curves: one curve per cube edge
  for (int v = 0; v < 8; ++v) EXPECT_EQ(f.kind[v], PointKind::corner) << "point " << v;
  // Each corner has one copy per face around it: three.
  EXPECT_EQ(f.num_copies(), 24);
  int diagonals = 0;
  for (int e = 0; e < f.edges.num_edges(); ++e) diagonals += f.curve_of_edge[e] < 0;
  EXPECT_EQ(diagonals, 6);
}

TEST(Features, CappedPipeRimsAreCreasesAndCutThreePatches) {
  const TriMesh m = synth::cylinder({.radius = 3.0, .length = 20.0, .resolution = 0.5, .capped = true});
  const Features f = detect_features(m);
  EXPECT_EQ(f.num_curves, 2);
  EXPECT_EQ(f.dropped_creases, 0);
  for (int v = 0; v < m.num_points(); ++v) {
    const Vec3& p = m.points[v];
    const bool on_rim = std::abs(std::hypot(p.x(), p.y()) - 3.0) < 1e-9 && (p.z() < 1e-9 || p.z() > 20.0 - 1e-9);
    EXPECT_EQ(f.kind[v] == PointKind::curve, on_rim) << "point " << v;
    EXPECT_NE(f.kind[v], PointKind::corner);
  }
  const TriMesh split = split_at_creases(m, f);
  int components = 0;
  mesh::triangle_components(split, mesh::build_edge_map(split), &components);
  EXPECT_EQ(components, 3);
  // The rim's curvature comes from the wall side (1/R around), a cap's middle is flat.
  const CurvatureField c = patch_curvature(m, f);
  for (int v = 0; v < m.num_points(); ++v) {
    const Vec3& p = m.points[v];
    const double kmax = std::max(std::abs(c.k1[v]), std::abs(c.k2[v]));
    if (f.kind[v] == PointKind::curve) {
      EXPECT_NEAR(kmax, 1.0 / 3.0, 0.05) << "rim point " << v;
    }
    if ((p.z() < 1e-9 || p.z() > 20.0 - 1e-9) && std::hypot(p.x(), p.y()) < 2.0) {
      EXPECT_NEAR(kmax, 0.0, 1e-6) << "cap point " << v;
    }
  }
}

TEST(Features, OpenEndsAreCurvesButNotCreases) {
  const TriMesh m = synth::cylinder({.radius = 3.0, .length = 20.0, .resolution = 0.5});
  const Features f = detect_features(m);
  EXPECT_EQ(f.num_creases, 0);
  EXPECT_EQ(f.num_curves, 2);
  EXPECT_EQ(f.num_copies(), m.num_points());
}

TEST(Features, ShortChainsOfSharpEdgesAreNoise) {
  TriMesh m = synth::sphere({.radius = 5.0, .resolution = 0.5});
  // One point pulled far out: a spike whose ten sharp edges (five to the tip, five around its
  // base) make one connected chain, no feature line.
  m.points[0] *= 1.4;
  const Features kept = detect_features(m, {.min_crease_edges = 5});
  EXPECT_EQ(kept.num_creases, 10);
  EXPECT_EQ(kept.dropped_creases, 0);
  const Features dropped = detect_features(m, {.min_crease_edges = 11});
  EXPECT_EQ(dropped.num_creases, 0);
  EXPECT_EQ(dropped.dropped_creases, 10);
  EXPECT_EQ(dropped.num_curves, 0);
  EXPECT_EQ(dropped.num_copies(), m.num_points());
}

TEST(Features, LabelBordersAreCurvesOnASmoothWall) {
  TriMesh m = synth::cylinder({.radius = 3.0, .length = 20.0, .resolution = 0.5});
  m.labels.resize(m.triangles.size());
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Triangle& g = m.triangles[t];
    m.labels[t] = (m.points[g[0]] + m.points[g[1]] + m.points[g[2]]).z() / 3.0 < 10.0 ? 1 : 2;
  }
  const Features f = detect_features(m);
  EXPECT_EQ(f.num_creases, 0);
  EXPECT_EQ(f.num_copies(), m.num_points());  // a label border does not cut patches
  // Every point where both labels meet is on a feature curve (a corner where the border
  // zigzags along the triangulation by more than the corner angle).
  const mesh::EdgeMap& edges = f.edges;
  int border_edges = 0;
  for (int e = 0; e < edges.num_edges(); ++e) {
    const auto ts = edges.triangles_of(e);
    if (ts.size() != 2 || m.labels[ts[0]] == m.labels[ts[1]]) continue;
    ++border_edges;
    EXPECT_GE(f.curve_of_edge[e], 0);
    for (int v : edges.edges[e]) EXPECT_NE(f.kind[v], PointKind::free);
  }
  EXPECT_GT(border_edges, 30);  // 2 pi 3 / 0.5 = 38 around
}

}  // namespace
}  // namespace vesselmesh::analysis
