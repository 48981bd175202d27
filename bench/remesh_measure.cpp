// Measures a remeshed surface against a size field, the same way for any remesher (ours, mmgs,
// Gmsh): edges of unit length, angles and quality in the field's metric (interpolated at the
// output's points), and the distance from the input, absolute and relative to the local radius.
//   bench_remesh_measure FIELD.vtp DISTANCE_MAP.vtp OUTPUT.{vtp,stl,mesh,msh}
// FIELD.vtp: what `vesselmesh size` writes (the checked input and point data metric);
// DISTANCE_MAP.vtp: what `vesselmesh centerline --distance-map` writes (point data radius) on
// the same surface. Prints one JSON object.
#include "io/surface.h"
#include "mesh/error.h"
#include "remesh/adapt.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

using namespace vesselmesh;

namespace {
const Field& find(const io::SurfaceFile& f, const std::string& name) {
  for (const Field& field : f.point_data)
    if (field.name == name) return field;
  throw InputError(fmt::format("{}: no point data '{}'", f.path, name));
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: bench_remesh_measure FIELD.vtp DISTANCE_MAP.vtp OUTPUT\n");
    return 2;
  }
  try {
    const io::SurfaceFile field = io::read_surface(argv[1]);
    const io::SurfaceFile distance = io::read_surface(argv[2]);
    const io::SurfaceFile output = io::read_surface(argv[3]);
    const Field& m = find(field, "metric");
    std::vector<Sym3> metric(field.mesh.points.size());
    for (size_t v = 0; v < metric.size(); ++v) std::copy_n(m.values.begin() + 6 * v, 6, metric[v].v.begin());
    if (distance.mesh.points != field.mesh.points) throw InputError("the distance map is not on the field's surface");
    const std::vector<double> radius = find(distance, "radius").values;
    const remesh::SurfaceModel model(field.mesh, metric, remesh::FeatureOptions{});
    std::vector<Sym3> at_output;
    for (const Vec3& p : output.mesh.points) at_output.push_back(model.project(p).metric);
    const remesh::RemeshStats s = remesh::measure(output.mesh, at_output, model, &radius);
    std::printf(
        "{\"points\": %d, \"triangles\": %d, \"edges_in_unit_range\": %.4f, \"min_angle_deg\": %.3f, "
        "\"mean_quality\": %.4f, \"min_quality\": %.4f, \"hausdorff\": %.5g, \"hausdorff_relative\": %.5g, "
        "\"hausdorff_facets\": %.5g, \"hausdorff_facets_relative\": %.5g}\n",
        s.points, s.triangles, s.edges_in_unit_range, s.min_angle_deg, s.mean_quality, s.min_quality, s.hausdorff,
        s.hausdorff_relative, s.hausdorff_facets, s.hausdorff_facets_relative);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_remesh_measure: %s\n", e.what());
    return 2;
  }
  return 0;
}
