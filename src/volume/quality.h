// Figures of a volume mesh, for `vesselmesh quality` and the tests: counts, inverted cells,
// dihedral angles (layer and interior apart when the mesh says which cells are layer cells),
// scaled Jacobian and aspect ratio, whether the tagged boundary closes the volume, and for the
// boundary layer the number of layers standing on each wall triangle and the thickness.
#pragma once

#include "mesh/tetmesh.h"

#include <map>
#include <string>
#include <vector>

namespace vesselmesh::volume {

struct VolumeQuality {
  int points = 0, tets = 0, prisms = 0;
  std::map<std::string, int> triangles_per_tag;  // by name ("tag_<n>" when unnamed)
  int inverted = 0;  // cells (prisms by their split) with volume <= 0
  // Degrees; over all cells, then the layer's and the interior's (-1 when there are none).
  double min_dihedral = 0, median_dihedral = 0, max_dihedral = 0;
  double min_dihedral_layer = -1, min_dihedral_interior = -1;
  // The layer's cells are flat by design (their least angle about atan(height / wall edge),
  // whatever the cut) and stand on the wall's triangles (an anisotropic wall's stretched by
  // design: the surface's own angles). In the layer's own frame, each cell mapped by the affine map
  // that takes its column's wall triangle to the equilateral one and its height to that triangle's
  // side, a column extruded straight and cut well is the unit prism's three tetrahedra (least
  // angle atan(sqrt(3) / 2) = 40.9 deg); a small angle there is what the layer made: a cut gone
  // wrong (a sliver or a needle across the column) or a column bent, twisted or pinched. Degrees;
  // -1 without columns.
  double min_dihedral_layer_frame = -1;
  double worst_scaled_jacobian = 0;
  double worst_aspect_ratio = 0;  // longest edge / (2 sqrt(6) x inradius): 1 for the regular tetrahedron
  bool closed = false;            // the tagged triangles are exactly the faces of one cell, outward
  int open_faces = 0, stray_triangles = 0;
  // Boundary layer (when the mesh has layer data): layers above each wall triangle.
  bool has_layers = false;
  int min_layers = 0, max_layers = 0;
  int wall_triangles = 0;
  // Layer thickness over the local radius, per wall triangle (needs `radius`).
  double min_thickness_ratio = -1, max_thickness_ratio = -1;
};

// The least dihedral angle (degrees) of tetrahedron `t` in the frame of the layer column standing
// on boundary triangle `column` (above); 0 when the cell has no height along the wall's normal or
// the wall triangle no area.
double layer_frame_angle(const TetMesh& mesh, int column, const Tet& t);

// `radius` (optional): per point, the local radius of the wall below layer points.
VolumeQuality measure_volume(const TetMesh& mesh, const std::vector<double>& radius = {});

}  // namespace vesselmesh::volume
