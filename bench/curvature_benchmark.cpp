// Curvature of a jittered torus of about a million points (R = 10, r = 3 mm, points moved along
// the surface by up to 30 % of the edge length, random diagonals): vesselmesh on one and two
// threads, with its fitted normals and with the paper's Max normals, against VTK's
// vtkCurvatures (mean and Gaussian curvature) on the same mesh, in the same run. Each reports
// its median relative error of the mean curvature H against the exact torus. ArraysOnly: the
// memory floor of vesselmesh's passes (below).
//   build/bench/bench_curvature            (or bench/curvature.sh for the table)
#include "analysis/curvature.h"
#include "mesh/connectivity.h"
#include "synth/shapes.h"

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <vtkCellArray.h>
#include <vtkCurvatures.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>

namespace {

using namespace vesselmesh;

constexpr double kMajor = 10.0, kMinor = 3.0;

const TriMesh& torus() {
  static const TriMesh mesh =
      synth::torus({.major_radius = kMajor, .minor_radius = kMinor, .resolution = 0.0393, .jitter = 0.3});
  return mesh;
}

// Exact mean curvature of the torus at a point on it (outward normals).
double exact_mean(const Vec3& p) {
  const double cos_v = (std::hypot(p.x(), p.y()) - kMajor) / kMinor;
  return 0.5 * (1.0 / kMinor + cos_v / (kMajor + kMinor * cos_v));
}

// Median of |H - H*| / |H*| over the points; `sign` turns a peer's convention into ours.
template <typename MeanOf>
double median_h_error(MeanOf mean_of, double sign) {
  const TriMesh& m = torus();
  std::vector<double> e(m.points.size());
  for (size_t v = 0; v < e.size(); ++v) e[v] = std::abs(sign * mean_of(v) - exact_mean(m.points[v])) / exact_mean(m.points[v]);
  std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
  return e[e.size() / 2];
}

void run_vesselmesh(benchmark::State& state, analysis::NormalMethod normals) {
  const TriMesh& m = torus();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0)));
  analysis::CurvatureField field;
  for (auto _ : state) {
    analysis::CurvatureField result = analysis::curvature(m, {.normals = normals});
    benchmark::DoNotOptimize(result.k1.data());
    state.PauseTiming();  // the last field is freed untimed, as in the trimesh2 driver
    field = std::move(result);
    state.ResumeTiming();
  }
  state.counters["points"] = m.num_points();
  state.counters["threads"] = static_cast<double>(state.range(0));
  state.counters["H_error_percent"] = 100.0 * median_h_error([&](size_t v) { return field.mean(static_cast<int>(v)); }, 1.0);
}

void BM_Curvature_vesselmesh(benchmark::State& state) { run_vesselmesh(state, analysis::NormalMethod::quadric_fit); }
void BM_Curvature_vesselmesh_MaxNormals(benchmark::State& state) { run_vesselmesh(state, analysis::NormalMethod::max); }

// The memory floor of vesselmesh's passes: the same arrays allocated, written and read in the
// same order (the incidence, a normal per point from its fan's points, a 48-byte record per
// triangle from its points and normals, a pass gathering each point's records into k1, k2, dir1,
// dir2) with trivial arithmetic. What no arithmetic can save at this interface.
void BM_Curvature_ArraysOnly(benchmark::State& state) {
  const TriMesh& m = torus();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<size_t>(state.range(0)));
  struct Record {
    float values[12];
  };
  const int np = m.num_points(), nt = m.num_triangles();
  for (auto _ : state) {
    analysis::CurvatureField f;
    const mesh::VertexTriangles corners = mesh::build_vertex_corners(m);
    f.normal.resize(np);
    tbb::parallel_for(tbb::blocked_range<int>(0, np, 4096), [&](const tbb::blocked_range<int>& range) {
      for (int v = range.begin(); v < range.end(); ++v) {
        Vec3 sum = Vec3::Zero();
        for (int corner : corners.of(v))
          for (int w : m.triangles[corner / 3]) sum += m.points[w];
        f.normal[v] = sum;
      }
    });
    std::vector<Record> records(nt);
    tbb::parallel_for(tbb::blocked_range<int>(0, nt, 4096), [&](const tbb::blocked_range<int>& range) {
      for (int t = range.begin(); t < range.end(); ++t)
        for (int i = 0; i < 12; ++i) {
          const int w = m.triangles[t][i % 3];
          records[t].values[i] = static_cast<float>(m.points[w][i / 4] + f.normal[w][i / 4]);
        }
    });
    f.k1.resize(np), f.k2.resize(np), f.dir1.resize(np), f.dir2.resize(np);
    tbb::parallel_for(tbb::blocked_range<int>(0, np, 4096), [&](const tbb::blocked_range<int>& range) {
      for (int v = range.begin(); v < range.end(); ++v) {
        double sum = 0.0;
        for (int corner : corners.of(v))
          for (float x : records[corner / 3].values) sum += x;
        f.k1[v] = sum, f.k2[v] = -sum, f.dir1[v] = Vec3(sum, 0, 0), f.dir2[v] = Vec3(0, sum, 0);
      }
    });
    benchmark::DoNotOptimize(f.k1.data());
    state.PauseTiming();  // freed untimed, as the runs above
    f = {};
    state.ResumeTiming();
  }
  state.counters["points"] = np;
  state.counters["threads"] = static_cast<double>(state.range(0));
  state.counters["H_error_percent"] = -1.0;  // no curvature
}

void BM_Curvature_vtkCurvatures(benchmark::State& state) {
  const TriMesh& m = torus();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const Vec3& p : m.points) points->InsertNextPoint(p.x(), p.y(), p.z());
  vtkNew<vtkCellArray> polys;
  for (const Triangle& f : m.triangles) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(polys);
  vtkDataArray* mean = nullptr;
  vtkNew<vtkCurvatures> mean_filter, gauss_filter;
  for (auto _ : state) {  // both kinds, as vesselmesh gives both
    mean_filter->SetInputData(poly);
    mean_filter->SetCurvatureTypeToMean();
    mean_filter->Modified();
    mean_filter->Update();
    gauss_filter->SetInputData(poly);
    gauss_filter->SetCurvatureTypeToGaussian();
    gauss_filter->Modified();
    gauss_filter->Update();
    mean = mean_filter->GetOutput()->GetPointData()->GetArray("Mean_Curvature");
    benchmark::DoNotOptimize(mean);
  }
  state.counters["points"] = m.num_points();
  state.counters["threads"] = 1;
  // vtkCurvatures has the same sign convention (positive where convex, outward).
  state.counters["H_error_percent"] = 100.0 * median_h_error([&](size_t v) { return mean->GetComponent(static_cast<vtkIdType>(v), 0); }, 1.0);
}

BENCHMARK(BM_Curvature_vesselmesh)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();
BENCHMARK(BM_Curvature_vesselmesh_MaxNormals)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();
BENCHMARK(BM_Curvature_ArraysOnly)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();
BENCHMARK(BM_Curvature_vtkCurvatures)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
