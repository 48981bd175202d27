// Vessels built as the zero set of a smooth union of tubes (distance to an axis minus the
// radius), cut open normal to their ends: the pieces the bifurcation and the anastomosis share.
#pragma once

#include "mesh/trimesh.h"
#include "synth/implicit_surface.h"

#include <cstdint>
#include <span>

namespace vesselmesh::synth {

struct TubeEnd {
  Vec3 center;
  Vec3 normal;  // unit, out of the lumen
  double radius;
};

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b);

// Distance to the circular arc of `radius` about `center` in the plane spanned by the unit,
// orthogonal vectors u and v, from angle 0 (center + radius u) to `sweep` (radians, >= 0,
// towards v).
double distance_to_arc(const Vec3& p, const Vec3& center, const Vec3& u, const Vec3& v, double radius,
                       double sweep);

// Polynomial smooth minimum (Quilez): equals min(a, b) where |a - b| >= k, and lies below both
// by up to k/4 where they are close: the blend of two tubes' distances.
double smooth_min(double a, double b, double k);

struct TubeSurfaceOptions {
  double resolution = 0.5;  // grid spacing and target edge length
  double jitter = 0.0;      // random move along the surface, a fraction of the shortest edge
  uint64_t seed = 1;
  double reach = 1.5;       // a cut removes points within reach x the end's radius of its axis
};

// The zero set of f (negative inside, positive on the faces of [lo, hi]) polygonized on a grid
// of `resolution`, relaxed on the zero set, its slivers flipped away, then cut open by the plane
// of every end (the part beyond it removed) with the new loops exactly in those planes. Returns
// a clean, outward surface whose boundary loops are the ends.
TriMesh open_tube_surface(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, std::span<const TubeEnd> ends,
                          const TubeSurfaceOptions& options);

}  // namespace vesselmesh::synth
