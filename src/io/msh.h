// Gmsh MSH 4.1 files of triangle surfaces, through Gmsh's own API (libgmsh).
#pragma once

#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"

#include <map>
#include <string>

namespace vesselmesh::io {

// Writes MSH 4.1 (ASCII) atomically: one discrete surface and one physical group per label
// (a single group "surface" when the mesh has no labels). Physical tags are the labels when
// they are all positive, else 1, 2, ... in label order; names come from `label_names`, else
// "label_<value>".
void write_msh(const std::string& path, const TriMesh& mesh,
               const std::map<int, std::string>& label_names = {});

// The 3-node triangles of an MSH file (any version Gmsh reads), labelled by the physical group
// of their entity (or the entity tag when none). Points are the nodes the triangles use.
TriMesh read_msh_surface(const std::string& path, std::map<int, std::string>* label_names = nullptr);

// A volume mesh as MSH 4.1 (ASCII), atomically: one volume entity (physical group
// `volume_name`, tag `volume_tag`) with the tetrahedra and prisms (Gmsh's node order, positive
// Jacobian), and one surface entity and physical group per boundary tag, named from
// `tag_names`. Layer data is not written (MSH has no cell data here; VTU keeps it).
void write_msh(const std::string& path, const TetMesh& mesh);

// The tetrahedra, prisms and tagged triangles of an MSH file (physical groups as tags and
// names; the entity's tag where a triangle has no group). Points: every node, in file order.
TetMesh read_msh_volume(const std::string& path);

}  // namespace vesselmesh::io
