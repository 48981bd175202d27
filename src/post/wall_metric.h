// Where a flow's wall shear stress is least well represented by a mesh: the error metric of the
// WSS's linear interpolation over the wall of a `vesselmesh simulate` result (sizing/hessian.h),
// for the flow-adapted size field (issue 52).
#pragma once

#include "mesh/reporter.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"
#include "sizing/hessian.h"

#include <string>
#include <vector>

namespace vesselmesh::post {

struct WallMetric {
  TriMesh wall;               // the flow's wall, in mm
  std::vector<Sym3> metric;   // per wall point: 1 / mm^2, up to a constant
  std::vector<double> times;  // s: the saved times it bounds together
};

// The intersection over `times` (linear between the saved frames around each; InputError where one
// lies outside them) of the metrics of the WSS's three components. With no times: every saved
// frame of the last period where the flow has one (its summary's `period`), else the last frame.
WallMetric wall_error_metric(const std::string& flow_directory, const std::vector<double>& times,
                             const sizing::ErrorMetricOptions& options = {},
                             const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::post
