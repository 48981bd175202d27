#include "remesh/surface_model.h"

#include "sizing/metric.h"
#include "synth/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vesselmesh::remesh {
namespace {

TEST(SurfaceModel, LocalProjectionFindsTheGlobalClosestPointNearItsHint) {
  const TriMesh input = synth::torus({.major_radius = 10.0, .minor_radius = 3.0, .resolution = 0.4, .jitter = 0.3});
  const SurfaceModel model(input, std::vector<Sym3>(input.points.size(), sizing::isotropic_metric(1.0)), FeatureOptions{});
  std::mt19937 random(3);
  std::uniform_int_distribution<int> pick(0, input.num_points() - 1);
  std::uniform_real_distribution<double> offset(-0.6, 0.6);
  for (int k = 0; k < 500; ++k) {
    // A point within an edge or so of an input point, the walk starting at a triangle there.
    const int v = pick(random);
    const Vec3 p = input.points[v] + Vec3(offset(random), offset(random), offset(random));
    const Projection local = model.project(p, model.triangle_at(v));
    const Projection global = model.project(p);
    EXPECT_NEAR((local.point - p).norm(), (global.point - p).norm(), 1e-12) << "point " << k;
    EXPECT_NEAR(model.distance(p, model.triangle_at(v)), model.distance(p), 1e-12);
    EXPECT_NEAR(local.normal.norm(), 1.0, 1e-9);
  }
  // From a hint on the opposite side of the torus the walk wanders past its limit and hands over
  // to the global query: the same closest point.
  const Vec3 p(13.5, 0.0, 0.2);  // just outside the outer equator
  int far = 0;
  for (int v = 0; v < input.num_points(); ++v)
    if (input.points[v].x() < -12.0) far = v;
  EXPECT_NEAR(model.distance(p, model.triangle_at(far)), model.distance(p), 1e-12);
  EXPECT_NEAR(model.distance(p), std::hypot(3.5, 0.2) - 3.0, 0.01);  // plus the facets' depth
}

}  // namespace
}  // namespace vesselmesh::remesh
