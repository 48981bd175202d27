#include "fuzz_targets.h"

#include "analysis/open_ends.h"
#include "io/obj.h"
#include "io/ply.h"
#include "io/stl.h"
#include "io/vtk_formats.h"
#include "mesh/clean.h"
#include "mesh/error.h"

#include <string_view>

namespace vesselmesh::fuzz {

int read_surface_bytes(Reader reader, const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    TriMesh mesh;
    switch (reader) {
      case Reader::stl: mesh = io::parse_stl(bytes, "fuzz.stl"); break;
      case Reader::vtp: mesh = io::parse_vtk_xml_surface(bytes, io::VtkFormat::vtp, "fuzz.vtp").mesh; break;
      case Reader::ply: mesh = io::parse_ply(bytes, "fuzz.ply"); break;
      case Reader::obj: mesh = io::parse_obj(bytes, "fuzz.obj"); break;
    }
    mesh::clean(mesh);
    analysis::open_ends(mesh);
  } catch (const InputError&) {
  } catch (const OptionError&) {
  }
  return 0;
}

}  // namespace vesselmesh::fuzz
