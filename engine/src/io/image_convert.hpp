// Internal: pixel conversions shared by the resolve stage and the image files.
#pragma once

#include <cstdint>

#include "facet/image.hpp"

namespace facet {

// [0, 1] -> 0..255, rounding half up; values outside are clamped, NaN gives 0. Inline: the resolve
// stage calls it for every channel of every pixel.
inline std::uint8_t to_unorm8(float v) noexcept {
  const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
  return static_cast<std::uint8_t>(c * 255.0f + 0.5f);
}

// Any view, read top row first, as tightly packed 8-bit RGBA.
Rgba8Image to_rgba8(const ImageView& view);

}  // namespace facet
