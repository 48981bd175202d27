#include "synth/implicit_surface.h"

#include "mesh/clean.h"
#include "mesh/connectivity.h"
#include "mesh/geometry.h"
#include "mesh/error.h"
#include "mesh/merge_points.h"

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::synth {

Vec3 gradient(const ImplicitFunction& f, const Vec3& p, double h) {
  Vec3 g;
  for (int i = 0; i < 3; ++i) {
    Vec3 a = p, b = p;
    a[i] += h;
    b[i] -= h;
    g[i] = (f(a) - f(b)) / (2.0 * h);
  }
  return g;
}

Vec3 project_to_zero_set(const ImplicitFunction& f, Vec3 p, double h) {
  for (int k = 0; k < 8; ++k) {
    const double value = f(p);
    if (std::abs(value) < 1e-12 * (1.0 + p.norm())) break;
    const Vec3 g = gradient(f, p, h);
    const double g2 = g.squaredNorm();
    if (g2 <= 0.0) break;
    p -= (value / g2) * g;
  }
  return p;
}

TriMesh polygonize(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, double spacing) {
  VM_CHECK(spacing > 0.0, "polygonize needs a positive spacing");
  int dims[3];
  for (int i = 0; i < 3; ++i) dims[i] = static_cast<int>(std::ceil((hi[i] - lo[i]) / spacing)) + 1;
  vtkNew<vtkImageData> image;
  image->SetDimensions(dims);
  image->SetOrigin(lo.x(), lo.y(), lo.z());
  image->SetSpacing(spacing, spacing, spacing);
  vtkNew<vtkFloatArray> values;
  values->SetName("f");
  values->SetNumberOfTuples(static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2]);
  tbb::parallel_for(0, dims[2], [&](int k) {  // every value on its own: the same grid on any thread count
    vtkIdType id = static_cast<vtkIdType>(k) * dims[0] * dims[1];
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) values->SetValue(id++, static_cast<float>(f(lo + spacing * Vec3(i, j, k))));
  });
  image->GetPointData()->SetScalars(values);

  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, 0.0);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  vtkPolyData* poly = contour->GetOutput();

  TriMesh mesh;
  mesh.points.resize(poly->GetNumberOfPoints());
  tbb::parallel_for(vtkIdType{0}, poly->GetNumberOfPoints(), [&](vtkIdType i) {
    double p[3];
    poly->GetPoint(i, p);
    mesh.points[i] = project_to_zero_set(f, Vec3(p[0], p[1], p[2]), 1e-3 * spacing);
  });
  vtkNew<vtkIdList> ids;
  vtkCellArray* polys = poly->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(ids);)
    if (ids->GetNumberOfIds() == 3)
      mesh.triangles.push_back({static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)),
                                static_cast<int>(ids->GetId(2))});
  return mesh;
}

void relax_on_zero_set(TriMesh& mesh, const ImplicitFunction& f, double h, int iterations,
                       std::span<const char> fixed) {
  const int np = mesh.num_points();
  std::vector<std::vector<int>> neighbours(np);
  for (const Triangle& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      neighbours[t[i]].push_back(t[(i + 1) % 3]);
      neighbours[t[i]].push_back(t[(i + 2) % 3]);
    }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<Vec3> next(np);
  for (int it = 0; it < iterations; ++it) {
    tbb::parallel_for(0, np, [&](int v) {  // Jacobi: each point from the last positions only
      next[v] = mesh.points[v];
      if ((!fixed.empty() && fixed[v]) || neighbours[v].empty()) return;
      Vec3 mean = Vec3::Zero();
      for (int w : neighbours[v]) mean += mesh.points[w];
      mean /= static_cast<double>(neighbours[v].size());
      const Vec3 normal = gradient(f, mesh.points[v], h).normalized();
      Vec3 step = 0.5 * (mean - mesh.points[v]);
      step -= step.dot(normal) * normal;
      next[v] = project_to_zero_set(f, mesh.points[v] + step, h);
    });
    mesh.points.swap(next);
  }
}

namespace {

double smallest_angle(const std::vector<Vec3>& p, const Triangle& f) {
  double smallest = std::numbers::pi;
  for (int i = 0; i < 3; ++i) {
    const Vec3 u = p[f[(i + 1) % 3]] - p[f[i]], v = p[f[(i + 2) % 3]] - p[f[i]];
    smallest = std::min(smallest, std::atan2(u.cross(v).norm(), u.dot(v)));
  }
  return smallest;
}

Vec3 unit_normal(const std::vector<Vec3>& p, const Triangle& f) {
  return (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized();
}

}  // namespace

int flip_to_improve_angles(TriMesh& mesh, double max_bend_deg) {
  const double min_cos = std::cos(max_bend_deg * std::numbers::pi / 180.0);
  int total = 0;
  for (int pass = 0; pass < 20; ++pass) {
    const mesh::EdgeMap edges = mesh::build_edge_map(mesh);
    const mesh::VertexTriangles around = mesh::build_vertex_triangles(mesh);
    // Points of flipped triangles are locked for the rest of the pass: the maps stay true
    // for every quad that has no locked point.
    std::vector<char> locked(mesh.points.size(), 0);
    int flips = 0;
    for (int e = 0; e < edges.num_edges(); ++e) {
      if (edges.valence(e) != 2) continue;
      const int t = edges.triangles_of(e)[0], u = edges.triangles_of(e)[1];
      const Triangle ft = mesh.triangles[t], fu = mesh.triangles[u];
      const auto [e0, e1] = edges.edges[e];
      const bool forward = ft[(mesh::corner_of(ft, e0) + 1) % 3] == e1;
      const int a = forward ? e0 : e1, b = forward ? e1 : e0;
      const int c = ft[(mesh::corner_of(ft, a) + 2) % 3];
      const int cb = mesh::corner_of(fu, b);
      if (cb == -1 || fu[(cb + 1) % 3] != a) continue;  // inconsistent orientation: leave it
      const int d = fu[(cb + 2) % 3];
      if (c == d || locked[a] || locked[b] || locked[c] || locked[d]) continue;
      bool exists = false;
      for (int s : around.of(c)) exists |= mesh::corner_of(mesh.triangles[s], d) != -1;
      if (exists) continue;
      const Triangle nt{a, d, c}, nu{d, b, c};
      const Vec3 n0 = unit_normal(mesh.points, ft), n1 = unit_normal(mesh.points, fu);
      const Vec3 m0 = unit_normal(mesh.points, nt), m1 = unit_normal(mesh.points, nu);
      if (n0.dot(n1) < min_cos || m0.dot(m1) < min_cos || m0.dot(n0 + n1) <= 0.0 || m1.dot(n0 + n1) <= 0.0) continue;
      const double now = std::min(smallest_angle(mesh.points, ft), smallest_angle(mesh.points, fu));
      const double then = std::min(smallest_angle(mesh.points, nt), smallest_angle(mesh.points, nu));
      if (!(then > now + 1e-9)) continue;
      mesh.triangles[t] = nt;
      mesh.triangles[u] = nu;
      for (int v : {a, b, c, d}) locked[v] = 1;
      ++flips;
    }
    total += flips;
    if (flips == 0) break;
  }
  return total;
}

}  // namespace vesselmesh::synth

