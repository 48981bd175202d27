// Mixed Voronoi areas (M. Meyer, M. Desbrun, P. Schroeder, A. Barr, "Discrete differential-
// geometry operators for triangulated 2-manifolds", VisMath 2002): the area of each triangle
// shared among its corners, by Voronoi regions when the triangle has no obtuse angle, else
// half to the obtuse corner and a quarter to each of the others. The corner areas of a
// triangle add up to its area; a point's areas add up to its share of the surface.
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <vector>

namespace vesselmesh::analysis {

// One triangle, from its edges: e[i] is the edge opposite corner i. Zero areas if degenerate.
std::array<double, 3> triangle_corner_areas(const Vec3 e[3]);
// The same from the squared lengths of those edges and the triangle's area.
std::array<double, 3> triangle_corner_areas(const double l2[3], double area);

// Per triangle, the areas of corners 0, 1, 2 (length unit squared).
std::vector<std::array<double, 3>> corner_areas(const TriMesh& mesh);

// Per point, the sum of its corner areas.
std::vector<double> point_areas(const TriMesh& mesh, const std::vector<std::array<double, 3>>& corners);

}  // namespace vesselmesh::analysis
