// Cube-map faces from an equirectangular picture (texture.hpp: cube_faces_from_equirect).
#include <cmath>
#include <cstdint>
#include <new>
#include <numbers>
#include <vector>

#include "facet/texture.hpp"
#include "common/try.hpp"
#include "texture/sampler.hpp"

namespace facet {
namespace {

// The direction through (s, t) of face f (+X, -X, +Y, -Y, +Z, -Z = 0..5), t counted from the
// face's bottom row: the inverse of GL 2.1's face selection (§3.8.6, table 3.21), where
// s = (sc / |ma| + 1) / 2 and, from the bottom, t = (1 - tc / |ma|) / 2.
void face_direction(int f, double s, double t, double (&d)[3]) {
  const double sc = 2.0 * s - 1.0, tc = 1.0 - 2.0 * t;
  switch (f) {
    case 0: d[0] = 1.0, d[1] = -tc, d[2] = -sc; break;
    case 1: d[0] = -1.0, d[1] = -tc, d[2] = sc; break;
    case 2: d[0] = sc, d[1] = 1.0, d[2] = tc; break;
    case 3: d[0] = sc, d[1] = -1.0, d[2] = -tc; break;
    case 4: d[0] = sc, d[1] = -tc, d[2] = 1.0; break;
    default: d[0] = -sc, d[1] = -tc, d[2] = -1.0; break;
  }
}

}  // namespace

void equirect_coordinates(const double (&d)[3], double& u, double& v) {
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double y = len > 0.0 ? d[1] / len : 0.0;
  u = 0.5 + std::atan2(d[0], -d[2]) / (2.0 * std::numbers::pi);
  v = 0.5 + std::asin(y < -1.0 ? -1.0 : y > 1.0 ? 1.0 : y) / std::numbers::pi;
}

Result<std::vector<Texture>> cube_faces_from_equirect(const Texture& equirect, int face_size, const std::string& name,
                                                      const TextureOptions& options,
                                                      const std::function<bool(double done)>& progress) {
  FACET_TRY(validate_texture(equirect, "equirect"));
  if (face_size < 1 || face_size > kEquirectMaxFace) {
    return Status{ErrorCode::invalid_argument, "face_size",
                  "face_size: a cube face is 1 to " + std::to_string(kEquirectMaxFace) + " texels per side, found " +
                      std::to_string(face_size)};
  }
  const std::uint64_t side = static_cast<std::uint64_t>(face_size);
  const std::uint64_t bytes = 6 * side * side * 4 * (options.filter == TextureFilter::trilinear ? 2 : 1);
  if (options.memory_budget_bytes != 0 && bytes > options.memory_budget_bytes) {
    return Status{ErrorCode::out_of_memory, "memory_budget_bytes",
                  "memory_budget_bytes: the six cube faces need " + std::to_string(bytes) + " bytes, over the memory budget of " +
                      std::to_string(options.memory_budget_bytes)};
  }
  try {
    texture::Sampler s = texture::make_sampler(equirect);
    s.filter = static_cast<std::int32_t>(TextureFilter::bilinear);
    s.wrap = static_cast<std::int32_t>(TextureWrap::repeat);
    // v stays within the first and last rows' centres: bilinear filtering never wraps over a pole.
    const double v_lo = 0.5 / equirect.height(), v_hi = 1.0 - v_lo;
    std::vector<Texture> faces;
    std::vector<std::uint8_t> rgba(4 * side * side);
    // The faces keep the picture's encoding.
    const bool srgb = equirect.encoding == TextureEncoding::srgb;
    TextureOptions face_options = options;
    face_options.encoding = equirect.encoding;
    static constexpr const char* kFace[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
    for (int f = 0; f < 6; ++f) {
      for (int j = 0; j < face_size; ++j) {
        if (progress && !progress((f * double(face_size) + j) / (6.0 * face_size))) {
          return Status{ErrorCode::cancelled, "", "the six cube faces: cancelled"};
        }
        for (int i = 0; i < face_size; ++i) {
          double sum[4] = {0.0, 0.0, 0.0, 0.0};
          for (int b = 0; b < kEquirectSamples; ++b) {
            for (int a = 0; a < kEquirectSamples; ++a) {
              const double s_face = (i + (a + 0.5) / kEquirectSamples) / face_size;
              const double t_face = (j + (b + 0.5) / kEquirectSamples) / face_size;
              double d[3], u, v;
              face_direction(f, s_face, t_face, d);
              equirect_coordinates(d, u, v);
              v = v < v_lo ? v_lo : v > v_hi ? v_hi : v;
              const auto texel = texture::sample_reference(s, u, v, 0.0);
              for (int c = 0; c < 4; ++c) sum[c] += texel[static_cast<std::size_t>(c)];
            }
          }
          // make_texture takes the top row first; j counts from the bottom.
          std::uint8_t* out = rgba.data() + 4 * ((side - 1 - static_cast<std::uint64_t>(j)) * side + static_cast<std::uint64_t>(i));
          for (int c = 0; c < 4; ++c) {
            const double mean = sum[c] / (kEquirectSamples * kEquirectSamples);
            if (srgb && c < 3) {  // averaged decoded (the reference sampler decodes): encoded back
              out[c] = static_cast<std::uint8_t>(texture::encode_srgb8(mean));
              continue;
            }
            const double byte = std::floor(mean * 255.0 + 0.5);
            out[c] = static_cast<std::uint8_t>(byte < 0.0 ? 0.0 : byte > 255.0 ? 255.0 : byte);
          }
        }
      }
      Result<Texture> t = make_texture(name + kFace[f], face_size, face_size, rgba, face_options);
      if (!t) return t.status();
      faces.push_back(std::move(*t));
    }
    return faces;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", "the six cube faces: out of memory"};
  }
}

}  // namespace facet
