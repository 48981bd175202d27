// Volume meshes from Gmsh MSH 4.1 text files, read as they stream by, without Gmsh.
//
// The flow solver's first process reads the whole mesh before it splits it among the processes;
// through Gmsh's API that took about 0.45 KB a tetrahedron at its peak (266 MB at 580k
// tetrahedra: 20-23 GB for a 50 M-tetrahedron cluster mesh) and left Gmsh's libraries mapped
// (40 MB). Read here, the file goes by in 1 MB blocks and only the mesh stays: about 30 bytes a
// tetrahedron. Gmsh stays the reader of every other MSH file (io/msh.h; io/volume_file.h chooses).
#pragma once

#include "mesh/tetmesh.h"

#include <optional>
#include <string>

namespace vesselmesh::io {

// The mesh of an MSH 4.1 text file (`$MeshFormat` 4.1, file type 0) as io::read_msh_volume reads
// it through Gmsh: every node in the order of its entity (by dimension, then tag), the 4-node
// tetrahedra and 6-node prisms of the volume entities (by tag; the volume's tag and name from its
// physical group) and the 3-node triangles of the surface entities (by tag), each tagged by its
// entity's first physical group (else the entity's tag) and named by it (else mesh::unnamed_tag).
// Other elements and sections are skipped. std::nullopt when the file is another version or binary
// (the caller reads those with Gmsh); InputError naming the file and line for a broken file.
std::optional<TetMesh> read_msh41_volume(const std::string& path);

}  // namespace vesselmesh::io
