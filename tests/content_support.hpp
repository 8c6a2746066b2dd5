// Helpers of the model import tests (content_test.cpp, obj_import_test.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "facet/facet.hpp"
#include "gltf_builder.hpp"
#include "test_support.hpp"

// In the tests' own unnamed namespace, as when they were one file; inline, so that a file
// leaving one unused is not warned.
namespace facet {
namespace {

class TempDir : public test::TempDir {
 public:
  TempDir() : test::TempDir("facet_content") {}
};

// A 2x2 RGBA PNG: red, green (top row), blue, white (bottom row).
inline std::string write_test_png(const std::string& path) {
  std::vector<std::uint8_t> px = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  const ImageView view{px.data(), 2, 2, 8, PixelFormat::rgba8, false};
  EXPECT_TRUE(write_png(path, view).ok());
  return test::read_bytes(path);
}

inline std::vector<std::uint8_t> render_rgba(const Scene& scene, int w = 64, int h = 48, int threads = 1) {
  std::vector<std::uint8_t> px(std::size_t(w) * h * 4);
  const ImageView view{px.data(), w, h, std::size_t(w) * 4, PixelFormat::rgba8, false};
  RenderOptions o = test::gl_options();
  o.threads = threads;
  Renderer r;
  const Status s = r.render(scene, o, view);
  EXPECT_TRUE(s.ok()) << s.message();
  return px;
}

}  // namespace
}  // namespace facet
