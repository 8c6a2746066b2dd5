// Internal: the one rule for where row y (y down, row 0 at the top of the picture) of a caller's
// image or depth view lives: views with y_up store the picture's bottom row first. In an unnamed
// namespace, so that the per-ISA files each keep their own copy (no inline function crosses ISA
// files).
#pragma once

#include <cstddef>
#include <cstdint>

#include "facet/image.hpp"

namespace facet::io {
namespace {

inline std::uint8_t* row_bytes(const ImageView& view, int y) {
  const int row = view.y_up ? view.height - 1 - y : y;
  return static_cast<std::uint8_t*>(view.data) + static_cast<std::size_t>(row) * view.stride_bytes;
}
inline std::uint8_t* row_bytes(const DepthView& view, int y) {
  const int row = view.y_up ? view.height - 1 - y : y;
  return reinterpret_cast<std::uint8_t*>(view.data) + static_cast<std::size_t>(row) * view.stride_bytes;
}

}  // namespace
}  // namespace facet::io
