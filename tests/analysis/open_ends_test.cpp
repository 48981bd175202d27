#include "analysis/open_ends.h"

#include "io/surface.h"
#include "mesh/clean.h"
#include "synth/bifurcation.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

namespace vesselmesh::analysis {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(OpenEnds, OpenPipeHasTwoEndsWithOutwardNormals) {
  const double R = 3.0, L = 12.0;
  const TriMesh m = synth::cylinder({.radius = R, .length = L, .resolution = 0.5});
  const auto ends = open_ends(m);
  ASSERT_EQ(ends.size(), 2u);
  const int n = static_cast<int>(ends[0].loop.size());
  // A regular n-gon inscribed in the circle: exact area, perimeter and centre.
  const double polygon_area = 0.5 * n * R * R * std::sin(2 * kPi / n);
  for (const OpenEnd& e : ends) {
    EXPECT_FALSE(e.capped);
    EXPECT_NEAR(e.area, polygon_area, 1e-9 * polygon_area);
    EXPECT_NEAR(e.radius, std::sqrt(polygon_area / kPi), 1e-9);
    EXPECT_NEAR(e.perimeter, 2 * n * R * std::sin(kPi / n), 1e-9);
    EXPECT_NEAR(e.center.head<2>().norm(), 0.0, 1e-9);
    const bool top = e.center.z() > L / 2;
    EXPECT_NEAR(e.center.z(), top ? L : 0.0, 1e-9);
    EXPECT_NEAR(e.normal.z(), top ? 1.0 : -1.0, 1e-12) << "normals point out of the lumen";
  }
}

TEST(OpenEnds, ClosedSurfaceWithoutCreasesHasNoEnds) {
  EXPECT_TRUE(open_ends(synth::sphere({.radius = 2.0, .resolution = 0.3, .jitter = 0.3})).empty());
  EXPECT_TRUE(open_ends(synth::torus({.resolution = 0.8})).empty());
}

TEST(OpenEnds, FlatCapsAreFoundWithTheirLabels) {
  const double R = 2.0, L = 10.0;
  const TriMesh m = synth::cylinder({.radius = R, .length = L, .resolution = 0.4, .capped = true, .jitter = 0.2});
  const auto ends = open_ends(m);
  ASSERT_EQ(ends.size(), 2u);
  for (const OpenEnd& e : ends) {
    EXPECT_TRUE(e.capped);
    const bool top = e.center.z() > L / 2;
    EXPECT_EQ(e.label, top ? 3 : 2);
    EXPECT_NEAR(e.center.z(), top ? L : 0.0, 1e-9);
    EXPECT_NEAR(e.center.head<2>().norm(), 0.0, 1e-9);
    EXPECT_NEAR(e.normal.z(), top ? 1.0 : -1.0, 1e-12);
    EXPECT_NEAR(e.radius, R, 0.01 * R);
    EXPECT_FALSE(e.cap_triangles.empty());
    for (int t : e.cap_triangles) EXPECT_EQ(m.labels[t], e.label);
  }
  // Without cap detection a closed surface has no ends.
  EXPECT_TRUE(open_ends(m, {.detect_caps = false}).empty());
}

TEST(OpenEnds, BifurcationEndsMatchTheirTubes) {
  const synth::BifurcationOptions options{.radius = 3.0, .daughter_radius = {2.0, 2.5}, .angle_deg = {40.0, 30.0},
                                          .resolution = 0.4};
  const TriMesh m = synth::bifurcation(options);
  const auto ends = open_ends(m);
  ASSERT_EQ(ends.size(), 3u);
  const auto tubes = synth::bifurcation_ends(options);
  // Largest first: parent (3.0), daughter 2 (2.5), daughter 1 (2.0).
  const int order[3] = {0, 2, 1};
  for (int i = 0; i < 3; ++i) {
    const synth::TubeEnd& tube = tubes[order[i]];
    EXPECT_NEAR(ends[i].radius, tube.radius, 0.02 * tube.radius) << "end " << i;
    EXPECT_NEAR((ends[i].center - tube.center).norm(), 0.0, 0.02 * tube.radius) << "end " << i;
    EXPECT_GT(ends[i].normal.dot(tube.normal), std::cos(kPi / 180.0)) << "end " << i;
  }
}

struct VesselCase {
  const char* file;
  const char* units;
  int open;
  int capped;
  friend void PrintTo(const VesselCase& c, std::ostream* os) { *os << c.file; }
};

class RealVessels : public ::testing::TestWithParam<VesselCase> {};

TEST_P(RealVessels, EndsAreFound) {
  const VesselCase c = GetParam();
  VESSELMESH_REQUIRE_SHARED(path, std::string("vessels/") + c.file);
  io::SurfaceFile file = io::read_surface(path, {.units = io::parse_unit(c.units)});
  const mesh::CleanReport report = mesh::clean(file.mesh);
  const auto ends = open_ends(file.mesh);
  int open = 0, capped = 0;
  for (const OpenEnd& e : ends) (e.capped ? capped : open)++;
  EXPECT_EQ(open, c.open);
  EXPECT_EQ(capped, c.capped);
  for (size_t i = 1; i < ends.size(); ++i) EXPECT_GE(ends[i - 1].area, ends[i].area);
  // Every end's normal points out of the lumen: from the surface's centre towards the end.
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : file.mesh.points) centre += p;
  centre /= file.mesh.num_points();
  for (const OpenEnd& e : ends) EXPECT_GT(e.normal.dot(e.center - centre), 0.0);
}

INSTANTIATE_TEST_SUITE_P(
    SharedData, RealVessels,
    ::testing::Values(VesselCase{"vmtk_aorta_iliac_bifurcation_open_mm.stl", "mm", 3, 0},
                      VesselCase{"vmtk_aorta_iliac_bifurcation_closed_mm.stl", "mm", 0, 0},
                      VesselCase{"gmsh_aortic_arch_open_cm.stl", "cm", 5, 0},
                      VesselCase{"gmsh_carotid_bifurcation_open_m.stl", "m", 3, 0},
                      VesselCase{"simvascular_demo_aorta_iliacs_capped_cm.stl", "cm", 0, 3}),
    [](const auto& param_info) { return test::test_name(param_info.param.file); });

TEST(OpenEnds, SimVascularCapsSitAtTheirLabelledFaces) {
  VESSELMESH_REQUIRE_SHARED(stl, "vessels/simvascular_demo_aorta_iliacs_capped_cm.stl");
  VESSELMESH_REQUIRE_SHARED(vtp, "vessels/simvascular_demo_aorta_iliacs_capped_cm.vtp");
  // Reference: the area centroids of the ModelFaceID 3, 4, 5 faces of the labelled model.
  io::SurfaceFile labelled = io::read_surface(vtp, {.units = io::Unit::cm});
  std::map<int, Vec3> weighted;
  std::map<int, double> area;
  for (int t = 0; t < labelled.mesh.num_triangles(); ++t) {
    const Triangle& f = labelled.mesh.triangles[t];
    const Vec3& a = labelled.mesh.points[f[0]];
    const double w = 0.5 * (labelled.mesh.points[f[1]] - a).cross(labelled.mesh.points[f[2]] - a).norm();
    // try_emplace: a map's Vec3 made by operator[] is not zeroed (Eigen leaves it unset).
    weighted.try_emplace(labelled.mesh.labels[t], Vec3::Zero()).first->second +=
        w * (a + labelled.mesh.points[f[1]] + labelled.mesh.points[f[2]]) / 3.0;
    area[labelled.mesh.labels[t]] += w;
  }
  io::SurfaceFile file = io::read_surface(stl, {.units = io::Unit::cm});
  mesh::clean(file.mesh);
  const auto ends = open_ends(file.mesh);
  ASSERT_EQ(ends.size(), 3u);
  for (int label : {3, 4, 5}) {
    const Vec3 reference = weighted[label] / area[label];
    double nearest = 1e300;
    for (const OpenEnd& e : ends) nearest = std::min(nearest, (e.center - reference).norm());
    EXPECT_LT(nearest, 1.0) << "cap of ModelFaceID " << label << " (mm)";
  }
  // Read from the labelled file, each cap carries its face's label.
  mesh::clean(labelled.mesh);
  const auto labelled_ends = open_ends(labelled.mesh);
  ASSERT_EQ(labelled_ends.size(), 3u);
  EXPECT_EQ(labelled_ends[0].label, 3);  // the aortic inlet is the largest
  EXPECT_EQ(labelled_ends[1].label, 4);
  EXPECT_EQ(labelled_ends[2].label, 5);
}

}  // namespace
}  // namespace vesselmesh::analysis
