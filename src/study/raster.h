// SVG rendered to PNG (librsvg and cairo, behind this header), for reports that want both.
#pragma once

#include <string>

namespace vesselmesh::study {

// The SVG document rendered at `scale` times its own size, as PNG bytes. Throws InputError
// when librsvg cannot read the document.
std::string png_from_svg(const std::string& svg, double scale = 2.0);

// Writes `stem`.svg and `stem`.png (both atomically).
void write_svg_and_png(const std::string& stem, const std::string& svg, double scale = 2.0);

}  // namespace vesselmesh::study
