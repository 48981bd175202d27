#include "study/adaptation.h"

#include "flow/case.h"
#include "io/atomic_file.h"
#include "io/surface.h"
#include "io/volume_file.h"
#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace vesselmesh::study {
namespace {

// The mean axial position of a volume's boundary triangles tagged `name`.
double tag_z(const TetMesh& mesh, const std::string& name) {
  double z = 0.0;
  int count = 0;
  for (size_t i = 0; i < mesh.boundary.size(); ++i)
    if (mesh.tag_names.at(mesh.boundary_tags[i]) == name)
      for (int v : mesh.boundary[i]) z += mesh.points[v].z(), ++count;
  return z / count;
}

// One cycle on a nozzle (2 mm pipes, a 1 mm throat; both ends of one radius, so that only the first
// mesh's naming keeps the inlet where it was) at Re 100 in the throat, steady: the first mesh
// uniform, the cycle's wall finer in the throat (as remesh --size flow makes it: 33 triangles a mm^2
// against 21 at 3000), at the same counts; its WSS moved from the
// first's and said so; the inlet where it was; the summary as returned.
TEST(Adaptation, ACycleAdaptsTheNozzleToItsFlowAtTheSameCounts) {
  test::TemporaryFolder tmp;
  const TriMesh input = synth::nozzle({.radius = 2, .throat_radius = 1, .throat_length = 4, .cone_half_angle_deg = 20,
                                       .inlet_length = 4, .outlet_length = 12, .resolution = 0.2});
  const flow::FlowCase flow_case = flow::parse_case(
      "mesh = \"replaced.msh\"\nlength_unit = \"mm\"\n[fluid]\ndensity = 1060\nviscosity = 0.0035\n[time]\n"
      "steady = true\n[[boundary]]\ntag = \"inlet\"\ntype = \"velocity\"\nprofile = \"parabolic\"\nflow = 0.52\n"
      "[[boundary]]\ntag = \"outlet_1\"\ntype = \"traction\"\n[[boundary]]\ntag = \"wall\"\ntype = \"wall\"\n",
      tmp.path("case.toml"));
  AdaptOptions options;
  options.target_triangles = 3000;
  options.cycles = 1;
  options.start = sizing::SizeKind::uniform;
  const std::vector<AdaptCycle> cycles = adapt_to_flow(input, flow_case, tmp.path("out"), options);
  ASSERT_EQ(cycles.size(), 2u);
  EXPECT_TRUE(std::isnan(cycles[0].change_l2));
  for (const AdaptCycle& c : cycles) {
    EXPECT_NEAR(c.triangles, 3000, 0.03 * 3000) << c.cycle;
    EXPECT_NEAR(c.volume_points, cycles[0].volume_points, 0.02 * cycles[0].volume_points) << c.cycle;
    EXPECT_GT(c.wall_mean_wss, 0.0);
    EXPECT_TRUE(std::filesystem::exists(c.folder + "/flow/wall.pvd")) << c.cycle;
  }
  EXPECT_GT(cycles[1].change_l2, 0.01);  // a new mesh, a new WSS
  EXPECT_LT(cycles[1].change_l2, 1.0);   // the same flow
  EXPECT_GT(cycles[1].change_p95, 0.0);
  const TriMesh first = io::read_surface(tmp.path("out/cycle_0/surface.vtp")).mesh;
  const TriMesh adapted = io::read_surface(tmp.path("out/cycle_1/surface.vtp")).mesh;
  EXPECT_GT(test::triangle_density_between(adapted, -4.0, 0.0), 1.3 * test::triangle_density_between(first, -4.0, 0.0));  // the throat
  const TetMesh v0 = io::read_volume(tmp.path("out/cycle_0/volume.msh"));
  const TetMesh v1 = io::read_volume(tmp.path("out/cycle_1/volume.msh"));
  EXPECT_NEAR(tag_z(v1, "inlet"), tag_z(v0, "inlet"), 1e-6);
  const nlohmann::json summary = nlohmann::json::parse(io::read_file(tmp.path("out/summary.json")));
  ASSERT_EQ(summary["cycles"].size(), 2u);
  EXPECT_TRUE(summary["cycles"][0]["wss_change_l2"].is_null());
  EXPECT_DOUBLE_EQ(summary["cycles"][1]["wss_change_l2"].get<double>(), cycles[1].change_l2);
  EXPECT_EQ(summary["target_points"].get<int>(), cycles[0].volume_points);
}

TEST(Adaptation, BadOptionsAreOptionErrors) {
  AdaptOptions o;
  EXPECT_THROW(check_adapt_options(o), OptionError);  // no target
  o.target_triangles = 1000;
  EXPECT_NO_THROW(check_adapt_options(o));
  o.cycles = 0;
  EXPECT_THROW(check_adapt_options(o), OptionError);
  o.cycles = 1;
  o.start = sizing::SizeKind::flow;
  EXPECT_THROW(check_adapt_options(o), OptionError);
  o.start = sizing::SizeKind::uniform;
  o.target_points = -1;
  EXPECT_THROW(check_adapt_options(o), OptionError);
}

}  // namespace
}  // namespace vesselmesh::study
