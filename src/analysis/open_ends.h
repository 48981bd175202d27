// The ends of a vessel surface: boundary loops of an open surface, and flat caps of a closed
// one (planar patches bounded all round by a sharp crease, as SimVascular writes them).
//
// Input: a manifold, consistently oriented surface (after mesh::clean), outward for normals
// that point out of the lumen. Output: one OpenEnd per end, largest area first.
// Open loop: centre = area centroid of the loop's polygon (fan from the vertex mean, in the
// plane of its vector area), normal = the outward normal of the surface that would close it,
// area = |vector area| of the loop, radius = sqrt(area / pi), perimeter = loop length.
// Cap: the same from the cap's triangles (area centroid, summed area vectors).
#pragma once

#include "mesh/trimesh.h"

#include <string>
#include <vector>

namespace vesselmesh::analysis {

struct OpenEnd {
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3::Zero();  // unit, pointing out of the lumen
  double area = 0.0;
  double radius = 0.0;  // equivalent radius sqrt(area / pi)
  double perimeter = 0.0;
  bool capped = false;
  // The end's vertex loop, in the direction of the wall triangles' own edges along it.
  std::vector<int> loop;
  // Capped ends: the cap's triangles, ascending.
  std::vector<int> cap_triangles;
  // Capped ends of a labelled surface: the label all cap triangles carry, else -1.
  int label = -1;
};

struct OpenEndsOptions {
  bool detect_caps = true;
  // Two triangles meet at a crease when their normals differ by more than this (degrees).
  double cap_crease_angle_deg = 45.0;
  // A cap's points lie within this fraction of its diameter from its plane.
  double cap_flatness = 1e-2;
  int cap_min_triangles = 3;
};

std::vector<OpenEnd> open_ends(const TriMesh& mesh, const OpenEndsOptions& options = {});

// The ends' names as `vesselmesh volume` gives them by default: "inlet" for end `inlet` (the
// largest, 0, unless said), "outlet_1", "outlet_2", ... for the others in their order.
std::vector<std::string> default_end_names(int ends, int inlet = 0);

// The surface with each open (not capped) end closed by a fan of triangles from its centre,
// oriented like the wall: a closed surface for inside tests, not a mesh to simulate on.
// Labels are dropped.
TriMesh fan_capped(const TriMesh& mesh, const std::vector<OpenEnd>& ends);

}  // namespace vesselmesh::analysis
