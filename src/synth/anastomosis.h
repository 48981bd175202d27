// A distal end-to-side anastomosis, as in a femoro-popliteal bypass: the graft joins the side of
// the host artery at an acute angle; the host upstream of the junction is occluded and kept as a
// blind stump; flow enters through the graft and leaves through the distal host. Lengths in mm.
//
// Built as the zero set of a smooth union of two swept tubes (the fillet blends heel, toe and
// sides without a crease), polygonized by VTK's flying edges, relaxed onto the exact zero set and
// cut open by three planes normal to the vessels (open_tube_surface).
//
// Geometry: the host's axis is the x axis, the flow leaving towards +x (distal). The graft lies
// in the xz plane above it (+z): it meets the host at `angle` from +x, heading down into it; a
// straight stretch above the junction, then an arc of `graft_bend` that turns it flatter (more
// nearly parallel to the host, as a tunnelled bypass arrives), then a straight stretch of
// `graft_length` to its inlet. The graft's axis ends above the host's axis, so that its end lies
// inside the host with the floor (the host's far wall) left flat; a graft wider than the host
// makes a hood that bulges out to the sides. The heel is the acute corner on the proximal side of
// the junction, the toe the obtuse one on the distal side. `tortuosity` > 0 bends the distal host
// out of the graft's plane in an S, after a straight stretch below the toe.
//
// Ends (anastomosis_landmarks): the graft inlet, the distal host outlet, the proximal stump.
#pragma once

#include "mesh/trimesh.h"
#include "synth/tubes.h"

#include <cstdint>
#include <string>
#include <vector>

namespace vesselmesh::synth {

struct AnastomosisOptions {
  double host_radius = 2.5;
  double graft_radius = 3.0;
  double angle_deg = 35.0;          // between the graft's axis at the junction and the distal host
  double graft_bend_deg = 20.0;     // the graft's turn above the junction, towards the host's direction
  double graft_bend_radius = 0.0;   // radius of that turn's centerline; 0: 4 graft radii
  double graft_length = 20.0;       // straight graft upstream of the turn, to the inlet
  double fillet = 1.0;              // width of the smooth blend at heel, toe and sides
  double stump_length = 10.0;       // host from the heel back to the stump's end
  double outlet_length = 40.0;      // host from the toe to the outlet
  double tortuosity = 0.0;          // amplitude of the distal host's S-bend out of the graft's plane
  double resolution = 0.15;         // target edge length
  double jitter = 0.0;
  uint64_t seed = 1;
};

struct NamedEnd {
  std::string name;  // "inlet" (the graft), "outlet" (the distal host), "stump" (the proximal host)
  TubeEnd end;
};

// Where the study looks, as in the seed paper's Fig. 9: points on the surface (in the plane of
// symmetry y = 0) and the planes of the two rings.
struct AnastomosisLandmarks {
  std::vector<NamedEnd> ends;        // inlet, outlet, stump
  Vec3 heel, toe;                    // on the fillet
  Vec3 floor;                        // on the host's far wall, across the lumen from the heel
  Vec3 ring1_point, ring1_normal;    // plane through heel and toe, across the mouth of the junction
  Vec3 ring2_point, ring2_normal;    // across the straight host downstream of the toe
  Vec3 graft_direction;              // unit, the graft's axis at the junction (into the host)
};

AnastomosisLandmarks anastomosis_landmarks(const AnastomosisOptions& options);

// OptionError for options that cannot make a valid vessel (saying which and what to change).
TriMesh anastomosis(const AnastomosisOptions& options);

}  // namespace vesselmesh::synth
