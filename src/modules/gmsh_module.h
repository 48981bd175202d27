// Gmsh, loaded only when a command needs it.
//
// libgmsh brings some 150 shared libraries (OpenCASCADE, FLTK, X11, ...) whose symbols the
// dynamic loader binds at start: a quarter of a second (measured: an empty program linked with
// our other libraries starts in 0.02 s, with libgmsh too in 0.25 s), paid by every command,
// though only .msh files, the volume fill and `remesh --engine gmsh` use Gmsh. So the library's
// code that calls Gmsh (io/msh.cpp, io/gmsh_session.cpp, remesh/reparametrize.cpp,
// volume/gmsh_fill.cpp) is compiled once and linked twice: into vesselmesh_lib, which the tests and the
// benchmarks link with Gmsh as usual, and into a module, libvesselmesh-gmsh.so, that the
// program opens on the first call of one of those functions (apps/vesselmesh/gmsh_calls.cpp
// defines them for the program, each forwarding to the module's table below).
// The tables of the program's modules (this one and modules/petsc_module.h) sit above the stages
// whose functions they list (io, remesh, volume; flow, parallel), so that includes run one way:
// no stage includes them; their namespaces stay those of the stages they serve.
#pragma once

#include "mesh/reporter.h"
#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"
#include "remesh/reparametrize.h"
#include "volume/fill.h"

#include <map>
#include <string>
#include <vector>

namespace vesselmesh::io {

// The module's file name (the program looks for it beside itself, then in ../lib/vesselmesh).
inline constexpr const char* kGmshModuleFile = "libvesselmesh-gmsh.so";

// The module's entry points. `layout` (first: the program's loader reads it there) is
// kGmshCallsLayout when the module was built with this header: a program and a module of
// different builds refuse each other. Raise it when this table or a type it passes changes
// (GmshRemeshOptions grew target_triangles: 1 -> 2; gmsh_fill a size function: 2 -> 3).
inline constexpr int kGmshCallsLayout = 3;
struct GmshCalls {
  int layout;
  void (*write_surface_msh)(const std::string& path, const TriMesh& mesh, const std::map<int, std::string>& label_names);
  TriMesh (*read_msh_surface)(const std::string& path, std::map<int, std::string>* label_names);
  void (*write_volume_msh)(const std::string& path, const TetMesh& mesh);
  TetMesh (*read_msh_volume)(const std::string& path);
  remesh::GmshRemeshResult (*reparametrize)(const TriMesh& input, const std::vector<Sym3>& metrics,
                                            const remesh::GmshRemeshOptions& options, const Reporter& reporter);
  volume::FillResult (*gmsh_fill)(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary,
                                  volume::FillAlgorithm algorithm, int threads, const Reporter& reporter,
                                  const volume::SizeFunction& size);
};

}  // namespace vesselmesh::io

// What the module exports (C linkage: one plain name for dlsym).
extern "C" const vesselmesh::io::GmshCalls* vesselmesh_gmsh_calls();
