// PNG textures through libpng, with every check libpng makes: a chunk's CRC, the zlib stream's
// Adler-32, the image data's length are errors, not warnings. libpng reports errors with longjmp,
// so the part that can jump is plain C-style code with no object that needs destroying; it hands
// out the raw rows (palette indices as they are, 16-bit samples as they are) and the conversion to
// RGBA8, with its own checks (every palette index within the palette), runs after it.
#include "texture/png_decode.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "facet/texture.hpp"

namespace facet {
namespace {

struct Input {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at;
};

struct State {
  char message[200];
  std::jmp_buf jump;
};

void on_error(png_structp png, png_const_charp message) {
  auto* state = static_cast<State*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof state->message, "%s", message ? message : "unknown error");
  std::longjmp(state->jump, 1);
}
void on_warning(png_structp, png_const_charp) {}  // ancillary-chunk warnings: the texels are not affected

void read_bytes(png_structp png, png_bytep out, png_size_t n) {
  auto* in = static_cast<Input*>(png_get_io_ptr(png));
  if (n > in->size - in->at) png_error(png, "the file ends early");
  std::memcpy(out, in->data + in->at, n);
  in->at += n;
}

struct Header {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0, channels = 0;
  std::size_t row_bytes = 0;
  int palette_size = 0;
  png_color palette[256];
  int trans_count = 0;
  png_byte trans_alpha[256];
  png_color_16 trans_color;
  bool has_trans_color = false;
  bool srgb = false, iccp = false;
  double gamma = 0.0;
};

// Phase 1 reads the header; phase 2 the rows into `pixels` (sized by the caller from the header).
// Returns false with `state.message` set when libpng reports an error. No C++ object with a
// destructor lives in this function: longjmp may leave it.
bool run_libpng(Input& input, State& state, Header& h, const std::function<std::uint8_t*(const Header&)>& allocate) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, on_error, on_warning);
  if (!png) {
    std::snprintf(state.message, sizeof state.message, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  png_bytep* volatile rows = nullptr;  // volatile: read after a longjmp
  if (!info || setjmp(state.jump)) {
    png_free(png, rows);
    png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    if (!info) std::snprintf(state.message, sizeof state.message, "out of memory");
    return false;
  }
  png_set_read_fn(png, &input, read_bytes);
  png_set_user_limits(png, 0x7fffffffu, 0x7fffffffu);  // facet checks the size itself, after the header
  png_read_info(png, info);
  png_get_IHDR(png, info, &h.width, &h.height, &h.bit_depth, &h.color_type, nullptr, nullptr, nullptr);
  // The colour-space tags (only recorded: the samples stay as they are stored).
  h.srgb = png_get_valid(png, info, PNG_INFO_sRGB) != 0;
  h.iccp = png_get_valid(png, info, PNG_INFO_iCCP) != 0;
  if (png_get_valid(png, info, PNG_INFO_gAMA)) {
    png_fixed_point g = 0;
    if (png_get_gAMA_fixed(png, info, &g)) h.gamma = double(g) / 100000.0;
  }
  if (h.color_type == PNG_COLOR_TYPE_PALETTE) {
    png_colorp pal = nullptr;
    if (png_get_PLTE(png, info, &pal, &h.palette_size) == 0) png_error(png, "a palette image without a palette");
    std::memcpy(h.palette, pal, sizeof(png_color) * static_cast<std::size_t>(h.palette_size));
  }
  if (png_get_valid(png, info, PNG_INFO_tRNS)) {
    png_bytep alpha = nullptr;
    png_color_16p color = nullptr;
    png_get_tRNS(png, info, &alpha, &h.trans_count, &color);
    if (h.color_type == PNG_COLOR_TYPE_PALETTE && alpha) {
      std::memcpy(h.trans_alpha, alpha, static_cast<std::size_t>(h.trans_count));
    } else if (color) {
      h.trans_color = *color;
      h.has_trans_color = true;
    }
  }
  // Only what keeps values as they are stored: sub-byte samples widened to bytes (grey scaled to
  // 8 bits, palette indices kept), and interlaced passes gathered.
  if (h.bit_depth < 8) {
    if (h.color_type == PNG_COLOR_TYPE_GRAY) png_set_expand_gray_1_2_4_to_8(png);
    else png_set_packing(png);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  h.channels = png_get_channels(png, info);
  h.row_bytes = png_get_rowbytes(png, info);
  std::uint8_t* pixels = allocate(h);
  if (!pixels) {
    png_destroy_read_struct(&png, &info, nullptr);
    return true;  // the caller refused (size or budget) and says why
  }
  rows = static_cast<png_bytep*>(png_malloc(png, sizeof(png_bytep) * h.height));
  for (png_uint_32 y = 0; y < h.height; ++y) rows[y] = pixels + std::size_t(y) * h.row_bytes;
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  png_free(png, rows);
  rows = nullptr;
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

}  // namespace

Result<PngPixels> decode_png(std::span<const std::uint8_t> bytes, const std::string& source_name,
                             const std::function<Status(int width, int height, std::uint64_t decode_bytes)>& admit) {
  auto fail = [&](ErrorCode code, const std::string& what) { return Status{code, "file", source_name + ": " + what}; };
  // The size first, from the header as it stands, before libpng sizes anything by it.
  if (bytes.size() >= 24 && std::memcmp(bytes.data() + 12, "IHDR", 4) == 0) {
    const std::uint64_t w = std::uint64_t{bytes[16]} << 24 | std::uint64_t{bytes[17]} << 16 | std::uint64_t{bytes[18]} << 8 | bytes[19];
    const std::uint64_t h = std::uint64_t{bytes[20]} << 24 | std::uint64_t{bytes[21]} << 16 | std::uint64_t{bytes[22]} << 8 | bytes[23];
    if (w < 1 || h < 1 || w > std::uint64_t(kMaxTextureDimension) || h > std::uint64_t(kMaxTextureDimension)) {
      return fail(ErrorCode::unsupported, std::to_string(w) + " x " + std::to_string(h) + " texels: a texture is 1 to " +
                                              std::to_string(kMaxTextureDimension) + " texels per side");
    }
  }
  Input input{bytes.data(), bytes.size(), 0};
  State state{};
  Header h;
  std::vector<std::uint8_t> raw;
  Status refused;
  const bool ok = run_libpng(input, state, h, [&](const Header& hh) -> std::uint8_t* {
    if (hh.width < 1 || hh.height < 1 || hh.width > png_uint_32(kMaxTextureDimension) || hh.height > png_uint_32(kMaxTextureDimension)) {
      refused = fail(ErrorCode::unsupported, std::to_string(hh.width) + " x " + std::to_string(hh.height) +
                                                 " texels: a texture is 1 to " + std::to_string(kMaxTextureDimension) + " texels per side");
      return nullptr;
    }
    const std::uint64_t need = std::uint64_t(hh.row_bytes) * hh.height;
    refused = admit(int(hh.width), int(hh.height), need);
    if (!refused.ok()) return nullptr;
    try {
      raw.resize(static_cast<std::size_t>(need));
    } catch (const std::bad_alloc&) {
      refused = fail(ErrorCode::out_of_memory, "out of memory for its " + std::to_string(need) + " bytes of pixels");
      return nullptr;
    }
    return raw.data();
  });
  if (!ok) {
    const std::string why = state.message;
    return fail(why == "out of memory" || why.find("Insufficient memory") != std::string::npos ? ErrorCode::out_of_memory
                                                                                               : ErrorCode::parse_error,
                "cannot decode the PNG: " + why);
  }
  if (!refused.ok()) return refused;
  PngPixels out;
  out.width = int(h.width);
  out.height = int(h.height);
  out.srgb_chunk = h.srgb, out.iccp_chunk = h.iccp, out.gamma = h.gamma;
  const std::size_t n = std::size_t(h.width) * h.height;
  try {
    out.rgba.resize(4 * n);
  } catch (const std::bad_alloc&) {
    return fail(ErrorCode::out_of_memory, "out of memory");
  }
  const bool sixteen = h.bit_depth == 16;
  // A sample as 8 bits: 16-bit values to the nearest 8-bit value, round(v * 255 / 65535).
  auto sample = [&](const std::uint8_t* row, std::size_t i) -> std::uint8_t {
    if (!sixteen) return row[i];
    const std::uint32_t v = std::uint32_t{row[2 * i]} << 8 | row[2 * i + 1];
    return static_cast<std::uint8_t>((v * 255u + 32767u) / 65535u);
  };
  auto raw16 = [&](const std::uint8_t* row, std::size_t i) -> std::uint32_t {
    return sixteen ? (std::uint32_t{row[2 * i]} << 8 | row[2 * i + 1]) : row[i];
  };
  for (std::size_t y = 0; y < h.height; ++y) {
    const std::uint8_t* row = raw.data() + y * h.row_bytes;
    std::uint8_t* o = out.rgba.data() + 4 * y * h.width;
    for (std::size_t x = 0; x < h.width; ++x, o += 4) {
      switch (h.color_type) {
        case PNG_COLOR_TYPE_PALETTE: {
          const int k = row[x];
          if (k >= h.palette_size) {
            return fail(ErrorCode::parse_error, "cannot decode the PNG: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                    ") uses palette entry " + std::to_string(k) + " of " +
                                                    std::to_string(h.palette_size));
          }
          o[0] = h.palette[k].red, o[1] = h.palette[k].green, o[2] = h.palette[k].blue;
          o[3] = k < h.trans_count ? h.trans_alpha[k] : 255;
          break;
        }
        case PNG_COLOR_TYPE_GRAY: {
          o[0] = o[1] = o[2] = sample(row, x);
          // Sub-byte grey was widened to 8 bits: its key is widened the same way.
          const std::uint32_t key = h.bit_depth < 8 ? h.trans_color.gray * (255u / ((1u << h.bit_depth) - 1u)) : h.trans_color.gray;
          o[3] = h.has_trans_color && raw16(row, x) == key ? 0 : 255;
          break;
        }
        case PNG_COLOR_TYPE_GRAY_ALPHA: {
          o[0] = o[1] = o[2] = sample(row, 2 * x);
          o[3] = sample(row, 2 * x + 1);
          break;
        }
        case PNG_COLOR_TYPE_RGB: {
          for (int c = 0; c < 3; ++c) o[c] = sample(row, 3 * x + std::size_t(c));
          const bool key = h.has_trans_color && raw16(row, 3 * x) == h.trans_color.red &&
                           raw16(row, 3 * x + 1) == h.trans_color.green && raw16(row, 3 * x + 2) == h.trans_color.blue;
          o[3] = key ? 0 : 255;
          break;
        }
        default: {  // RGBA
          for (int c = 0; c < 4; ++c) o[c] = sample(row, 4 * x + std::size_t(c));
          break;
        }
      }
    }
  }
  return out;
}

}  // namespace facet
