// OpenEXR output (facet/image.hpp: write_exr). OpenEXR reports errors as exceptions; they become a
// Status naming the file. Its global thread pool is left at its default of no threads.
#include <cstring>
#include <exception>
#include <new>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include "common/format.hpp"
#include "facet/image.hpp"
#include "io/rows.hpp"

namespace facet {

Status write_exr(const std::string& path, const ImageView& image) {
  if (Status s = validate_image_view(image); !s.ok()) return s;
  try {
    const auto w = static_cast<std::size_t>(image.width), h = static_cast<std::size_t>(image.height);
    std::vector<float> rgb(3 * w * h);  // top row first
    for (std::size_t y = 0; y < h; ++y) {
      const std::uint8_t* p = io::row_bytes(image, static_cast<int>(y));  // picture row y (y_up handled there)
      for (std::size_t x = 0; x < w; ++x, p += bytes_per_pixel(image.format)) {
        float* out = rgb.data() + 3 * (y * w + x);
        if (image.format == PixelFormat::rgba32f) {
          std::memcpy(out, p, 3 * sizeof(float));
        } else {
          const bool bgr = image.format == PixelFormat::bgra8;
          for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(p[bgr ? 2 - c : c]) / 255.0f;
        }
      }
    }
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::FrameBuffer frame;
    char* base = reinterpret_cast<char*>(rgb.data());
    for (int c = 0; c < 3; ++c) {
      frame.insert(c == 0 ? "R" : c == 1 ? "G" : "B",
                   Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 3 * sizeof(float), 3 * sizeof(float) * w));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
    return {};
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "path", quote(path, 200) + ": out of memory while writing OpenEXR"};
  } catch (const std::exception& e) {
    return {ErrorCode::io_error, "path", quote(path, 200) + ": cannot write OpenEXR: " + quote(e.what(), 200)};
  }
}

}  // namespace facet
