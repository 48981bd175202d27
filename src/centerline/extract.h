// Centerlines of a vessel tree (L. Antiga, D. Steinman, IEEE TMI 2004; as in VMTK's
// vmtkcenterlines and vmtkbranchextractor).
//
// From the internal Voronoi diagram (centerline/voronoi.h), the path from the inlet to every
// outlet that minimizes the integral of 1/R along it (R the maximal inscribed sphere radius):
// Dijkstra on the Voronoi graph, edges costing their length times the mean of 1/R at their
// ends, so paths keep to the middle of the lumen and never cut through narrow gaps. The paths
// share their way until they part: the union is a tree whose forks are the bifurcations and
// whose edges are the branches. Each branch is resampled at a fixed step and lightly smoothed
// (its ends stay); every point carries its MISR, measured as its distance to the surface.
//
// End points come from the open ends (analysis/open_ends.h; flat caps included): the largest
// end is the inlet unless `inlet` names another; `source` and `targets` override them.
// Lengths in the mesh's unit.
#pragma once

#include "analysis/open_ends.h"
#include "mesh/reporter.h"
#include "mesh/trimesh.h"

#include <optional>
#include <vector>

namespace vesselmesh::centerline {

struct CenterlineOptions {
  std::optional<int> inlet = {};         // index into open_ends(); default the largest (0)
  std::optional<Vec3> source = {};       // overrides the inlet
  std::vector<Vec3> targets = {};        // override the outlets when not empty
  double resampling_step = 0.0;          // <= 0: a tenth of the smallest end radius
  int smoothing_iterations = 10;         // Laplacian passes over each branch, ends fixed
  double smoothing_factor = 0.5;
};

struct Polyline {
  std::vector<Vec3> points;
  std::vector<double> radius;  // MISR at each point
  double length() const;
};

struct Branch : Polyline {
  int id = 0;
  int parent = -1;            // the branch it leaves, -1 for the first
  std::vector<int> children;  // the branches that leave its far end
  int end = -1;               // the end it reaches (index into Centerlines::ends), -1 at a bifurcation
};

struct Centerlines {
  std::vector<analysis::OpenEnd> ends;  // as found (or made from source / target points)
  int inlet = 0;                        // index into ends
  std::vector<int> outlets;             // indices into ends, in path order
  std::vector<Branch> branches;         // branch 0 starts at the inlet
  std::vector<Vec3> bifurcations;       // where branches part
  std::vector<Polyline> paths;          // inlet to each outlet (the branches joined)
};

// Input: a clean, outward surface (mesh::clean). Throws InputError when there are fewer than
// two ends, or an end cannot be reached from the inlet (naming it).
Centerlines extract(const TriMesh& surface, const CenterlineOptions& options = {},
                    const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::centerline
