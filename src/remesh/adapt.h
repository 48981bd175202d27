// The surface remesher: adapts a surface to a metric field by local operations, as MMG's mmgs
// and P. Frey, F. Alauzet, "Anisotropic mesh adaptation for CFD computations" (CMAME 2005).
//
// Input: a clean, manifold surface (mesh::clean) and an SPD metric per input point
// (sizing/). Output: a surface whose edges have unit length in the metric, with well-shaped
// triangles (quality measured in the metric; where the distance bound stretched an isotropic
// kind's metric along tubes, the last flips and moves shape them in space; where the metric itself
// is stretched, they turn its caps in space into needles), on the input surface.
//
// Passes of: splitting edges longer than sqrt 2 in the metric (the new point projected onto
// the input), collapsing edges shorter than 1/sqrt 2 (when the topology stays the same and no
// triangle gets worse than the worst it replaces or than 0.3), flipping edges where that
// raises the smaller quality of the two triangles without bending the surface, and moving
// points to the mean of their neighbours in their tangent plane (then back onto the input)
// where that raises the worst quality of their ball. Until splits and collapses stop, then a
// few more flips and moves.
// Guarantees: every point lies on the input (its closest point on the input triangles, found
// by a walk from the input triangle it came from, or the AABB tree when that walk wanders); feature curves (open ends, creases above the feature angle, label borders) are
// remeshed along themselves and their corners stay; labels follow their triangles; the
// topology (components, boundary loops, genus) is kept; no triangle is created degenerate or
// with its normal more than 60 degrees from the input's normal there. Deterministic.
#pragma once

#include "analysis/curvature.h"
#include "mesh/reporter.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"
#include "remesh/surface_model.h"

#include <functional>
#include <string>
#include <vector>

namespace vesselmesh::remesh {

struct RemeshOptions {
  FeatureOptions features;
  int max_iterations = 15;        // passes of split / collapse / flip / move
  // Distance bounds: no output triangle farther from the input than `hausdorff` (> 0) nor than
  // `hausdorff_relative` (> 0) times the local radius: `input_radius` per input point (the
  // distance map's radius, or centerline::pole_radius on a surface without ends, as `vesselmesh
  // remesh` passes them; the figures then report the largest relative distance), or without it
  // the radius of the tightest normal section, 1 / max(|k1|, |k2|), which a bumpy wall shrinks.
  double hausdorff = 0.0;
  double hausdorff_relative = 0.02;
  const std::vector<double>* input_radius = nullptr;
  // What the points lie on and the bounds measure against: the smooth surface the input's
  // triangles stand for (phong: SurfaceModel), or the triangles themselves (facets, as mmgs: a
  // coarse segmentation's facets are then reproduced to within the bound, at a cost in triangles
  // where the input's edges are as long as a small branch's radius).
  Reconstruction reconstruction = Reconstruction::phong;
  // The metric is first intersected with the chord bound for half the distance bound
  // (sizing::chord_metric; isotropic where the metric is, along the principal directions where
  // it is not; an isotropic kind's up to 1.55 times longer along a tube, then graded by 1.3,
  // its last flips and moves then judging shapes in space), never refining more than tenfold:
  // the bound shapes the mesh, as in mmgs, instead of being enforced by splits at the end
  // (remesh/bound.h). The figures are against that metric.
  bool geometric_metric = true;
  // The input's curvature (per point, e.g. what sizing used); computed on each side of the
  // creases when absent.
  const analysis::CurvatureField* curvature = nullptr;
};

// Where the distance bound refined the size field most: an input point and the factor it put on
// the metric there (the triangle density; 1: nowhere).
struct BoundPeak {
  int point = -1;
  double factor = 1.0;
  void raise(int v, double f) {
    if (f > factor) {
      factor = f;
      point = v;
    }
  }
};

// Figures of an adapted surface against its metric (lengths and quality in the metric).
struct RemeshStats {
  int points = 0;
  int triangles = 0;
  double edges_in_unit_range = 0.0;  // fraction of edges of metric length in [1/sqrt 2, sqrt 2]
  double min_angle_deg = 0.0;        // smallest Euclidean angle
  double mean_quality = 0.0, min_quality = 0.0;
  double hausdorff = 0.0;            // largest distance of an output triangle from the input
  double hausdorff_relative = -1.0;  // largest such distance over the local radius (-1: unknown)
  // The same against the input's triangles themselves (equal to the above with facets).
  double hausdorff_facets = 0.0, hausdorff_facets_relative = -1.0;
  int splits = 0, collapses = 0, flips = 0, moves = 0;
  int refinements = 0;               // splits made to meet the distance bounds at the end
  int geometric_points = 0;          // input points whose metric the chord bound refined
  int tightened = 0;                 // triangles too far from the input that refined the metric
  BoundPeak bound_peak;              // where the bound (its chord metric, its tightening) refined most
  Vec3 bound_location = Vec3::Zero();  // that input point
  double seconds = 0.0;
};

struct RemeshResult {
  TriMesh mesh;
  std::vector<Sym3> metric;  // per output point: what the mesh was adapted to
  RemeshStats stats;
  // fit_count: why the count stays more than 3 % off the target (which bound, where, what
  // relaxes it; or the count's scatter), also warned; empty when it is within.
  std::string count_note;
  // fit_count, where the distance bound held the count over its target and coarsening the field
  // stopped moving it (two steps that moved it by under a quarter of what they asked): that count,
  // about the least this kind has within the bound; 0 where not so.
  int least_count = 0;
};

RemeshResult adapt(const TriMesh& input, const std::vector<Sym3>& metrics, const RemeshOptions& options = {},
                   const Reporter& reporter = silent_reporter());

// adapt(), then, while the triangle count is off `target_triangles` by more than `tolerance`
// (relative), the metric scaled (while no two runs bracket the target: first by target / count,
// the count going as the metric's density, then along the secant of the last two runs in log-log;
// then interpolating the bracketing runs in log-log) and adapt() again, `max_corrections` times at
// most; the closest run is returned. The sizing issue's target count (3 %; the 2 % default leaves
// a margin). The distance bound's refinement does not scale, so a count it dominates may stay
// above target: two unbracketed steps in a row that each move the count by less than a quarter of
// what they asked (in log) end the loop (RemeshResult::least_count). A count left more than 3 % off:
// RemeshResult::count_note.
RemeshResult adapt_to_count(const TriMesh& input, const std::vector<Sym3>& metrics, double target_triangles,
                            const RemeshOptions& options = {}, const Reporter& reporter = silent_reporter(),
                            double tolerance = 0.02, int max_corrections = 6);

// A remeshing engine: the surface adapted to the given metric (native: adapt; Gmsh: reparametrize).
using Engine = std::function<RemeshResult(const std::vector<Sym3>& metric)>;
// What adapt_to_count does, for any engine.
RemeshResult fit_count(const Engine& engine, const std::vector<Sym3>& metrics, double target_triangles,
                       const Reporter& reporter = silent_reporter(), double tolerance = 0.02, int max_corrections = 6);

// The metric adapt() works to: `metrics` intersected with the chord bound of the distance bounds
// (as RemeshOptions::geometric_metric says; unchanged without bounds). `changed` (may be null)
// counts the points it refined. For other engines, so that they meet the same field.
std::vector<Sym3> effective_metric(const TriMesh& input, const std::vector<Sym3>& metrics, const RemeshOptions& options,
                                   int* changed = nullptr);

// The figures of `mesh` against per-point metrics, its distance from `model`'s input (its
// reconstruction, and its triangles), and (with radii) relative to the local radius. The distance is the global closest point's, or
// with `hints` (an input triangle per point) the local one (SurfaceModel::project with a hint:
// never smaller, on the same wall), which is what adapt() reports.
RemeshStats measure(const TriMesh& mesh, const std::vector<Sym3>& metric, const SurfaceModel& model,
                    const std::vector<double>* input_radius = nullptr, const std::vector<int>* hints = nullptr);

}  // namespace vesselmesh::remesh
