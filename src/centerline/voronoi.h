// The internal Voronoi diagram of a lumen surface (L. Antiga, D. Steinman, "Robust and
// objective decomposition and mapping of bifurcating vessels", IEEE TMI 23(6), 2004; VMTK).
//
// The Delaunay tetrahedralization of the surface points is built with exact predicates
// (CGAL); the circumcentre of each tetrahedron is a Voronoi vertex, the centre of an empty ball
// touching four surface points. Vertices inside the lumen, with their ball radius (the
// maximal inscribed sphere radius, MISR), approximate the medial axis; two of them are joined
// when their tetrahedra share a face. Points are inserted in a fixed (Hilbert) order: the same
// surface always gives the same graph.
#pragma once

#include "mesh/locator.h"
#include "mesh/reporter.h"
#include "mesh/trimesh.h"

#include <vector>

namespace vesselmesh::centerline {

struct VoronoiGraph {
  std::vector<Vec3> centers;    // Voronoi vertices inside the lumen
  std::vector<double> radius;   // their ball radius (MISR), in the mesh's unit
  std::vector<int> offsets;     // CSR adjacency: neighbours of i are
  std::vector<int> neighbours;  //   neighbours[offsets[i] .. offsets[i + 1])
  // Per surface point, the radius of its inner pole: the largest of the inside balls that touch
  // it (Amenta et al.'s pole), about the vessel's radius there; 0 where no inside ball touches.
  std::vector<double> pole_radius;
  int size() const { return static_cast<int>(centers.size()); }
};

// `inside` answers for the lumen closed at its open ends (see close_open_ends()).
VoronoiGraph internal_voronoi(const TriMesh& surface, const mesh::InsideTest& inside,
                              const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::centerline
