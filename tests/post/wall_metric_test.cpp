#include "post/wall_metric.h"

#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace vesselmesh::post {
namespace {

// A pipe's wall (radius 3, 10 long, in cm as the summary says) with an axial WSS of
// `amplitude[k] * z^2` Pa at the k-th saved time (0.1, 0.2, 0.4 s).
void write_results(const test::TemporaryFolder& tmp, const TriMesh& wall,
                   const std::vector<double>& amplitude, const std::string& period) {
  std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n  <Collection>\n";
  const double times[] = {0.1, 0.2, 0.4};
  for (size_t k = 0; k < amplitude.size(); ++k) {
    std::vector<Vec3> wss;
    for (const Vec3& p : wall.points) wss.push_back(Vec3(0, 0, amplitude[k] * p.z() * p.z()));
    const std::string name = "wall_00000" + std::to_string(k) + ".vtp";
    io::write_vtp(tmp.path(name), wall, {Field::vector("wss", wss)});
    pvd += "    <DataSet timestep=\"" + std::to_string(times[k]) +
           "\" group=\"\" part=\"0\" file=\"" + name + "\"/>\n";
  }
  test::write_bytes(tmp.path("wall.pvd"), pvd + "  </Collection>\n</VTKFile>\n");
  test::write_bytes(tmp.path("summary.json"),
                    R"({"units": {"points": "cm", "length_scale_m": 0.01})" + period + "}");
}

TEST(WallMetric, BoundsTheSavedTimesOfTheLastPeriodAlongTheFlow) {
  const TriMesh wall =
      synth::cylinder({.radius = 3.0, .length = 10.0, .resolution = 0.5, .jitter = 0.3});
  test::TemporaryFolder tmp;
  write_results(tmp, wall, {1.0, 5.0, 2.0}, R"(, "period": 0.3)");
  const sizing::ErrorMetricOptions no_det{.p = INFINITY, .floor = 1e-6};
  const WallMetric m = wall_error_metric(tmp.folder().string(), {}, no_det);
  EXPECT_EQ(m.times, (std::vector<double>{0.1, 0.2, 0.4}));  // the last period: from 0.4 - 0.3
  ASSERT_EQ(m.wall.points.size(), wall.points.size());
  EXPECT_NEAR(m.wall.points[7].z(), 10.0 * wall.points[7].z(), 1e-12);  // cm -> mm
  // Along the axis: the largest amplitude's 2 x 5 Pa/cm^2, i.e. 0.1 Pa/mm^2; round it, the floor.
  int checked = 0;
  for (size_t v = 0; v < wall.points.size(); ++v) {
    const Vec3& p = wall.points[v];
    if (p.z() < 1.0 || p.z() > 9.0) continue;  // the open ends' one-sided fits
    const Vec3 round = Vec3(-p.y(), p.x(), 0).normalized();
    EXPECT_NEAR(m.metric[v].form(Vec3::UnitZ(), Vec3::UnitZ()), 0.1, 0.01) << v;
    EXPECT_LT(m.metric[v].form(round, round), 1e-3) << v;
    ++checked;
  }
  EXPECT_GT(checked, 100);
  // A steady flow (no period): its last frame; given times: the walls interpolated there.
  test::TemporaryFolder steady;
  write_results(steady, wall, {1.0, 5.0, 2.0}, "");
  EXPECT_EQ(wall_error_metric(steady.folder().string(), {}, no_det).times,
            std::vector<double>{0.4});
  const WallMetric at = wall_error_metric(steady.folder().string(), {0.15}, no_det);  // amplitude 3
  EXPECT_NEAR(at.metric[wall.points.size() / 2].form(Vec3::UnitZ(), Vec3::UnitZ()), 0.06, 0.006);
  EXPECT_THROW(wall_error_metric(steady.folder().string(), {0.5}),
               InputError);  // beyond the saved times
}

TEST(WallMetric, RefusesFramesOnDifferentWallsAndAUniformWss) {
  const TriMesh wall = synth::cylinder({.radius = 3.0, .length = 10.0, .resolution = 0.5});
  test::TemporaryFolder tmp;
  write_results(tmp, wall, {1.0, 2.0}, R"(, "period": 1.0)");
  const TriMesh other = synth::cylinder({.radius = 3.0, .length = 10.0, .resolution = 0.6});
  io::write_vtp(tmp.path("wall_000001.vtp"), other,
                {Field::vector("wss", std::vector<Vec3>(other.points.size(), Vec3::Zero()))});
  EXPECT_THROW(wall_error_metric(tmp.folder().string(), {}), InputError);
  test::TemporaryFolder uniform;
  write_results(uniform, wall, {0.0}, "");
  EXPECT_THROW(wall_error_metric(uniform.folder().string(), {}), InputError);
}

TEST(WallMetric, FirstLayerHeightsAreTheViscousLengthOfTheLargestShear) {
  // WSS amplitude z^2 at 0.1 s, 5 z^2 at 0.2 s (z in cm): the largest 5 z^2 Pa; rho 1000, mu 0.004:
  // y = y+ mu / sqrt(rho 5 z^2) metres, in mm.
  const TriMesh wall = synth::cylinder({.radius = 3.0, .length = 10.0, .resolution = 0.5, .jitter = 0.3});
  test::TemporaryFolder tmp;
  write_results(tmp, wall, {1.0, 5.0},
                R"(, "fluid": {"density_kg_m3": 1000.0, "viscosity_Pa_s": 0.004})");
  const WallHeights h = first_layer_heights(tmp.folder().string(), {}, 2.0);
  ASSERT_EQ(h.heights.size(), wall.points.size());
  ASSERT_EQ(h.times.size(), 1u) << "a steady flow's last frame alone";
  EXPECT_NEAR(h.times[0], 0.2, 1e-12);
  const std::function<double(const Vec3&)> at = height_function(h);
  for (size_t v = 0; v < wall.points.size(); ++v) {
    const double z = wall.points[v].z();
    if (z < 1.0) continue;  // the shear vanishes at z = 0: no height asked (a huge one)
    const double expected = 2.0 * 0.004 / std::sqrt(1000.0 * 5.0 * z * z) / 1e-3;
    EXPECT_NEAR(h.heights[v], expected, 1e-9 * expected) << "at z = " << z;
    EXPECT_NEAR(h.wall.points[v].z(), 10.0 * z, 1e-9) << "the wall in mm";
    EXPECT_NEAR(at(h.wall.points[v]), expected, 1e-6 * expected) << "the field at the wall point";
  }
  // Linear over the closest triangle: at a triangle's centroid, 0.5 mm outside it, its corners' mean.
  for (const Triangle& t : h.wall.triangles) {
    const Vec3 a = h.wall.points[t[0]], b = h.wall.points[t[1]], c = h.wall.points[t[2]];
    const Vec3 outward = (b - a).cross(c - a).normalized();
    const double mean = (h.heights[t[0]] + h.heights[t[1]] + h.heights[t[2]]) / 3.0;
    EXPECT_NEAR(at((a + b + c) / 3.0 + 0.5 * outward), mean, 1e-9 * mean);
  }
  // Both frames bounded together (the times given): the largest shear of the two.
  EXPECT_EQ(first_layer_heights(tmp.folder().string(), {0.1, 0.2}).times.size(), 2u);
  EXPECT_THROW(first_layer_heights(tmp.folder().string(), {}, 0.0), OptionError);
  write_results(tmp, wall, {1.0}, "");  // a summary that names no fluid: the caller's (the study's case), or none
  EXPECT_THROW(first_layer_heights(tmp.folder().string(), {}), InputError);
  const WallHeights given =
      first_layer_heights(tmp.folder().string(), {}, 1.0, {.density = 4000.0, .viscosity = 0.004});
  for (size_t v = 0; v < wall.points.size(); ++v)
    if (wall.points[v].z() > 1.0) {  // |WSS| = z^2: y = mu / sqrt(rho z^2)
      EXPECT_NEAR(given.heights[v], 0.004 / std::sqrt(4000.0) / wall.points[v].z() / 1e-3, 1e-12);
    }
  // A flow made before the summary named its fluid: the case file it names, where that still reads.
  test::write_bytes(tmp.path("case.toml"), "mesh = \"m.msh\"\n[fluid]\ndensity = 4000\nviscosity = 0.004\n"
                                           "[time]\nsteady = true\n[[boundary]]\ntag = \"wall\"\ntype = \"wall\"\n");
  write_results(tmp, wall, {1.0}, ", \"case\": \"" + tmp.path("case.toml") + "\"");
  EXPECT_EQ(first_layer_heights(tmp.folder().string(), {}).heights, given.heights);
  write_results(tmp, wall, {1.0}, ", \"case\": \"" + tmp.path("gone.toml") + "\"");
  EXPECT_THROW(first_layer_heights(tmp.folder().string(), {}), InputError);
}

}  // namespace
}  // namespace vesselmesh::post
