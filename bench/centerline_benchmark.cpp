// Centerlines and distance map: the Gmsh aortic arch (41k triangles, from ../shared/data when
// present; goal under 2 s) and a 500k-triangle jittered pipe (goal under 30 s on 2 cores).
//   build/bench/bench_centerline
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "io/surface.h"
#include "mesh/clean.h"
#include "synth/shapes.h"

#include <benchmark/benchmark.h>

#include <filesystem>

#ifndef VESSELMESH_SHARED_DATA
#define VESSELMESH_SHARED_DATA ""
#endif

namespace {

using namespace vesselmesh;

void run(benchmark::State& state, const TriMesh& mesh) {
  size_t branches = 0;
  for (auto _ : state) {
    const centerline::Centerlines c = centerline::extract(mesh);
    const centerline::DistanceMap map = centerline::distance_map(mesh, c);
    branches = c.branches.size();
    benchmark::DoNotOptimize(map.distance.data());
  }
  state.counters["triangles"] = mesh.num_triangles();
  state.counters["branches"] = static_cast<double>(branches);
}

void BM_Centerline_AorticArch(benchmark::State& state) {
  const std::string path = std::string(VESSELMESH_SHARED_DATA) + "/vessels/gmsh_aortic_arch_open_cm.stl";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("../shared/data is absent: no aortic arch to run on");
    return;
  }
  io::SurfaceFile file = io::read_surface(path, {.units = io::Unit::cm});
  mesh::clean(file.mesh);
  run(state, file.mesh);
}

void BM_Centerline_Pipe500k(benchmark::State& state) {
  static const TriMesh pipe = synth::cylinder({.radius = 3.0, .length = 115.0, .resolution = 0.1, .jitter = 0.3});
  run(state, pipe);
}

BENCHMARK(BM_Centerline_AorticArch)->Unit(benchmark::kSecond)->MinTime(2.0)->UseRealTime();
BENCHMARK(BM_Centerline_Pipe500k)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
