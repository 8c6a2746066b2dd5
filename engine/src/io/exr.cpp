// OpenEXR output (facet/image.hpp: write_exr). OpenEXR reports errors as exceptions; they become a
// Status naming the file. No thread pool: the file is written on the calling thread.
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <exception>
#include <new>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>

#include "common/format.hpp"
#include "facet/image.hpp"
#include "io/file_access.hpp"
#include "io/rows.hpp"

namespace facet {
namespace {

// OpenEXR's output stream over the temporary file io::write_file_atomically gives.
class FileStream final : public Imf::OStream {
 public:
  FileStream(std::FILE* f, const std::string& name) : Imf::OStream(name.c_str()), f_(f) {}
  void write(const char c[], int n) override {
    if (std::fwrite(c, 1, static_cast<std::size_t>(n), f_) != static_cast<std::size_t>(n)) {
      throw std::runtime_error(std::strerror(errno));
    }
  }
  std::uint64_t tellp() override {
    const long at = std::ftell(f_);
    if (at < 0) throw std::runtime_error(std::strerror(errno));
    return static_cast<std::uint64_t>(at);
  }
  void seekp(std::uint64_t pos) override {
    if (std::fseek(f_, static_cast<long>(pos), SEEK_SET) != 0) throw std::runtime_error(std::strerror(errno));
  }

 private:
  std::FILE* f_;
};

}  // namespace

// Rows are converted into a strip of kStrip rows at a time, so the writer holds no copy of the
// image (its memory is the strip and OpenEXR's own line buffer), and the file is written beside
// the target and renamed over it as PNG and PFM are.
Status write_exr(const std::string& path, const ImageView& image) {
  if (Status s = validate_image_view(image); !s.ok()) return s;
  return io::write_file_atomically(path, "OpenEXR file", [&](std::FILE* f) -> Status {
    try {
      constexpr int kStrip = 16;
      const auto w = static_cast<std::size_t>(image.width);
      std::vector<float> strip(3 * w * kStrip);
      FileStream stream(f, path);
      Imf::Header header(image.width, image.height);
      header.compression() = Imf::ZIP_COMPRESSION;
      for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      Imf::OutputFile file(stream, header, 1);
      for (int y0 = 0; y0 < image.height; y0 += kStrip) {
        const int rows = std::min(kStrip, image.height - y0);
        for (int r = 0; r < rows; ++r) {
          const std::uint8_t* p = io::row_bytes(image, y0 + r);  // picture row y0 + r (y_up handled there)
          for (std::size_t x = 0; x < w; ++x, p += bytes_per_pixel(image.format)) {
            float* out = strip.data() + 3 * (static_cast<std::size_t>(r) * w + x);
            if (image.format == PixelFormat::rgba32f) {
              std::memcpy(out, p, 3 * sizeof(float));
            } else {
              const bool bgr = image.format == PixelFormat::bgra8;
              for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(p[bgr ? 2 - c : c]) / 255.0f;
            }
          }
        }
        // OpenEXR addresses a slice by absolute row: the base is the strip moved back by y0 rows
        // (computed as an integer; only rows y0 .. y0 + rows - 1 are touched).
        const std::uintptr_t base = reinterpret_cast<std::uintptr_t>(strip.data()) -
                                    static_cast<std::uintptr_t>(y0) * 3 * sizeof(float) * w;
        Imf::FrameBuffer frame;
        for (int c = 0; c < 3; ++c) {
          frame.insert(c == 0 ? "R" : c == 1 ? "G" : "B",
                       Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + c * sizeof(float)), 3 * sizeof(float),
                                  3 * sizeof(float) * w));
        }
        file.setFrameBuffer(frame);
        file.writePixels(rows);
      }
      return {};
    } catch (const std::bad_alloc&) {
      return {ErrorCode::out_of_memory, "path", quote(path, 200) + ": out of memory while writing OpenEXR"};
    } catch (const std::exception& e) {
      return {ErrorCode::io_error, "path", quote(path, 200) + ": cannot write OpenEXR: " + quote(e.what(), 200)};
    }
  });
}

}  // namespace facet
