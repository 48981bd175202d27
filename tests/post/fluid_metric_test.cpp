#include "post/fluid_metric.h"

#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "mesh/point_graph.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace vesselmesh::post {
namespace {

// A box 1.2 x 0.6 x 0.6 cm of Kuhn tetrahedra (cells of 0.1 cm, the summary saying cm) with the
// velocity (0, 0, amplitude[k] * f(x)) m/s at the k-th saved time (0.1, 0.2, 0.4 s).
TetMesh box() { return test::kuhn_box({12, 6, 6}, Vec3(1.2, 0.6, 0.6)); }

void write_results(const test::TemporaryFolder& tmp, const TetMesh& mesh, const std::vector<double>& amplitude,
                   const std::function<double(double)>& f, const std::string& period) {
  std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n  <Collection>\n";
  const double times[] = {0.1, 0.2, 0.4};
  for (size_t k = 0; k < amplitude.size(); ++k) {
    std::vector<Vec3> velocity;
    for (const Vec3& p : mesh.points) velocity.push_back(Vec3(0, 0, amplitude[k] * f(p.x())));
    const std::string name = "fluid_00000" + std::to_string(k) + ".vtu";
    io::write_vtu(tmp.path(name), mesh,
                  {Field::vector("velocity", velocity), Field::scalar("pressure", std::vector<double>(velocity.size()))});
    pvd += "    <DataSet timestep=\"" + std::to_string(times[k]) + "\" group=\"\" part=\"0\" file=\"" + name + "\"/>\n";
  }
  test::write_bytes(tmp.path("fluid.pvd"), pvd + "  </Collection>\n</VTKFile>\n");
  test::write_bytes(tmp.path("summary.json"), R"({"units": {"points": "cm", "length_scale_m": 0.01})" + period + "}");
}

// The integral over the cells of the mean of the corners' h^-3 (the count the sizes ask for, up to a
// constant).
double count_integral(const TetMesh& mesh, const std::vector<double>& h) {
  double sum = 0.0;
  for (const Tet& t : mesh.tets) {
    double density = 0.0;
    for (int v : t) density += std::pow(h[v], -3.0) / 4.0;
    sum += std::abs(mesh::tet_volume6(mesh, t)) / 6.0 * density;
  }
  return sum;
}

// A velocity of Hessian 2 a e_x e_x everywhere (a the largest amplitude of the last period): sizes the
// same everywhere, their count the flow mesh's own (each point's mean edge length), the mesh in mm;
// then exp(x / 2 mm): sizes falling along x as the Hessian to the power -2/7 (p = 2) and graded; read
// anywhere inside, zero outside.
TEST(FluidMetric, SizesSpreadTheVelocitysErrorAtTheFlowMeshsCount) {
  const TetMesh mesh = box();
  test::TemporaryFolder tmp;
  write_results(tmp, mesh, {1.0, 5.0, 2.0}, [](double x) { return x * x; }, R"(, "period": 0.3)");
  const FluidSizes s = fluid_error_sizes(tmp.folder().string(), {}, 1.3);
  EXPECT_EQ(s.times, (std::vector<double>{0.1, 0.2, 0.4}));
  ASSERT_EQ(s.mesh.num_points(), mesh.num_points());
  EXPECT_NEAR(s.mesh.points[50].x(), 10.0 * mesh.points[50].x(), 1e-12);  // cm -> mm
  for (double h : s.sizes) EXPECT_NEAR(h, s.sizes[0], 1e-6 * s.sizes[0]);
  const mesh::PointGraph graph = mesh::point_graph(s.mesh.num_points(), s.mesh.tets);
  std::vector<double> own(s.mesh.points.size(), 0.0);
  for (int v = 0; v < s.mesh.num_points(); ++v) {
    for (int k = graph.start[v]; k < graph.start[v + 1]; ++k)
      own[v] += (s.mesh.points[graph.next[k]] - s.mesh.points[v]).norm() / graph.degree(v);
  }
  EXPECT_NEAR(count_integral(s.mesh, s.sizes), count_integral(s.mesh, own), 1e-6 * count_integral(s.mesh, own));

  test::TemporaryFolder smooth;
  write_results(smooth, mesh, {1.0}, [](double x) { return std::exp(5.0 * x); }, "");  // x in cm: exp(x / 2 mm)
  const FluidSizes e = fluid_error_sizes(smooth.folder().string(), {}, 1.3);
  const auto at = [&](const Vec3& x) {  // mm
    for (int v = 0; v < e.mesh.num_points(); ++v)
      if ((e.mesh.points[v] - x).norm() < 1e-9) return e.sizes[v];
    ADD_FAILURE() << "no point at " << x.transpose();
    return 0.0;
  };
  // From x = 4 to 8 mm the Hessian grows by exp(2): the sizes fall by exp(4 / 7).
  EXPECT_NEAR(at(Vec3(4, 3, 3)) / at(Vec3(8, 3, 3)), std::exp(4.0 / 7.0), 0.02 * std::exp(4.0 / 7.0));
  for (const Tet& t : e.mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        EXPECT_LE(e.sizes[t[i]] - e.sizes[t[j]],
                  std::log(1.3) * (e.mesh.points[t[i]] - e.mesh.points[t[j]]).norm() + 1e-12);
  const FluidSizeField field(e);
  const Vec3 a(4.05, 3.0, 3.0);
  EXPECT_GT(field.at(a), std::min(at(Vec3(4, 3, 3)), at(Vec3(5, 3, 3))) * (1 - 1e-9));
  EXPECT_LT(field.at(a), std::max(at(Vec3(4, 3, 3)), at(Vec3(5, 3, 3))) * (1 + 1e-9));
  EXPECT_EQ(field.at(Vec3(-1, 3, 3)), 0.0);
  EXPECT_DOUBLE_EQ(size_function(e)(a), field.at(a));
}

// Given times: the frames interpolated there; a time outside them, frames of different meshes, a
// uniform velocity and a folder without fluid frames are InputErrors.
TEST(FluidMetric, GivenTimesAndWhatItRefuses) {
  const TetMesh mesh = box();
  test::TemporaryFolder tmp;
  write_results(tmp, mesh, {1.0, 5.0, 2.0}, [](double x) { return x * x; }, "");
  EXPECT_EQ(fluid_error_sizes(tmp.folder().string(), {}, 1.3).times, std::vector<double>{0.4});  // steady: the last
  EXPECT_EQ(fluid_error_sizes(tmp.folder().string(), {0.15, 0.3}, 1.3).times, (std::vector<double>{0.15, 0.3}));
  EXPECT_THROW(fluid_error_sizes(tmp.folder().string(), {0.5}, 1.3), InputError);
  io::write_vtu(tmp.path("fluid_000001.vtu"), test::kuhn_box({6, 3, 3}, Vec3(1.2, 0.6, 0.6)),
                {Field::vector("velocity", std::vector<Vec3>(112, Vec3::Zero())),
                 Field::scalar("pressure", std::vector<double>(112, 0.0))});
  EXPECT_THROW(fluid_error_sizes(tmp.folder().string(), {0.1, 0.2}, 1.3), InputError);
  test::TemporaryFolder uniform;
  write_results(uniform, mesh, {1.0}, [](double) { return 1.0; }, "");
  EXPECT_THROW(fluid_error_sizes(uniform.folder().string(), {}, 1.3), InputError);
  test::TemporaryFolder empty;
  EXPECT_THROW(fluid_error_sizes(empty.folder().string(), {}, 1.3), InputError);
}

}  // namespace
}  // namespace vesselmesh::post
