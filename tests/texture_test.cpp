// Textures: making and decoding them (every PNG layout, JPEG, bad files), the mipmap chain, and the
// samplers: the SIMD sampler of every ISA against its scalar twin (bit for bit), the scalar one
// against the double-precision reference (within a step of 8-bit output), GL's wrap rules at the
// exact texel borders, and hostile coordinates (1e7, infinities, NaN).
#include <png.h>
#include <zlib.h>
#include <stb_image_write.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "tile/tile_raster.hpp"
#include "test_support.hpp"
#include "texture/sampler.hpp"
#include "texture/srgb_table.hpp"

namespace facet {
namespace {

using texture::Sampler;

std::vector<std::uint8_t> rgba_pattern(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> px(4 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (auto& b : px) b = static_cast<std::uint8_t>(rng() & 0xff);
  return px;
}

Texture must_make(int w, int h, TextureFilter filter, TextureWrap wrap, unsigned seed = 1,
                  TextureEncoding encoding = TextureEncoding::linear) {
  TextureOptions o{filter, wrap};
  o.encoding = encoding;
  Result<Texture> t = make_texture("t", w, h, rgba_pattern(w, h, seed), o);
  EXPECT_TRUE(t.ok()) << t.status().message();
  return std::move(*t);
}

TEST(Texture, LevelsAndRowsAsGl) {
  // 2 x 2, top row first: red green / blue white. Stored bottom row first.
  const std::vector<std::uint8_t> px = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  Result<Texture> t = make_texture("rgbw", 2, 2, px, {TextureFilter::trilinear, TextureWrap::repeat});
  ASSERT_TRUE(t.ok()) << t.status().message();
  ASSERT_TRUE(validate_texture(*t).ok());
  ASSERT_EQ(t->levels.size(), 2u);
  EXPECT_EQ(t->texels[0], 0xffff0000u);  // (0, 0): bottom-left = blue (R in the low byte)
  EXPECT_EQ(t->texels[2], 0xff0000ffu);  // (0, 1): top-left = red
  // Level 1: the average of the four, rounded: (255 + 0 + 0 + 255) / 4 = 127.5 -> 128.
  EXPECT_EQ(t->texels[4], 0xff808080u);
  // 5 x 3 (odd sides): levels 2 x 1, 1 x 1; each texel of a level weighs the same in the next.
  std::vector<std::uint8_t> grey(5 * 3 * 4, 0);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i)
      for (int c = 0; c < 4; ++c) grey[4 * (j * 5 + i) + c] = static_cast<std::uint8_t>(i * 50);
  Result<Texture> odd = make_texture("odd", 5, 3, grey, {TextureFilter::trilinear, TextureWrap::repeat});
  ASSERT_TRUE(odd.ok());
  ASSERT_EQ(odd->levels.size(), 3u);
  EXPECT_EQ(odd->levels[1].width, 2);
  EXPECT_EQ(odd->levels[1].height, 1);
  // Level 1 texel 0 covers texels 0, 1 and half of 2: (0 + 50 + 0.5 * 100) / 2.5 = 40.
  EXPECT_EQ(odd->texels[odd->levels[1].offset] & 0xff, 40u);
  // texel 1: (0.5 * 100 + 150 + 200) / 2.5 = 160.
  EXPECT_EQ(odd->texels[odd->levels[1].offset + 1] & 0xff, 160u);
  EXPECT_EQ(odd->texels[odd->levels[2].offset] & 0xff, 100u);  // (40 + 160) / 2
  // 1 x N and N x 1 reach 1 x 1; bilinear and nearest keep level 0 only.
  EXPECT_EQ(must_make(1, 9, TextureFilter::trilinear, TextureWrap::clamp).levels.size(), 4u);
  EXPECT_EQ(must_make(16384, 1, TextureFilter::trilinear, TextureWrap::clamp).levels.size(), 15u);
  EXPECT_EQ(must_make(8, 8, TextureFilter::bilinear, TextureWrap::clamp).levels.size(), 1u);
}

TEST(Texture, BadArguments) {
  const std::vector<std::uint8_t> px(16, 0);
  EXPECT_EQ(make_texture("t", 0, 4, {}).status().code(), ErrorCode::invalid_argument);
  EXPECT_EQ(make_texture("t", 16385, 1, std::vector<std::uint8_t>(16385 * 4)).status().code(),
            ErrorCode::invalid_argument);
  EXPECT_EQ(make_texture("t", 2, 2, std::span(px).first(12)).status().field(), "rgba8");
  TextureOptions small;
  small.memory_budget_bytes = 100;
  EXPECT_EQ(make_texture("t", 8, 8, std::vector<std::uint8_t>(256), small).status().code(), ErrorCode::out_of_memory);
  TextureOptions bad;
  bad.wrap = static_cast<TextureWrap>(7);
  EXPECT_EQ(make_texture("t", 2, 2, px, bad).status().field(), "wrap");
  Texture t = must_make(4, 4, TextureFilter::trilinear, TextureWrap::repeat);
  t.texels.pop_back();
  EXPECT_EQ(validate_texture(t, "textures[0]").field(), "textures[0].texels");
  t = must_make(4, 4, TextureFilter::trilinear, TextureWrap::repeat);
  t.filter = TextureFilter::nearest;  // one level expected
  EXPECT_EQ(validate_texture(t, "textures[0]").field(), "textures[0].levels");
}

// PNG bytes from libpng's simplified writer.
std::vector<std::uint8_t> png_bytes(int w, int h, png_uint_32 format, const void* pixels, const void* colormap = nullptr,
                                    int colormap_entries = 0) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(w);
  img.height = static_cast<png_uint_32>(h);
  img.format = format;
  img.colormap_entries = static_cast<png_uint_32>(colormap_entries);
  png_alloc_size_t size = 0;
  EXPECT_TRUE(png_image_write_to_memory(&img, nullptr, &size, 0, pixels, 0, colormap));
  std::vector<std::uint8_t> out(size);
  EXPECT_TRUE(png_image_write_to_memory(&img, out.data(), &size, 0, pixels, 0, colormap)) << img.message;
  out.resize(size);
  return out;
}

// The top-left texel of a decoded texture (stored rows are bottom first).
std::uint32_t top_left(const Texture& t) {
  return t.texels[static_cast<std::size_t>(t.height() - 1) * static_cast<std::size_t>(t.width())];
}

TEST(Texture, DecodesEveryPngLayout) {
  const std::uint8_t grey[2] = {10, 200};
  const std::uint8_t grey_alpha[4] = {10, 77, 200, 255};
  const std::uint8_t rgb[6] = {1, 2, 3, 4, 5, 6};
  const std::uint8_t rgba[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  const std::uint16_t rgb16[6] = {0, 65535, 32767, 32768, 128, 129};
  const std::uint8_t palette_index[2] = {1, 0};
  const std::uint8_t palette[6] = {9, 8, 7, 60, 50, 40};
  struct Case {
    const char* name;
    std::vector<std::uint8_t> bytes;
    std::uint32_t first;
  } cases[] = {
      {"grey", png_bytes(2, 1, PNG_FORMAT_GRAY, grey), 0xff0a0a0au},
      {"grey+alpha", png_bytes(2, 1, PNG_FORMAT_GA, grey_alpha), 0x4d0a0a0au},
      {"rgb", png_bytes(2, 1, PNG_FORMAT_RGB, rgb), 0xff030201u},
      {"rgba", png_bytes(2, 1, PNG_FORMAT_RGBA, rgba), 0x04030201u},
      // 16-bit: round(v * 255 / 65535): 0 -> 0, 65535 -> 255, 32767 -> 127 (127.498).
      {"rgb16", png_bytes(2, 1, PNG_FORMAT_LINEAR_RGB, rgb16), 0xff7fff00u},
      {"palette", png_bytes(2, 1, PNG_FORMAT_RGB_COLORMAP, palette_index, palette, 2), 0xff28323cu},
  };
  for (const Case& c : cases) {
    Result<Texture> t = decode_texture(c.bytes, c.name, c.name, {TextureFilter::nearest, TextureWrap::clamp});
    ASSERT_TRUE(t.ok()) << c.name << ": " << t.status().message();
    EXPECT_EQ(t->width(), 2) << c.name;
    EXPECT_EQ(top_left(*t), c.first) << c.name << std::hex << " got " << top_left(*t);
  }
  // The second 16-bit texel: 32768 -> 128 (127.502), 128 -> 0 (0.498), 129 -> 1 (0.502).
  Result<Texture> t16 = decode_texture(cases[4].bytes, "rgb16", "t", {TextureFilter::nearest, TextureWrap::clamp});
  EXPECT_EQ(t16->texels[1], 0xff010080u);
}

void write_to_vector(void* context, void* data, int size) {
  auto* v = static_cast<std::vector<std::uint8_t>*>(context);
  v->insert(v->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
}

TEST(Texture, DecodesJpeg) {
  // A flat colour survives JPEG within a step or two.
  std::vector<std::uint8_t> px(16 * 8 * 3);
  for (std::size_t i = 0; i < px.size(); i += 3) px[i] = 200, px[i + 1] = 100, px[i + 2] = 50;
  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(stbi_write_jpg_to_func(write_to_vector, &jpeg, 16, 8, 3, px.data(), 95));
  Result<Texture> t = decode_texture(jpeg, "flat.jpg", "flat");
  ASSERT_TRUE(t.ok()) << t.status().message();
  EXPECT_EQ(t->width(), 16);
  EXPECT_EQ(t->height(), 8);
  const std::uint32_t texel = t->texels[0];
  EXPECT_NEAR(double(texel & 0xff), 200, 3);
  EXPECT_NEAR(double((texel >> 8) & 0xff), 100, 3);
  EXPECT_NEAR(double((texel >> 16) & 0xff), 50, 3);
  EXPECT_EQ(texel >> 24, 255u);
}

TEST(Texture, BadFilesAreRefusedWithTheirName) {
  const std::uint8_t rgba[16] = {};
  std::vector<std::uint8_t> png = png_bytes(2, 2, PNG_FORMAT_RGBA, rgba);
  // Truncated: the header reads, the pixels do not.
  const std::vector<std::uint8_t> cut(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() / 2));
  Result<Texture> t = decode_texture(cut, "'cut.png'", "t");
  EXPECT_FALSE(t.ok());
  EXPECT_NE(t.status().message().find("'cut.png': cannot decode the PNG"), std::string::npos) << t.status().message();
  // Other formats, and nothing at all.
  const std::string gif = "GIF89a\x01\x00\x01\x00";
  t = decode_texture({reinterpret_cast<const std::uint8_t*>(gif.data()), gif.size()}, "'a.gif'", "t");
  EXPECT_EQ(t.status().code(), ErrorCode::unsupported);
  EXPECT_NE(t.status().message().find("not a PNG, JPEG, TGA or BMP"), std::string::npos);
  EXPECT_EQ(decode_texture({}, "'empty'", "t").status().code(), ErrorCode::unsupported);
  // Too wide.
  std::vector<std::uint8_t> wide_px(16385, 0);
  t = decode_texture(png_bytes(16385, 1, PNG_FORMAT_GRAY, wide_px.data()), "'wide.png'", "t");
  EXPECT_EQ(t.status().code(), ErrorCode::unsupported);
  EXPECT_NE(t.status().message().find("16385 x 1"), std::string::npos) << t.status().message();
  // Over the memory budget, before decoding.
  TextureOptions tiny;
  tiny.memory_budget_bytes = 40;  // 2 x 2: 32 bytes to decode and 20 of texels
  EXPECT_EQ(decode_texture(png, "'p.png'", "t", tiny).status().code(), ErrorCode::out_of_memory);
  // Files: missing, a directory.
  EXPECT_EQ(load_texture("/nonexistent/facet/t.png", "t").status().code(), ErrorCode::io_error);
  EXPECT_EQ(load_texture(test::data_dir(), "t").status().code(), ErrorCode::io_error);
}

// --- samplers ----------------------------------------------------------------------------------

struct Inputs {
  std::vector<float> u, v, dsdx, dtdx, dsdy, dtdy;
  void add(float a, float b, float dx0, float dx1, float dy0, float dy1) {
    u.push_back(a), v.push_back(b), dsdx.push_back(dx0), dtdx.push_back(dx1), dsdy.push_back(dy0), dtdy.push_back(dy1);
  }
  std::size_t size() const { return u.size(); }
};

// Random coordinates over several repeats, random derivatives over every level, and hostile values.
Inputs sample_inputs(unsigned seed, int width, int height) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-3.0f, 3.0f), exponent(-12.0f, 8.0f), unit(-1.0f, 1.0f);
  Inputs in;
  for (int i = 0; i < 4000; ++i) {
    const float scale = std::exp2(exponent(rng));
    in.add(coord(rng), coord(rng), unit(rng) * scale, unit(rng) * scale, unit(rng) * scale, unit(rng) * scale);
  }
  // Exact texel borders and centres of level 0, and the ends of the range.
  for (int i = -1; i <= width + 1; ++i) {
    const float s = float(i) / float(width), c = (float(i) + 0.5f) / float(width);
    in.add(s, float(i % 3) / float(height), 0, 0, 0, 0);
    in.add(c, (float(i % 3) + 0.5f) / float(height), 1.0f / float(width), 0, 0, 1.0f / float(height));
  }
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float hostile[] = {0.0f, -0.0f, 1.0f, -1.0f, 2.0f, 1e7f, -1e7f, 1e7f + 1.0f, 1e30f, -1e30f, inf, -inf, nan,
                           std::nextafter(1.0f, 0.0f), std::nextafter(0.0f, -1.0f), 1e-40f};
  for (float a : hostile) {
    for (float b : hostile) in.add(a, b, a, b, b, a);
  }
  return in;
}

struct Outputs {
  std::vector<float> c[4];
};

class TextureSampler : public ::testing::TestWithParam<Isa> {};

TEST_P(TextureSampler, SimdMatchesItsScalarTwinBitForBit) {
  if (!isa_supported(GetParam())) GTEST_SKIP() << "this CPU does not have " << to_string(GetParam());
  const tile::simd::Kernels* kernels = tile::simd_raster_kernels(GetParam());
  ASSERT_NE(kernels, nullptr);
  const int sizes[][2] = {{1, 1}, {1, 7}, {2, 2}, {3, 5}, {16, 16}, {5, 3}, {64, 32}, {16384, 1}};
  for (const auto& size : sizes) {
    for (TextureFilter filter : {TextureFilter::nearest, TextureFilter::bilinear, TextureFilter::trilinear}) {
      for (TextureWrap wrap : {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror})
      for (TextureEncoding encoding : {TextureEncoding::linear, TextureEncoding::srgb}) {
        const Texture tex = must_make(size[0], size[1], filter, wrap, 7, encoding);
        const Sampler s = texture::make_sampler(tex);
        const Inputs in = sample_inputs(11, size[0], size[1]);
        Outputs simd;
        for (auto& c : simd.c) c.assign(in.size(), -1.0f);
        const float* ins[6] = {in.u.data(), in.v.data(), in.dsdx.data(), in.dtdx.data(), in.dsdy.data(), in.dtdy.data()};
        float* outs[4] = {simd.c[0].data(), simd.c[1].data(), simd.c[2].data(), simd.c[3].data()};
        kernels->sample(s, in.size(), ins, outs);
        for (std::size_t i = 0; i < in.size(); ++i) {
          const float lambda = texture::lod_scalar(s, in.dsdx[i], in.dtdx[i], in.dsdy[i], in.dtdy[i]);
          const auto scalar = texture::sample_scalar(s, in.u[i], in.v[i], lambda);
          for (int c = 0; c < 4; ++c) {
            ASSERT_EQ(std::bit_cast<std::uint32_t>(simd.c[c][i]), std::bit_cast<std::uint32_t>(scalar[c]))
                << to_string(filter) << " " << to_string(wrap) << " " << to_string(encoding) << " " << size[0] << "x"
                << size[1] << " sample " << i
                << " (u " << in.u[i] << ", v " << in.v[i] << ", lambda " << lambda << ") channel " << c;
          }
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Isas, TextureSampler, ::testing::Values(Isa::sse2, Isa::avx2, Isa::avx512),
                         [](const ::testing::TestParamInfo<Isa>& p) { return std::string(to_string(p.param)); });

// The 16-bit tier's fixed-point sampler: the SIMD twin returns the scalar twin's bytes on every
// ISA, for every filter, wrap mode and size, on random, border and hostile coordinates.
TEST_P(TextureSampler, FixedPointSimdMatchesItsScalarTwin) {
  if (!isa_supported(GetParam())) GTEST_SKIP() << "this CPU does not have " << to_string(GetParam());
  const tile::simd::Kernels* kernels = tile::simd_raster_kernels(GetParam());
  ASSERT_NE(kernels, nullptr);
  const int sizes[][2] = {{1, 1}, {1, 7}, {2, 2}, {3, 5}, {16, 16}, {5, 3}, {64, 32}, {16384, 1}};
  for (const auto& size : sizes) {
    for (TextureFilter filter : {TextureFilter::nearest, TextureFilter::bilinear, TextureFilter::trilinear}) {
      for (TextureWrap wrap : {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror}) {
        const Texture tex = must_make(size[0], size[1], filter, wrap, 7);
        const Sampler s = texture::make_sampler(tex);
        const Inputs in = sample_inputs(13, size[0], size[1]);
        std::vector<std::uint32_t> simd(in.size(), 0xdeadbeefu);
        const float* ins[6] = {in.u.data(), in.v.data(), in.dsdx.data(), in.dtdx.data(), in.dsdy.data(), in.dtdy.data()};
        kernels->sample_fixed(s, in.size(), ins, simd.data());
        for (std::size_t i = 0; i < in.size(); ++i) {
          const float lambda = texture::lod_scalar(s, in.dsdx[i], in.dtdx[i], in.dsdy[i], in.dtdy[i]);
          ASSERT_EQ(simd[i], texture::sample_fixed_scalar(s, in.u[i], in.v[i], lambda))
              << to_string(filter) << " " << to_string(wrap) << " " << size[0] << "x" << size[1] << " sample " << i
              << " (u " << in.u[i] << ", v " << in.v[i] << ", lambda " << lambda << ")";
        }
      }
    }
  }
}

// Each fixed-point lerp is the correctly rounded lerp (halves up) of two bytes with weight w/256,
// for every pair of bytes and every weight.
TEST(TextureSampler, FixedPointLerpRoundsCorrectly) {
  for (std::uint32_t w = 0; w <= 256; ++w) {
    for (std::uint32_t a = 0; a < 256; ++a) {
      for (std::uint32_t b = 0; b < 256; ++b) {
        const double exact = (double(a) * (256 - w) + double(b) * w) / 256.0;
        const auto want = static_cast<std::uint32_t>(std::floor(exact + 0.5));
        const std::uint32_t got = texture::lerp_bytes(a | (b << 8) | (a << 16) | (b << 24), b | (a << 8) | (b << 16) | (a << 24), w);
        ASSERT_EQ(got & 0xffu, want) << a << " " << b << " " << w;
        ASSERT_EQ((got >> 16) & 0xffu, want);
        const auto back = static_cast<std::uint32_t>(std::floor((double(b) * (256 - w) + double(a) * w) / 256.0 + 0.5));
        ASSERT_EQ((got >> 8) & 0xffu, back);
        ASSERT_EQ(got >> 24, back);
      }
    }
  }
}

// The fixed-point sampler's contract against the double-precision reference sampler, in 8-bit
// steps: a sweep of texture sizes (1 x 1 to 16384 wide), magnifications up to 1024x (random
// coordinates within one texel of a 1 x 1 .. 16 x 16 texture's texels), and UVs within +-64
// (documented range; the wrapped coordinate keeps 8 sub-texel bits there), per filter.
TEST(TextureSampler, FixedPointContractAgainstReference) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), exponent(-10.0f, 6.0f), sign(-1.0f, 1.0f);
  struct Bound {
    TextureFilter filter;
    double max_steps, mean_steps;
  };
  // Measured: bilinear 1.40 / 0.31 steps, trilinear 1.57 / 0.32 (the float sampler: under 1 / 0.01).
  for (const Bound bound : {Bound{TextureFilter::nearest, 0.0, 0.0}, Bound{TextureFilter::bilinear, 1.5, 0.35},
                            Bound{TextureFilter::trilinear, 2.0, 0.35}}) {
    double worst = 0, sum = 0;
    std::size_t count = 0, border = 0;
    for (const auto& size : {std::array<int, 2>{1, 1}, std::array<int, 2>{3, 5}, std::array<int, 2>{16, 16},
                             std::array<int, 2>{64, 32}, std::array<int, 2>{256, 256}, std::array<int, 2>{16384, 2}}) {
      for (TextureWrap wrap : {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror}) {
        const Texture tex = must_make(size[0], size[1], bound.filter, wrap, 9);
        const Sampler s = texture::make_sampler(tex);
        for (int i = 0; i < 3000; ++i) {
          const float u = 128.0f * (unit(rng) - 0.5f), v = 128.0f * (unit(rng) - 0.5f);
          const float scale = std::exp2(exponent(rng));  // derivatives: magnified up to 1024x, minified to 64
          const float dx = sign(rng) * scale / float(size[0]), dy = sign(rng) * scale / float(size[1]);
          const float lf = texture::lod_scalar(s, dx, 0, 0, dy);
          const double ld = texture::lod_reference(s, dx, 0, 0, dy);
          const std::uint32_t got = texture::sample_fixed_scalar(s, u, v, lf);
          const auto want = texture::sample_reference(s, u, v, ld);
          double d = 0;
          for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(double((got >> (8 * c)) & 0xffu) - 255.0 * want[c]));
          if (bound.filter == TextureFilter::nearest && d > 1e-9) {
            // The float coordinate can round across a texel border; the reference's double does not.
            const double x = double(u) * size[0], y = double(v) * size[1];
            ASSERT_TRUE(std::abs(x - std::round(x)) < 1e-2 || std::abs(y - std::round(y)) < 1e-2) << u << ", " << v;
            ++border;
            continue;
          }
          worst = std::max(worst, d), sum += d, ++count;
        }
      }
    }
    const double mean = sum / double(count);
    std::printf("fixed-point %s: largest %.3f, mean %.4f steps from the reference over %zu samples (%zu nearest on borders)\n",
                to_string(bound.filter), worst, mean, count, border);
    EXPECT_LE(worst, bound.max_steps) << to_string(bound.filter);
    EXPECT_LE(mean, bound.mean_steps) << to_string(bound.filter);
  }
}

TEST(TextureSampler, Log2AndLodAgainstExact) {
  double worst = 0;
  for (float x = 1e-30f; x < 1e30f; x *= 1.0007f) {
    worst = std::max(worst, std::abs(double(texture::log2_approx(x)) - std::log2(double(x))));
  }
  std::printf("log2_approx: largest error %.3g\n", worst);
  EXPECT_LT(worst, 2e-5);
  const Texture tex = must_make(256, 64, TextureFilter::trilinear, TextureWrap::repeat);
  const Sampler s = texture::make_sampler(tex);
  EXPECT_EQ(texture::lod_scalar(s, 0, 0, 0, 0), -1.0f);  // zero derivatives: magnification
  EXPECT_EQ(texture::lod_scalar(s, std::nanf(""), 0, 0, 0), -1.0f);
  EXPECT_GT(texture::lod_scalar(s, 1e30f, 0, 0, 0), 14.0f);  // rho^2 overflows: past the last level
  EXPECT_NEAR(texture::lod_scalar(s, 2.0f / 256, 0, 0, 0), 1.0f, 1e-5);
  EXPECT_NEAR(texture::lod_scalar(s, 0, 0, 0, 8.0f / 64), 3.0f, 1e-5);
}

// The scalar float sampler against the double reference: within a step of 8-bit output
// (bilinear, trilinear), and nearest picks the same texel except where the coordinate lies within
// float rounding of a texel border.
TEST(TextureSampler, ScalarAgainstReference) {
  for (TextureFilter filter : {TextureFilter::bilinear, TextureFilter::trilinear, TextureFilter::nearest}) {
    for (TextureWrap wrap : {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror})
    for (TextureEncoding encoding : {TextureEncoding::linear, TextureEncoding::srgb}) {
      for (const auto& size : {std::array<int, 2>{64, 32}, std::array<int, 2>{5, 3}, std::array<int, 2>{1, 1}}) {
        const Texture tex = must_make(size[0], size[1], filter, wrap, 3, encoding);
        const Sampler s = texture::make_sampler(tex);
        const Inputs in = sample_inputs(5, size[0], size[1]);
        double worst = 0;
        std::size_t near_border = 0;
        for (std::size_t i = 0; i < in.size(); ++i) {
          if (!std::isfinite(in.u[i]) || !std::isfinite(in.v[i]) || std::abs(in.u[i]) > 100 || std::abs(in.v[i]) > 100)
            continue;
          const float lf = texture::lod_scalar(s, in.dsdx[i], in.dtdx[i], in.dsdy[i], in.dtdy[i]);
          const double ld = texture::lod_reference(s, in.dsdx[i], in.dtdx[i], in.dsdy[i], in.dtdy[i]);
          if (filter == TextureFilter::trilinear && lf > -1.0f && lf < 100.0f) {
            ASSERT_NEAR(lf, ld, 1e-5);
          }
          const auto a = texture::sample_scalar(s, in.u[i], in.v[i], lf);
          const auto b = texture::sample_reference(s, in.u[i], in.v[i], ld);
          double d = 0;
          for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(double(a[c]) - b[c]) * 255.0);
          if (filter == TextureFilter::nearest && d > 1e-3) {
            // Must be a border: the exact position is within 1e-6 texels of a whole number.
            const double x = double(in.u[i]) * size[0], y = double(in.v[i]) * size[1];
            const bool border = std::abs(x - std::round(x)) < 1e-3 || std::abs(y - std::round(y)) < 1e-3;
            ASSERT_TRUE(border) << "nearest differs away from a border at " << in.u[i] << ", " << in.v[i];
            ++near_border;
            continue;
          }
          worst = std::max(worst, d);
        }
        std::printf("%s %s %s %dx%d: largest difference from the reference %.4f steps (%zu nearest samples on borders)\n",
                    to_string(filter), to_string(wrap), to_string(encoding), size[0], size[1], worst, near_border);
        EXPECT_LT(worst, 1.0);
      }
    }
  }
}

// GL's rules at exact coordinates: texel centres return the texel, wrap modes fold as GL_REPEAT,
// GL_CLAMP_TO_EDGE and GL_MIRRORED_REPEAT do, hostile coordinates give a texel, never NaN.
TEST(TextureSampler, WrapRulesAtTexelBorders) {
  const int w = 4;
  std::vector<std::uint8_t> px(4 * w);
  for (int i = 0; i < w; ++i) px[4 * i] = static_cast<std::uint8_t>(10 * (i + 1)), px[4 * i + 3] = 255;
  auto make = [&](TextureFilter f, TextureWrap wrap) {
    Result<Texture> t = make_texture("row", w, 1, px, {f, wrap});
    EXPECT_TRUE(t.ok());
    return std::move(*t);
  };
  auto red = [](const Texture& t, float u) {
    return std::lround(texture::sample_scalar(texture::make_sampler(t), u, 0.5f, 0.0f)[0] * 255.0f);
  };
  const Texture rn = make(TextureFilter::nearest, TextureWrap::repeat);
  const Texture cn = make(TextureFilter::nearest, TextureWrap::clamp);
  const Texture mn = make(TextureFilter::nearest, TextureWrap::mirror);
  EXPECT_EQ(red(rn, 0.0f), 10);
  EXPECT_EQ(red(rn, 0.25f), 20);  // the border between texels 0 and 1 belongs to texel 1
  EXPECT_EQ(red(rn, 1.0f), 10);   // repeat: s = 1 is s = 0
  EXPECT_EQ(red(rn, -0.25f), 40);
  EXPECT_EQ(red(cn, 1.0f), 40);
  EXPECT_EQ(red(cn, -5.0f), 10);
  EXPECT_EQ(red(mn, 1.0f), 40);   // mirror: [1, 2) runs backwards
  EXPECT_EQ(red(mn, 1.25f), 30);
  EXPECT_EQ(red(mn, -0.1f), 10);
  const Texture rb = make(TextureFilter::bilinear, TextureWrap::repeat);
  const Texture cb = make(TextureFilter::bilinear, TextureWrap::clamp);
  const Texture mb = make(TextureFilter::bilinear, TextureWrap::mirror);
  for (int i = 0; i < w; ++i) EXPECT_EQ(red(rb, (float(i) + 0.5f) / float(w)), 10 * (i + 1));  // centres
  EXPECT_EQ(red(rb, 0.0f), 25);  // halfway between the last and the first texel
  EXPECT_EQ(red(cb, 0.0f), 10);  // clamp: the edge texel
  EXPECT_EQ(red(mb, 0.0f), 10);  // mirror: texel 0 meets its mirror image
  EXPECT_EQ(red(mb, 1.0f), 40);
  for (float u : {1e7f, -1e7f, 1e30f, std::numeric_limits<float>::infinity(), std::nanf("")}) {
    for (const Texture* t : {&rb, &cb, &mb, &rn}) {
      const auto c = texture::sample_scalar(texture::make_sampler(*t), u, u, u);
      for (float v : c) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << u;
    }
  }
}

// The sRGB table is the transfer function (IEC 61966-2-1) computed in double and rounded to float,
// entry by entry; its ends and the linear segment's join are exact.
TEST(TextureEncoding, TableIsTheTransferFunction) {
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    const double linear = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    ASSERT_EQ(texture::kSrgbDecode255[i], static_cast<float>(255.0 * linear)) << i;
  }
  EXPECT_EQ(texture::kSrgbDecode255[0], 0.0f);
  EXPECT_EQ(texture::kSrgbDecode255[255], 255.0f);
}

// Decode, then filter (EXT_texture_sRGB): a bilinear sample halfway between sRGB 0 and 255 is
// linear 0.5, not the decoding of 127.5; the alpha channel is read as stored; mipmaps average in
// linear light, so a black and white checkerboard's 1x1 level is sRGB 188 (linear 0.5), not 128.
TEST(TextureEncoding, SrgbDecodesBeforeFilteringAndMipmapsInLinear) {
  const std::vector<std::uint8_t> two = {0, 0, 0, 0, 255, 255, 255, 128};  // 2x1: black, white
  TextureOptions o{TextureFilter::bilinear, TextureWrap::clamp};
  o.encoding = TextureEncoding::srgb;
  const Result<Texture> t = make_texture("t", 2, 1, two, o);
  ASSERT_TRUE(t.ok()) << t.status().message();
  const Sampler s = texture::make_sampler(*t);
  const auto mid = texture::sample_scalar(s, 0.5f, 0.5f, 0.0f);
  const auto ref = texture::sample_reference(s, 0.5, 0.5, 0.0);
  EXPECT_NEAR(mid[0], 0.5f, 1e-6f);
  EXPECT_NEAR(ref[0], 0.5, 1e-12);
  EXPECT_NEAR(mid[3], 64.0f / 255.0f, 1e-6f);  // alpha: (0 + 128) / 2, linear
  std::vector<std::uint8_t> checker(4 * 4 * 4);
  for (int i = 0; i < 16; ++i) {
    const std::uint8_t v = ((i % 4) + (i / 4)) % 2 ? 255 : 0;
    checker[4 * i] = checker[4 * i + 1] = checker[4 * i + 2] = v, checker[4 * i + 3] = 255;
  }
  TextureOptions tri{TextureFilter::trilinear, TextureWrap::repeat};
  tri.encoding = TextureEncoding::srgb;
  const Result<Texture> m = make_texture("m", 4, 4, checker, tri);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->texels.back() & 0xffu, 188u) << "the 1x1 level of an sRGB checkerboard";
  tri.encoding = TextureEncoding::linear;
  const Result<Texture> l = make_texture("l", 4, 4, checker, tri);
  EXPECT_EQ(l->texels.back() & 0xffu, 128u) << "the same stored linear";
}

// A PNG's colour tags decide an untold encoding: sRGB and iCCP chunks and gAMA 1/2.2 are sRGB,
// gAMA 1 linear, untagged linear; another gamma is refused with the file's name; a told encoding wins.
TEST(TextureEncoding, PngTagsDecideWhenNotTold) {
  const std::uint8_t pixel[4] = {200, 100, 50, 255};
  auto untagged = [&] {  // stb_image_write writes no colour chunk
    std::vector<std::uint8_t> out;
    stbi_write_png_to_func([](void* c, void* d, int n) {
      auto* o = static_cast<std::vector<std::uint8_t>*>(c);
      o->insert(o->end(), static_cast<std::uint8_t*>(d), static_cast<std::uint8_t*>(d) + n);
    }, &out, 1, 1, 4, pixel, 4);
    return out;
  };
  auto png_with = [&](const char* type, const std::vector<std::uint8_t>& data) {
    std::vector<std::uint8_t> png = untagged();
    // The chunk goes after IHDR (8 bytes of signature + 25 of IHDR).
    std::vector<std::uint8_t> chunk = {0, 0, 0, static_cast<std::uint8_t>(data.size())};
    for (int k = 0; k < 4; ++k) chunk.push_back(static_cast<std::uint8_t>(type[k]));
    chunk.insert(chunk.end(), data.begin(), data.end());
    const auto crc = static_cast<std::uint32_t>(::crc32(0, chunk.data() + 4, static_cast<uInt>(chunk.size() - 4)));
    for (int k = 3; k >= 0; --k) chunk.push_back(static_cast<std::uint8_t>(crc >> (8 * k)));
    png.insert(png.begin() + 33, chunk.begin(), chunk.end());
    return png;
  };
  auto encoding_of = [](const std::vector<std::uint8_t>& bytes, std::optional<TextureEncoding> told = std::nullopt) {
    TextureOptions o;
    o.encoding = told;
    return decode_texture(bytes, "tagged.png", "t", o);
  };
  EXPECT_EQ(encoding_of(untagged())->encoding, TextureEncoding::linear);
  EXPECT_EQ(encoding_of(png_with("sRGB", {0}))->encoding, TextureEncoding::srgb);
  EXPECT_EQ(encoding_of(png_with("gAMA", {0, 0, 0xb1, 0x8f}))->encoding, TextureEncoding::srgb);  // 45455
  EXPECT_EQ(encoding_of(png_with("gAMA", {0, 0x01, 0x86, 0xa0}))->encoding, TextureEncoding::linear);  // 100000
  const auto odd = encoding_of(png_with("gAMA", {0, 0, 0x75, 0x30}));  // 30000: gamma 0.3
  ASSERT_FALSE(odd.ok());
  EXPECT_NE(odd.status().message().find("tagged.png"), std::string::npos) << odd.status().message();
  EXPECT_NE(odd.status().message().find("gamma 0.3"), std::string::npos) << odd.status().message();
  EXPECT_EQ(encoding_of(png_with("gAMA", {0, 0, 0x75, 0x30}), TextureEncoding::linear)->encoding, TextureEncoding::linear);
  EXPECT_EQ(encoding_of(png_with("sRGB", {0}), TextureEncoding::linear)->encoding, TextureEncoding::linear);
}

}  // namespace
}  // namespace facet
