// Shared by the fuzz targets: a caller buffer fenced by guard bytes, and a trap that makes the
// fuzzer report a broken invariant as a crash.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "facet/facet.hpp"

namespace facet::fuzz {

[[noreturn]] inline void broken(const char* what) {
  std::fprintf(stderr, "facet fuzz: invariant broken: %s\n", what);
  __builtin_trap();
}

// Pixels between guard bytes; any byte facet writes outside the view's pixels is a bug.
class GuardedImage {
 public:
  static constexpr std::size_t kGuard = 64;
  static constexpr std::uint8_t kFill = 0x5A;
  GuardedImage(int w, int h, PixelFormat f, std::size_t padding, bool y_up)
      : stride_(static_cast<std::size_t>(w) * bytes_per_pixel(f) + padding),
        bytes_(2 * kGuard + stride_ * static_cast<std::size_t>(h), kFill),
        view_{bytes_.data() + kGuard, w, h, stride_, f, y_up} {}
  const ImageView& view() const { return view_; }
  void check() const {
    const std::size_t pixel_bytes = static_cast<std::size_t>(view_.width) * bytes_per_pixel(view_.format);
    for (std::size_t i = 0; i < kGuard; ++i)
      if (bytes_[i] != kFill || bytes_[bytes_.size() - 1 - i] != kFill) broken("write outside the image buffer");
    for (int y = 0; y < view_.height; ++y)
      for (std::size_t i = pixel_bytes; i < stride_; ++i)
        if (bytes_[kGuard + static_cast<std::size_t>(y) * stride_ + i] != kFill) broken("write into row padding");
  }

 private:
  std::size_t stride_;
  std::vector<std::uint8_t> bytes_;
  ImageView view_;
};

// Reads values off the front of the fuzzer's bytes; zeros once they run out.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  T take() {
    T v{};
    const std::size_t n = std::min(sizeof(T), size_ - pos_);
    std::memcpy(&v, data_ + pos_, n);
    pos_ += n;
    return v;
  }
  std::size_t left() const { return size_ - pos_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
};

}  // namespace facet::fuzz
