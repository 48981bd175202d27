// Small geometric helpers on triangles of a TriMesh.
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <string>
#include <vector>

namespace vesselmesh::mesh {

// Twice-area vector (p1 - p0) x (p2 - p0): direction is the right-hand normal.
inline Vec3 triangle_area_vector(const TriMesh& m, int t) {
  const Triangle& f = m.triangles[t];
  const Vec3& a = m.points[f[0]];
  return (m.points[f[1]] - a).cross(m.points[f[2]] - a);
}

inline double triangle_area(const TriMesh& m, int t) { return 0.5 * triangle_area_vector(m, t).norm(); }

inline Vec3 triangle_centroid(const TriMesh& m, int t) {
  const Triangle& f = m.triangles[t];
  return (m.points[f[0]] + m.points[f[1]] + m.points[f[2]]) / 3.0;
}

// The point of triangle (a, b, c) closest to p (C. Ericson, Real-Time Collision Detection,
// 5.1.5: by Voronoi regions of the corners and edges).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// The barycentric coordinates of p's projection onto the plane of triangle (a, b, c), clamped to
// the triangle (non-negative, summing to one); a third each for a degenerate triangle.
std::array<double, 3> barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
// A field given per point of `m`, linear over triangle t, at p (its projection, clamped as above).
inline double linear_on_triangle(const TriMesh& m, int t, const Vec3& p, const std::vector<double>& values) {
  const Triangle& f = m.triangles[t];
  const std::array<double, 3> w = barycentric(p, m.points[f[0]], m.points[f[1]], m.points[f[2]]);
  return w[0] * values[f[0]] + w[1] * values[f[1]] + w[2] * values[f[2]];
}

// Interior angles at corners 0, 1, 2, in radians (0 for a corner with a zero-length edge).
std::array<double, 3> triangle_angles(const TriMesh& m, int t);

// Total area of all triangles.
double surface_area(const TriMesh& m);

// Axis-aligned bounding box of the points (min, max); both zero for an empty mesh.
std::array<Vec3, 2> bounding_box(const std::vector<Vec3>& points);

// "(x, y, z)" with 6 significant digits, for messages that say where something is.
std::string format_point(const Vec3& p);

}  // namespace vesselmesh::mesh
