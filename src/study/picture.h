// Pictures of a surface as SVG: an orthographic view, triangles painted back to front and
// shaded by their facing, with thin edges (to show a mesh) or coloured by a point scalar
// (viridis, with a colour bar). Made for reports: no GPU, no display, the same picture run
// after run.
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::study {

struct PictureOptions {
  std::string title;
  int width = 760, height = 520;
  std::optional<Vec3> view;   // the direction looked along; default broadside_view()
  bool edges = true;          // draw triangle edges
  std::string scalar_label;   // the colour bar's title
  double low = 0.0, high = 0.0;  // the colour range; low >= high: the scalar's own range
};

// The direction of least spread of the points (the last principal axis): looking along it
// shows the vessel broadside.
Vec3 broadside_view(const TriMesh& mesh);

// The viridis colour map at t in [0, 1] (clamped), as RGB in [0, 1].
std::array<double, 3> viridis(double t);

// The pictures' screen "up" when looking along `view` (unit): the coordinate axis least along the
// view, made orthogonal to it.
Vec3 screen_up(const Vec3& view);

// `scalar`: one value per point, or null for a grey mesh.
std::string surface_svg(const TriMesh& mesh, const std::vector<double>* scalar, const PictureOptions& options);

}  // namespace vesselmesh::study
