// Flow extensions: a straight tube added to chosen open ends of a vessel surface, as VMTK's
// vmtkflowextensions and VaMPy's preprocessing do, so that a profile imposed at an end, or a
// traction, does not distort the region of interest.
//
// Input: a clean, consistently oriented surface (mesh::clean) and its ends (analysis::open_ends).
// Each chosen open end's loop is extruded along the end's outward normal n by `length` x the end's
// equivalent radius R, in rings about the loop's mean edge length apart (the wall's own triangle
// size there), each of as many points as the loop evenly spaced along it (every other ring shifted
// by half a spacing; the first ring zipped to the loop's own points, however uneven). Ring by ring
// the loop's shape turns into a circle of radius R (its polygon's area pi R^2, so the new end's
// equivalent radius is R) in the plane normal to n, over the first min(length R / 2, 2 R) (a
// smoothstep); in `smooth` mode the tube also leaves each loop point in
// the wall's own direction there and turns to n over the same span (a cubic that meets both, so
// the wall has no crease where the tube begins). The last ring is the new end: planar, normal to
// n, its centre the old centre + length R n. Each tube triangle carries the label of the wall
// triangle on the loop edge at its place round the loop. Output: the surface (old points and triangles first,
// unchanged), and per extended end where it was and where it is.
#pragma once

#include "analysis/open_ends.h"
#include "mesh/trimesh.h"

#include <string>
#include <vector>

namespace vesselmesh::remesh {

enum class ExtensionMode { straight, smooth };
ExtensionMode parse_extension_mode(const std::string& text);  // InputError naming what is accepted

struct ExtensionOptions {
  double length = 5.0;  // in radii of each end
  ExtensionMode mode = ExtensionMode::smooth;
  std::vector<int> ends = {};  // indices into the ends given (open_ends' order); empty: every open end
};

struct ExtendedEnd {
  int end = 0;  // its index among the ends given
  Vec3 old_center = Vec3::Zero(), center = Vec3::Zero(), normal = Vec3::Zero();
  double radius = 0.0;  // the equivalent radius, kept
  double length = 0.0;  // the tube's length (mesh units)
  int rings = 0;        // the tube's rings of points beyond the loop
};

struct ExtensionResult {
  TriMesh mesh;
  std::vector<ExtendedEnd> extended;
};

// Throws InputError for a capped end among those chosen (extensions start from open loops), an
// index out of range, or a length that is not positive.
ExtensionResult extend_ends(const TriMesh& mesh, const std::vector<analysis::OpenEnd>& ends,
                            const ExtensionOptions& options);

}  // namespace vesselmesh::remesh
