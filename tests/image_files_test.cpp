// Image files read back: every pixel format x y-up x padded stride, written as PNG and PFM by
// facet and read back (PNG through libpng, PFM through the parser below, written from the format's
// description, not from facet's writer), against the pixel values put in. A wrong stride, a
// flipped row order or a shifted channel changes a value here.
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include "test_support.hpp"

namespace facet {
namespace {

// The value of channel c (0 R, 1 G, 2 B, 3 A) of pixel (x, y), y from the top, as an 8-bit step:
// distinct for every pixel and channel of a 13 x 7 image.
int step(int x, int y, int c) { return (x * 17 + y * 31 + c * 59 + 3) % 256; }

struct Source {
  std::vector<std::uint8_t> bytes;
  ImageView view;
};

Source make_source(PixelFormat format, bool y_up, std::size_t padding) {
  constexpr int kW = 13, kH = 7;
  Source s;
  const std::size_t bpp = bytes_per_pixel(format);
  const std::size_t stride = kW * bpp + padding;
  s.bytes.assign(stride * kH, 0x5A);
  for (int y = 0; y < kH; ++y) {
    const int row = y_up ? kH - 1 - y : y;
    for (int x = 0; x < kW; ++x) {
      std::uint8_t* p = s.bytes.data() + static_cast<std::size_t>(row) * stride + bpp * static_cast<std::size_t>(x);
      for (int c = 0; c < 4; ++c) {
        if (format == PixelFormat::rgba32f) {
          const float v = static_cast<float>(step(x, y, c)) / 255.0f;
          std::memcpy(p + 4 * c, &v, 4);
        } else {
          const int at = format == PixelFormat::bgra8 && c < 3 ? 2 - c : c;
          p[at] = static_cast<std::uint8_t>(step(x, y, c));
        }
      }
    }
  }
  s.view = ImageView{s.bytes.data(), kW, kH, stride, format, y_up};
  return s;
}

// A PFM file: "PF" or "Pf", width height, scale (negative: little-endian), then rows bottom to top.
struct Pfm {
  int channels = 0, width = 0, height = 0;
  std::vector<float> values;  // top row first
};

Pfm read_pfm_for_test(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  Pfm p;
  std::string magic;
  float scale = 0;
  in >> magic >> p.width >> p.height >> scale;
  in.get();  // the single whitespace after the scale
  EXPECT_TRUE(magic == "PF" || magic == "Pf") << magic;
  EXPECT_LT(scale, 0.0f);  // little-endian
  p.channels = magic == "PF" ? 3 : 1;
  const std::size_t row = static_cast<std::size_t>(p.width * p.channels);
  std::vector<float> file(row * static_cast<std::size_t>(p.height));
  in.read(reinterpret_cast<char*>(file.data()), static_cast<std::streamsize>(file.size() * sizeof(float)));
  EXPECT_EQ(in.gcount(), static_cast<std::streamsize>(file.size() * sizeof(float)));
  EXPECT_EQ(in.peek(), EOF) << "bytes after the pixels";
  p.values.resize(file.size());
  for (int y = 0; y < p.height; ++y) {
    std::memcpy(&p.values[static_cast<std::size_t>(y) * row], &file[static_cast<std::size_t>(p.height - 1 - y) * row],
                row * sizeof(float));
  }
  return p;
}

TEST(ImageFiles, EveryFormatYUpAndStrideReadsBackExactly) {
  const std::string dir = std::filesystem::temp_directory_path() / ("facet_img_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (PixelFormat format : {PixelFormat::rgba8, PixelFormat::bgra8, PixelFormat::rgba32f}) {
    for (bool y_up : {false, true}) {
      for (std::size_t padding : {std::size_t{0}, std::size_t{4}, std::size_t{7}}) {
        const Source src = make_source(format, y_up, padding);
        const std::string what = std::string(to_string(format)) + (y_up ? ", y-up" : "") + ", padding " +
                                 std::to_string(padding);
        const std::string png_path = dir + "/x.png", pfm_path = dir + "/x.pfm";
        ASSERT_TRUE(write_png(png_path, src.view).ok()) << what;
        const Result<Rgba8Image> png = read_png(png_path);
        ASSERT_TRUE(png.ok()) << what;
        ASSERT_EQ(png->width, 13);
        ASSERT_EQ(png->height, 7);
        ASSERT_TRUE(write_pfm(pfm_path, src.view).ok()) << what;
        const Pfm pfm = read_pfm_for_test(pfm_path);
        ASSERT_EQ(pfm.channels, 3);
        ASSERT_EQ(pfm.width, 13);
        ASSERT_EQ(pfm.height, 7);
        int png_errors = 0, pfm_errors = 0;
        for (int y = 0; y < 7; ++y) {
          for (int x = 0; x < 13; ++x) {
            for (int c = 0; c < 4; ++c) {
              png_errors += png->pixels[static_cast<std::size_t>((y * 13 + x) * 4 + c)] != step(x, y, c);
              if (c == 3) continue;
              const float v = pfm.values[static_cast<std::size_t>((y * 13 + x) * 3 + c)];
              pfm_errors += v != static_cast<float>(step(x, y, c)) / 255.0f;
            }
          }
        }
        EXPECT_EQ(png_errors, 0) << what;
        EXPECT_EQ(pfm_errors, 0) << what;
        // OpenEXR, read back with OpenEXR itself: float RGB, top row first.
        const std::string exr_path = dir + "/x.exr";
        ASSERT_TRUE(write_exr(exr_path, src.view).ok()) << what;
        Imf::InputFile exr(exr_path.c_str());
        const Imath::Box2i window = exr.header().dataWindow();
        ASSERT_EQ(window.max.x - window.min.x + 1, 13);
        ASSERT_EQ(window.max.y - window.min.y + 1, 7);
        std::vector<float> rgb(13 * 7 * 3);
        Imf::FrameBuffer frame;
        for (int c = 0; c < 3; ++c) {
          frame.insert(c == 0 ? "R" : c == 1 ? "G" : "B",
                       Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb.data() + c), 3 * sizeof(float), 3 * sizeof(float) * 13));
        }
        exr.setFrameBuffer(frame);
        exr.readPixels(window.min.y, window.max.y);
        int exr_errors = 0;
        for (int y = 0; y < 7; ++y)
          for (int x = 0; x < 13; ++x)
            for (int c = 0; c < 3; ++c) {
              exr_errors += rgb[static_cast<std::size_t>((y * 13 + x) * 3 + c)] != static_cast<float>(step(x, y, c)) / 255.0f;
            }
        EXPECT_EQ(exr_errors, 0) << what;
        // The padding was never read into the file, and the source was not written.
        EXPECT_TRUE(make_source(format, y_up, padding).bytes == src.bytes) << what;
      }
    }
  }
  // Depth as a one-channel PFM, with y-up and a padded stride.
  for (bool y_up : {false, true}) {
    constexpr int kW = 5, kH = 3, kStride = 7;
    std::vector<float> depth(kStride * kH, -1.0f);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) depth[static_cast<std::size_t>((y_up ? kH - 1 - y : y) * kStride + x)] = float(y * 10 + x);
    const DepthView d{depth.data(), kW, kH, kStride * sizeof(float), y_up};
    ASSERT_TRUE(write_pfm(dir + "/d.pfm", d).ok());
    const Pfm pfm = read_pfm_for_test(dir + "/d.pfm");
    ASSERT_EQ(pfm.channels, 1);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) EXPECT_EQ(pfm.values[static_cast<std::size_t>(y * kW + x)], float(y * 10 + x)) << y_up;
  }
  // A file that cannot be written is an error naming it, not an exception.
  const Source src = make_source(PixelFormat::rgba32f, false, 0);
  const Status bad = write_exr(dir + "/no/such/folder/x.exr", src.view);
  EXPECT_EQ(bad.code(), ErrorCode::io_error);
  EXPECT_NE(bad.message().find("x.exr"), std::string::npos) << bad.message();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace facet
