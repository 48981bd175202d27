#include "study/wall_difference.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::study {
namespace {

using test::unit_square;

TEST(WallDifference, LumpedAreasSumToTheArea) {
  const std::vector<double> a = lumped_areas(unit_square(7));
  double sum = 0.0;
  for (double x : a) sum += x;
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_NEAR(a[0], 1.0 / 49 / 3, 1e-15);  // one corner of one triangle (the diagonal leaves it one)
}

// A linear field is carried exactly from one wall to another of other triangles: no difference.
TEST(WallDifference, ALinearFieldCarriedToAnotherWallIsTheSame) {
  const TriMesh coarse = unit_square(5), fine = unit_square(12, true);
  const auto field = [](const Vec3& x) { return Vec3(1.0 + 2.0 * x.x(), 3.0 - x.y(), 0.5 * x.x() + x.y()); };
  std::vector<Vec3> on_coarse, on_fine;
  for (const Vec3& p : coarse.points) on_coarse.push_back(field(p));
  for (const Vec3& p : fine.points) on_fine.push_back(field(p));
  const std::vector<Vec3> carried = interpolate(map_onto(coarse, fine), on_coarse);
  for (size_t i = 0; i < carried.size(); ++i) ASSERT_NEAR((carried[i] - on_fine[i]).norm(), 0.0, 1e-12) << i;
  const WallDifference d = wall_difference(lumped_areas(fine), carried, on_fine);
  EXPECT_NEAR(d.l2, 0.0, 1e-12);
  EXPECT_NEAR(d.p95, 0.0, 1e-12);
}

TEST(WallDifference, MeasuresOverTheReferencesMean) {
  const TriMesh m = unit_square(10);
  const std::vector<double> area = lumped_areas(m);
  // The reference a uniform 2 Pa along x; the field off by (0, 0.5, 0) everywhere: |d| = 0.5, mean 2.
  const std::vector<Vec3> reference(m.points.size(), Vec3(2, 0, 0)), field(m.points.size(), Vec3(2, 0.5, 0));
  const WallDifference d = wall_difference(area, field, reference);
  EXPECT_NEAR(d.mean, 2.0, 1e-12);
  EXPECT_NEAR(d.l2, 0.25, 1e-12);
  EXPECT_NEAR(d.p95, 0.25, 1e-12);
  // Off by 1 on the points of x > 0.85 only (the strip's lumped area: 0.1 of the square less half a
  // column's, about 0.075 < 5 %, or 0.125 > 5 % with x > 0.75): the 95th percentile sees it or not.
  for (const double edge : {0.85, 0.75}) {
    std::vector<double> scalar_ref(m.points.size(), 2.0), scalar(m.points.size(), 2.0);
    double strip = 0.0;
    for (size_t i = 0; i < m.points.size(); ++i)
      if (m.points[i].x() > edge) {
        scalar[i] = 3.0;
        strip += area[i];
      }
    const WallDifference s = wall_difference(area, scalar, scalar_ref);
    EXPECT_NEAR(s.l2, std::sqrt(strip) / 2.0, 1e-12);
    EXPECT_DOUBLE_EQ(s.p95, strip > 0.05 ? 0.5 : 0.0) << edge << " " << strip;
  }
}

}  // namespace
}  // namespace vesselmesh::study
