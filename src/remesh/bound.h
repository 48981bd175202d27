// The distance bound as a run of the remesher works to it: per input point, how far the output
// may stray from the input there, and the size field intersected with the bound's chord metric
// (RemeshOptions: hausdorff, hausdorff_relative, input_radius, geometric_metric).
#pragma once

#include "analysis/features.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"
#include "remesh/adapt.h"

#include <vector>

namespace vesselmesh::remesh {

struct BoundedField {
  analysis::Features features;
  std::vector<double> bound;  // per input point: the largest distance allowed there (inf: none)
  std::vector<Sym3> metric;   // per input point: the field within the bound's chord metric
  int geometric_points = 0;   // points whose metric the chord bound refined
  BoundPeak peak;             // where it refined most
  // An isotropic kind's field, made longer along tubes by the bound (bounded_metrics): its
  // triangles are stretched there by up to 1.55, so the remesher's last flips and moves judge
  // shapes in space (the user asked for an isotropic mesh), within the bound and the count.
  bool stretched = false;
};

BoundedField bounded_field(const TriMesh& input, const std::vector<Sym3>& metrics, const RemeshOptions& options);

}  // namespace vesselmesh::remesh
