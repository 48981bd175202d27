#include "sizing/gradation.h"

#include "mesh/connectivity.h"
#include "mesh/point_graph.h"
#include "test_support.h"
#include "sizing/metric.h"
#include "synth/shapes.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vesselmesh::sizing {
namespace {

TEST(Gradation, IsotropicSizesGrowAtMostLinearlyAlongEdges) {
  const TriMesh m = synth::cylinder({.radius = 2, .length = 20, .resolution = 0.3, .jitter = 0.3});
  std::vector<double> h(m.points.size());
  for (size_t v = 0; v < h.size(); ++v) h[v] = m.points[v].z() < 10.0 ? 0.05 : 2.0;  // a jump
  const double g = 1.3;
  const int passes = grade_sizes(m, h, g);
  EXPECT_GT(passes, 1);
  const mesh::EdgeMap edges = mesh::build_edge_map(m);
  for (int e = 0; e < edges.num_edges(); ++e) {
    const auto [a, b] = edges.edges[e];
    const double l = (m.points[a] - m.points[b]).norm();
    EXPECT_LE(std::abs(h[a] - h[b]), std::log(g) * l + 1e-12) << e;
  }
  // Sizes only shrink, and the small side keeps its size.
  for (size_t v = 0; v < h.size(); ++v) {
    EXPECT_LE(h[v], m.points[v].z() < 10.0 ? 0.05 : 2.0);
    if (m.points[v].z() < 9.0) {
      EXPECT_EQ(h[v], 0.05);
    }
  }
  std::vector<double> untouched = h;
  EXPECT_EQ(grade_sizes(m, untouched, 1.0), 0);
  EXPECT_EQ(untouched, h);
}

TEST(Gradation, MetricsNeverExceedTheirNeighboursSpreadMetric) {
  const TriMesh m = synth::cylinder({.radius = 2, .length = 10, .resolution = 0.4, .jitter = 0.2});
  std::vector<Sym3> metrics(m.points.size());
  for (size_t v = 0; v < metrics.size(); ++v) {
    const double angle = std::atan2(m.points[v].y(), m.points[v].x());
    const Vec3 around(-std::sin(angle), std::cos(angle), 0), out(std::cos(angle), std::sin(angle), 0);
    const bool fine = m.points[v].z() < 5.0;
    metrics[v] = metric_from_sizes(around, fine ? 0.05 : 0.8, Vec3::UnitZ(), fine ? 0.5 : 3.0, out, fine ? 0.05 : 0.8);
  }
  const double g = 1.3;
  grade_metrics(m, metrics, g);
  const mesh::EdgeMap edges = mesh::build_edge_map(m);
  for (int e = 0; e < edges.num_edges(); ++e) {
    for (auto [from, to] : {std::pair{edges.edges[e][0], edges.edges[e][1]}, std::pair{edges.edges[e][1], edges.edges[e][0]}}) {
      const Vec3 d = m.points[to] - m.points[from];
      const Sym3 spread = scale_sizes(metrics[from], 1.0 + metric_length(metrics[from], d) * std::log(g));
      // M_to must be at least as fine as the spread metric: M_to - spread >= 0 (to round-off).
      const Eigen::Matrix3d difference = metrics[to].matrix() - spread.matrix();
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(difference).eigenvalues().minCoeff(),
                -1e-5 * metrics[to].matrix().norm())
          << e;
    }
  }
}

// Over a volume's point graph (the flow interior's grading): on a chain, exactly the least over paths of
// h_i + (length) ln g; on a jittered Kuhn box with random sizes, every edge graded, every size at most
// what it was, and each the least of its neighbours' bounds or its own (nothing lowered further than it
// must); a graded field is left as it is.
TEST(Gradation, VolumeGraphSizesAreTheLeastOverPaths) {
  const std::vector<Vec3> chain = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3.5, 0, 0)};
  const mesh::PointGraph line = {{0, 1, 3, 5, 6}, {1, 0, 2, 1, 3, 2}};
  std::vector<double> h = {10.0, 0.5, 10.0, 10.0};
  EXPECT_EQ(grade_sizes(chain, line, h, std::exp(1.0)), 3);
  EXPECT_NEAR(h[0], 1.5, 1e-12);
  EXPECT_NEAR(h[2], 1.5, 1e-12);
  EXPECT_NEAR(h[3], 3.0, 1e-12);

  TetMesh box = test::kuhn_box({5, 5, 5}, Vec3(1, 1, 1));
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05), size(0.02, 1.0);
  for (Vec3& p : box.points) p += Vec3(jitter(random), jitter(random), jitter(random));
  const mesh::PointGraph graph = mesh::point_graph(box.num_points(), box.tets);
  std::vector<double> sizes(box.points.size());
  for (double& s : sizes) s = size(random);
  const std::vector<double> given = sizes;
  const double slope = std::log(1.3);
  EXPECT_GT(grade_sizes(box.points, graph, sizes, 1.3), 0);
  for (int v = 0; v < box.num_points(); ++v) {
    EXPECT_LE(sizes[v], given[v]);
    double least = given[v];
    for (int k = graph.start[v]; k < graph.start[v + 1]; ++k) {
      const int q = graph.next[k];
      const double bound = sizes[q] + slope * (box.points[q] - box.points[v]).norm();
      EXPECT_LE(sizes[v], bound + 1e-12);
      least = std::min(least, bound);
    }
    EXPECT_NEAR(sizes[v], least, 1e-12) << v;
  }
  std::vector<double> again = sizes;
  EXPECT_EQ(grade_sizes(box.points, graph, again, 1.3), 0);
  EXPECT_EQ(again, sizes);
}

}  // namespace
}  // namespace vesselmesh::sizing
