// A volume mesh in the formats of the solvers our users run (issue 33), written by us (no
// dependency on the solvers): the mesh's points scaled by `scale` (metres per mesh unit, 1e-3 for a
// mesh in mm to metres), its tags and their names carried through.
//
// - svfsi: svMultiPhysics's (svFSIplus, SimVascular) "mesh-complete" folder, as SimVascular's
//   mesher writes it: OUT/mesh-complete/mesh-complete.mesh.vtu (the tetrahedra; point data
//   GlobalNodeID, cell data GlobalElementID, both from 1), mesh-complete.exterior.vtp (every
//   boundary triangle), mesh-surfaces/NAME.vtp per boundary tag and walls_combined.vtp (the tags
//   named wall*): point data GlobalNodeID (the volume's), cell data GlobalElementID (the
//   tetrahedron the triangle bounds) and ModelFaceID (the tag); and OUT/solver.xml, a skeleton
//   naming every face (blood, a parabolic 1 mL/s at the largest non-wall face, zero traction at the
//   others, no slip on the walls: edit it). svMultiPhysics takes one element type: a volume with
//   prisms is refused (build it with `volume`'s default, the prisms cut into tetrahedra).
// - openfoam: OUT/constant/polyMesh (points, faces, owner, neighbour, boundary; ASCII), one cell per
//   tetrahedron and per prism: internal faces first in upper-triangular order (by owner, then
//   neighbour; owner < neighbour, each face's normal out of its owner), then the boundary faces by
//   patch (a patch per boundary tag, type wall for the tags named wall*, patch otherwise); a prism's
//   quadrilateral on the boundary takes the tag of the triangles that cover it.
// - xdmf: XDMF + HDF5 as dolfinx (FEniCSx, VaMPy) reads them: OUT/mesh.h5, OUT/mesh.xdmf (grid
//   "mesh", tetrahedra, attribute "cell_tags") and OUT/facets.xdmf (grid "facet_tags", the boundary
//   triangles over the same points, attribute "facet_tags"; the tags' names in an Information);
//   XDMFFile.read_mesh(name="mesh"), read_meshtags(mesh, name="facet_tags"). One cell type:
//   prisms are refused. The HDF5 data through PETSc's module (io/hdf5_file.h).
// - fluent: Ansys Fluent's ASCII mesh (.msh): the nodes, the cells (tetrahedra, wedges), the faces
//   of OpenFOAM's listing (each once, indices in hexadecimal) in zones — the internal faces, then a
//   zone per boundary tag (wall for wall*, velocity-inlet for "inlet", pressure-outlet otherwise,
//   each named by its tag) — each face's right-hand normal pointing to its first cell (c0), a
//   boundary face's into the domain, as Fluent writes them.
// - vtu: the volume as `vesselmesh volume` writes it (io::write_vtu), scaled.
// - medit: INRIA Medit .mesh (MMG, Tetgen's and many FEM codes' input): Vertices, Triangles
//   (reference: the tag), Tetrahedra and Prisms (reference: the volume's tag; positively oriented,
//   a prism's first triangle facing its second).
#pragma once

#include "mesh/tetmesh.h"

#include <string>
#include <vector>

namespace vesselmesh::io {

enum class ExportFormat { svfsi, openfoam, vtu, medit, fluent, xdmf };

// "svfsi", "openfoam", "xdmf", "fluent", "vtu" or "medit"; InputError naming the accepted ones otherwise.
ExportFormat parse_export_format(const std::string& name);
std::string to_string(ExportFormat format);

struct ExportReport {
  std::vector<std::string> files;  // written, in order
  int points = 0, tetrahedra = 0, prisms = 0, boundary_triangles = 0;
};

// Writes `mesh` to `out` (a folder for svfsi, a file otherwise), every file whole or not at all.
// InputError for what the format cannot hold (prisms for svfsi, a tag name unfit for a file name).
ExportReport export_volume(const TetMesh& mesh, const std::string& out, ExportFormat format, double scale);

}  // namespace vesselmesh::io
