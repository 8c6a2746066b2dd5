// Textures: RGBA8 images with their mipmap chain, sampled as OpenGL 2.1 samples a 2D texture
// (§3.8.8). Decoded from PNG or JPEG (stb_image) or made from caller pixels; the mipmaps are built
// once, when the texture is made, never per frame.
//
// Conventions, as in GL:
//  - texture coordinates (s, t) = (0, 0) are the bottom-left corner of the picture and (1, 1) its
//    top-right corner: decoders deliver the top row first, so rows are stored bottom row first
//    (the flip an OpenGL program does before glTexImage2D for OBJ/glTF-style coordinates);
//  - texel (i, j) has its centre at ((i + 1/2) / width, (j + 1/2) / height);
//  - a linear texture's values are used as they are stored, like a GL_RGBA8 texture; an sRGB
//    texture's colour channels are decoded to linear per texel before filtering, like a
//    GL_SRGB8_ALPHA8 texture (EXT_texture_sRGB: decode, then filter; alpha is linear).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "facet/status.hpp"

namespace facet {

// Largest accepted width or height.
inline constexpr int kMaxTextureDimension = 16384;

enum class TextureFilter {
  nearest,    // GL_NEAREST: the texel under the sample point, level 0 only
  bilinear,   // GL_LINEAR: the 2x2 texels around it, level 0 only
  trilinear,  // GL_LINEAR_MIPMAP_LINEAR minification, GL_LINEAR magnification (the default)
};
enum class TextureWrap {
  repeat,  // GL_REPEAT
  clamp,   // GL_CLAMP_TO_EDGE
  mirror,  // GL_MIRRORED_REPEAT
};
// How the stored colour channels encode light (alpha is always linear).
enum class TextureEncoding {
  linear,  // stored value v / 255 is the colour (normal, occlusion and metal-roughness maps)
  srgb,    // the sRGB transfer function: linear = c / 12.92 for c <= 0.04045, ((c + 0.055) / 1.055)^2.4
           // above, c = v / 255 (colour pictures: glTF base colour and emission)
};
const char* to_string(TextureFilter filter) noexcept;
const char* to_string(TextureWrap wrap) noexcept;
const char* to_string(TextureEncoding encoding) noexcept;

struct TextureLevel {
  int width = 0, height = 0;
  std::size_t offset = 0;  // first texel of the level in Texture::texels
};

struct Texture {
  std::string name;
  TextureFilter filter = TextureFilter::trilinear;
  TextureWrap wrap = TextureWrap::repeat;
  TextureEncoding encoding = TextureEncoding::linear;
  // RGBA8 texels as little-endian words (R in the low byte), level after level, each level's rows
  // bottom row first. A trilinear texture has every level down to 1x1 (level k is
  // max(1, width >> k) x max(1, height >> k), as in GL); the others have level 0 only.
  std::vector<std::uint32_t> texels;
  std::vector<TextureLevel> levels;

  int width() const noexcept { return levels.empty() ? 0 : levels[0].width; }
  int height() const noexcept { return levels.empty() ? 0 : levels[0].height; }
};

struct TextureOptions {
  TextureFilter filter = TextureFilter::trilinear;
  TextureWrap wrap = TextureWrap::repeat;
  // A texture whose decoding and texels would need more memory than this is refused
  // (ErrorCode::out_of_memory) before it is decoded. 0 = no limit.
  std::uint64_t memory_budget_bytes = std::uint64_t{4} << 30;
  // The texels' encoding; none: the file's own tag where it has one (a PNG's sRGB or iCCP chunk:
  // sRGB; a gAMA chunk of 1/2.2, within 2 %: sRGB; of 1: linear; another gamma is refused, as
  // facet cannot decode it exactly), otherwise linear (GL_RGBA8's rule), and linear for caller pixels.
  std::optional<TextureEncoding> encoding = std::nullopt;
};

// From caller pixels: width x height RGBA8, top row first, rows packed (4 * width bytes). Any size
// from 1x1 to kMaxTextureDimension per side; sizes need not be powers of two.
//
// Mipmaps (trilinear only): level k + 1 is a box filter of level k. Each texel of the smaller
// level averages the rectangle of the larger level it covers, with fractional weights at the
// edges when a side is odd (a 5-texel row becomes 2 texels of 2.5 texels each), so every texel of
// level k contributes equally to level k + 1. The average is taken in float on the stored values
// (as glGenerateMipmap on GL_RGBA8) and rounded to the nearest 8-bit value; for an sRGB texture
// on the decoded (linear) colour channels, encoded back to the nearest sRGB byte.
Result<Texture> make_texture(std::string name, int width, int height, std::span<const std::uint8_t> rgba8,
                             const TextureOptions& options = {});

// PNG (8 or 16 bits per channel; grey, grey + alpha, RGB, RGBA or palette; interlaced or not) or
// JPEG (baseline or progressive; grey or colour), told apart by their signatures. Grey becomes
// R = G = B; a missing alpha is 1; 16-bit values are rounded to the nearest 8-bit value.
// Other formats are refused (ErrorCode::unsupported). `source_name` is used in messages.
Result<Texture> decode_texture(std::span<const std::uint8_t> bytes, const std::string& source_name,
                               std::string name, const TextureOptions& options = {});
// The same from a file (regular files only), refused if larger than the budget.
Result<Texture> load_texture(const std::string& path, std::string name, const TextureOptions& options = {});

// Cube maps from an equirectangular (latitude-longitude) picture: the six faces, in the order
// +X, -X, +Y, -Y, +Z, -Z and GL's orientation (GL 2.1 table 3.21; rows bottom first, as every
// facet texture), each face_size x face_size (1 to kEquirectMaxFace), named `name` + "+x" ... "-z",
// made with `options` (their budget counts the faces). Picture coordinates of a direction d:
// u = 1/2 + atan2(d.x, -d.z) / 2 pi (the picture's centre looks along -Z, +X a quarter turn to its
// right; u wraps), v = 1/2 + asin(d.y / |d|) / pi (+Y, the picture's top, is up). Each face texel
// is the mean of kEquirectSamples x kEquirectSamples directions spread evenly over it, each read
// bilinearly from the picture's level 0 (v held within the first and last rows' centres, so the
// filter never reaches across a pole), rounded to the nearest 8-bit value: a box filter over the
// texel's footprint, which matches the picture's own resolution when face_size is about a quarter
// of its width and averages away the rows that crowd towards the poles.
// `progress`, when set, is called at least every tenth of a second or so (after each row of a
// face) with the share done; returning false stops with ErrorCode::cancelled.
inline constexpr int kEquirectMaxFace = 4096;
inline constexpr int kEquirectSamples = 4;
Result<std::vector<Texture>> cube_faces_from_equirect(const Texture& equirect, int face_size, const std::string& name,
                                                      const TextureOptions& options = {},
                                                      const std::function<bool(double done)>& progress = {});
// The picture coordinates (u, v) of direction d, as cube_faces_from_equirect reads them.
void equirect_coordinates(const double (&d)[3], double& u, double& v);

// Checks that the levels and texels are consistent with the filter (as make_texture builds
// them). `field` prefixes the error's field name.
Status validate_texture(const Texture& texture, const std::string& field = "texture");

}  // namespace facet
