// Rings and points on the wall: where a user reads wall shear stress.
//
// A ring is the cut of the wall surface by a plane (a point and a normal). Triangles crossing
// the plane give segments whose ends lie on the crossed edges, the field interpolated linearly
// along them; the segments chain into loops, and the loop nearest the plane's point is the
// ring (a plane through a bifurcation crosses several branches). The ring runs counter-
// clockwise about the normal and starts where its angle about its own centroid is zero,
// measured from `reference` projected into the plane (by default the coordinate axis least
// aligned with the normal). Each sample: arc length from the start, angle, position, the
// vector, and its axial (along the normal), circumferential and magnitude parts.
// A point reads the field at the nearest wall location, interpolated in its triangle.
#pragma once

#include "centerline/extract.h"
#include "mesh/reporter.h"
#include "mesh/trimesh.h"

#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::post {

struct RingSpec {
  std::string name;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  std::optional<Vec3> reference;
};

struct RingSample {
  double arc_length = 0.0;  // mesh units, from the ring's start
  double angle = 0.0;       // degrees, 0 to 360, counter-clockwise about the normal
  Vec3 point = Vec3::Zero();
  Vec3 value = Vec3::Zero();
  double axial = 0.0, circumferential = 0.0, magnitude = 0.0;
};

struct Ring {
  std::string name;
  Vec3 centroid = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  bool closed = true;       // false when the loop ran into the wall's boundary
  int other_loops = 0;      // loops of the same plane left aside (farther from the point)
  double length = 0.0;      // mesh units
  std::vector<RingSample> samples;  // closed: the first sample is repeated at the end (s = length)
  int minimum = 0;          // index of the least magnitude
};

// The plane normal to the centerlines at their point nearest `near`: the ring "at a
// centerline position". The plane's point is that centerline point; its normal the local
// direction of the branch (over its neighbouring segments). Throws InputError without branches.
RingSpec centerline_ring(const centerline::Centerlines& centerlines, const std::string& name, const Vec3& near);

// `values`: one vector per wall point. Throws InputError naming the ring when the plane
// misses the wall.
Ring cut_ring(const TriMesh& wall, const std::vector<Vec3>& values, const RingSpec& spec);

// The ring's magnitude at `count` evenly spaced positions, to compare rings of different meshes
// point by point: at angles 360 k / count degrees on a closed ring (periodic), at the fractions
// k / count of its length on an open one (closed = false); linear between samples.
std::vector<double> resampled_magnitude(const Ring& ring, int count);

// A ring as a user asks for it: a plane, or (on_centerline) a point whose plane is normal to
// the centerline nearest it.
struct RingRequest {
  RingSpec spec;
  bool on_centerline = false;
};

// Planes for the requests: those on the centerline placed on `surface`'s centerlines (traced
// once, only when a request needs them); the others as given.
std::vector<RingSpec> place_rings(const TriMesh& surface, const std::vector<RingRequest>& requests,
                                  const Reporter& reporter = silent_reporter());

struct PointProbe {
  std::string name;
  Vec3 requested = Vec3::Zero();
  Vec3 point = Vec3::Zero();  // nearest wall location
  double distance = 0.0;
  int triangle = -1;
  Vec3 value = Vec3::Zero();
};

struct PointSpec {
  std::string name;
  Vec3 point = Vec3::Zero();
};

std::vector<PointProbe> probe_points(const TriMesh& wall, const std::vector<Vec3>& values,
                                     const std::vector<PointSpec>& points);

}  // namespace vesselmesh::post
