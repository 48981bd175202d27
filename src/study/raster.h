// SVG rendered to PNG (librsvg and cairo, behind this header), for reports that want both; PNG
// files read back (for checking pictures, e.g. a browser's screenshot of a report).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vesselmesh::study {

// The SVG document rendered at `scale` times its own size, as PNG bytes. Throws InputError
// when librsvg cannot read the document.
std::string png_from_svg(const std::string& svg, double scale = 2.0);

// Writes `stem`.svg and `stem`.png (both atomically).
void write_svg_and_png(const std::string& stem, const std::string& svg, double scale = 2.0);

// A PNG file's pixels, row by row from the top left, as 0xAARRGGBB (alpha not premultiplied).
struct Image {
  int width = 0, height = 0;
  std::vector<uint32_t> pixels;
  uint32_t at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
};
// Throws InputError naming the file when it is not a readable PNG.
Image read_png(const std::string& path);

}  // namespace vesselmesh::study
