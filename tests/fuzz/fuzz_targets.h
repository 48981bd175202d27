// What the fuzz targets run: a surface reader on arbitrary bytes, then the mesh doctor and the
// open-end finder on what it read. Any exception other than a vesselmesh InputError or
// OptionError, any crash or sanitizer report is a finding.
#pragma once

#include <cstddef>
#include <cstdint>

namespace vesselmesh::fuzz {

enum class Reader { stl, vtp, ply, obj };

int read_surface_bytes(Reader reader, const uint8_t* data, size_t size);

}  // namespace vesselmesh::fuzz
