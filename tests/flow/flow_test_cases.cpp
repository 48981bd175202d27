#include "flow_test_cases.h"

#include "analysis/open_ends.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>

#include <cmath>
#include <vector>

namespace vesselmesh::flow {

TetMesh pipe_volume(double radius, double length, double resolution, bool layer) {
  const TriMesh pipe = synth::cylinder({.radius = radius, .length = length, .resolution = resolution});
  auto ends = analysis::open_ends(pipe);
  volume::VolumeOptions options;
  if (!layer) options.layer.layers = 0;
  options.inlet = ends[0].center.z() < ends[1].center.z() ? 0 : 1;
  return volume::build_volume(pipe, ends, std::vector<double>(pipe.points.size(), radius), options).mesh;
}

TetMesh bend_volume(double R) {
  const TriMesh bend = synth::bend({.radius = R, .bend_radius = 6.0, .angle_deg = 180.0, .inlet_length = 8.0,
                                    .outlet_length = 8.0, .resolution = 0.6});
  volume::VolumeOptions options;
  options.layer.layers = 2;
  options.inlet = 0;
  return volume::build_volume(bend, analysis::open_ends(bend), std::vector<double>(bend.points.size(), R), options)
      .mesh;
}

FlowCase pipe_case(const std::string& time, const std::string& inflow, const std::string& path) {
  return parse_case(fmt::format(R"(
mesh = "pipe.msh"
length_unit = "mm"
[time]
{}
[[boundary]]
tag = "inlet"
type = "velocity"
{}
[[boundary]]
tag = "outlet_1"
type = "traction"
[[boundary]]
tag = "wall"
type = "wall"
)",
                                time, inflow),
                    path);
}

TetMesh nozzle_volume(const synth::NozzleOptions& o) {
  const TriMesh nozzle = synth::nozzle(o);
  std::vector<double> radius;
  for (const Vec3& x : nozzle.points) radius.push_back(std::hypot(x.x(), x.y()));
  auto ends = analysis::open_ends(nozzle);
  volume::VolumeOptions options;
  options.layer.layers = 2;
  options.inlet = ends[0].center.z() < ends[1].center.z() ? 0 : 1;
  return volume::build_volume(nozzle, ends, radius, options).mesh;
}

}  // namespace vesselmesh::flow
