// Textures: decoding (PNG through libpng, JPEG through libjpeg-turbo, TGA and BMP through
// stb_image from Debian's libstb, each walked first), the mipmap chain and validation.
#include "facet/texture.hpp"

#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>

#include "common/format.hpp"
#include "common/try.hpp"
#include "io/file_access.hpp"
#include "texture/jpeg_decode.hpp"
#include "texture/png_decode.hpp"
#include "texture/sampler.hpp"
#include "texture/srgb_table.hpp"
#include "texture/texture_file.hpp"

namespace facet {
namespace {

Status invalid(const std::string& field, const std::string& what) {
  return {ErrorCode::invalid_argument, field, field + ": " + what};
}

int level_count(int width, int height) {
  int levels = 1;
  for (int w = width, h = height; w > 1 || h > 1; w = std::max(1, w / 2), h = std::max(1, h / 2)) ++levels;
  return levels;
}

// Bytes the texels of a texture need (all levels when trilinear).
std::uint64_t texel_bytes(int width, int height, TextureFilter filter) {
  std::uint64_t texels = 0;
  int w = width, h = height;
  for (int k = 0, n = filter == TextureFilter::trilinear ? level_count(width, height) : 1; k < n; ++k) {
    texels += static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
    w = std::max(1, w / 2), h = std::max(1, h / 2);
  }
  return 4 * texels;
}

Status check_budget(std::uint64_t bytes, const TextureOptions& options, const std::string& source) {
  if (options.memory_budget_bytes != 0 && bytes > options.memory_budget_bytes) {
    return {ErrorCode::out_of_memory, "memory_budget_bytes",
            source + ": the texture needs " + format_bytes(bytes) + " to decode and keep, more than the memory budget (" +
                format_bytes(options.memory_budget_bytes) + ")"};
  }
  return {};
}

// The weights with which the texels of a row of `from` texels fall into texel `i` of a row of
// `to` texels: texel i covers [i * from / to, (i + 1) * from / to) of the larger row.
struct Span {
  int first = 0, last = 0;        // texels of the larger row, inclusive
  float w_first = 1, w_last = 1;  // coverage of the first and last one (inner ones: 1)
  float inv_size = 1;             // 1 / (from / to)
};
Span box_span(int i, int from, int to) {
  Span s;
  const double scale = double(from) / double(to);
  const double a = i * scale, b = (i + 1) * scale;
  s.first = static_cast<int>(std::floor(a));
  s.last = std::min(from - 1, static_cast<int>(std::ceil(b)) - 1);
  s.w_first = static_cast<float>(std::min(b, s.first + 1.0) - a);
  s.w_last = s.last == s.first ? s.w_first : static_cast<float>(b - s.last);
  s.inv_size = static_cast<float>(1.0 / scale);
  return s;
}

float span_weight(const Span& s, int k) {
  if (k == s.first) return s.w_first;
  if (k == s.last) return s.w_last;
  return 1.0f;
}

// srgb: the colour channels are averaged decoded (texture::kSrgbDecode255) and encoded back.
void build_level(const std::uint32_t* src, int sw, int sh, std::uint32_t* dst, int dw, int dh, bool srgb) {
  std::vector<Span> xs(static_cast<std::size_t>(dw));
  for (int i = 0; i < dw; ++i) xs[static_cast<std::size_t>(i)] = box_span(i, sw, dw);
  for (int j = 0; j < dh; ++j) {
    const Span ys = box_span(j, sh, dh);
    for (int i = 0; i < dw; ++i) {
      const Span& x = xs[static_cast<std::size_t>(i)];
      float sum[4] = {0, 0, 0, 0};
      for (int y = ys.first; y <= ys.last; ++y) {
        const float wy = span_weight(ys, y);
        for (int xx = x.first; xx <= x.last; ++xx) {
          const float w = wy * span_weight(x, xx);
          const std::uint32_t t = src[static_cast<std::size_t>(y) * static_cast<std::size_t>(sw) + static_cast<std::size_t>(xx)];
          for (int c = 0; c < 4; ++c) {
            const std::uint32_t v = (t >> (8 * c)) & 0xffu;
            sum[c] += w * (srgb && c < 3 ? texture::kSrgbDecode255[v] : static_cast<float>(v));
          }
        }
      }
      std::uint32_t out = 0;
      for (int c = 0; c < 4; ++c) {
        const float v = sum[c] * x.inv_size * ys.inv_size;
        const auto q = srgb && c < 3 ? texture::encode_srgb8(double(v) / 255.0)
                                     : static_cast<std::uint32_t>(std::clamp(v + 0.5f, 0.0f, 255.0f));
        out |= q << (8 * c);
      }
      dst[static_cast<std::size_t>(j) * static_cast<std::size_t>(dw) + static_cast<std::size_t>(i)] = out;
    }
  }
}

bool is_png(std::span<const std::uint8_t> b) {
  static constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return b.size() >= 8 && std::memcmp(b.data(), kSignature, 8) == 0;
}
bool is_jpeg(std::span<const std::uint8_t> b) { return b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff; }

enum class ImageKind { unknown, tga, bmp };

// TGA has no signature: a header whose colour-map and image types are TGA's, with stb_image
// agreeing that it can read it.
ImageKind image_kind(std::span<const std::uint8_t> b) {
  if (b.size() >= 26 && b[0] == 'B' && b[1] == 'M') return ImageKind::bmp;
  const bool tga_header = b.size() >= 18 && b[1] <= 1 &&
                          (b[2] == 1 || b[2] == 2 || b[2] == 3 || b[2] == 9 || b[2] == 10 || b[2] == 11);
  return tga_header ? ImageKind::tga : ImageKind::unknown;
}

std::uint32_t le32(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint32_t{b[at]} | std::uint32_t{b[at + 1]} << 8 | std::uint32_t{b[at + 2]} << 16 | std::uint32_t{b[at + 3]} << 24;
}

// stb_image reads a palette BMP's colours into a table it does not clear, so an index past the
// palette would read whatever was on the stack: every index is checked first. It also reads the
// rows of a cut-short BMP as zeros: every uncompressed BMP's rows must be in the file.
template <class Fail>
Status check_bmp(std::span<const std::uint8_t> b, const Fail& fail) {
  const std::uint32_t offset = le32(b, 10), header = le32(b, 14);
  if (header != 12 && header < 40) return {};  // stb refuses it
  const bool os2 = header == 12;
  if (b.size() < (os2 ? 26u : 50u)) return fail(ErrorCode::parse_error, "the BMP header is cut short");
  const std::int64_t width = os2 ? (b[18] | b[19] << 8) : static_cast<std::int32_t>(le32(b, 18));
  std::int64_t height = os2 ? (b[20] | b[21] << 8) : static_cast<std::int32_t>(le32(b, 22));
  const int bpp = os2 ? (b[24] | b[25] << 8) : (b[28] | b[29] << 8);
  if (height < 0) height = -height;  // rows stored top-down
  if (bpp == 16 || bpp == 24 || bpp == 32) {
    const std::uint32_t compression = os2 ? 0 : le32(b, 30);
    if (compression != 0 && compression != 3) return {};  // stb refuses it
    if (width < 1 || width > kMaxTextureDimension || height < 1 || height > kMaxTextureDimension) return {};
    const std::uint64_t row = ((std::uint64_t(width) * std::uint64_t(bpp) + 31) / 32) * 4;
    if (offset > b.size() || row * std::uint64_t(height) > b.size() - offset) return fail(ErrorCode::parse_error, "the BMP's rows are cut short");
    return {};
  }
  if (bpp != 1 && bpp != 4 && bpp != 8) return {};  // not a palette BMP (or, as 0 and 2 bits, one stb refuses)
  const std::int64_t colours = os2 ? (std::int64_t(offset) - 14 - 24) / 3 : (std::int64_t(offset) - 14 - header) / 4;
  // stb computes the same count and refuses 0 and more than 256, but takes a negative one (a pixel
  // offset inside the header) as a palette of no colours it then reads (found by fuzz_texture).
  if (colours < 1) return fail(ErrorCode::parse_error, "the BMP has no palette: its pixel offset lies inside its header");
  if (colours > 256) return {};  // stb refuses it
  if (width < 1 || width > kMaxTextureDimension || height < 1 || height > kMaxTextureDimension) return {};
  const std::uint64_t row = ((std::uint64_t(width) * std::uint64_t(bpp) + 31) / 32) * 4;
  if (offset > b.size() || row * std::uint64_t(height) > b.size() - offset) {
    return fail(ErrorCode::parse_error, "the BMP's pixels are cut short");
  }
  for (std::int64_t y = 0; y < height; ++y) {
    const std::uint8_t* r = b.data() + offset + std::uint64_t(y) * row;
    for (std::int64_t x = 0; x < width; ++x) {
      const std::uint64_t bit = std::uint64_t(x) * std::uint64_t(bpp);
      const int v = (r[bit / 8] >> (8 - bpp - int(bit % 8))) & ((1 << bpp) - 1);
      if (v >= colours) {
        return fail(ErrorCode::parse_error, "cannot decode the BMP: a pixel uses palette entry " + std::to_string(v) + " of " +
                                                std::to_string(colours));
      }
    }
  }
  return {};
}

// stb_image reads an uncompressed TGA's rows without checking that they are there (the missing
// rows keep whatever the heap held: found by fuzz_texture), reads past the end of an RLE one as
// zeros, takes a colour-map index past the map as entry 0, and skips "first entry index" bytes
// where the format means an index offset. Every pixel is walked first, so that each of these is
// refused instead of read wrongly.
template <class Fail>
Status check_tga(std::span<const std::uint8_t> b, const Fail& fail) {
  const bool indexed = b[1] == 1;
  const bool rle = b[2] >= 8;
  const std::uint32_t first_entry = b[3] | b[4] << 8, map_length = b[5] | b[6] << 8, map_bits = b[7];
  const std::uint64_t width = b[12] | b[13] << 8, height = b[14] | b[15] << 8, bits = b[16];
  if (indexed && first_entry != 0) {
    return fail(ErrorCode::unsupported, "a TGA colour map whose first entry index is not 0 is not supported");
  }
  if (indexed && map_length == 0) return fail(ErrorCode::parse_error, "the TGA's colour map is empty");
  const std::uint64_t map_bytes = indexed ? std::uint64_t(map_length) * ((map_bits + 7) / 8) : 0;
  const std::uint64_t pixel_bytes = (bits + 7) / 8;
  if (pixel_bytes == 0 || pixel_bytes > 4) return {};  // stb refuses it
  std::uint64_t at = 18 + std::uint64_t(b[0]) + map_bytes;
  if (at > b.size()) return fail(ErrorCode::parse_error, "the TGA's colour map is cut short");
  auto pixel = [&](std::uint64_t count) -> Status {
    if (count * pixel_bytes > b.size() - at) return fail(ErrorCode::parse_error, "the TGA's pixels are cut short");
    for (std::uint64_t k = 0; indexed && k < count; ++k) {
      const std::uint32_t index = pixel_bytes == 1 ? b[at + k] : (b[at + 2 * k] | b[at + 2 * k + 1] << 8);
      if (index >= map_length) {
        return fail(ErrorCode::parse_error, "cannot decode the TGA: a pixel uses colour-map entry " + std::to_string(index) +
                                                " of " + std::to_string(map_length));
      }
    }
    at += count * pixel_bytes;
    return {};
  };
  const std::uint64_t pixels = width * height;
  if (!rle) return pixel(pixels);
  for (std::uint64_t done = 0; done < pixels;) {
    if (at >= b.size()) return fail(ErrorCode::parse_error, "the TGA's pixels are cut short");
    const std::uint8_t command = b[at++];
    const std::uint64_t run = 1 + (command & 127);
    if (run > pixels - done) return fail(ErrorCode::parse_error, "a TGA run-length packet runs past the end of the image");
    FACET_TRY(pixel(command & 128 ? 1 : std::min(run, pixels - done)));
    done += run;
  }
  return {};
}

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

std::uint32_t texture::encode_srgb8(double linear) noexcept {
  const double l = linear > 0.0 ? (linear < 1.0 ? linear : 1.0) : 0.0;  // NaN -> 0
  const double c = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint32_t>(std::floor(255.0 * c + 0.5));
}

const char* to_string(TextureFilter filter) noexcept {
  switch (filter) {
    case TextureFilter::nearest: return "nearest";
    case TextureFilter::bilinear: return "bilinear";
    case TextureFilter::trilinear: return "trilinear";
  }
  return "?";
}

const char* to_string(TextureEncoding encoding) noexcept {
  switch (encoding) {
    case TextureEncoding::linear: return "linear";
    case TextureEncoding::srgb: return "srgb";
  }
  return "?";
}

const char* to_string(TextureWrap wrap) noexcept {
  switch (wrap) {
    case TextureWrap::repeat: return "repeat";
    case TextureWrap::clamp: return "clamp";
    case TextureWrap::mirror: return "mirror";
  }
  return "?";
}

Result<Texture> make_texture(std::string name, int width, int height, std::span<const std::uint8_t> rgba8,
                             const TextureOptions& options) {
  if (width < 1 || height < 1 || width > kMaxTextureDimension || height > kMaxTextureDimension) {
    return invalid("width", "a texture is 1 to " + std::to_string(kMaxTextureDimension) + " texels per side, found " +
                                std::to_string(width) + " x " + std::to_string(height));
  }
  const std::uint64_t count = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  if (rgba8.size() != 4 * count) {
    return invalid("rgba8", "expected " + std::to_string(4 * count) + " bytes (" + std::to_string(width) + " x " +
                                std::to_string(height) + " RGBA8), found " + std::to_string(rgba8.size()));
  }
  const int filter = static_cast<int>(options.filter), wrap = static_cast<int>(options.wrap);
  if (filter < 0 || filter > 2) return invalid("filter", "unknown texture filter " + std::to_string(filter));
  if (wrap < 0 || wrap > 2) return invalid("wrap", "unknown texture wrap mode " + std::to_string(wrap));
  const TextureEncoding encoding = options.encoding.value_or(TextureEncoding::linear);
  if (encoding != TextureEncoding::linear && encoding != TextureEncoding::srgb) {
    return invalid("encoding", "unknown texture encoding " + std::to_string(static_cast<int>(encoding)));
  }
  const std::uint64_t bytes = texel_bytes(width, height, options.filter);
  FACET_TRY(check_budget(bytes, options, "texture '" + name + "'"));
  try {
    Texture t;
    t.filter = options.filter;
    t.wrap = options.wrap;
    t.encoding = encoding;
    const int levels = options.filter == TextureFilter::trilinear ? level_count(width, height) : 1;
    t.texels.resize(static_cast<std::size_t>(bytes / 4));
    std::size_t offset = 0;
    for (int k = 0, w = width, h = height; k < levels; ++k, w = std::max(1, w / 2), h = std::max(1, h / 2)) {
      t.levels.push_back({w, h, offset});
      offset += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    }
    // Level 0, bottom row first.
    for (int j = 0; j < height; ++j) {
      const std::uint8_t* row = rgba8.data() + static_cast<std::size_t>(height - 1 - j) * 4 * static_cast<std::size_t>(width);
      std::uint32_t* out = t.texels.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(width);
      for (int i = 0; i < width; ++i) {
        const std::uint8_t* p = row + 4 * static_cast<std::size_t>(i);
        out[i] = std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
      }
    }
    for (int k = 1; k < levels; ++k) {
      const TextureLevel& a = t.levels[static_cast<std::size_t>(k - 1)];
      const TextureLevel& b = t.levels[static_cast<std::size_t>(k)];
      build_level(t.texels.data() + a.offset, a.width, a.height, t.texels.data() + b.offset, b.width, b.height,
                  t.encoding == TextureEncoding::srgb);
    }
    t.name = std::move(name);
    return t;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", "texture '" + name + "': out of memory"};
  }
}

Result<Texture> decode_texture(std::span<const std::uint8_t> bytes, const std::string& source_name, std::string name,
                               const TextureOptions& options) {
  auto fail = [&](ErrorCode code, const std::string& what) { return Status{code, "file", source_name + ": " + what}; };
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    return fail(ErrorCode::unsupported, "the file is larger than 2 GiB, more than the decoder takes");
  }
  // Sizes are checked, and the budget asked, before any pixel memory is taken.
  auto admit = [&](int w, int h, std::uint64_t decode_bytes) -> Status {
    if (w < 1 || h < 1 || w > kMaxTextureDimension || h > kMaxTextureDimension) {
      return fail(ErrorCode::unsupported, std::to_string(w) + " x " + std::to_string(h) + " texels: a texture is 1 to " +
                                              std::to_string(kMaxTextureDimension) + " texels per side");
    }
    const std::uint64_t pixels = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
    return check_budget(decode_bytes + 4 * pixels + texel_bytes(w, h, options.filter), options, source_name);
  };
  if (is_png(bytes)) {
    Result<PngPixels> png = decode_png(bytes, source_name, admit);
    if (!png) return png.status();
    TextureOptions tagged = options;
    if (!tagged.encoding) {  // the file's own tag (TextureOptions::encoding)
      if (png->srgb_chunk || png->iccp_chunk) {
        tagged.encoding = TextureEncoding::srgb;
      } else if (png->gamma > 0.0) {
        if (std::abs(png->gamma * 2.2 - 1.0) <= 0.02) {
          tagged.encoding = TextureEncoding::srgb;
        } else if (png->gamma == 1.0) {
          tagged.encoding = TextureEncoding::linear;
        } else {
          return fail(ErrorCode::unsupported, "its gAMA chunk gives gamma " + format_number(png->gamma) +
                                                  ", neither sRGB's 1/2.2 nor linear's 1: facet cannot decode it "
                                                  "exactly (give the texture an encoding to read it as sRGB or linear)");
        }
      }
    }
    Result<Texture> t = make_texture(std::move(name), png->width, png->height, png->rgba, tagged);
    if (!t) return fail(t.status().code(), t.status().message());
    return t;
  }
  if (is_jpeg(bytes)) {
    Result<PngPixels> jpeg = decode_jpeg(bytes, source_name, admit, options.memory_budget_bytes);
    if (!jpeg) return jpeg.status();
    Result<Texture> t = make_texture(std::move(name), jpeg->width, jpeg->height, jpeg->rgba, options);
    if (!t) return fail(t.status().code(), t.status().message());
    return t;
  }
  const ImageKind kind = image_kind(bytes);
  if (kind == ImageKind::unknown) return fail(ErrorCode::unsupported, "not a PNG, JPEG, TGA or BMP file (the image formats facet reads)");
  const char* format = kind == ImageKind::tga ? "TGA" : "BMP";
  const auto* data = bytes.data();
  const int size = static_cast<int>(bytes.size());
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(data, size, &w, &h, &channels)) {
    return fail(ErrorCode::parse_error, std::string("cannot read the ") + format + " header");
  }
  if (kind == ImageKind::bmp && h < 0 && h > -kMaxTextureDimension - 1) h = -h;  // a top-down BMP
  if (kind == ImageKind::bmp) FACET_TRY(check_bmp(bytes, fail));
  if (kind == ImageKind::tga) FACET_TRY(check_tga(bytes, fail));
  // The decoder's output and its working copy, then the texels.
  FACET_TRY(admit(w, h, 2 * static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) * 4));
  const std::uint64_t pixels = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
  std::vector<std::uint8_t> rgba;
  try {
    rgba.resize(4 * pixels);
  } catch (const std::bad_alloc&) {
    return fail(ErrorCode::out_of_memory, "out of memory");
  }
  int dw = 0, dh = 0, dc = 0;
  std::unique_ptr<stbi_uc, StbFree> p(stbi_load_from_memory(data, size, &dw, &dh, &dc, 4));
  if (!p) {
    const char* reason = stbi_failure_reason();
    const std::string why = reason && *reason ? reason : "the decoder gave no reason";
    return fail(why == "outofmem" ? ErrorCode::out_of_memory : ErrorCode::parse_error,
                std::string("cannot decode the ") + format + ": " + quote(why, 60));
  }
  if (dw != w || dh != h) return fail(ErrorCode::parse_error, "the image's size changed while decoding");
  std::memcpy(rgba.data(), p.get(), rgba.size());
  Result<Texture> t = make_texture(std::move(name), w, h, rgba, options);
  if (!t) return fail(t.status().code(), t.status().message());
  return t;
}

Result<Texture> load_texture(const std::string& path, std::string name, const TextureOptions& options) {
  Result<std::string> bytes =
      io::read_file(path, "texture file", options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes);
  if (!bytes) return bytes.status();
  return decode_texture({reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size()}, quote(path, 200),
                        std::move(name), options);
}

Result<Texture> read_texture(const io::AssetFolder& folder, std::string_view file, const std::string& where,
                             std::string name, const TextureOptions& options) {
  const std::uint64_t limit = options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes;
  Result<std::string> bytes = folder.read(file, where, "texture file", limit);
  if (!bytes) return bytes.status();
  return decode_texture({reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size()}, where + " " + quote(file, 80),
                        std::move(name), options);
}

Status validate_texture(const Texture& t, const std::string& field) {
  const int filter = static_cast<int>(t.filter), wrap = static_cast<int>(t.wrap);
  if (filter < 0 || filter > 2) return invalid(field + ".filter", "unknown texture filter " + std::to_string(filter));
  if (wrap < 0 || wrap > 2) return invalid(field + ".wrap", "unknown texture wrap mode " + std::to_string(wrap));
  if (t.encoding != TextureEncoding::linear && t.encoding != TextureEncoding::srgb) {
    return invalid(field + ".encoding", "unknown texture encoding " + std::to_string(static_cast<int>(t.encoding)));
  }
  if (t.levels.empty()) return invalid(field + ".levels", "a texture needs at least level 0");
  const int w = t.levels[0].width, h = t.levels[0].height;
  if (w < 1 || h < 1 || w > kMaxTextureDimension || h > kMaxTextureDimension) {
    return invalid(field + ".levels[0]", "a texture is 1 to " + std::to_string(kMaxTextureDimension) +
                                             " texels per side, found " + std::to_string(w) + " x " + std::to_string(h));
  }
  const std::size_t expected_levels = t.filter == TextureFilter::trilinear ? static_cast<std::size_t>(level_count(w, h)) : 1;
  if (t.levels.size() != expected_levels) {
    return invalid(field + ".levels", std::string("a ") + to_string(t.filter) + " " + std::to_string(w) + " x " +
                                          std::to_string(h) + " texture has " + std::to_string(expected_levels) +
                                          " levels, found " + std::to_string(t.levels.size()));
  }
  std::size_t offset = 0;
  for (std::size_t k = 0; k < t.levels.size(); ++k) {
    const TextureLevel& l = t.levels[k];
    const int ew = std::max(1, w >> k), eh = std::max(1, h >> k);
    if (l.width != ew || l.height != eh || l.offset != offset) {
      return invalid(field + ".levels[" + std::to_string(k) + "]",
                     "expected " + std::to_string(ew) + " x " + std::to_string(eh) + " at texel " + std::to_string(offset));
    }
    offset += static_cast<std::size_t>(ew) * static_cast<std::size_t>(eh);
  }
  if (t.texels.size() != offset) {
    return invalid(field + ".texels", "expected " + std::to_string(offset) + " texels, found " + std::to_string(t.texels.size()));
  }
  return {};
}

}  // namespace facet
