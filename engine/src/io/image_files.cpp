// PNG through libpng's simplified API (png_image: no setjmp/longjmp across C++ frames), PFM by
// hand, and image comparison.
#include <png.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#include "io/rows.hpp"
#include "common/format.hpp"
#include "facet/image.hpp"
#include "io/file_access.hpp"
#include "io/image_convert.hpp"

namespace facet {
namespace {

Status io_error(const std::string& path, const std::string& what) {
  return {ErrorCode::io_error, "path", quote(path, 200) + ": " + what};
}

}  // namespace

Status write_png(const std::string& path, const ImageView& image) {
  if (Status s = validate_image_view(image); !s.ok()) return s;
  try {
    const Rgba8Image rgba = to_rgba8(image);
    return io::write_file_atomically(path, "PNG file", [&](std::FILE* f) -> Status {
      png_image png;
      std::memset(&png, 0, sizeof png);
      png.version = PNG_IMAGE_VERSION;
      png.width = static_cast<png_uint_32>(rgba.width);
      png.height = static_cast<png_uint_32>(rgba.height);
      png.format = PNG_FORMAT_RGBA;
      if (!png_image_write_to_stdio(&png, f, 0, rgba.pixels.data(), 0, nullptr)) {
        const std::string why = png.message;
        png_image_free(&png);
        return io_error(path, "cannot write PNG: " + why);
      }
      return {};
    });
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "path", quote(path, 200) + ": out of memory"};
  }
}

Result<Rgba8Image> read_png(const std::string& path) {
  // Through io::read_file: regular files only (a FIFO would block forever), read whole.
  Result<std::string> bytes = io::read_file(path, "PNG file");
  if (!bytes) return bytes.status();
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes->data(), bytes->size())) {
    return io_error(path, std::string("cannot read PNG: ") + png.message);
  }
  if (png.width < 1 || png.height < 1 || png.width > static_cast<png_uint_32>(kMaxImageDimension) ||
      png.height > static_cast<png_uint_32>(kMaxImageDimension)) {
    png_image_free(&png);
    return io_error(path, "PNG size out of range (1.." + std::to_string(kMaxImageDimension) + " per side)");
  }
  png.format = PNG_FORMAT_RGBA;
  Rgba8Image out;
  out.width = static_cast<int>(png.width);
  out.height = static_cast<int>(png.height);
  try {
    out.pixels.resize(PNG_IMAGE_SIZE(png));
  } catch (const std::bad_alloc&) {
    png_image_free(&png);
    return Status{ErrorCode::out_of_memory, "path", quote(path, 200) + ": out of memory"};
  }
  if (!png_image_finish_read(&png, nullptr, out.pixels.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    return io_error(path, "cannot decode PNG: " + why);
  }
  return out;
}

namespace {

// PFM rows go bottom to top; a negative scale means little-endian floats.
template <class Pixel>
Status write_pfm_rows(const std::string& path, const char* magic, int width, int height, int channels, Pixel pixel) {
  try {
    std::vector<float> row(static_cast<std::size_t>(width) * static_cast<std::size_t>(channels));
    return io::write_file_atomically(path, "PFM file", [&](std::FILE* f) -> Status {
      if (std::fprintf(f, "%s\n%d %d\n-1.0\n", magic, width, height) < 0) return io_error(path, "write failed");
      for (int y = height - 1; y >= 0; --y) {  // y counts from the top
        for (int x = 0; x < width; ++x) pixel(x, y, &row[static_cast<std::size_t>(x * channels)]);
        if (std::fwrite(row.data(), sizeof(float), row.size(), f) != row.size()) return io_error(path, "write failed");
      }
      return {};
    });
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "path", quote(path, 200) + ": out of memory"};
  }
}

}  // namespace

Status write_pfm(const std::string& path, const ImageView& image) {
  if (Status s = validate_image_view(image); !s.ok()) return s;
  return write_pfm_rows(path, "PF", image.width, image.height, 3, [&](int x, int y, float* out) {
    const std::uint8_t* p = io::row_bytes(image, y) + bytes_per_pixel(image.format) * static_cast<std::size_t>(x);
    if (image.format == PixelFormat::rgba32f) {
      std::memcpy(out, p, 3 * sizeof(float));
    } else {
      const bool bgr = image.format == PixelFormat::bgra8;
      for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(p[bgr ? 2 - c : c]) / 255.0f;
    }
  });
}

Status write_pfm(const std::string& path, const DepthView& depth) {
  if (Status s = validate_depth_view(depth, depth.width, depth.height); !s.ok()) return s;
  return write_pfm_rows(path, "Pf", depth.width, depth.height, 1, [&](int x, int y, float* out) {
    std::memcpy(out, io::row_bytes(depth, y) + sizeof(float) * static_cast<std::size_t>(x), sizeof(float));
  });
}

Result<ImageDifference> compare_images(const Rgba8Image& a, const Rgba8Image& b) {
  if (a.width != b.width || a.height != b.height) {
    return Status{ErrorCode::invalid_argument, "size",
                  "size: " + std::to_string(a.width) + " x " + std::to_string(a.height) + " differs from " +
                      std::to_string(b.width) + " x " + std::to_string(b.height)};
  }
  const std::size_t pixels = static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height);
  if (a.pixels.size() != pixels * 4 || b.pixels.size() != pixels * 4) {
    return Status{ErrorCode::invalid_argument, "pixels", "pixels: buffer size does not match width x height x 4"};
  }
  ImageDifference d;
  double sum_abs = 0, sum_sq = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    bool differs = false;
    for (int c = 0; c < 3; ++c) {
      const int diff = std::abs(int(a.pixels[4 * i + c]) - int(b.pixels[4 * i + c]));
      d.max_channel_difference = std::max(d.max_channel_difference, diff);
      sum_abs += diff;
      sum_sq += double(diff) * diff;
      differs |= diff != 0;
    }
    d.differing_pixels += differs ? 1 : 0;
  }
  const double n = 3.0 * static_cast<double>(pixels);
  d.mean_absolute_difference = sum_abs / n;
  const double mse = sum_sq / n;
  d.psnr_db = mse == 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
  return d;
}

}  // namespace facet
