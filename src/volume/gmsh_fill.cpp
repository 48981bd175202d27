#include "volume/gmsh_fill.h"

#include "io/gmsh_session.h"
#include "mesh/error.h"

#include <fmt/format.h>
#include <gmsh.h>
#include <tbb/info.h>

#include <unordered_map>

namespace vesselmesh::volume {
namespace {
constexpr int kTriangle3 = 2, kTetrahedron4 = 4;  // Gmsh element types

// Gmsh's Delaunay leaves poorly shaped tetrahedra where its interior meets the boundary layer's
// stretched top (an anisotropic wall's): its optimizer, at its default quality threshold 0.3,
// leaves them, and the velocity just above the layer was twice as wrong as on a uniform wall
// (0.60 % of the peak against 0.31 % at r/R 0.8-0.9, the 2 mm Womersley pipe of
// tests/flow/navier_stokes_test.cpp), the first harmonic of its WSS 1.4 points worse. Every
// tetrahedron under quality 0.8 is optimized, then three more passes: on that pipe the gap goes
// to 0.4 points and the uniform wall's own errors fall (Poiseuille +1.38 -> +1.07 %), for about
// three times the fill's time (the carotid's 118k interior tetrahedra: 2.9 -> 9.5 s). HXT is left
// at Gmsh's default: its optimizer at 0.8 took minutes.
constexpr double kDelaunayOptimizeThreshold = 0.8;
constexpr int kDelaunayOptimizePasses = 3;

// Gmsh's interior edges come out longer than the size it is given: median edge over size 1.30
// (Delaunay) and 1.38 (HXT) on the pipe of tests/volume/interior_size_test.cpp. It is given the
// size over these, so that the size field means the median edge for every engine.
double size_scale(FillAlgorithm algorithm) {
  switch (algorithm) {
    case FillAlgorithm::delaunay: return 1.0 / 1.30;
    case FillAlgorithm::hxt: return 1.0 / 1.38;
    default: return 1.0;
  }
}
}

FillResult gmsh_fill(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary, FillAlgorithm algorithm,
                     int threads, const Reporter& reporter, const SizeFunction& size) {
  // Gmsh node tags 1, 2, ... for the points the boundary uses, in index order (contiguous, so
  // that Gmsh's renumbering after meshing keeps them).
  std::vector<int> tag_of(points.size(), 0);
  for (const Triangle& f : boundary)
    for (int v : f) tag_of[v] = 1;
  std::vector<std::size_t> node_tags;
  std::vector<int> point_of_tag(1, -1);
  std::vector<double> coords;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!tag_of[i]) continue;
    tag_of[i] = static_cast<int>(point_of_tag.size());
    node_tags.push_back(point_of_tag.size());
    point_of_tag.push_back(static_cast<int>(i));
    coords.insert(coords.end(), {points[i].x(), points[i].y(), points[i].z()});
  }
  std::vector<std::size_t> element_tags, element_nodes;
  for (size_t t = 0; t < boundary.size(); ++t) {
    element_tags.push_back(t + 1);
    for (int v : boundary[t]) element_nodes.push_back(static_cast<std::size_t>(tag_of[v]));
  }

  FillResult out;
  out.points = points;
  io::GmshSession session;
  io::ScopedGmshOptions options;
  io::call_gmsh("interior tetrahedra (Gmsh)", [&] {
    if (algorithm == FillAlgorithm::frontal) {
      std::string build;
      gmsh::option::getString("General.BuildOptions", build);
      if (build.find("Netgen") == std::string::npos)
        throw OptionError("--algorithm frontal: this Gmsh was built without Netgen, which its 3D Frontal "
                          "algorithm needs; use delaunay or hxt");
    }
    gmsh::model::add("lumen");
    gmsh::model::addDiscreteEntity(2, 1);
    gmsh::model::mesh::addNodes(2, 1, node_tags, coords);
    gmsh::model::mesh::addElementsByType(1, kTriangle3, element_tags, element_nodes);
    const int loop = gmsh::model::geo::addSurfaceLoop({1});
    gmsh::model::geo::addVolume({loop}, 1);
    gmsh::model::geo::synchronize();
    gmsh::option::setNumber("Mesh.Algorithm3D", algorithm == FillAlgorithm::delaunay ? 1
                                                 : algorithm == FillAlgorithm::frontal ? 4
                                                                                        : 10);
    gmsh::option::setNumber("Mesh.MaxNumThreads3D", threads > 0 ? threads : tbb::info::default_concurrency());
    gmsh::option::setNumber("Mesh.Optimize", 1);
    if (algorithm == FillAlgorithm::delaunay) options.set("Mesh.OptimizeThreshold", kDelaunayOptimizeThreshold);
    if (size) {
      // Our sizes alone: Gmsh's from the boundary, its points and curvature left out.
      options.set("Mesh.MeshSizeExtendFromBoundary", 0);
      options.set("Mesh.MeshSizeFromPoints", 0);
      options.set("Mesh.MeshSizeFromCurvature", 0);
      const double scale = size_scale(algorithm);
      options.size_callback(
          [&size, scale](int, int, double x, double y, double z) { return scale * size(Vec3(x, y, z)); });
    } else {
      options.set("Mesh.MeshSizeExtendFromBoundary", 1);
    }
    reporter.progress("interior tetrahedra", 0.0);
    gmsh::model::mesh::generate(3);
    if (algorithm == FillAlgorithm::delaunay) gmsh::model::mesh::optimize("", false, kDelaunayOptimizePasses);
    reporter.progress("interior tetrahedra", 1.0);

    std::vector<std::size_t> tags;
    std::vector<double> xyz, parametric;
    gmsh::model::mesh::getNodes(tags, xyz, parametric, 3, 1, true, false);
    std::unordered_map<std::size_t, int> index_of;
    const std::size_t boundary_nodes = node_tags.size();
    for (size_t i = 0; i < tags.size(); ++i) {
      const Vec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      if (tags[i] >= 1 && tags[i] <= boundary_nodes) {
        const int ours = point_of_tag[tags[i]];
        if (p != points[ours])
          throw InternalError(fmt::format("Gmsh renumbered the boundary: its node {} is not point {}", tags[i], ours));
        index_of.emplace(tags[i], ours);
        continue;
      }
      index_of.emplace(tags[i], static_cast<int>(out.points.size()));
      out.points.push_back(p);
    }
    std::vector<std::size_t> tet_tags, tet_nodes;
    gmsh::model::mesh::getElementsByType(kTetrahedron4, tet_tags, tet_nodes, 1);
    out.tets = io::in_our_numbering<4>(tet_nodes, index_of, "tetrahedron");
  });
  if (out.tets.empty())
    throw InputError("Gmsh made no tetrahedra inside the surface: it is not closed, or it intersects itself");
  return out;
}

}  // namespace vesselmesh::volume
