// Environment pictures (facet/environment_light.hpp: load_environment_image): Radiance .hdr
// (RGBE, flat or run-length encoded; read here, every count checked against the scanline, so that
// a hostile file can neither overrun a row nor loop), OpenEXR through the library (the header's
// size checked before any pixel is allocated), and 8-bit PNG or JPEG through facet's texture
// decoders as sRGB. Told apart by their signatures; errors name the file and what is wrong.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfRgbaFile.h>

#include "common/format.hpp"
#include "common/try.hpp"
#include "facet/environment_light.hpp"
#include "facet/texture.hpp"
#include "io/assets.hpp"
#include "texture/srgb_table.hpp"

namespace facet {
namespace {

Status bad(const std::string& source, const std::string& what) {
  return {ErrorCode::parse_error, "environment_image", quote(source, 200) + ": " + what};
}

// Width and height of an equirectangular picture, and the memory its floats take, checked before
// anything of that size is allocated.
Status check_size(const std::string& source, std::uint64_t w, std::uint64_t h, std::uint64_t budget) {
  if (w == 0 || h == 0 || w > std::uint64_t(kMaxEnvironmentSide) || h > std::uint64_t(kMaxEnvironmentSide) || w != 2 * h) {
    return bad(source, "an environment picture is equirectangular: twice as wide as high, at most " +
                           std::to_string(kMaxEnvironmentSide) + " texels a side; this one is " + std::to_string(w) + "x" +
                           std::to_string(h));
  }
  const std::uint64_t bytes = w * h * 3 * sizeof(float);
  if (budget != 0 && bytes > budget) {
    return {ErrorCode::out_of_memory, "environment_image",
            quote(source, 200) + ": its " + std::to_string(w) + "x" + std::to_string(h) + " floats need " +
                std::to_string(bytes >> 20) + " MiB, beyond the memory budget of " + std::to_string(budget >> 20) + " MiB"};
  }
  return {};
}

// Radiance RGBE: (m + 0.5) 2^(e - 136) per channel, 0 for e = 0 (Radiance's colr_color).
void rgbe_to_float(const std::uint8_t* p, float* out) {
  if (p[3] == 0) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  const float f = std::ldexp(1.0f, int(p[3]) - 136);
  for (int c = 0; c < 3; ++c) out[c] = (float(p[c]) + 0.5f) * f;
}

Result<EnvironmentLight> decode_hdr(std::span<const std::uint8_t> bytes, const std::string& source, std::uint64_t budget) {
  std::size_t at = 0;
  auto line = [&](std::string& out) {
    out.clear();
    while (at < bytes.size() && bytes[at] != '\n') {
      if (out.size() > 4096) return false;
      out.push_back(char(bytes[at++]));
    }
    if (at >= bytes.size()) return false;
    ++at;
    return true;
  };
  std::string text;
  if (!line(text) || text.rfind("#?", 0) != 0) return bad(source, "not a Radiance picture (no \"#?\" first line)");
  double exposure = 1.0;
  bool format_ok = true;
  for (int lines = 0;; ++lines) {
    if (lines > 10000 || !line(text)) return bad(source, "its header never ends (no empty line before the resolution)");
    if (text.empty()) break;
    if (text.rfind("FORMAT=", 0) == 0) format_ok = text == "FORMAT=32-bit_rle_rgbe";
    if (text.rfind("EXPOSURE=", 0) == 0) {
      char* end = nullptr;
      const double e = std::strtod(text.c_str() + 9, &end);
      if (!(e > 0.0 && e < 1e30)) return bad(source, "its EXPOSURE is not a positive number");
      exposure *= e;
    }
    if (text.rfind("COLORCORR=", 0) == 0) return bad(source, "COLORCORR is not supported");
  }
  if (!format_ok) return bad(source, "only FORMAT=32-bit_rle_rgbe is supported (not XYZE)");
  if (!line(text)) return bad(source, "no resolution line");
  char ys = 0, xs = 0, ya = 0, xa = 0;
  long long h = 0, w = 0;
  int used = 0;
  if (std::sscanf(text.c_str(), "%c%c %lld %c%c %lld%n", &ys, &ya, &h, &xs, &xa, &w, &used) != 6 || ya != 'Y' || xa != 'X' ||
      xs != '+' || (ys != '-' && ys != '+') || std::size_t(used) != text.size() || h <= 0 || w <= 0) {
    return bad(source, "the resolution line is not \"-Y H +X W\" (or \"+Y H +X W\"): " + quote(text, 40));
  }
  FACET_TRY(check_size(source, std::uint64_t(w), std::uint64_t(h), budget));
  EnvironmentLight e;
  e.source = EnvironmentSource::image;
  e.width = int(w), e.height = int(h);
  e.rgb.resize(std::size_t(w) * std::size_t(h) * 3);
  std::vector<std::uint8_t> row(std::size_t(w) * 4);
  const float scale = float(1.0 / exposure);
  for (long long y = 0; y < h; ++y) {
    const std::string where = "scanline " + std::to_string(y) + " (byte " + std::to_string(at) + ")";
    if (at + 4 > bytes.size()) return bad(source, where + ": the file ends early");
    const std::uint8_t* p = bytes.data() + at;
    if (w >= 8 && w < 32768 && p[0] == 2 && p[1] == 2 && (p[2] & 0x80) == 0) {  // run-length encoded, channel by channel
      if ((long long)(p[2] << 8 | p[3]) != w) return bad(source, where + ": its length is not the picture's width");
      at += 4;
      for (int c = 0; c < 4; ++c) {
        for (long long x = 0; x < w;) {
          if (at >= bytes.size()) return bad(source, where + ": the file ends early");
          int count = bytes[at++];
          if (count > 128) {
            count -= 128;
            if (at >= bytes.size()) return bad(source, where + ": the file ends early");
            if (x + count > w) return bad(source, where + ": a run passes the end of the scanline");
            const std::uint8_t v = bytes[at++];
            for (int k = 0; k < count; ++k) row[std::size_t(x++) * 4 + std::size_t(c)] = v;
          } else {
            if (count == 0 || x + count > w) return bad(source, where + ": a literal run is empty or passes the end of the scanline");
            if (at + std::size_t(count) > bytes.size()) return bad(source, where + ": the file ends early");
            for (int k = 0; k < count; ++k) row[std::size_t(x++) * 4 + std::size_t(c)] = bytes[at++];
          }
        }
      }
    } else {  // flat RGBE (old-style runs, r = g = b = 1, are not supported)
      if (at + std::size_t(w) * 4 > bytes.size()) return bad(source, where + ": the file ends early");
      std::memcpy(row.data(), bytes.data() + at, std::size_t(w) * 4);
      for (long long x = 0; x < w; ++x) {
        const std::uint8_t* q = row.data() + std::size_t(x) * 4;
        if (q[0] == 1 && q[1] == 1 && q[2] == 1) return bad(source, where + ": old-style run-length encoding is not supported");
      }
      at += std::size_t(w) * 4;
    }
    const long long to = ys == '-' ? y : h - 1 - y;  // +Y: the bottom row first
    for (long long x = 0; x < w; ++x) {
      float* o = e.rgb.data() + 3 * (std::size_t(to) * std::size_t(w) + std::size_t(x));
      rgbe_to_float(row.data() + std::size_t(x) * 4, o);
      for (int c = 0; c < 3; ++c) o[c] *= scale;
    }
  }
  return e;
}

// OpenEXR's input stream over bytes in memory.
class MemoryStream final : public Imf::IStream {
 public:
  MemoryStream(std::span<const std::uint8_t> bytes, const std::string& name) : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || at_ + std::uint64_t(n) > bytes_.size()) throw std::runtime_error("the file ends early");
    std::memcpy(c, bytes_.data() + at_, std::size_t(n));
    at_ += std::uint64_t(n);
    return at_ < bytes_.size();
  }
  std::uint64_t tellg() override { return at_; }
  void seekg(std::uint64_t pos) override {
    if (pos > bytes_.size()) throw std::runtime_error("a seek past the end of the file");
    at_ = pos;
  }

 private:
  std::span<const std::uint8_t> bytes_;
  std::uint64_t at_ = 0;
};

Result<EnvironmentLight> decode_exr(std::span<const std::uint8_t> bytes, const std::string& source, std::uint64_t budget) {
  try {
    MemoryStream stream(bytes, "environment picture");
    Imf::RgbaInputFile file(stream, 0);
    const Imath::Box2i dw = file.dataWindow();
    const std::int64_t w = std::int64_t(dw.max.x) - dw.min.x + 1, h = std::int64_t(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0) return bad(source, "its data window is empty");
    FACET_TRY(check_size(source, std::uint64_t(w), std::uint64_t(h), budget));
    std::vector<Imf::Rgba> pixels(std::size_t(w) * std::size_t(h));
    file.setFrameBuffer(pixels.data() - std::ptrdiff_t(dw.min.x) - std::ptrdiff_t(dw.min.y) * std::ptrdiff_t(w), 1, std::size_t(w));
    file.readPixels(dw.min.y, dw.max.y);
    EnvironmentLight e;
    e.source = EnvironmentSource::image;
    e.width = int(w), e.height = int(h);
    e.rgb.resize(std::size_t(w) * std::size_t(h) * 3);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      const float v[3] = {float(pixels[i].r), float(pixels[i].g), float(pixels[i].b)};
      for (int c = 0; c < 3; ++c) {
        if (!(v[c] >= 0.0f && std::isfinite(v[c]))) {
          return bad(source, "texel " + std::to_string(i % std::size_t(w)) + ", " + std::to_string(i / std::size_t(w)) +
                                 " holds a negative, infinite or NaN value (" + format_number(v[c]) + ")");
        }
        e.rgb[3 * i + std::size_t(c)] = v[c];
      }
    }
    return e;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "environment_image", quote(source, 200) + ": out of memory reading it"};
  } catch (const std::exception& ex) {
    return bad(source, "not a readable OpenEXR picture (" + quote(ex.what(), 120) + ")");
  }
}

Result<EnvironmentLight> decode_8bit(std::span<const std::uint8_t> bytes, const std::string& source, std::uint64_t budget) {
  TextureOptions o;
  o.encoding = TextureEncoding::srgb;
  o.filter = TextureFilter::bilinear;  // level 0 only
  if (budget != 0) o.memory_budget_bytes = budget;
  Result<Texture> t = decode_texture(bytes, source, "environment", o);
  if (!t) return t.status();
  FACET_TRY(check_size(source, std::uint64_t(t->width()), std::uint64_t(t->height()), budget));
  EnvironmentLight e;
  e.source = EnvironmentSource::image;
  e.width = t->width(), e.height = t->height();
  e.rgb.resize(std::size_t(e.width) * std::size_t(e.height) * 3);
  for (int y = 0; y < e.height; ++y) {
    for (int x = 0; x < e.width; ++x) {
      // Textures hold their rows bottom first; the picture is top row first.
      const std::uint32_t texel = t->texels[std::size_t(e.height - 1 - y) * std::size_t(e.width) + std::size_t(x)];
      float* out = e.rgb.data() + 3 * (std::size_t(y) * std::size_t(e.width) + std::size_t(x));
      for (int c = 0; c < 3; ++c) out[c] = texture::kSrgbDecode255[(texel >> (8 * c)) & 255u] / 255.0f;
    }
  }
  return e;
}

}  // namespace

Result<EnvironmentLight> decode_environment_image(std::span<const std::uint8_t> bytes, const std::string& source_name,
                                                  std::uint64_t memory_budget_bytes) {
  try {
    if (bytes.size() >= 2 && bytes[0] == '#' && bytes[1] == '?') return decode_hdr(bytes, source_name, memory_budget_bytes);
    if (bytes.size() >= 4 && bytes[0] == 0x76 && bytes[1] == 0x2f && bytes[2] == 0x31 && bytes[3] == 0x01) {
      return decode_exr(bytes, source_name, memory_budget_bytes);
    }
    const bool png = bytes.size() >= 8 && bytes[0] == 0x89 && bytes[1] == 'P' && bytes[2] == 'N' && bytes[3] == 'G';
    const bool jpeg = bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
    if (png || jpeg) return decode_8bit(bytes, source_name, memory_budget_bytes);
    return Status{ErrorCode::unsupported, "environment_image",
                  quote(source_name, 200) + ": not a picture facet reads as surroundings (Radiance .hdr, OpenEXR .exr, PNG or JPEG)"};
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "environment_image", quote(source_name, 200) + ": out of memory reading it"};
  }
}

Result<EnvironmentLight> load_environment_image(const std::string& path, const AssetAccess& access,
                                                std::uint64_t memory_budget_bytes) {
  Result<std::string> bytes = io::read_named_by_host(access, path, "environment picture",
                                                     memory_budget_bytes == 0 ? io::kNoSizeLimit : memory_budget_bytes);
  if (!bytes) return bytes.status();
  return decode_environment_image(
      std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size()), path,
      memory_budget_bytes);
}

}  // namespace facet
