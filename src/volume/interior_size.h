// The interior's size field: the edge length a tetrahedron of the lumen should have, by design
// rather than by whatever the fill engine makes of the boundary's edges.
//
// At the wall, a point's size is its triangles' area-equivalent size: the side of the
// equilateral triangle of their mean area, sqrt(4 A / sqrt 3). For a wall remeshed to a metric
// of sizes h1, h2 along the wall this is sqrt(h1 h2), so an anisotropic and an isotropic wall
// with the same triangle count give the lumen the same point density (the long edge, which the
// engines' own sizes follow, starves the core; the short one would crowd it).
// Inside, the size at x is carried from the wall's closest point c (its size h(c) and radius
// R(c), interpolated on c's triangle) and graded with the depth d = |x - c| - t(c) below the
// boundary layer of thickness t (0 without a layer), so that the fill meets the layer's inner
// surface at the wall's size:
//   size(x) = factor * min(h(c) + d ln g, max(h(c), core_fraction * R(c))),
// the growth per unit length of the surface's gradation (sizing/gradation.h: h_j <= h_i + |e| ln g),
// and the core of a vessel coarsening to at most core_fraction of the local radius (never finer
// than the wall's own size). Without radii (none given) the core bound is left out. Finer regions
// (RefineRegion) bound it further, graded outward from each. Where a flow's sizes are given (the
// flow kind: post/fluid_metric.h), they take the core bound's place wherever they have a size:
//   size(x) = factor * min(h(c) + d ln g, flow(x)),
// so that the wall's growth inward still meets the layer, and the flow sets the rest (or bound it
// beside the core bound: flow_keeps_core).
// Every fill engine is given this field (volume/fill.h), so the engine changes the tetrahedra's
// shape, not their number. Queries are const and thread-safe once built.
#pragma once

#include "mesh/locator.h"
#include "mesh/trimesh.h"

#include <functional>
#include <vector>

namespace vesselmesh::volume {

// A region of the lumen that the flow, not the wall, asks to be finer (a jet and its shear layer, an
// aneurysm's inflow): the capsule of points within `radius` of the segment from `from` to `to`
// (mesh units), whose interior size is at most `size` there, growing outside it by the gradation
// (`volume --refine`).
struct RefineRegion {
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();
  double radius = 0.0, size = 0.0;
};

struct InteriorSizeOptions {
  double factor = 1.0;          // scales the whole field (`--interior-size`)
  double gradation = 1.3;       // growth from the wall inward (`--interior-gradation`; 1: none)
  // The core's size at most this times the local radius (twenty sizes across the diameter),
  // never finer than the wall's. Coarser cores cost accuracy, measured on the 2 mm pipe's
  // Poiseuille flow (tests/flow/navier_stokes_test.cpp): 0.25 coarsened its core from 0.44 to
  // 0.5 mm and the median WSS error went from 1.4 to 1.8 % (uniform wall) and 1.8 to 3.0 %
  // (anisotropic, Gmsh's Delaunay); 0.2 let a 0.18 mm wall's core grow to 0.4 mm, and the velocity
  // error rose from under 1 % of the peak to 1.27 %.
  double core_fraction = 0.1;
  // Finer regions: the size at x at most region.size + ln(g) * (its distance outside the region).
  std::vector<RefineRegion> regions = {};
  // The flow's sizes at a point (mesh units; 0 or less where it has none, as outside its mesh), or
  // empty for none; called concurrently.
  std::function<double(const Vec3&)> flow = {};
  // true: the flow's sizes bound the field beside the core bound instead of in its place (the study's
  // envelope levels, finer than a flow kind's interior and than the geometric kinds' cores alike).
  bool flow_keeps_core = false;
};

// OptionError for a factor <= 0, a gradation < 1, a core fraction <= 0, or a region of radius or size
// <= 0 (naming the option).
void check_interior_size_options(const InteriorSizeOptions& options);

// Per point of `mesh`: the area-equivalent size of the triangles around it (0 for a point no
// triangle uses).
std::vector<double> area_equivalent_sizes(const TriMesh& mesh);

class InteriorSize {
 public:
  // `wall`: the lumen's wall (its points and triangles); `radius`: per wall point, the local
  // radius (distance map), or empty for no core bound; `layer`: per wall point, the boundary
  // layer's thickness, or empty for none.
  InteriorSize(const TriMesh& wall, const std::vector<double>& radius, const InteriorSizeOptions& options = {},
               const std::vector<double>& layer = {});

  double at(const Vec3& x) const;
  // The field's value at wall point v (the factor applied).
  double at_wall_point(int v) const { return options_.factor * size_[v]; }

 private:
  TriMesh wall_;
  std::vector<double> size_, radius_, layer_;
  InteriorSizeOptions options_;
  double slope_ = 0.0;
  mesh::SurfaceLocator locator_;
};

}  // namespace vesselmesh::volume
