#include "post/fluid_sample.h"

#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <random>

namespace vesselmesh::post {
namespace {

// A box [0, 2] x [0, 1] x [0, 3] of n x n x n cubes, each cut into six tetrahedra (Kuhn).
TetMesh box(int n) { return test::kuhn_box({n, n, n}, Vec3(2.0, 1.0, 3.0)); }

Vec3 velocity_at(const Vec3& p) { return Vec3(p.x() + 2 * p.y(), 3 * p.z() - p.x(), 0.5 + p.y()); }
double pressure_at(const Vec3& p) { return 3 * p.x() - p.z() + 7; }

FluidField linear_field(int n) {
  FluidField field;
  field.mesh = box(n);
  for (const Vec3& p : field.mesh.points) {
    field.velocity.push_back(velocity_at(p));
    field.pressure.push_back(pressure_at(p));
  }
  return field;
}

TEST(FluidSample, LinearFieldsAreExactEverywhereInside) {
  const FluidField field = linear_field(5);
  const TetLocator locator(field.mesh);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < 500; ++i) points.emplace_back(2 * unit(random), unit(random), 3 * unit(random));
  points.emplace_back(0.0, 0.0, 0.0);  // a corner
  points.emplace_back(2.0, 0.5, 1.2);  // on a face of the box
  points.emplace_back(0.8, 0.4, 1.2);  // on grid planes: faces shared by several tetrahedra
  const std::vector<FluidSample> samples = sample_points(field, locator, points);
  ASSERT_EQ(samples.size(), points.size());
  for (const FluidSample& s : samples) {
    ASSERT_TRUE(s.inside) << s.point.transpose();
    EXPECT_LT((s.velocity - velocity_at(s.point)).norm(), 1e-12) << s.point.transpose();
    EXPECT_NEAR(s.pressure, pressure_at(s.point), 1e-12) << s.point.transpose();
  }
}

TEST(FluidSample, PointsOutsideAreMarkedAndTheLineIsEvenlySpaced) {
  const FluidField field = linear_field(4);
  const TetLocator locator(field.mesh);
  // From outside (x < 0) through the box and out again (x > 2): 21 samples, 0.15 apart.
  const std::vector<FluidSample> line = sample_line(field, locator, Vec3(-0.5, 0.5, 1.0), Vec3(2.5, 0.5, 1.0), 21);
  ASSERT_EQ(line.size(), 21u);
  for (size_t i = 0; i < line.size(); ++i) {
    EXPECT_NEAR(line[i].distance, 0.15 * i, 1e-12);
    const double x = line[i].point.x();
    EXPECT_EQ(line[i].inside, x >= 0.0 && x <= 2.0) << x;
    if (line[i].inside) EXPECT_NEAR(line[i].pressure, pressure_at(line[i].point), 1e-12);
    else EXPECT_EQ(line[i].pressure, 0.0);
  }
  EXPECT_FALSE(locator.locate(Vec3(1.0, 0.5, 3.5)).has_value());
  EXPECT_FALSE(locator.locate(Vec3(1.0, -1e-3, 1.0)).has_value());
  EXPECT_THROW(sample_line(field, locator, Vec3::Zero(), Vec3::Ones(), 1), OptionError);
}

TEST(FluidSample, ReadsTheSolversFluidFramesBack) {
  test::TemporaryFolder tmp;
  const FluidField field = linear_field(3);
  io::write_vtu(tmp.path("fluid_000000.vtu"), field.mesh,
                {Field::vector("velocity", field.velocity), Field::scalar("pressure", field.pressure)});
  test::write_bytes(tmp.path("fluid.pvd"),
                    "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n  <Collection>\n"
                    "    <DataSet timestep=\"0.5\" group=\"\" part=\"0\" file=\"fluid_000000.vtu\"/>\n"
                    "  </Collection>\n</VTKFile>\n");
  const WallSeries series = read_wall_series(tmp.folder().string(), "fluid");
  ASSERT_EQ(series.frames.size(), 1u);
  const FluidField back = read_fluid_frame(series.frames[0]);
  EXPECT_DOUBLE_EQ(back.time, 0.5);
  ASSERT_EQ(back.velocity.size(), field.velocity.size());
  ASSERT_EQ(back.mesh.tets.size(), field.mesh.tets.size());
  const TetLocator locator(back.mesh);
  const FluidSample s = sample_points(back, locator, {Vec3(1.3, 0.2, 2.9)})[0];
  ASSERT_TRUE(s.inside);
  EXPECT_LT((s.velocity - velocity_at(s.point)).norm(), 1e-12);
  // A volume without the solver's fields is refused by name.
  io::write_vtu(tmp.path("bare.vtu"), field.mesh);
  try {
    read_fluid_frame({0.0, tmp.path("bare.vtu")});
    FAIL() << "a volume without velocity and pressure";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no point data `velocity`"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vesselmesh::post
