// Validation of caller-owned image views, and conversion of any view to 8-bit RGBA.
#include <cstring>
#include <limits>

#include "io/rows.hpp"
#include "facet/image.hpp"
#include "io/image_convert.hpp"

namespace facet {

std::size_t bytes_per_pixel(PixelFormat format) noexcept {
  switch (format) {
    case PixelFormat::rgba8:
    case PixelFormat::bgra8: return 4;
    case PixelFormat::rgba32f: return 16;
  }
  return 0;
}

const char* to_string(PixelFormat format) noexcept {
  switch (format) {
    case PixelFormat::rgba8: return "rgba8";
    case PixelFormat::bgra8: return "bgra8";
    case PixelFormat::rgba32f: return "rgba32f";
  }
  return "unknown";
}

namespace {

Status check_view(const void* data, int width, int height, std::size_t stride, std::size_t pixel_bytes,
                  const char* name) {
  const std::string n = name;
  auto bad = [&](const std::string& field, const std::string& what) {
    return Status{ErrorCode::invalid_argument, n + "." + field, n + "." + field + ": " + what};
  };
  if (pixel_bytes == 0) return bad("format", "unknown pixel format");
  if (width < 1 || height < 1 || width > kMaxImageDimension || height > kMaxImageDimension) {
    return bad(width < 1 || width > kMaxImageDimension ? "width" : "height",
               "expected 1.." + std::to_string(kMaxImageDimension) + ", found " + std::to_string(width) + " x " +
                   std::to_string(height));
  }
  if (data == nullptr) return bad("data", "is null");
  const std::size_t row = static_cast<std::size_t>(width) * pixel_bytes;
  if (stride < row) {
    return bad("stride_bytes", "expected at least " + std::to_string(row) + " (width x " + std::to_string(pixel_bytes) +
                                   " bytes), found " + std::to_string(stride));
  }
  if (stride > std::numeric_limits<std::size_t>::max() / static_cast<std::size_t>(height)) {
    return bad("stride_bytes", "stride x height overflows the address space");
  }
  return {};
}

}  // namespace

Status validate_image_view(const ImageView& view) {
  return check_view(view.data, view.width, view.height, view.stride_bytes, bytes_per_pixel(view.format), "image");
}

Status validate_depth_view(const DepthView& view, int width, int height) {
  if (Status s = check_view(view.data, view.width, view.height, view.stride_bytes, sizeof(float), "depth"); !s.ok()) {
    return s;
  }
  if (view.width != width || view.height != height) {
    return {ErrorCode::invalid_argument, "depth",
            "depth: size " + std::to_string(view.width) + " x " + std::to_string(view.height) +
                " differs from the image's " + std::to_string(width) + " x " + std::to_string(height)};
  }
  return {};
}

Rgba8Image to_rgba8(const ImageView& view) {
  Rgba8Image out;
  out.width = view.width;
  out.height = view.height;
  out.pixels.resize(static_cast<std::size_t>(view.width) * static_cast<std::size_t>(view.height) * 4);
  for (int y = 0; y < view.height; ++y) {
    const std::uint8_t* src = io::row_bytes(view, y);
    std::uint8_t* dst = out.pixels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(view.width) * 4;
    for (int x = 0; x < view.width; ++x, dst += 4) {
      switch (view.format) {
        case PixelFormat::rgba8: std::memcpy(dst, src + 4 * x, 4); break;
        case PixelFormat::bgra8:
          dst[0] = src[4 * x + 2];
          dst[1] = src[4 * x + 1];
          dst[2] = src[4 * x + 0];
          dst[3] = src[4 * x + 3];
          break;
        case PixelFormat::rgba32f: {
          float f[4];
          std::memcpy(f, src + 16 * static_cast<std::size_t>(x), sizeof f);
          for (int c = 0; c < 4; ++c) dst[c] = to_unorm8(f[c]);
          break;
        }
      }
    }
  }
  return out;
}

}  // namespace facet
