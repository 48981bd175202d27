#include "post/wall_series.h"

#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace vesselmesh::post {
namespace {

// Three frames of a two-triangle wall with wss = (t, 2t, 0) per point, as simulate lists them.
void write_results(const test::TemporaryFolder& tmp) {
  TriMesh wall;
  wall.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}};
  std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n  <Collection>\n";
  const double times[] = {0.1, 0.2, 0.4};
  for (int k = 0; k < 3; ++k) {
    const std::string name = "wall_00000" + std::to_string(k) + ".vtp";
    io::write_vtp(tmp.path(name), wall, {Field::vector("wss", std::vector<Vec3>(4, Vec3(times[k], 2 * times[k], 0)))});
    pvd += "    <DataSet timestep=\"" + std::to_string(times[k]) + "\" group=\"\" part=\"0\" file=\"" + name + "\"/>\n";
  }
  test::write_bytes(tmp.path("wall.pvd"), pvd + "  </Collection>\n</VTKFile>\n");
  test::write_bytes(tmp.path("summary.json"),
                    R"({"units": {"points": "cm", "length_scale_m": 0.01}, "period": 0.3})");
}

TEST(WallSeries, ReadsTheFramesAndInterpolatesInTime) {
  test::TemporaryFolder tmp;
  write_results(tmp);
  const WallSeries s = read_wall_series(tmp.folder().string());
  ASSERT_EQ(s.frames.size(), 3u);
  EXPECT_DOUBLE_EQ(s.frames[1].time, 0.2);
  EXPECT_EQ(s.length_unit, "cm");
  EXPECT_DOUBLE_EQ(s.length_scale, 0.01);
  EXPECT_DOUBLE_EQ(s.period, 0.3);
  const WallField at = wall_at_time(s, 0.25);
  ASSERT_EQ(at.wss.size(), 4u);
  EXPECT_NEAR(at.wss[2].x(), 0.25, 1e-12);
  EXPECT_NEAR(at.wss[2].y(), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(at.time, 0.25);
  EXPECT_NEAR(wall_at_time(s, 0.4).wss[0].x(), 0.4, 1e-12);
  EXPECT_NEAR(wall_at_time(s, 0.1).wss[0].x(), 0.1, 1e-12);
  try {
    wall_at_time(s, 0.5);
    FAIL() << "beyond the saved span";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the saved results (0.1 to 0.4 s"), std::string::npos) << e.what();
  }
}

TEST(WallSeries, RefusesWhatIsNotASimulationsOutput) {
  test::TemporaryFolder tmp;
  EXPECT_THROW(read_wall_series(tmp.folder().string()), InputError);  // no wall.pvd
  test::write_bytes(tmp.path("wall.pvd"), "<VTKFile><Collection></Collection></VTKFile>");
  EXPECT_THROW(read_wall_series(tmp.folder().string()), InputError);  // no frames
  test::write_bytes(tmp.path("wall.pvd"), "<DataSet timestep=\"x1\" file=\"a.vtp\"/>");
  EXPECT_THROW(read_wall_series(tmp.folder().string()), InputError);  // a bad time
  // A frame without wss.
  TriMesh wall;
  wall.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)};
  wall.triangles = {{0, 1, 2}};
  io::write_vtp(tmp.path("a.vtp"), wall);
  test::write_bytes(tmp.path("wall.pvd"), "<DataSet timestep=\"0\" file=\"a.vtp\"/>");
  const WallSeries s = read_wall_series(tmp.folder().string());
  try {
    read_wall_frame(s.frames[0]);
    FAIL() << "no wss array";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no point data `wss`"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vesselmesh::post
