// The Gmsh peer of bench/remesh.sh, when no mmgs is given: Debian's Gmsh remeshes the input
// triangulation with the isotropic size of FIELD.vtp (point data size) as a background field:
// the surface reclassified (40-degree feature angle) and reparametrized, then meshed with
// Frontal-Delaunay. Writes OUTPUT.vtp. (Before the model's size was set after adding the nodes,
// Gmsh made 2.6 times the triangles the field asked for on the aortic arch.)
//   bench_remesh_gmsh FIELD.vtp OUTPUT.vtp
#include "io/gmsh_session.h"
#include "io/surface.h"
#include "mesh/error.h"

#include <gmsh.h>

#include <cstdio>
#include <map>
#include <numbers>

using namespace vesselmesh;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bench_remesh_gmsh FIELD.vtp OUTPUT.vtp\n");
    return 2;
  }
  try {
    const io::SurfaceFile field = io::read_surface(argv[1]);
    const Field* size = nullptr;
    for (const Field& f : field.point_data)
      if (f.name == "size") size = &f;
    if (!size) throw InputError(std::string(argv[1]) + ": no point data 'size'");
    const TriMesh& in = field.mesh;
    TriMesh out;
    io::GmshSession session;
    io::call_gmsh("Gmsh remeshing", [&] {
      gmsh::model::add("input");
      io::add_discrete_surface(in);  // sets the model's size too, which Gmsh's tolerances follow
      // The size on the input's triangles, as a post-processing view for the background field.
      std::vector<double> data;
      for (const Triangle& t : in.triangles) {
        for (int k = 0; k < 3; ++k)
          for (int v : t) data.push_back(in.points[v][k]);
        for (int v : t) data.push_back(size->values[v]);
      }
      const int view = gmsh::view::add("size");
      gmsh::view::addListData(view, "ST", in.num_triangles(), data);
      gmsh::model::mesh::classifySurfaces(40.0 * std::numbers::pi / 180.0, true, true, std::numbers::pi);
      gmsh::model::mesh::createGeometry();
      const int background = gmsh::model::mesh::field::add("PostView");
      gmsh::model::mesh::field::setNumber(background, "ViewTag", view);
      gmsh::model::mesh::field::setAsBackgroundMesh(background);
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::option::setNumber("Mesh.Algorithm", 6);
      gmsh::model::mesh::generate(2);
      std::vector<std::size_t> tags;
      std::vector<double> xyz, parametric;
      gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, true, false);
      std::map<std::size_t, int> index;
      for (std::size_t i = 0; i < tags.size(); ++i) {
        index[tags[i]] = static_cast<int>(i);
        out.points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      }
      std::vector<std::size_t> elements, element_nodes;
      gmsh::model::mesh::getElementsByType(2, elements, element_nodes);
      for (std::size_t e = 0; e < elements.size(); ++e)
        out.triangles.push_back({index.at(element_nodes[3 * e]), index.at(element_nodes[3 * e + 1]),
                                 index.at(element_nodes[3 * e + 2])});
    });
    io::write_surface(argv[2], out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_remesh_gmsh: %s\n", e.what());
    return 2;
  }
  return 0;
}
