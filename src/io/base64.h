// Base64 (RFC 4648, with padding) both ways: VTK XML's inline and appended data read
// (io/vtk_xml_reader.cpp), the study report's 3D view's arrays written (study/view3d.h).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace vesselmesh::io {

// `size` bytes from `data` as base64, padded with '='.
std::string encode_base64(const void* data, size_t size);

// Decodes base64 from `text` at `pos` (whitespace skipped) until `count` bytes are out or the
// base64 stops (padding, another character, the end).
std::string decode_base64(std::string_view text, size_t pos = 0, size_t count = std::string::npos);

}  // namespace vesselmesh::io
