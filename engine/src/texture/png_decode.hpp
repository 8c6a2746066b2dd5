// Internal: PNG files to RGBA8 through libpng (png_decode.cpp says which checks it makes).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "facet/status.hpp"

namespace facet {

struct PngPixels {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // top row first, packed
  // What the file says of its colour encoding: an sRGB or iCCP chunk (srgb), a gAMA chunk (gamma
  // = its value, 1/2.2 for sRGB-like files), or nothing (untagged, gamma 0).
  bool srgb_chunk = false, iccp_chunk = false;
  double gamma = 0.0;
};

// `admit` is asked, once the header is read and before any pixel memory is taken, whether
// width x height (needing `decode_bytes` for the raw rows) may be decoded; its error is returned.
Result<PngPixels> decode_png(std::span<const std::uint8_t> bytes, const std::string& source_name,
                             const std::function<Status(int width, int height, std::uint64_t decode_bytes)>& admit);

}  // namespace facet
