#include "flow/navier_stokes.h"

#include "flow/womersley.h"
#include "flow_test_cases.h"

#include "analysis/curvature.h"
#include "analysis/open_ends.h"
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "mesh/error.h"
#include "mesh/reorder.h"
#include "post/wss.h"
#include "remesh/adapt.h"
#include "remesh/extend.h"
#include "sizing/size_field.h"
#include "synth/shapes.h"
#include "test_support.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <set>

namespace vesselmesh::flow {
namespace {

// The wall of a pipe mesh, its cells as tetrahedra and its points in metres.
struct Wall {
  std::vector<Tet> all;
  post::WallSurface surface;
  std::vector<Vec3> si;

  explicit Wall(const TetMesh& mesh) : all(mesh::all_tetrahedra(mesh)) {
    int wall_tag = 0;
    for (const auto& [tag, name] : mesh.tag_names)
      if (name == "wall") wall_tag = tag;
    surface = post::extract_wall(mesh, all, {wall_tag});
    for (const Vec3& x : mesh.points) si.push_back(x * 1e-3);
  }
  std::vector<Vec3> wss(const std::vector<Vec3>& velocity, double viscosity,
                        post::WssMethod method = post::WssMethod::quadratic) const {
    return post::wall_shear_stress(surface, all, si, velocity, viscosity, method);
  }
};

// Per wall point away from the ends (the middle 40 %), the relative error of the stress's
// magnitude against 4 mu Q / (pi R^3): the mean error (signed) and the worst. Expects the stress
// along the flow (+z) at every such point.
struct WssErrors {
  double mean = 0.0, worst = 0.0;
};
WssErrors poiseuille_wss_errors(const Wall& wall, const std::vector<Vec3>& velocity, double viscosity, double q,
                                double R, double L, post::WssMethod method, double z0 = 0.0) {
  const double r = R * 1e-3, exact = 4.0 * viscosity * q / (M_PI * r * r * r);
  const std::vector<Vec3> wss = wall.wss(velocity, viscosity, method);
  WssErrors e;
  int count = 0;
  for (size_t v = 0; v < wall.surface.mesh.points.size(); ++v) {
    const double z = wall.surface.mesh.points[v].z() - z0;  // the pipe from z0 to z0 + L
    if (z < 0.3 * L || z > 0.7 * L) continue;
    e.mean += (wss[v].norm() - exact) / exact;
    e.worst = std::max(e.worst, std::abs(wss[v].norm() - exact) / exact);
    EXPECT_GT(wss[v].z(), 0.0) << post::to_string(method) << ": along the flow";
    ++count;
  }
  EXPECT_GT(count, 50);
  e.mean /= std::max(count, 1);
  return e;
}

// A steady solve settled to `tolerance`: by its last change (Picard's iterations, the pseudo time
// steps) or by the steady residual at its answer (Newton's, the default, stops on the residual its
// last step reached, its change then larger).
bool settled(const StepReport& r, double tolerance) {
  return r.change < tolerance || (r.residual >= 0.0 && r.residual < tolerance);
}

// Steady Poiseuille flow (issue 8): the axial velocity within 1 % of its peak and the wall shear
// stress within 2 % of 4 mu Q / (pi R^3), away from the ends. The nodal velocity error is the P1
// discretization's, O(h^2): 4.0 / 2.1 / 0.86 % of the peak with 0.35 / 0.25 / 0.18 mm edges
// (measured); its sign is the flux's doing (a piecewise-linear profile carrying the flow of a
// parabola lies above it at the points).
TEST(NavierStokes, SteadyPoiseuilleInAPipeWithABoundaryLayer) {
  const double R = 2.0, L = 8.0, Q = 0.5;  // mm, mm, mL/s
  const TetMesh mesh = pipe_volume(R, L, 0.18);
  const FlowCase fc = pipe_case("steady = true", fmt::format("profile = \"parabolic\"\nflow = {}", Q), "steady.toml");
  NavierStokes ns(mesh, fc);
  const StepReport report = ns.solve_steady();
  EXPECT_TRUE(settled(report, 1e-6)) << report.change << ", residual " << report.residual;

  const double q = Q * 1e-6, r = R * 1e-3;
  const double peak = 2.0 * q / (M_PI * r * r);
  double worst = 0.0;
  int checked = 0;
  for (int i = 0; i < mesh.num_points(); ++i) {
    const Vec3& x = mesh.points[i];
    if (x.z() < 0.3 * L || x.z() > 0.7 * L) continue;
    const double rr = std::hypot(x.x(), x.y()) / R;
    if (rr > 0.999) continue;
    const double exact = peak * (1.0 - rr * rr);
    worst = std::max(worst, std::abs(ns.gathered_velocity()[i].z() - exact) / peak);
    ++checked;
  }
  EXPECT_GT(checked, 100);
  EXPECT_LT(worst, 0.01) << "largest axial velocity error, of the peak";

  // Flux: in at the inlet, out at the outlet.
  for (const BoundaryFlow& f : ns.boundary_flows()) {
    if (f.tag == "inlet") {
      EXPECT_NEAR(f.flux, -q, 1e-9 * q);
    } else if (f.tag == "outlet_1") {
      EXPECT_NEAR(f.flux, q, 1e-3 * q);
    }
  }

  const Wall wall(mesh);
  for (post::WssMethod method : {post::WssMethod::quadratic, post::WssMethod::face}) {
    const WssErrors e = poiseuille_wss_errors(wall, ns.gathered_velocity(), fc.viscosity, q, R, L, method);
    std::printf("Poiseuille: %d points, %d dofs, velocity error %.3f %% of peak, WSS (%s) mean %.2f %% off, worst "
                "%.2f %%, %d linear iterations, %.2f s\n",
                mesh.num_points(), ns.dofs(), 100 * worst, post::to_string(method), 100 * e.mean, 100 * e.worst,
                report.linear_iterations, report.seconds);
    EXPECT_LT(std::abs(e.mean), 0.02) << post::to_string(method);
    EXPECT_LT(e.worst, 0.05) << post::to_string(method);
  }
}

// Flow extensions (issue 32): a 5 mm pipe extended by 1.5 radii at each end (remesh/extend.h: the
// tube's own rings and triangles) carries Poiseuille's flow as a pipe of the same whole length
// meshed in one piece: the WSS in the middle of the original pipe within half a point of the long
// pipe's at the same distance from its inlet.
TEST(NavierStokes, PoiseuilleInAnExtendedPipeAsInAnEquallyLongOne) {
  const double R = 2.0, L = 5.0, extension = 1.5, Q = 0.5, h = 0.3;
  const TriMesh pipe = synth::cylinder({.radius = R, .length = L, .resolution = h});
  const remesh::ExtensionResult extended = remesh::extend_ends(pipe, analysis::open_ends(pipe), {.length = extension});
  const auto ends = analysis::open_ends(extended.mesh);
  ASSERT_EQ(ends.size(), 2u);
  volume::VolumeOptions options;
  options.inlet = ends[0].center.z() < ends[1].center.z() ? 0 : 1;
  const TetMesh long_mesh = pipe_volume(R, L + 2.0 * extension * R, h);
  const TetMesh extended_mesh =
      volume::build_volume(extended.mesh, ends, std::vector<double>(extended.mesh.points.size(), R), options).mesh;
  const FlowCase fc = pipe_case("steady = true", fmt::format("profile = \"parabolic\"\nflow = {}", Q), "steady.toml");
  const double q = Q * 1e-6;
  std::array<WssErrors, 2> errors;
  for (int k = 0; k < 2; ++k) {
    const TetMesh& mesh = k == 0 ? long_mesh : extended_mesh;
    NavierStokes ns(mesh, fc);
    ns.solve_steady();
    // The original pipe's middle: z from 0 to L in the extended mesh, from 1.5 R to 1.5 R + L in the long one.
    errors[k] = poiseuille_wss_errors(Wall(mesh), ns.gathered_velocity(), fc.viscosity, q, R, L, post::WssMethod::quadratic,
                                      k == 0 ? extension * R : 0.0);
  }
  std::printf("Poiseuille WSS, mean error in the middle: one long pipe %+.2f %%, an extended pipe %+.2f %% (%d and %d "
              "points)\n",
              100 * errors[0].mean, 100 * errors[1].mean, long_mesh.num_points(), extended_mesh.num_points());
  EXPECT_LT(std::abs(errors[1].mean), 0.03);
  EXPECT_LT(std::abs(errors[1].mean), std::abs(errors[0].mean) + 0.005);
}

// The steady solve's flow is the flow a long unsteady run settles to (issue 29): the 180-degree bend
// of the Newton test at Re ~ 190, constant inflow, time steps from the Stokes flow for 12 s (the
// slowest viscous decay, R^2 / (5.78 nu), is 0.2 s), against Newton's steady flow to a 1e-10 change.
// They differ by the stabilization's time term alone (tau_M's 4 / dt^2, which the steady equations
// do not have): the difference falls as dt^-2 (measured, largest velocity difference over the peak:
// 7.5e-4 at dt = 0.02 s, 1.2e-4 at 0.05, 3.1e-5 at 0.1; the linear solver's tolerance, 1e-6 or
// 1e-10, changes nothing) and is under 1e-4 from dt = 0.1 s. Settled: the last step's change under
// 1e-5, the linear solver's tolerance (1e-6 of the right-hand side) at work — each step starts from
// the velocity extrapolated from the last two (2 u^n - u^(n-1)), so the solver's own error
// (a few 1e-6) is what changes once the flow has settled (from u^n, as before, a settled step's
// residual was under the tolerance and the change fell to zero).
TEST(NavierStokes, SteadyFlowIsWhereALongUnsteadyRunSettles) {
  const double R = 2.0, Q = 2.0;
  const TetMesh mesh = bend_volume(R);
  const std::string inflow = fmt::format("profile = \"parabolic\"\nflow = {}", Q);
  NavierStokes steady(mesh, pipe_case("steady = true\nsteady_tolerance = 1e-10\nsteady_iterations = 80\n"
                                      "steady_method = \"newton\"",
                                      inflow, "steady.toml"));
  steady.solve_steady();
  const double peak = 2.0 * Q * 1e-6 / (M_PI * R * R * 1e-6);
  std::map<double, double> difference;
  for (double dt : {0.05, 0.1}) {
    const int steps = static_cast<int>(std::lround(12.0 / dt));
    NavierStokes unsteady(mesh, pipe_case(fmt::format("dt = {}\nend = 12.0\ninitial = \"stokes\"", dt), inflow,
                                          "unsteady.toml"));
    unsteady.start_from_stokes();
    double change = 1.0;
    for (int k = 0; k < steps; ++k) change = unsteady.step().change;
    EXPECT_LT(change, 1e-5) << "settled, dt " << dt;
    double worst = 0.0, worst_p = 0.0, p_scale = 0.0;
    for (int a = 0; a < mesh.num_points(); ++a) {
      worst = std::max(worst, (unsteady.gathered_velocity()[a] - steady.gathered_velocity()[a]).norm());
      worst_p = std::max(worst_p, std::abs(unsteady.gathered_pressure()[a] - steady.gathered_pressure()[a]));
      p_scale = std::max(p_scale, std::abs(steady.gathered_pressure()[a]));
    }
    difference[dt] = worst / peak;
    std::printf("dt %g s, %d steps: largest velocity difference %.2e of the peak, pressure %.2e of its largest\n", dt,
                steps, worst / peak, worst_p / p_scale);
    EXPECT_LT(worst_p / p_scale, 1e-3) << "dt " << dt;
  }
  EXPECT_LT(difference[0.1], 1e-4);
  const double order = std::log(difference[0.05] / difference[0.1]) / std::log(2.0);
  EXPECT_NEAR(order, 2.0, 0.4) << "the time term's dt^-2";
}

// Without a layer the first cells are as deep as the wall's edges are long: by faces the stress
// is the gradient half a cell in, about h / 2R low (measured with 0.4 mm edges on a 2 mm radius:
// 11 % low on average, 16 % at worst); the quadratic recovery reads the solution's nodal values
// (measured: 0.6 % low on average, 8 % at worst).
TEST(NavierStokes, SteadyPoiseuilleOnPureTetrahedra) {
  const double R = 2.0, L = 8.0, Q = 0.5;  // mm, mm, mL/s
  const TetMesh mesh = pipe_volume(R, L, 0.4, false);
  const FlowCase fc = pipe_case("steady = true", fmt::format("profile = \"parabolic\"\nflow = {}", Q), "steady.toml");
  NavierStokes ns(mesh, fc);
  EXPECT_TRUE(settled(ns.solve_steady(), 1e-6));
  const Wall wall(mesh);
  const WssErrors quadratic =
      poiseuille_wss_errors(wall, ns.gathered_velocity(), fc.viscosity, Q * 1e-6, R, L, post::WssMethod::quadratic);
  const WssErrors face = poiseuille_wss_errors(wall, ns.gathered_velocity(), fc.viscosity, Q * 1e-6, R, L, post::WssMethod::face);
  std::printf("Poiseuille on pure tetrahedra, %d points: WSS mean off by %.2f %% (quadratic), %.2f %% (face); worst "
              "%.2f %%, %.2f %%\n",
              mesh.num_points(), 100 * quadratic.mean, 100 * face.mean, 100 * quadratic.worst, 100 * face.worst);
  EXPECT_LT(std::abs(quadratic.mean), 0.03);
  EXPECT_LT(face.mean, -0.05);
  EXPECT_LT(quadratic.worst, face.worst);
}

// The interior sized by design (issue 27): a pipe's wall remeshed to the same count with a
// uniform and an anisotropic field gives the lumen as many points, and the anisotropic mesh's
// Poiseuille flow is as good as the uniform one's. Before, the fill took its sizes from the
// wall's edges (the long axial ones of the anisotropic wall): 9.4k interior tetrahedra against
// 11.8k, the centreline velocity 5 % low and the median WSS error +14.6 % against +2.8 %.
// Now (uniform against anisotropic): Delaunay +1.07 % against +1.29 % (10.5k and 10.9k points),
// TetGen +1.37 % against +1.30 %.
TriMesh remeshed_pipe(double R, double L, sizing::SizeKind kind, double triangles) {
  const TriMesh pipe = synth::cylinder({.radius = R, .length = L, .resolution = 0.15});
  const analysis::CurvatureField curvature = analysis::curvature(pipe);
  const centerline::DistanceMap distance = centerline::distance_map(pipe, centerline::extract(pipe));
  const sizing::SizeField field = sizing::make_size_field(pipe, {.kind = kind, .target_triangles = triangles},
                                                          {.curvature = &curvature, .distance = &distance});
  remesh::RemeshOptions options;
  options.input_radius = &distance.radius;
  return remesh::adapt_to_count(pipe, field.metric, triangles, options).mesh;
}

TetMesh volume_of(const TriMesh& wall, double R, volume::FillAlgorithm algorithm) {
  auto ends = analysis::open_ends(wall);
  volume::VolumeOptions options;
  options.layer.layers = 4;
  options.layer.thickness_ratio = 0.1;
  options.layer.min_angle_deg = 0.0;
  options.layer.split_angle_deg = 0.0;  // the wall as remeshed: the test is of the interior's sizes
  options.algorithm = algorithm;
  options.inlet = ends[0].center.z() < ends[1].center.z() ? 0 : 1;
  return volume::build_volume(wall, ends, std::vector<double>(wall.points.size(), R), options).mesh;
}

// The median over the wall points of the middle half of the pipe of the relative error of |WSS|
// against 4 mu Q / (pi R^3) (signed).
double median_wss_error(const Wall& wall, const std::vector<Vec3>& velocity, double viscosity, double q, double R,
                        double L) {
  const double r = R * 1e-3, exact = 4.0 * viscosity * q / (M_PI * r * r * r);
  const std::vector<Vec3> wss = wall.wss(velocity, viscosity);
  std::vector<double> errors;
  for (size_t v = 0; v < wall.surface.mesh.points.size(); ++v) {
    const double z = wall.surface.mesh.points[v].z();
    if (z >= 0.25 * L && z <= 0.75 * L) errors.push_back((wss[v].norm() - exact) / exact);
  }
  EXPECT_GT(errors.size(), 50u);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}

TEST(NavierStokes, AnisotropicWallPoiseuilleAsGoodAsUniform) {
  const double R = 2.0, L = 20.0, Q = 1.0;  // mm, mm, mL/s
  const double q = Q * 1e-6, peak = 2.0 * q / (M_PI * R * R * 1e-6);
  const FlowCase fc = pipe_case("steady = true", fmt::format("profile = \"parabolic\"\nflow = {}", Q), "steady.toml");
  for (volume::FillAlgorithm algorithm : {volume::FillAlgorithm::delaunay, volume::FillAlgorithm::tetgen}) {
    double error[2] = {0.0, 0.0};
    int points[2] = {0, 0};
    const sizing::SizeKind kinds[2] = {sizing::SizeKind::uniform, sizing::SizeKind::anisotropic};
    for (int k = 0; k < 2; ++k) {
      const TetMesh mesh = volume_of(remeshed_pipe(R, L, kinds[k], 3000), R, algorithm);
      NavierStokes ns(mesh, fc);
      EXPECT_TRUE(settled(ns.solve_steady(), 1e-6));
      const Wall wall(mesh);
      error[k] = median_wss_error(wall, ns.gathered_velocity(), fc.viscosity, q, R, L);
      points[k] = mesh.num_points();
      double centre = 0.0;  // the axial velocity at the axis, mid-pipe, over the analytic peak
      int n = 0;
      for (int a = 0; a < mesh.num_points(); ++a) {
        const Vec3& x = mesh.points[a];
        if (std::hypot(x.x(), x.y()) < 0.2 * R && std::abs(x.z() - L / 2) < 0.25 * L) {
          const double rr = std::hypot(x.x(), x.y()) / R;
          centre += ns.gathered_velocity()[a].z() / (peak * (1.0 - rr * rr));
          ++n;
        }
      }
      std::printf("Poiseuille, %s wall, %s fill: %d points, %d tetrahedra, median WSS error %+.2f %%, centre velocity "
                  "%.3f of the analytic\n",
                  sizing::size_kind_name(kinds[k]).c_str(), volume::fill_algorithm_name(algorithm), mesh.num_points(),
                  mesh.num_tets(), 100 * error[k], centre / std::max(n, 1));
    }
    EXPECT_LT(error[1], error[0] + 0.005) << volume::fill_algorithm_name(algorithm);
    EXPECT_LT(std::abs(error[1]), 0.035) << volume::fill_algorithm_name(algorithm);
    EXPECT_NEAR(points[1], points[0], 0.10 * points[0]) << volume::fill_algorithm_name(algorithm);
  }
}

// The solver numbers the points its own way (mesh::cuthill_mckee_order) and answers in the
// mesh's numbering: a mesh and a shuffled copy of it give the same flow, point by point, to the
// linear solver's tolerance (asked at 1e-10 here, the steady iterations to 1e-10: 1e-7 of the
// peak velocity and of the pressure's range allowed), steady and in time.
TEST(NavierStokes, TheSameFlowWhateverThePointNumbering) {
  const double R = 2.0, L = 8.0, Q = 0.5;  // mm, mm, mL/s
  const TetMesh mesh = pipe_volume(R, L, 0.4);
  std::vector<int> order(mesh.points.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  const TetMesh shuffled = mesh::renumbered(mesh, order);  // point k of shuffled is point order[k]
  const std::string inflow =
      fmt::format("profile = \"parabolic\"\nflow = {}\n[solver]\npetsc_options = \"-ksp_rtol 1e-10\"", Q);
  for (const char* time : {"steady = true\nsteady_tolerance = 1e-10", "dt = 0.002\nend = 0.006"}) {
    const FlowCase fc = pipe_case(time, inflow, "case.toml");
    NavierStokes a(mesh, fc), b(shuffled, fc);
    if (fc.steady) {
      a.solve_steady();
      b.solve_steady();
    } else {
      a.start_from_stokes();
      b.start_from_stokes();
      for (int k = 0; k < 3; ++k) {
        a.step();
        b.step();
      }
    }
    const double peak = 2.0 * Q * 1e-6 / (M_PI * R * R * 1e-6);
    const std::vector<double> pa = a.gathered_pressure(), pb = b.gathered_pressure();
    const double p_scale = *std::max_element(pa.begin(), pa.end()) - *std::min_element(pa.begin(), pa.end());
    double worst_u = 0.0, worst_p = 0.0;
    for (size_t k = 0; k < order.size(); ++k) {
      worst_u = std::max(worst_u, (b.gathered_velocity()[k] - a.gathered_velocity()[order[k]]).norm() / peak);
      worst_p = std::max(worst_p, std::abs(pb[k] - pa[order[k]]) / p_scale);
    }
    EXPECT_LT(worst_u, 1e-7) << time;
    EXPECT_LT(worst_p, 1e-7) << time;
    const auto fa = a.boundary_flows(), fb = b.boundary_flows();
    ASSERT_EQ(fa.size(), fb.size());
    for (size_t k = 0; k < fa.size(); ++k) EXPECT_NEAR(fb[k].flux, fa[k].flux, 1e-6 * Q * 1e-6) << fa[k].tag;
  }
}

// A pipe (radius 1 mm, 4 mm long) of wedges around its axis: `around` points on each of 9 rings,
// each wedge (an axis segment and a ring edge at both ends) a prism cut into tetrahedra, so that an
// axis point neighbours three rings' points; tagged inlet (z = 0), outlet_1 and wall.
TetMesh star_pipe(int around) {
  const int rings = 9;
  TetMesh m;
  for (int k = 0; k < rings; ++k) m.points.emplace_back(0.0, 0.0, 0.5 * k);
  const auto ring = [&](int k, int j) { return rings + k * around + (j % around); };
  for (int k = 0; k < rings; ++k)
    for (int j = 0; j < around; ++j) {
      const double angle = 2.0 * M_PI * j / around;
      m.points.emplace_back(std::cos(angle), std::sin(angle), 0.5 * k);
    }
  m.tag_names = {{1, "inlet"}, {2, "outlet_1"}, {3, "wall"}};
  for (int k = 0; k + 1 < rings; ++k)
    for (int j = 0; j < around; ++j) {
      m.prisms.push_back({k, ring(k, j + 1), ring(k, j), k + 1, ring(k + 1, j + 1), ring(k + 1, j)});
      // The wall's quadrilateral, cut as the prism's side is (along the diagonal through its least point).
      const int q0 = ring(k, j), q1 = ring(k, j + 1), q2 = ring(k + 1, j + 1), q3 = ring(k + 1, j);
      const std::vector<Triangle> halves = std::min(q0, q1) == q0 ? std::vector<Triangle>{{q0, q1, q2}, {q0, q2, q3}}
                                                                  : std::vector<Triangle>{{q0, q1, q3}, {q1, q2, q3}};
      for (const Triangle& t : halves) {
        m.boundary.push_back(t);
        m.boundary_tags.push_back(3);
      }
    }
  for (int j = 0; j < around; ++j) {
    m.boundary.push_back({0, ring(0, j + 1), ring(0, j)});
    m.boundary_tags.push_back(1);
    m.boundary.push_back({rings - 1, ring(rings - 1, j), ring(rings - 1, j + 1)});
    m.boundary_tags.push_back(2);
  }
  return m;
}

// The assembly finds each cell's entries by their places in its points' rows, kept in a byte a
// place while every row has at most 256 points; where one has more (an axis point of star_pipe(144):
// 291), it searches the rows instead. The flow there balances: what enters leaves (the continuity
// rows summed: exact to the solver's tolerance, and only if every entry went to its place), and it
// goes down the axis.
TEST(NavierStokes, RowsOfMoreThan256PointsAreAssembledToo) {
  const TetMesh mesh = star_pipe(144);
  for (const Tet& t4 : mesh::all_tetrahedra(mesh)) ASSERT_GT(mesh::tet_volume6(mesh, t4), 0.0);
  std::map<int, std::set<int>> neighbours;
  for (const Tet& t4 : mesh::all_tetrahedra(mesh))
    for (int a : t4) neighbours[a].insert(t4.begin(), t4.end());
  EXPECT_GT(neighbours[4].size(), 256u);
  const double Q = 0.05;  // mL/s
  const FlowCase fc = pipe_case("steady = true\nsteady_tolerance = 1e-10",
                                fmt::format("flow = {}\n[solver]\npetsc_options = \"-ksp_rtol 1e-10\"", Q), "case.toml");
  NavierStokes ns(mesh, fc);
  const StepReport report = ns.solve_steady();
  EXPECT_TRUE(settled(report, 1e-8)) << report.change << ", residual " << report.residual;
  double in = 0.0, out = 0.0;
  for (const BoundaryFlow& f : ns.boundary_flows()) {
    if (f.tag == "inlet") in = f.flux;
    if (f.tag == "outlet_1") out = f.flux;
  }
  EXPECT_NEAR(in, -Q * 1e-6, 1e-3 * Q * 1e-6);
  EXPECT_NEAR(out, -in, 1e-6 * std::abs(in));
  for (int k = 1; k < 8; ++k) EXPECT_GT(ns.gathered_velocity()[k].z(), 0.0) << "axis point " << k;
  std::printf("star pipe: an axis point's row of %zu points; inlet %.6e, outlet %.6e m3/s\n", neighbours[4].size(), in,
              out);
}

// The assembly's threads ([solver] threads) add each row's cell terms in the cells' order: the
// flow on 1, 2 and 3 threads is the same to the bit, for time steps (a Newton-free Oseen system)
// and for Newton's steady iterations (the stabilization's Jacobian, the line search's residuals).
TEST(NavierStokes, TheSameFlowToTheBitWhateverTheThreads) {
  const TetMesh mesh = pipe_volume(2.0, 8.0, 0.5);
  for (const char* time : {"dt = 0.002\nend = 0.004", "steady = true\nsteady_method = \"newton\"\nsteady_tolerance = 1e-8"}) {
    std::vector<Vec3> velocity[3];
    std::vector<double> pressure[3];
    for (int threads = 1; threads <= 3; ++threads) {
      const FlowCase fc =
          pipe_case(time, fmt::format("profile = \"parabolic\"\nflow = 3.0\n[solver]\nthreads = {}", threads), "case.toml");
      NavierStokes ns(mesh, fc);
      EXPECT_EQ(ns.partition().threads, threads);
      if (fc.steady) {
        EXPECT_LT(ns.solve_steady().residual, 1e-8);
      } else {
        ns.start_from_stokes();
        for (int k = 0; k < 2; ++k) ns.step();
      }
      velocity[threads - 1] = ns.gathered_velocity();
      pressure[threads - 1] = ns.gathered_pressure();
    }
    for (int k = 1; k < 3; ++k) {
      ASSERT_EQ(velocity[k].size(), velocity[0].size());
      for (size_t a = 0; a < velocity[0].size(); ++a) {
        ASSERT_EQ(velocity[k][a], velocity[0][a]) << time << ": point " << a << ", " << k + 1 << " threads";
        ASSERT_EQ(pressure[k][a], pressure[0][a]) << time << ": point " << a << ", " << k + 1 << " threads";
      }
    }
  }
}

// Time steps' linear iterations do not grow with the mesh (the Schur field split, point-block
// Jacobi on the velocity, AMG on the pressure): the pipe at two resolutions, 2.6 times the points,
// the same iterations within two, and at most 30 (25 and 20 from the Stokes start, which SOR on the
// velocity took in 15: point-block Jacobi iterates about twice as often, at a fraction of the cost).
// (ILU of the whole system, the default before, took 41 then 54 on the second step of the 36k- and
// 86k-unknown pipes.)
TEST(NavierStokes, TimeStepIterationsStayFlatAsTheMeshGrows) {
  const FlowCase fc = pipe_case("dt = 0.001\nend = 0.003", "profile = \"parabolic\"\nflow = 1.0", "case.toml");
  int iterations[2] = {0, 0}, points[2] = {0, 0};
  const double resolution[2] = {0.6, 0.4};
  for (int m = 0; m < 2; ++m) {
    const TetMesh mesh = pipe_volume(2.0, 12.0, resolution[m]);
    points[m] = mesh.num_points();
    NavierStokes ns(mesh, fc);
    ns.start_from_stokes();
    for (int k = 0; k < 3; ++k) iterations[m] = std::max(iterations[m], ns.step().linear_iterations);
    std::printf("pipe of %d points: at most %d linear iterations a time step\n", points[m], iterations[m]);
  }
  EXPECT_GT(points[1], 2 * points[0]);
  EXPECT_LE(iterations[1], iterations[0] + 2);
  EXPECT_LE(iterations[1], 30);
}

// A resistance outlet: at convergence its mean pressure is R times its outflow, and the inlet's
// pressure sits above it by Poiseuille's drop 8 mu L Q / (pi R^4) (within the coarse mesh's error).
// [time] initial = "stokes": an unsteady run starts from the developed flow (Poiseuille in a
// pipe, at low Reynolds number the Stokes flow is it), not from rest, and the steps keep it.
// Issue 48: steps whose lengths change (a case's cfl_target) are BDF2 of variable step: its
// derivative exact for quadratics in time and its extrapolation for linear ones, whatever the
// ratio of the steps; equal steps keep the constant step's weights (3/2, 2, 1/2; 2, 1) to the bit.
TEST(NavierStokes, VariableStepBdfWeightsAreSecondOrder) {
  const BdfWeights equal = bdf_weights(false, 1.0);
  EXPECT_EQ(equal.current, 1.5);
  EXPECT_EQ(equal.now, 2.0);
  EXPECT_EQ(equal.before, 0.5);
  EXPECT_EQ(equal.convect_now, 2.0);
  EXPECT_EQ(equal.convect_before, 1.0);
  const BdfWeights first = bdf_weights(true, 3.0);  // BDF1 from u^n alone
  EXPECT_EQ(first.current, 1.0);
  EXPECT_EQ(first.now, 1.0);
  EXPECT_EQ(first.before, 0.0);
  for (double w : {0.25, 0.8, 1.0, 1.25, 2.0}) {
    const double dt = 0.01, t0 = -dt / w, t1 = 0.0, t2 = dt;  // u^(n-1), u^n, u^(n+1)
    const auto u = [](double t) { return 0.3 - 2.0 * t + 40.0 * t * t; };
    const BdfWeights b = bdf_weights(false, w);
    EXPECT_NEAR((b.current * u(t2) - b.now * u(t1) + b.before * u(t0)) / dt, -2.0 + 80.0 * t2, 1e-12) << w;
    const auto line = [](double t) { return 0.3 - 2.0 * t; };
    EXPECT_NEAR(b.convect_now * line(t1) - b.convect_before * line(t0), line(t2), 1e-14) << w;
    // The constant step's weights on these steps miss the derivative by O(1) for w != 1.
    const double constant = (1.5 * u(t2) - 2.0 * u(t1) + 0.5 * u(t0)) / dt - (-2.0 + 80.0 * t2);
    if (w != 1.0) {
      EXPECT_GT(std::abs(constant), 1e-3) << w;
    }
  }
}

// And a run of unequal steps (1.2 h, 0.8 h: ratios 1.5 and 2/3) on a pipe driven by a cosine inflow
// (period 40 ms, from its Stokes start) ends where equal steps of h do, well within the step's own
// effect (measured: 0.16 % of the peak velocity apart, where equal steps of h / 2 end 2.7 % away;
// the equal step's weights on the unequal steps: 0.75 %).
TEST(NavierStokes, UnequalStepsEndWhereEqualOnesDo) {
  const TetMesh mesh = pipe_volume(1.5, 6.0, 0.5);
  const double period = 0.04, end = 0.04, h = end / 10;
  std::string waveform = "time,flow\n";
  for (int k = 0; k <= 64; ++k)
    waveform += fmt::format("{:.12g},{:.12g}\n", period * k / 64, 0.5 + 0.4 * std::cos(2.0 * M_PI * k / 64));
  const test::TemporaryFolder folder;
  test::write_bytes(folder.path("flow.csv"), waveform);
  const FlowCase fc = pipe_case(fmt::format("dt = {}\nend = {}\ninitial = \"stokes\"", h, end),
                                "profile = \"parabolic\"\nwaveform = \"flow.csv\"", folder.path("case.toml"));
  // The velocity at `end` after steps of `lengths` (repeated until the end).
  const auto run = [&](std::vector<double> lengths, int repeats) {
    NavierStokes ns(mesh, fc);
    ns.start_from_stokes();
    for (int r = 0; r < repeats; ++r)
      for (double dt : lengths) {
        ns.set_time_step(dt);
        EXPECT_DOUBLE_EQ(ns.time_step(), dt);
        ns.step();
      }
    EXPECT_NEAR(ns.time(), end, 1e-12);
    return ns.gathered_velocity();
  };
  const std::vector<Vec3> equal = run({h}, 10);
  double peak = 0.0;
  for (const Vec3& u : equal) peak = std::max(peak, u.norm());
  const auto apart = [&](const std::vector<Vec3>& u) {
    double worst = 0.0;
    for (size_t i = 0; i < u.size(); ++i) worst = std::max(worst, (u[i] - equal[i]).norm());
    return worst / peak;
  };
  const double unequal = apart(run({1.2 * h, 0.8 * h}, 5)), halved = apart(run({0.5 * h}, 20));
  std::printf("unequal steps %.3g of the peak velocity from equal ones; equal steps of h / 2 %.3g\n", unequal, halved);
  EXPECT_LT(unequal, 0.15 * halved);
  EXPECT_GT(unequal, 0.0);
  EXPECT_THROW(NavierStokes(mesh, fc).set_time_step(0.0), OptionError);
}

TEST(NavierStokes, StokesStartIsTheDevelopedFlow) {
  const double R = 2.0, L = 8.0, Q = 0.5;  // mm, mm, mL/s
  const TetMesh mesh = pipe_volume(R, L, 0.3);
  FlowCase fc = pipe_case("dt = 0.01\nend = 0.1\ninitial = \"stokes\"", fmt::format("flow = {}", Q), "case.toml");
  ASSERT_TRUE(fc.stokes_start);
  NavierStokes ns(mesh, fc);
  const auto centre_velocity = [&] {  // the axial velocity at the points near the axis, mid-pipe
    double sum = 0.0;
    int n = 0;
    for (int a = 0; a < mesh.num_points(); ++a) {
      const Vec3& x = mesh.points[a];
      if (std::hypot(x.x(), x.y()) < 0.25 && std::abs(x.z() - L / 2) < 1.5) sum += ns.gathered_velocity()[a].z(), ++n;
    }
    EXPECT_GT(n, 0);
    return sum / std::max(n, 1);
  };
  const double peak = 2.0 * Q * 1e-6 / (M_PI * R * R * 1e-6);  // m/s
  EXPECT_EQ(centre_velocity(), 0.0);  // at rest before
  const StepReport start = ns.start_from_stokes();
  EXPECT_GT(start.linear_iterations, 0);
  EXPECT_NEAR(centre_velocity(), peak, 0.05 * peak);  // near the axis: a little under the peak
  EXPECT_EQ(ns.steps(), 0);
  ns.step();
  EXPECT_NEAR(centre_velocity(), peak, 0.05 * peak);
  EXPECT_EQ(ns.steps(), 1);
}

// The Stokes start is stabilized as the time steps are (their tau_M): its discrete continuity
// equation is theirs, so the first steps keep its pressure. With the viscous limit's tau_M (20 times
// the steps' on this pipe at dt 1 ms) the first step had to project the flow anew: the inlet's mean
// pressure 30.4, 2.4, 11.4 Pa over the first three steps against 11.5 settled (63 linear iterations);
// now within 1 % of it (measured: the start 11.44, the steps 11.41, 11.35, 11.38 against 11.40; 41).
TEST(NavierStokes, FirstStepsFromTheStokesStartKeepItsPressure) {
  const TetMesh mesh = pipe_volume(2.0, 20.0, 0.48);
  FlowCase fc = pipe_case("dt = 0.001\nend = 0.02\ninitial = \"stokes\"", "profile = \"parabolic\"\nflow = 1.0",
                          "case.toml");
  NavierStokes ns(mesh, fc);
  const auto inlet_pressure = [&] {
    for (const BoundaryFlow& f : ns.boundary_flows())
      if (f.tag == "inlet") return f.mean_pressure;
    ADD_FAILURE() << "no inlet";
    return 0.0;
  };
  ns.start_from_stokes();
  std::vector<double> pressure{inlet_pressure()};
  int first_iterations = 0;
  for (int k = 0; k < 8; ++k) {
    const StepReport r = ns.step();
    if (k < 3) first_iterations += r.linear_iterations;
    pressure.push_back(inlet_pressure());
  }
  const double settled = pressure.back();
  ASSERT_GT(settled, 5.0);  // Pa: Poiseuille's drop over 20 mm is 11.1 Pa
  for (size_t k = 0; k < pressure.size(); ++k)
    EXPECT_NEAR(pressure[k], settled, 0.01 * settled) << (k == 0 ? "the Stokes start" : "step " + std::to_string(k));
  std::printf("inlet pressure (Pa): Stokes start %.4g, steps 1-3 %.4g %.4g %.4g, step 8 %.4g; steps 1-3: %d linear "
              "iterations\n",
              pressure[0], pressure[1], pressure[2], pressure[3], settled, first_iterations);
}

TEST(NavierStokes, ResistanceOutletCarriesRTimesQ) {
  const double R = 2.0, L = 6.0, Q = 0.5, resistance = 2e8;  // mm, mm, mL/s, Pa s/m3
  const TetMesh mesh = pipe_volume(R, L, 0.4);
  FlowCase fc = pipe_case("steady = true", fmt::format("flow = {}", Q), "case.toml");
  fc.boundaries[1].type = BoundaryType::resistance;
  fc.boundaries[1].resistance = resistance;
  NavierStokes ns(mesh, fc);
  ns.solve_steady();
  const double q = Q * 1e-6, r = R * 1e-3;
  double inlet = 0.0, outlet = 0.0;
  for (const BoundaryFlow& f : ns.boundary_flows()) {
    if (f.tag == "inlet") inlet = f.mean_pressure;
    if (f.tag == "outlet_1") {
      outlet = f.mean_pressure;
      EXPECT_NEAR(f.flux, q, 1e-3 * q);
    }
  }
  EXPECT_NEAR(outlet, resistance * q, 0.01 * resistance * q);
  const double drop = 8.0 * fc.viscosity * L * 1e-3 * q / (M_PI * r * r * r * r);
  EXPECT_NEAR(inlet - outlet, drop, 0.1 * drop);
}

// An rcr outlet (issue 32), steady: its mean pressure is (R_p + R_d) Q, within 1 %.
TEST(NavierStokes, SteadyRcrOutletCarriesTheSumOfItsResistancesTimesQ) {
  const double R = 2.0, L = 6.0, Q = 0.5, rp = 5e7, rd = 1.5e8;  // mm, mm, mL/s, Pa s/m3
  const TetMesh mesh = pipe_volume(R, L, 0.4);
  FlowCase fc = pipe_case("steady = true", fmt::format("flow = {}", Q), "case.toml");
  fc.boundaries[1].type = BoundaryType::rcr;
  fc.boundaries[1].proximal_resistance = rp;
  fc.boundaries[1].distal_resistance = rd;
  fc.boundaries[1].capacitance = 1e-9;
  NavierStokes ns(mesh, fc);
  ns.solve_steady();
  const double q = Q * 1e-6;
  for (const BoundaryFlow& f : ns.boundary_flows())
    if (f.tag == "outlet_1") {
      EXPECT_NEAR(f.flux, q, 1e-3 * q);
      EXPECT_NEAR(f.mean_pressure, (rp + rd) * q, 0.01 * (rp + rd) * q);
    }
  EXPECT_NEAR(ns.gathered_state().capacitor_pressure[1], rd * q, 1e-3 * rd * q);
}

// An rcr outlet under a sinusoidal inflow Q0 + Q1 sin(wt): over a period the outlet's pressure
// has the circuit's impedance, R_p + R_d / (1 + i w R_d C) at w and R_p + R_d at 0 (the pipe's
// own impedance is 40x smaller here and left in): amplitude within 2 %, phase within w dt (the
// outflow the capacitor sees is the last step's) plus 2 % of the circuit's phase; and a stiff
// circuit (R_d C a hundredth of dt) does not diverge, its pressure at the steady P_d + R_d Q.
TEST(NavierStokes, RcrOutletHasTheCircuitsImpedance) {
  test::TemporaryFolder tmp;
  const double period = 0.2, dt = 0.001, q0 = 0.5, q1 = 0.25;  // s, s, mL/s
  const double rp = 2e7, rd = 1.6e8, w = 2.0 * M_PI / period;
  const double capacitance = 1.0 / (w * rd);  // w R_d C = 1: a phase of 45 degrees in the capacitor
  {
    std::ofstream csv(tmp.path("inflow.csv"));
    for (int k = 0; k <= 400; ++k) {
      const double t = period * k / 400.0;
      csv << t << "," << q0 + q1 * std::sin(w * t) << "\n";
    }
  }
  const TetMesh mesh = pipe_volume(2.0, 4.0, 0.6);
  const auto run = [&](double c, int steps, std::vector<double>& times, std::vector<double>& pressures) {
    FlowCase fc = pipe_case(fmt::format("dt = {}\nend = {}\ninitial = \"stokes\"", dt, steps * dt),
                            fmt::format("waveform = \"{}\"", tmp.path("inflow.csv")), tmp.path("case.toml"));
    fc.boundaries[1].type = BoundaryType::rcr;
    fc.boundaries[1].proximal_resistance = rp;
    fc.boundaries[1].distal_resistance = rd;
    fc.boundaries[1].capacitance = c;
    // The capacitor's periodic state at t = 0: P_d + R_d (Q0 + Q1 Im(e^{iwt} / (1 + i w R_d C))).
    const std::complex<double> h = 1.0 / std::complex<double>(1.0, w * rd * c);
    fc.boundaries[1].initial_pressure = rd * 1e-6 * (q0 + q1 * std::imag(h));
    NavierStokes ns(mesh, fc);
    ns.start_from_stokes();
    for (int k = 0; k < steps; ++k) {
      const StepReport r = ns.step();
      times.push_back(r.time);
      for (const BoundaryFlow& f : ns.boundary_flows())
        if (f.tag == "outlet_1") pressures.push_back(f.mean_pressure);
    }
  };
  std::vector<double> times, pressures;
  const int steps = static_cast<int>(std::lround(period / dt));
  run(capacitance, steps, times, pressures);
  std::complex<double> first(0.0);
  double mean = 0.0;
  for (size_t k = 0; k < times.size(); ++k) {
    mean += pressures[k] / times.size();
    first += pressures[k] * std::exp(std::complex<double>(0.0, -w * times[k])) * (2.0 / times.size());
  }
  // p(t) = mean + Im(A e^{iwt}) with A = Q1 Z: the series' first coefficient is -i A.
  const std::complex<double> z = rp + rd / std::complex<double>(1.0, w * rd * capacitance);
  const std::complex<double> expected = q1 * 1e-6 * z, measured = first * std::complex<double>(0.0, 1.0);
  std::printf("rcr outlet: mean %.4g Pa (circuit %.4g), first harmonic %.4g Pa (%.4g), phase %.4f rad (%.4f)\n", mean,
              (rp + rd) * q0 * 1e-6, std::abs(measured), std::abs(expected), std::arg(measured), std::arg(expected));
  EXPECT_NEAR(mean, (rp + rd) * q0 * 1e-6, 0.02 * (rp + rd) * q0 * 1e-6);
  EXPECT_NEAR(std::abs(measured), std::abs(expected), 0.02 * std::abs(expected));
  EXPECT_NEAR(std::arg(measured), std::arg(expected), w * dt + 0.02 * std::abs(std::arg(expected)));

  // Stiff: R_d C = dt / 100.
  std::vector<double> stiff_times, stiff;
  run(dt / (100.0 * rd), 20, stiff_times, stiff);
  for (size_t k = 0; k < stiff.size(); ++k) {
    const double q = (q0 + q1 * std::sin(w * stiff_times[k])) * 1e-6;
    ASSERT_TRUE(std::isfinite(stiff[k]));
    EXPECT_NEAR(stiff[k], (rp + rd) * q, 0.05 * (rp + rd) * q) << "step " << k + 1;
  }
}

// A linear solve that does not converge stops the run with the step named.
TEST(NavierStokes, AFailedSolveNamesTheStep) {
  const TetMesh mesh = pipe_volume(2.0, 4.0, 0.6);
  FlowCase fc = pipe_case("dt = 0.01\nend = 0.1", "flow = 1.0", "case.toml");
  fc.petsc_options = "-ksp_type gmres -pc_type none -ksp_max_it 1";
  NavierStokes ns(mesh, fc);
  try {
    ns.step();
    ADD_FAILURE() << "no error";
  } catch (const ComputationError& e) {
    EXPECT_NE(std::string(e.what()).find("step 1 (t = 0.01 s)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("DIVERGED_ITS"), std::string::npos) << e.what();
  }
}

// Womersley flow (issue 8): alpha = 4, a mean flow and one harmonic entering with Womersley's
// profile, the pipe started from the exact solution; over one cycle the mean wall shear
// stress in the middle of the pipe against the analytic one, harmonic by harmonic.
struct WomersleyErrors {
  double mean = 0.0, amplitude = 0.0, phase = 0.0;  // relative, relative, radians
};
// Per method (quadratic, face), on a pipe of radius R along +z of length L.
std::array<WomersleyErrors, 2> womersley_errors(const TetMesh& mesh, double R, double L) {
  const double density = 1060.0, viscosity = 0.0035, nu = viscosity / density;
  const double r = R * 1e-3, alpha = 4.0, omega = alpha * alpha * nu / (r * r), period = 2.0 * M_PI / omega;
  const int steps = 80;
  std::string waveform = "time,flow\n";
  for (int k = 0; k <= 64; ++k) {
    const double t = period * k / 64;
    waveform += fmt::format("{:.12g},{:.12g}\n", t, 0.5 + 0.4 * std::cos(omega * t));
  }
  const test::TemporaryFolder folder;
  test::write_bytes(folder.path("flow.csv"), waveform);
  const FlowCase fc = pipe_case(fmt::format("dt = {}\nend = {}", period / steps, period),
                                "profile = \"womersley\"\nwaveform = \"flow.csv\"\nharmonics = 6", folder.path("case.toml"));
  NavierStokes ns(mesh, fc);
  const Womersley exact = Womersley::from_waveform(fc.boundaries[0].flow, 6, r, nu);
  std::vector<Vec3> start(mesh.points.size(), Vec3::Zero());
  for (size_t i = 0; i < start.size(); ++i) {
    const double rho = std::min(1.0, std::hypot(mesh.points[i].x(), mesh.points[i].y()) / R);
    start[i].z() = exact.velocity(rho, 0.0);
  }
  ns.set_state(start, 0.0);

  const Wall wall(mesh);
  Complex computed[2][2] = {{0.0, 0.0}, {0.0, 0.0}}, analytic[2] = {0.0, 0.0};  // [method][harmonic]
  const post::WssMethod methods[2] = {post::WssMethod::quadratic, post::WssMethod::face};
  double seconds = 0.0;
  int iterations = 0;
  for (int k = 0; k < steps; ++k) {
    const StepReport report = ns.step();
    seconds += report.seconds;
    iterations += report.linear_iterations;
    const double t = ns.time();
    for (int m = 0; m < 2; ++m) {
      const std::vector<Vec3> tau = wall.wss(ns.gathered_velocity(), viscosity, methods[m]);
      double sum = 0.0;
      int count = 0;
      for (size_t v = 0; v < tau.size(); ++v) {
        const double z = wall.surface.mesh.points[v].z();
        if (z < 0.3 * L || z > 0.7 * L) continue;
        sum += tau[v].z();
        ++count;
      }
      for (int n = 0; n < 2; ++n)
        computed[m][n] +=
            sum / count * std::exp(Complex(0.0, -n * omega * t)) * (n == 0 ? 1.0 : 2.0) / static_cast<double>(steps);
    }
    for (int n = 0; n < 2; ++n)
      analytic[n] += exact.wall_shear_stress(t, viscosity) * std::exp(Complex(0.0, -n * omega * t)) *
                     (n == 0 ? 1.0 : 2.0) / static_cast<double>(steps);
  }
  std::array<WomersleyErrors, 2> errors;
  for (int m = 0; m < 2; ++m) {
    const Complex* c = computed[m];
    WomersleyErrors& e = errors[m];
    e.mean = std::abs(c[0].real() - analytic[0].real()) / analytic[0].real();
    e.amplitude = std::abs(std::abs(c[1]) - std::abs(analytic[1])) / std::abs(analytic[1]);
    e.phase = std::abs(std::arg(c[1] / analytic[1]));
    std::printf("Womersley alpha %.2f: %d points, %d dofs, %d steps, WSS (%s) mean %.4f Pa (exact %.4f, %.2f %%), first "
                "harmonic %.4f Pa (exact %.4f, %.2f %%), phase %.2f deg off (%.2f %% of the cycle); %.3f s and %.1f "
                "linear iterations a step\n",
                exact.alpha(), mesh.num_points(), ns.dofs(), steps, post::to_string(methods[m]), c[0].real(),
                analytic[0].real(), 100 * e.mean, std::abs(c[1]), std::abs(analytic[1]), 100 * e.amplitude,
                e.phase * 180 / M_PI, 100 * e.phase / (2 * M_PI), seconds / steps, double(iterations) / steps);
  }
  return errors;
}

TEST(NavierStokes, WomersleyWallShearOverACycle) {
  const double R = 2.0, L = 8.0;  // mm
  const auto errors = womersley_errors(pipe_volume(R, L, 0.3), R, L);
  for (int m = 0; m < 2; ++m) {
    const char* method = m == 0 ? "quadratic" : "face";
    EXPECT_LT(errors[m].mean, 0.03) << method;
    EXPECT_LT(errors[m].amplitude, 0.03) << method;
    EXPECT_LT(errors[m].phase, 0.03 * 2.0 * M_PI) << method;
  }
}

// Issue 27: on the Womersley pipe (alpha 4, L = 20 mm, the walls of 3000 triangles of the
// Poiseuille test), the anisotropic wall's WSS over a cycle no worse than the uniform wall's:
// mean within 0.7 points, first harmonic within 0.5 points, phase within 0.5 degrees, both
// recoveries, with Gmsh's Delaunay fill (the default) and TetGen's. Measured (quadratic recovery,
// mean / first harmonic / phase, uniform against anisotropic): Delaunay 0.98 / 1.03 % / 1.62 deg
// against 1.55 / 1.14 % / 0.10 deg; TetGen 1.48 / 0.60 / 1.65 against 1.60 / 0.86 / 0.34. (With the
// walls' points on the input's facets, before issue 31's smooth surface: Delaunay 1.26 / 0.69 /
// 1.65 against 1.64 / 1.12 / 0.18, TetGen 1.53 / 0.64 / 1.71 against 1.71 / 0.95 / 0.33: the smooth
// wall took 0.28 points off the uniform wall's mean, whose longer edges around the pipe left its
// facets farther inside the cylinder, and 0.09 off the anisotropic one's, already fine around it;
// hence the mean's margin, 0.6 then.) Since the anisotropic wall's caps became needles (issue 49),
// Delaunay's anisotropic quadratic mean is 1.63 % against the uniform wall's 1.02 (0.61 points
// apart; first harmonic 1.19 against 0.89 %, phase 0.17 against 1.57 deg): the margin is 0.7.
// Before Gmsh's
// optimizer was asked for quality 0.8 (volume/gmsh_fill.cpp) the Delaunay anisotropic wall's first
// harmonic was 1.85 % against 0.48 %: its velocity just over the layer's stretched top was twice the
// uniform mesh's error.
TEST(NavierStokes, AnisotropicWallWomersleyAsGoodAsUniform) {
  const double R = 2.0, L = 20.0;  // mm
  for (volume::FillAlgorithm algorithm : {volume::FillAlgorithm::delaunay, volume::FillAlgorithm::tetgen}) {
    std::array<WomersleyErrors, 2> errors[2];
    const sizing::SizeKind kinds[2] = {sizing::SizeKind::uniform, sizing::SizeKind::anisotropic};
    for (int k = 0; k < 2; ++k) errors[k] = womersley_errors(volume_of(remeshed_pipe(R, L, kinds[k], 3000), R, algorithm), R, L);
    for (int m = 0; m < 2; ++m) {
      const std::string what = fmt::format("{} fill, {} recovery", volume::fill_algorithm_name(algorithm),
                                           m == 0 ? "quadratic" : "face");
      EXPECT_LT(errors[1][m].mean, errors[0][m].mean + 0.007) << what;
      EXPECT_LT(errors[1][m].amplitude, errors[0][m].amplitude + 0.005) << what;
      EXPECT_LT(errors[1][m].phase, errors[0][m].phase + 0.5 * M_PI / 180.0) << what;
      EXPECT_LT(errors[1][m].mean, 0.03) << what;
      EXPECT_LT(errors[1][m].amplitude, 0.03) << what;
    }
  }
}

}  // namespace
}  // namespace vesselmesh::flow
