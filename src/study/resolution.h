// What a mesh resolves where the study measures (issue 46): at each measured place (a ring: its
// positions round the vessel; a point: one position), the mesh's
//  - surface size: the mean study::triangle_size (the shortest direction's) of its wall triangles
//    whose centroids lie within `reach` x the local radius of the position (the nearest triangle
//    when none does);
//  - first-layer height: the mean, over its wall points within that reach (the nearest one when
//    none is), of the height of the first cells above the point: |e . n| of the point's edge to a
//    point off the boundary that is nearest the wall's normal n there (in a layer, its column's);
//  - interior size: the mean edge length of its cells whose centroids lie within `depth_reach` x
//    the radius of the point `depth` x the radius inward from the position (below the layer).
// The local radius and the inward normal come from the input surface the places were given on.
// Lengths in the meshes' unit; NaN where a mesh has nothing to measure (no layer: its first cells'
// heights are still measured).
#pragma once

#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"

#include <string>
#include <vector>

namespace vesselmesh::study {

struct Place {
  std::string name;              // "ring NAME", "point NAME"
  std::vector<Vec3> positions;   // on the wall
  std::vector<Vec3> inward;      // unit, per position
  std::vector<double> radius;    // the vessel's local radius, per position
};

struct PlaceResolution {
  std::vector<double> surface, first_height, interior;  // per position of the place
};

struct ResolutionOptions {
  double reach = 0.2;        // of the local radius, round a position on the wall
  double depth = 0.5;        // of the local radius, inward, the interior's sample
  double depth_reach = 0.25; // of the local radius, round that sample
};

// Per point of the volume mesh: the height of the first cells above it when it is a wall point
// (|e . n| of its edge to a point off the boundary that is nearest the normal: in a layer, its
// column's), else NaN; n the area-weighted normal of its wall triangles. (The least |e . n| over
// those edges took a neighbour column's edge, nearly along the wall where it curves: at the
// anastomosis's heel 0.0001-0.004 mm on the uniform mesh of 8000 triangles whose columns' first
// cells are 0.035-0.037 mm high, a mean of 0.013.)
std::vector<double> first_heights(const TetMesh& volume);

// One PlaceResolution per place; `wall` is the mesh's wall (its surface mesh), `volume` its volume
// mesh (the wall's triangles are its boundary triangles tagged `wall`).
std::vector<PlaceResolution> measure_resolution(const TriMesh& wall, const TetMesh& volume,
                                                const std::vector<Place>& places,
                                                const ResolutionOptions& options = {});

// The mean of a place's values (NaN values left out; NaN when none is left).
double mean_of(const std::vector<double>& values);
// The least, over a place's positions, of coarse[i] / fine[i] (how many times finer `fine` is
// there at its least); NaN when no position has both.
double least_ratio(const std::vector<double>& coarse, const std::vector<double>& fine);

}  // namespace vesselmesh::study
