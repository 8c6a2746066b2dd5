// Internal: JPEG files to RGBA8 through libjpeg-turbo (jpeg_decode.cpp says which checks it makes).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "facet/status.hpp"
#include "texture/png_decode.hpp"

namespace facet {

// As decode_png: `admit` is asked, once the header is read and before any pixel memory is taken,
// whether width x height (needing `decode_bytes` of the decoder's own) may be decoded. `max_bytes`
// bounds libjpeg's own working memory (0 = no limit).
Result<PngPixels> decode_jpeg(std::span<const std::uint8_t> bytes, const std::string& source_name,
                              const std::function<Status(int width, int height, std::uint64_t decode_bytes)>& admit,
                              std::uint64_t max_bytes);

}  // namespace facet
