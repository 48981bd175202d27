#include "study/view3d.h"

#include "io/atomic_file.h"
#include "io/base64.h"
#include "study/picture.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <numbers>

namespace vesselmesh::study {
namespace {

std::vector<float> floats_of(const std::string& text) {
  const std::string bytes = io::decode_base64(text);
  std::vector<float> v(bytes.size() / sizeof(float));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(float));
  return v;
}

// The JSON the page holds (between the data script's tags).
nlohmann::json page_data(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"view3d-data\">";
  const size_t from = html.find(open) + open.size();
  std::string text = html.substr(from, html.find("</script>", from) - from);
  for (size_t at = text.find("<\\/"); at != std::string::npos; at = text.find("<\\/", at)) text.replace(at, 3, "</");
  return nlohmann::json::parse(text);
}

// A pipe of radius 3 along z, |WSS| = 1 + z / 10 Pa on it (z from 0 to 30 mm).
ViewedWall pipe(const std::string& name, double resolution, double offset) {
  const TriMesh wall = synth::cylinder({.radius = 3.0, .length = 30.0, .resolution = resolution});
  std::vector<double> magnitude;
  for (const Vec3& p : wall.points) magnitude.push_back(1.0 + p.z() / 10.0 + offset);
  return viewed_wall(name, wall, magnitude);
}

// A compared wall's |WSS| on the reference's wall, minus the reference's: the field is linear along
// the pipe, so its difference is the offset at every point of the reference, whatever the meshes.
TEST(View3d, DifferencesAreTakenOnTheReferencesWall) {
  const ViewedWall reference = pipe("reference", 0.4, 0.0);
  const TriMesh coarse = synth::cylinder({.radius = 3.0, .length = 30.0, .resolution = 1.0});
  std::vector<double> magnitude;
  for (const Vec3& p : coarse.points) magnitude.push_back(1.5 + p.z() / 10.0);
  const std::vector<double> d = difference_on(reference, coarse, magnitude);
  ASSERT_EQ(d.size(), reference.mesh.points.size());
  for (double v : d) EXPECT_NEAR(v, 0.5, 0.02);
}

// A wall over the display count is made coarser and its field moved onto the coarser wall.
TEST(View3d, LargeWallsAreShownCoarserWithTheirField) {
  const TriMesh wall = synth::cylinder({.radius = 3.0, .length = 30.0, .resolution = 0.2});
  std::vector<double> magnitude;
  for (const Vec3& p : wall.points) magnitude.push_back(1.0 + p.z() / 10.0);
  const ViewedWall v = viewed_wall("fine", wall, magnitude, 3000);
  EXPECT_LE(v.mesh.num_triangles(), 3000);
  ASSERT_EQ(v.magnitude.size(), v.mesh.points.size());
  for (size_t i = 0; i < v.magnitude.size(); ++i) EXPECT_NEAR(v.magnitude[i], 1.0 + v.mesh.points[i].z() / 10.0, 0.01);
}

// The page: a canvas per wall, the data that draws them (points as float32, the differences on the
// reference's points), names that cannot close a script element, both colour legends.
TEST(View3d, ThePageHoldsEveryWallAndItsData) {
  ViewScene scene;
  scene.walls = {pipe("uniform </script><b>", 1.0, 0.3), pipe("reference", 0.6, 0.0)};
  scene.reference = 1;
  scene.walls[0].difference = difference_on(scene.walls[1], scene.walls[0].mesh, scene.walls[0].magnitude);
  scene.walls[0].rings = {{Vec3(3, 0, 10), Vec3(0, 3, 10), Vec3(-3, 0, 10)}};
  scene.points = {{"A", Vec3(3, 0, 15)}};
  scene.high = 4.0;
  scene.difference_range = 0.5;
  const std::string html = view3d_html(scene, {"/* three */", "/* controls */"});
  EXPECT_NE(html.find("id=\"view3d-canvas-0\""), std::string::npos);
  EXPECT_NE(html.find("id=\"view3d-canvas-1\""), std::string::npos);
  EXPECT_EQ(html.find("id=\"view3d-canvas-2\""), std::string::npos);
  EXPECT_NE(html.find("reference (reference)"), std::string::npos);
  EXPECT_EQ(html.find("</script><b>"), std::string::npos);  // the name escaped in the caption and in the data
  EXPECT_NE(html.find("id=\"view3d-legend-wss\""), std::string::npos);
  EXPECT_NE(html.find("id=\"view3d-legend-difference\""), std::string::npos);
  const nlohmann::json data = page_data(html);
  ASSERT_EQ(data["walls"].size(), 2u);
  EXPECT_EQ(data["walls"][0]["name"], "uniform </script><b>");
  EXPECT_EQ(data["reference"], 1);
  const std::vector<float> points = floats_of(data["walls"][1]["points"]);
  ASSERT_EQ(points.size(), 3 * scene.walls[1].mesh.points.size());
  for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(points[k], static_cast<float>(scene.walls[1].mesh.points[0][k]));
  EXPECT_EQ(floats_of(data["walls"][0]["difference"]).size(), scene.walls[1].mesh.points.size());
  EXPECT_FALSE(data["walls"][1].contains("difference"));
  EXPECT_EQ(floats_of(data["walls"][0]["rings"][0]).size(), 9u);
  EXPECT_EQ(data["points"][0]["name"], "A");
  EXPECT_DOUBLE_EQ(data["high"].get<double>(), 4.0);
  EXPECT_EQ(data["wss_table"].size(), 3u * 33u);
}

}  // namespace

TEST(View3d, ChromiumDrawsEveryViewInTheScalesColours) {
  const std::optional<ThreeScripts> scripts = read_three_scripts();
  if (!scripts) GTEST_SKIP() << "three.js is not installed (apt-get install libjs-three)";
  ViewScene scene;
  scene.walls = {pipe("compared", 1.0, 0.3), pipe("reference", 0.6, 0.0)};
  scene.reference = 1;
  scene.walls[0].difference = difference_on(scene.walls[1], scene.walls[0].mesh, scene.walls[0].magnitude);
  scene.points = {{"A", Vec3(3, 0, 15)}};
  scene.high = 4.3;
  scene.difference_range = 0.4;
  scene.view = Vec3::UnitY();
  test::TemporaryFolder tmp;
  io::write_text(tmp.path("page.html"), "<!DOCTYPE html><html><head><meta charset=\"utf-8\"></head><body><h1>A "
                                        "page</h1>\n" + view3d_html(scene, *scripts) + "</body></html>\n");
  test::expect_views_drawn(tmp.path("page.html"), 2);
}

}  // namespace vesselmesh::study
