// Reading a 2-million-triangle binary STL (goal: under 1 s on one core), against VTK's
// vtkSTLReader (which also merges coincident points) on the same file, in the same run.
//   build/bench/bench_read_stl            (or bench/read_stl.sh for the ratio)
#include "io/stl.h"
#include "synth/shapes.h"

#include <benchmark/benchmark.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>

#include <filesystem>
#include <unistd.h>

namespace {

using namespace vesselmesh;

// A torus of about 2 million triangles, written once per run.
const std::string& large_stl() {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() /
                           ("vesselmesh-bench-" + std::to_string(::getpid()) + "-torus.stl")).string();
    // 2 * (2 pi 13 / h) * (2 pi 3 / h) = 2e6 triangles for h = 0.0393.
    io::write_stl(p, synth::torus({.major_radius = 10.0, .minor_radius = 3.0, .resolution = 0.0393}));
    std::atexit([] { std::filesystem::remove(large_stl()); });
    return p;
  }();
  return path;
}

void BM_ReadStl_vesselmesh(benchmark::State& state) {
  const std::string& path = large_stl();
  long long triangles = 0;
  for (auto _ : state) {
    const TriMesh mesh = io::read_stl(path);
    triangles = mesh.num_triangles();
    benchmark::DoNotOptimize(mesh.points.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["triangles_per_s"] = benchmark::Counter(static_cast<double>(triangles), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ReadStl_vtkSTLReader(benchmark::State& state) {
  const std::string& path = large_stl();
  long long triangles = 0;
  for (auto _ : state) {
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName(path.c_str());
    reader->MergingOn();
    reader->Update();
    triangles = reader->GetOutput()->GetNumberOfPolys();
    benchmark::DoNotOptimize(reader->GetOutput());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["triangles_per_s"] = benchmark::Counter(static_cast<double>(triangles), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_ReadStl_vesselmesh)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_ReadStl_vtkSTLReader)->Unit(benchmark::kMillisecond)->MinTime(3.0);

}  // namespace

BENCHMARK_MAIN();
