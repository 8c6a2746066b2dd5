// Environment pictures (facet/environment_light.hpp): Radiance .hdr decoded as Radiance does
// (flat and run-length scanlines, EXPOSURE divided out, both row orders), OpenEXR and sRGB PNG
// through their decoders, and every malformed file refused by name, without reading past it.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "facet/environment_light.hpp"
#include "facet/image.hpp"
#include "gltf_builder.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

std::span<const std::uint8_t> span_of(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

// A texel's RGBE bytes, deterministic and varied.
std::array<std::uint8_t, 4> rgbe_at(int x, int y) {
  return {std::uint8_t(17 * x + 3 * y), std::uint8_t(200 - 5 * x), std::uint8_t(40 + 9 * y), std::uint8_t(x == 3 ? 0 : 120 + y)};
}

float radiance(std::uint8_t m, std::uint8_t e) { return e == 0 ? 0.0f : (float(m) + 0.5f) * std::ldexp(1.0f, int(e) - 136); }

// A w x h Radiance file, each scanline run-length encoded (w >= 8) or flat.
std::string hdr_file(int w, int h, bool rle, const std::string& extra_header = "", const std::string& resolution = "") {
  std::string s = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n" + extra_header + "\n" +
                  (resolution.empty() ? "-Y " + std::to_string(h) + " +X " + std::to_string(w) : resolution) + "\n";
  for (int y = 0; y < h; ++y) {
    if (!rle) {
      for (int x = 0; x < w; ++x)
        for (std::uint8_t b : rgbe_at(x, y)) s.push_back(char(b));
      continue;
    }
    s += {char(2), char(2), char(w >> 8), char(w & 255)};
    for (int c = 0; c < 4; ++c) {
      // The first half as one literal run, the second as runs of one repeated byte each.
      const int half = w / 2;
      s.push_back(char(half));
      for (int x = 0; x < half; ++x) s.push_back(char(rgbe_at(x, y)[std::size_t(c)]));
      for (int x = half; x < w; ++x) {
        s.push_back(char(128 + 1));
        s.push_back(char(rgbe_at(x, y)[std::size_t(c)]));
      }
    }
  }
  return s;
}

void expect_texels(const EnvironmentLight& e, int w, int h, float scale, bool flipped) {
  ASSERT_EQ(e.width, w);
  ASSERT_EQ(e.height, h);
  ASSERT_EQ(e.source, EnvironmentSource::image);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const auto p = rgbe_at(x, flipped ? h - 1 - y : y);
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(e.rgb[3 * (std::size_t(y) * std::size_t(w) + std::size_t(x)) + std::size_t(c)], radiance(p[std::size_t(c)], p[3]) * scale)
            << x << "," << y << " channel " << c;
      }
    }
  }
}

TEST(EnvironmentImage, RadianceFilesDecodeAsRadianceDoes) {
  for (bool rle : {true, false}) {
    Result<EnvironmentLight> e = decode_environment_image(span_of(hdr_file(16, 8, rle)), "sky.hdr");
    ASSERT_TRUE(e.ok()) << e.status().message();
    expect_texels(*e, 16, 8, 1.0f, false);
  }
  Result<EnvironmentLight> exposed = decode_environment_image(span_of(hdr_file(16, 8, true, "EXPOSURE=2\nEXPOSURE=2\n")), "sky.hdr");
  ASSERT_TRUE(exposed.ok()) << exposed.status().message();
  expect_texels(*exposed, 16, 8, 0.25f, false);
  Result<EnvironmentLight> bottom_up = decode_environment_image(span_of(hdr_file(16, 8, true, "", "+Y 8 +X 16")), "sky.hdr");
  ASSERT_TRUE(bottom_up.ok()) << bottom_up.status().message();
  expect_texels(*bottom_up, 16, 8, 1.0f, true);
}

TEST(EnvironmentImage, MalformedRadianceFilesAreRefusedByName) {
  const std::string good = hdr_file(16, 8, true);
  struct Case {
    std::string bytes, says;
  };
  std::string past = good;
  past[good.find("\n-Y") + 1 + std::string("-Y 8 +X 16\n").size() + 4] = char(100);  // a literal run of 100 in a row of 16
  std::string zero = good;
  zero[good.find("\n-Y") + 1 + std::string("-Y 8 +X 16\n").size() + 4] = char(0);
  std::string repeat = good;  // the first repeated run of the first scanline (after 2 2 0 16, the literal run of 8)
  repeat[good.find("\n-Y") + 1 + std::string("-Y 8 +X 16\n").size() + 4 + 1 + 8] = char(128 + 20);
  std::string length = good;
  length[good.find("\n-Y") + 1 + std::string("-Y 8 +X 16\n").size() + 3] = char(15);
  const Case cases[] = {
      {good.substr(0, good.size() - 5), "ends early"},
      {past, "passes the end of the scanline"},
      {repeat, "a run passes the end of the scanline"},
      {zero, "literal run is empty"},
      {length, "its length is not the picture's width"},
      {hdr_file(16, 7, false), "twice as wide as high"},
      {hdr_file(16, 8, true, "", "-X 8 +Y 16"), "resolution line"},
      {hdr_file(16, 8, true, "", "-Y 99999999999 +X 16"), "twice as wide as high"},
      {"#?RADIANCE\n\n-Y 20000 +X 40000\n", "at most 16384"},
      {hdr_file(16, 8, true, "COLORCORR=1 1 1\n"), "COLORCORR"},
      {"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 8 +X 16\n", "XYZE"},
      {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", "header never ends"},
      {"GIF89a", "not a picture facet reads"},
  };
  for (const Case& c : cases) {
    Result<EnvironmentLight> e = decode_environment_image(span_of(c.bytes), "bad\x01sky.hdr");
    ASSERT_FALSE(e.ok()) << c.says;
    EXPECT_NE(e.status().message().find(c.says), std::string::npos) << e.status().message();
    EXPECT_NE(e.status().message().find("bad"), std::string::npos) << e.status().message();
    EXPECT_EQ(e.status().message().find('\x01'), std::string::npos) << "no raw control character in a message";
  }
  // Old-style runs are refused rather than read wrongly.
  std::string old = hdr_file(16, 8, false);
  const std::size_t first = old.find("\n-Y") + std::string("\n-Y 8 +X 16\n").size();
  old[first] = old[first + 1] = old[first + 2] = char(1);
  Result<EnvironmentLight> e = decode_environment_image(span_of(old), "old.hdr");
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.status().message().find("old-style"), std::string::npos) << e.status().message();
  // A budget smaller than the picture's floats refuses it before they are allocated.
  Result<EnvironmentLight> small = decode_environment_image(span_of(good), "sky.hdr", 100);
  ASSERT_FALSE(small.ok());
  EXPECT_EQ(small.status().code(), ErrorCode::out_of_memory);
}

TEST(EnvironmentImage, OpenExrAndPngRoundTrip) {
  test::TempDir dir;
  std::vector<float> rgba(4 * 16 * 8);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = (i % 4 == 3) ? 1.0f : float(i % 37) * 0.25f;
  const ImageView view{rgba.data(), 16, 8, 16 * 16, PixelFormat::rgba32f, false};
  ASSERT_TRUE(write_exr(dir / "sky.exr", view).ok());
  Result<EnvironmentLight> e = load_environment_image(dir / "sky.exr");
  ASSERT_TRUE(e.ok()) << e.status().message();
  ASSERT_EQ(e->width, 16);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 16; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float want = rgba[4 * (std::size_t(y) * 16 + std::size_t(x)) + std::size_t(c)];
        EXPECT_NEAR(e->rgb[3 * (std::size_t(y) * 16 + std::size_t(x)) + std::size_t(c)], want, want * 1e-3f);  // (read as half)
      }
    }
  }
  std::vector<std::uint8_t> bytes(4 * 16 * 8);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = i % 4 == 3 ? 255 : std::uint8_t(i * 7);
  ASSERT_TRUE(write_png(dir / "sky.png", ImageView{bytes.data(), 16, 8, 64, PixelFormat::rgba8, false}).ok());
  Result<EnvironmentLight> p = load_environment_image(dir / "sky.png");
  ASSERT_TRUE(p.ok()) << p.status().message();
  // sRGB decoded: byte 255 is 1, 128 is 0.2158605, top row first as written.
  for (std::size_t i = 0; i < 16 * 8; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double s = bytes[4 * i + std::size_t(c)] / 255.0;
      const double want = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
      EXPECT_NEAR(p->rgb[3 * i + std::size_t(c)], want, 1e-6) << i;
    }
  }
  // An EXR with a negative texel is refused by name.
  rgba[4 * 5 + 1] = -2.0f;
  ASSERT_TRUE(write_exr(dir / "negative.exr", view).ok());
  Result<EnvironmentLight> n = load_environment_image(dir / "negative.exr");
  ASSERT_FALSE(n.ok());
  EXPECT_NE(n.status().message().find("texel 5, 0"), std::string::npos) << n.status().message();
  // A truncated EXR is an error, not a crash.
  const std::string whole = test::read_bytes(dir / "sky.exr");
  test::write_text(dir / "cut.exr", whole.substr(0, whole.size() / 2));
  EXPECT_FALSE(load_environment_image(dir / "cut.exr").ok());
}

}  // namespace
}  // namespace facet
