// Images owned by the caller. facet writes only the width x height pixels a view describes: the
// padding bytes at the end of each row are never touched. Row 0 of `data` is the top row unless
// `y_up` is set (then it is the bottom row, as in OpenGL).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "facet/status.hpp"

namespace facet {

// Largest accepted width or height. Screen coordinates are 24.8 fixed point inside a guard band of
// +-32768 pixels (see README "Rasterization"), which covers any image up to this size.
inline constexpr int kMaxImageDimension = 16384;

enum class PixelFormat {
  rgba8,    // 4 bytes: R G B A, sRGB-agnostic: linear values scaled to 0..255 and rounded
  bgra8,    // 4 bytes: B G R A
  rgba32f,  // 16 bytes: four floats, linear; unclamped when RenderOptions::hdr is set. Any alignment.
};

std::size_t bytes_per_pixel(PixelFormat format) noexcept;
const char* to_string(PixelFormat format) noexcept;

struct ImageView {
  void* data = nullptr;
  int width = 0;
  int height = 0;
  std::size_t stride_bytes = 0;  // >= width * bytes_per_pixel(format)
  PixelFormat format = PixelFormat::rgba8;
  bool y_up = false;
};

// Window-space depth per pixel (0 = near plane, 1 = far plane; 1 where nothing was drawn).
struct DepthView {
  float* data = nullptr;
  int width = 0;
  int height = 0;
  std::size_t stride_bytes = 0;  // >= width * sizeof(float); any alignment
  bool y_up = false;
};

Status validate_image_view(const ImageView& view);
// Also checks that the depth view has the colour image's size.
Status validate_depth_view(const DepthView& view, int width, int height);

// An 8-bit RGBA image in memory (top row first, no padding), for files and comparisons.
struct Rgba8Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 4
};

// PNG, 8-bit RGBA. The view may be in any format (floats are clamped to [0, 1] and rounded).
Status write_png(const std::string& path, const ImageView& image);
Result<Rgba8Image> read_png(const std::string& path);
// PFM (Portable Float Map): colour as RGB floats ("PF"), depth as one channel ("Pf").
Status write_pfm(const std::string& path, const ImageView& image);
Status write_pfm(const std::string& path, const DepthView& depth);
// OpenEXR: R, G and B as 32-bit floats (8-bit views divided by 255), top row first, no
// compression tricks (ZIP). Errors name the file.
Status write_exr(const std::string& path, const ImageView& image);

// Differences between two images of the same size, per 8-bit channel (R, G, B; alpha ignored).
struct ImageDifference {
  int max_channel_difference = 0;
  double mean_absolute_difference = 0;  // over all channels of all pixels, in 8-bit steps
  double psnr_db = 0;                   // infinity when identical
  std::size_t differing_pixels = 0;     // pixels with any channel different
};
Result<ImageDifference> compare_images(const Rgba8Image& a, const Rgba8Image& b);

}  // namespace facet
