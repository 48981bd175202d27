#include "study/raster.h"

#include "io/atomic_file.h"
#include "mesh/error.h"

#include <cairo.h>
#include <fmt/format.h>
#include <librsvg/rsvg.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace vesselmesh::study {

std::string png_from_svg(const std::string& svg, double scale) {
  GError* error = nullptr;
  RsvgHandle* raw = rsvg_handle_new_from_data(reinterpret_cast<const guint8*>(svg.data()), svg.size(), &error);
  if (!raw) {
    const std::string what = error ? error->message : "unknown error";
    if (error) g_error_free(error);
    throw InputError(fmt::format("SVG not readable for PNG rendering: {}", what));
  }
  const std::unique_ptr<RsvgHandle, void (*)(gpointer)> handle(raw, g_object_unref);
  gdouble width = 0.0, height = 0.0;
  if (!rsvg_handle_get_intrinsic_size_in_pixels(handle.get(), &width, &height) || !(width > 0.0) || !(height > 0.0))
    throw InputError("SVG for PNG rendering has no size in pixels (width and height attributes)");
  const int w = static_cast<int>(std::ceil(width * scale)), h = static_cast<int>(std::ceil(height * scale));
  const std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h), cairo_surface_destroy);
  const std::unique_ptr<cairo_t, void (*)(cairo_t*)> cr(cairo_create(surface.get()), cairo_destroy);
  const RsvgRectangle viewport = {0.0, 0.0, static_cast<double>(w), static_cast<double>(h)};
  if (!rsvg_handle_render_document(handle.get(), cr.get(), &viewport, &error)) {
    const std::string what = error ? error->message : "unknown error";
    if (error) g_error_free(error);
    throw InputError(fmt::format("SVG could not be rendered to PNG: {}", what));
  }
  cairo_surface_flush(surface.get());
  std::string png;
  const auto append = [](void* closure, const unsigned char* data, unsigned int length) -> cairo_status_t {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
  };
  if (cairo_surface_write_to_png_stream(surface.get(), append, &png) != CAIRO_STATUS_SUCCESS)
    throw InputError("PNG encoding failed");
  return png;
}

void write_svg_and_png(const std::string& stem, const std::string& svg, double scale) {
  io::write_text(stem + ".svg", svg);
  io::write_text(stem + ".png", png_from_svg(svg, scale));
}

Image read_png(const std::string& path) {
  const std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface(
      cairo_image_surface_create_from_png(path.c_str()), cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw InputError(fmt::format("{}: not a readable PNG file ({})", path,
                                 cairo_status_to_string(cairo_surface_status(surface.get()))));
  cairo_surface_flush(surface.get());
  const cairo_format_t format = cairo_image_surface_get_format(surface.get());
  Image image;
  image.width = cairo_image_surface_get_width(surface.get());
  image.height = cairo_image_surface_get_height(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  image.pixels.resize(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      uint32_t p = *reinterpret_cast<const uint32_t*>(data + static_cast<size_t>(y) * stride + 4 * x);
      if (format == CAIRO_FORMAT_RGB24) p |= 0xff000000u;
      const uint32_t a = p >> 24;
      if (a > 0 && a < 255) {  // cairo keeps colours premultiplied by alpha
        const auto channel = [&](int shift) { return std::min(255u, ((p >> shift) & 255u) * 255u / a) << shift; };
        p = (a << 24) | channel(16) | channel(8) | channel(0);
      }
      image.pixels[static_cast<size_t>(y) * image.width + x] = p;
    }
  return image;
}

}  // namespace vesselmesh::study
