#include "io/surface.h"

#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace vesselmesh::io {
namespace {

class CountingReporter : public Reporter {
 public:
  void warning(std::string_view message) const override { warnings.emplace_back(message); }
  mutable std::vector<std::string> warnings;
};

TEST(Surface, FormatComesFromTheExtension) {
  EXPECT_EQ(surface_format("a/b.STL"), SurfaceFormat::stl);
  EXPECT_EQ(surface_format("x.vtp"), SurfaceFormat::vtp);
  EXPECT_EQ(surface_format("x.msh"), SurfaceFormat::msh);
  EXPECT_THROW(surface_format("x.step"), OptionError);
  EXPECT_THROW(surface_format("noextension"), OptionError);
}

TEST(Surface, UnitsScaleToMillimetres) {
  test::TemporaryFolder tmp;
  const TriMesh m = test::tetrahedron();
  write_surface(tmp.path("t.vtp"), m);
  const SurfaceFile cm = read_surface(tmp.path("t.vtp"), {.units = Unit::cm});
  EXPECT_EQ(cm.scale_to_mm, 10.0);
  EXPECT_TRUE(cm.unit_given);
  EXPECT_EQ(cm.mesh.points[0], Vec3(10, 10, 10));
  const SurfaceFile m_ = read_surface(tmp.path("t.vtp"), {.units = parse_unit("m")});
  EXPECT_EQ(m_.mesh.points[1], Vec3(1000, -1000, -1000));
}

TEST(Surface, UnitNames) {
  EXPECT_EQ(parse_unit("MM"), Unit::mm);
  EXPECT_EQ(parse_unit("micron"), Unit::um);
  EXPECT_EQ(millimetres_per(Unit::um), 1e-3);
  EXPECT_THROW(parse_unit("ft"), OptionError);
  EXPECT_THROW(parse_unit(""), OptionError);
}

TEST(Surface, TinySurfaceWithoutUnitGetsAWarning) {
  test::TemporaryFolder tmp;
  write_surface(tmp.path("t.stl"), test::tetrahedron(Vec3::Zero(), 0.01));
  CountingReporter reporter;
  read_surface(tmp.path("t.stl"), {}, reporter);
  ASSERT_EQ(reporter.warnings.size(), 1u);
  EXPECT_NE(reporter.warnings[0].find("--units m"), std::string::npos);
  reporter.warnings.clear();
  read_surface(tmp.path("t.stl"), {.units = Unit::m}, reporter);
  EXPECT_TRUE(reporter.warnings.empty());
}

TEST(Surface, EveryWritableFormatReadsBack) {
  test::TemporaryFolder tmp;
  const TriMesh m = synth::sphere({.radius = 2.0, .resolution = 0.8});
  for (const std::string name : {"s.stl", "s.vtp", "s.msh"}) {
    write_surface(tmp.path(name), m);
    const SurfaceFile back = read_surface(tmp.path(name));
    EXPECT_EQ(back.mesh.num_triangles(), m.num_triangles()) << name;
    EXPECT_EQ(back.mesh.num_points(), m.num_points()) << name;
  }
  EXPECT_THROW(write_surface(tmp.path("s.ply"), m), OptionError);
  EXPECT_THROW(read_surface(tmp.path("missing.stl")), InputError);
}

}  // namespace
}  // namespace vesselmesh::io
