// The command-line tests of the post-processing of a flow's results: sample and wss.
#include "io/vtk_formats.h"
#include "test_support.h"

#include "cli_run.h"

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace vesselmesh {
namespace {

// `sample` (issue 9): Poiseuille's centreline velocity along a line and at a named point, the CSV's
// header and columns, the pressure falling along the flow, points outside the mesh counted; a time
// outside the saved results or nothing to sample: exit 2.
TEST(Cli, SampleReadsTheFlowAlongALineAndAtPoints) {
  test::TemporaryFolder tmp;
  ASSERT_EQ(run({"synth", "cylinder", "--radius", "2", "--length", "8", "--resolution", "0.4", "-o", tmp.path("p.stl"),
                 "-q"}).code, 0);
  ASSERT_EQ(run({"volume", tmp.path("p.stl"), "-o", tmp.path("pipe.msh"), "-q"}).code, 0);
  // examples/pipe_steady.toml: 1 mL/s of Poiseuille flow.
  std::string text = read_text(std::string(VESSELMESH_EXAMPLES_DIR) + "/pipe_steady.toml");
  const std::string mesh_path = "../build/pipe.msh";
  ASSERT_NE(text.find(mesh_path), std::string::npos);
  text.replace(text.find(mesh_path), mesh_path.size(), "pipe.msh");
  test::write_bytes(tmp.path("case.toml"), text);
  ASSERT_EQ(run({"simulate", tmp.path("case.toml"), "-o", tmp.path("out"), "-q"}).code, 0);
  const RunResult r = run({"sample", tmp.path("out"), "--line", "0,0,-1:0,0,9", "--samples", "11", "--point",
                           "middle:0,0,4", "-o", tmp.path("axis.csv"), "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.json()["outside"].get<int>(), 2);  // z = -1 and z = 9
  EXPECT_NE(r.err.find("2 of 12 sample(s) lie outside the mesh"), std::string::npos) << r.err;
  const double centre = 2.0 * 1e-6 / (std::numbers::pi * 4e-6);  // m/s: twice the mean, Q / (pi R^2)
  EXPECT_NEAR(r.json()["points"][0]["velocity"][2].get<double>(), centre, 0.03 * centre);
  std::istringstream csv(read_text(tmp.path("axis.csv")));
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find("lengths in mm, velocity in m/s, pressure in Pa"), std::string::npos) << line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("name,distance_mm,x_mm,y_mm,z_mm,inside,velocity_x_m_s", 0), 0u) << line;
  std::vector<double> pressure;
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    ASSERT_EQ(cells.size(), 11u) << line;
    if (cells[0] != "line" || cells[5] == "0") continue;
    const double z = std::stod(cells[4]);
    if (z > 1.0 && z < 7.0) {
      EXPECT_NEAR(std::stod(cells[8]), centre, 0.03 * centre) << line;
    }
    pressure.push_back(std::stod(cells[10]));
  }
  EXPECT_EQ(rows, 12);
  ASSERT_EQ(pressure.size(), 9u);
  for (size_t i = 1; i < pressure.size(); ++i) EXPECT_LT(pressure[i], pressure[i - 1]);  // falls along the flow
  const RunResult late = run({"sample", tmp.path("out"), "--point", "a:0,0,4", "--time", "2", "-o", tmp.path("x.csv")});
  EXPECT_EQ(late.code, 2);
  EXPECT_NE(last_line(late.err).find("outside the saved results"), std::string::npos) << late.err;
  EXPECT_EQ(run({"sample", tmp.path("out"), "-o", tmp.path("x.csv")}).code, 2);  // nothing to sample
}

// Issue 9: rings, points, a time between saved frames and the indices from a simulation's output.
TEST(Cli, WssReadsRingsPointsAndIndicesFromResults) {
  test::TemporaryFolder tmp;
  ExampleCase example(tmp, "pipe.msh", {}, "0.02");
  example.replace("save_every = 10", "save_every = 1");
  test::write_bytes(tmp.path("case.toml"), example.text);
  ASSERT_EQ(run({"simulate", tmp.path("case.toml"), "-o", tmp.path("out"), "-q"}).code, 0);
  // simulate wrote the indices over the whole run (the case gives no period).
  ASSERT_TRUE(std::filesystem::exists(tmp.path("out/indices.vtp")));
  const io::SurfaceData indices = io::read_vtk_surface(tmp.path("out/indices.vtp"), io::VtkFormat::vtp);
  std::vector<std::string> names;
  for (const Field& f : indices.point_data) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"tawss", "osi", "rrt", "twssg", "mean_wss"}));
  const Json summary = Json::parse(read_text(tmp.path("out/summary.json")));
  EXPECT_EQ(summary["indices"]["units"]["tawss"], "Pa");
  EXPECT_NEAR(summary["indices"]["end_s"].get<double>(), 0.02, 1e-9);

  const RunResult r = run({"wss", tmp.path("out"), "-o", tmp.path("wss"), "--time", "0.0125", "--ring",
                           "mid:0,0,4:0,0,1", "--ring", "onaxis:0.3,0.1,5", "--point", "A:2.5,0,3", "--indices",
                           "0:1", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = r.json();
  EXPECT_DOUBLE_EQ(j["time_s"].get<double>(), 0.0125);
  ASSERT_EQ(j["rings"].size(), 2u);
  for (const Json& ring : j["rings"]) {
    EXPECT_TRUE(ring["closed"].get<bool>());
    EXPECT_NEAR(ring["length"].get<double>(), 2 * 3.14159265 * 2.0, 0.03 * 2 * 3.14159265 * 2.0) << ring["name"];
    const double least = ring["minimum"]["wss_magnitude"].get<double>();
    EXPECT_GT(least, 0.0);
    EXPECT_LE(least, ring["mean_wss_magnitude"].get<double>());
  }
  // The centerline ring is normal to the pipe's axis.
  EXPECT_NEAR(std::abs(j["rings"][1]["normal"][2].get<double>()), 1.0, 1e-3);
  EXPECT_NEAR(j["rings"][1]["centroid"][2].get<double>(), 5.0, 0.1);
  ASSERT_EQ(j["points"].size(), 1u);
  EXPECT_NEAR(j["points"][0]["distance"].get<double>(), 0.5, 0.05);
  EXPECT_EQ(j["indices"]["frames"].get<int>(), 4);  // steps 1 to 4
  for (const char* file : {"wall_at_time.vtp", "rings.vtp", "ring_mid.csv", "ring_mid.svg", "ring_mid.png",
                           "ring_mid_angle.svg", "ring_mid_angle.png", "ring_onaxis.csv", "points.csv", "indices.vtp",
                           "wss.json"})
    EXPECT_TRUE(std::filesystem::exists(tmp.path(std::string("wss/") + file))) << file;
  const std::string csv = read_text(tmp.path("wss/ring_mid.csv"));
  EXPECT_EQ(static_cast<size_t>(std::count(csv.begin(), csv.end(), '\n')), j["rings"][0]["samples"].get<size_t>() + 2);
  EXPECT_NE(csv.find("arc_length_mm,angle_deg"), std::string::npos);

  // Between frames 2 (t = 0.01) and 3 (t = 0.015): the mean of the two.
  const auto wss = [&](const std::string& file) {
    for (const Field& f : io::read_vtk_surface(file, io::VtkFormat::vtp).point_data)
      if (f.name == "wss") return f.values;
    return std::vector<double>{};
  };
  const std::vector<double> a = wss(tmp.path("out/wall_000001.vtp")), b = wss(tmp.path("out/wall_000002.vtp")),
                            mid = wss(tmp.path("wss/wall_at_time.vtp"));
  ASSERT_EQ(mid.size(), a.size());
  ASSERT_FALSE(mid.empty());
  for (size_t i = 0; i < mid.size(); i += 97) EXPECT_NEAR(mid[i], 0.5 * (a[i] + b[i]), 1e-12 + 1e-9 * std::abs(a[i]));

  // Bad requests: exit 2, what is wrong said, nothing written.
  const RunResult late = run({"wss", tmp.path("out"), "-o", tmp.path("late"), "--time", "9"});
  EXPECT_EQ(late.code, 2);
  EXPECT_NE(late.err.find("outside the saved results"), std::string::npos) << late.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.path("late")));
  const RunResult bad = run({"wss", tmp.path("out"), "-o", tmp.path("bad"), "--ring", "mid:0,0"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("is not a point"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.path("bad")));
  const RunResult miss = run({"wss", tmp.path("out"), "-o", tmp.path("miss"), "--ring", "far:0,0,50:0,0,1"});
  EXPECT_EQ(miss.code, 2);
  EXPECT_NE(last_line(miss.err).find("ring far"), std::string::npos) << miss.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.path("miss")));  // nothing written, not even the wall
  const RunResult window = run({"wss", tmp.path("out"), "-o", tmp.path("window"), "--indices", "0:1x"});
  EXPECT_EQ(window.code, 2);
  EXPECT_FALSE(std::filesystem::exists(tmp.path("window")));
}

}  // namespace
}  // namespace vesselmesh
