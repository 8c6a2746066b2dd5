// Helpers for the rendering tests: caller-owned images surrounded by guard bytes, and small scenes.
#pragma once

#include <cstring>
#include <utility>
#include <vector>

#include "test_support.hpp"

namespace facet::test {

// A caller-owned image with `padding` extra bytes per row and guard bytes before and after; all
// bytes not belonging to a pixel must survive any render untouched.
class Canvas {
 public:
  static constexpr std::uint8_t kFill = 0xA5;
  static constexpr std::size_t kGuard = 64;

  Canvas(int width, int height, PixelFormat format = PixelFormat::rgba8, std::size_t padding = 0, bool y_up = false)
      : stride_(static_cast<std::size_t>(width) * bytes_per_pixel(format) + padding),
        bytes_(2 * kGuard + stride_ * static_cast<std::size_t>(height), kFill) {
    view_ = ImageView{bytes_.data() + kGuard, width, height, stride_, format, y_up};
  }
  const ImageView& view() const { return view_; }
  std::uint8_t* row(int y) { return bytes_.data() + kGuard + static_cast<std::size_t>(y) * stride_; }
  // Channel c of pixel (x, y) of an 8-bit image, in memory order.
  int byte(int x, int y, int c) { return row(y)[4 * x + c]; }
  float channel_f(int x, int y, int c) {
    float v;
    std::memcpy(&v, row(y) + 16 * static_cast<std::size_t>(x) + 4 * static_cast<std::size_t>(c), sizeof v);
    return v;
  }
  bool untouched() const { return std::all_of(bytes_.begin(), bytes_.end(), [](std::uint8_t b) { return b == kFill; }); }
  // Guard bytes and row padding still hold kFill.
  bool outside_pixels_untouched() const {
    const std::size_t pixel_bytes = static_cast<std::size_t>(view_.width) * bytes_per_pixel(view_.format);
    for (std::size_t i = 0; i < kGuard; ++i)
      if (bytes_[i] != kFill || bytes_[bytes_.size() - 1 - i] != kFill) return false;
    for (int y = 0; y < view_.height; ++y)
      for (std::size_t i = pixel_bytes; i < stride_; ++i)
        if (bytes_[kGuard + static_cast<std::size_t>(y) * stride_ + i] != kFill) return false;
    return true;
  }
  std::vector<std::uint8_t> pixels() const { return {bytes_.begin() + kGuard, bytes_.end() - kGuard}; }

 private:
  std::size_t stride_;
  std::vector<std::uint8_t> bytes_;
  ImageView view_;
};

// Camera at the origin looking down -z (90 deg vertical field of view), near 1, far 100, no
// ambient light; one emissive material per colour added with add_quad.
// Every lighting path this machine runs: the reference, the scalar path, and SIMD on each ISA it has.
inline std::vector<std::pair<LightingPath, Isa>> every_path() {
  std::vector<std::pair<LightingPath, Isa>> p = {{LightingPath::reference, Isa::best}, {LightingPath::scalar, Isa::best}};
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) p.push_back({LightingPath::simd, isa});
  return p;
}

inline Scene camera_scene() {
  Scene s;
  s.camera.eye = Vec3(0, 0, 0);
  s.camera.target = Vec3(0, 0, -1);
  s.camera.vertical_fov_deg = 90;
  s.camera.near = 1;
  s.camera.far = 100;
  s.global_ambient = Color3::Zero();
  return s;
}

// `m` as a new object of `s` with an emissive material of `colour` (no other light terms).
inline void add_emissive(Scene& s, Mesh m, const Color3& colour) {
  Material mat;
  mat.ambient = mat.diffuse = mat.specular = Color3::Zero();
  mat.emissive = colour;
  s.meshes.push_back({"mesh" + std::to_string(s.meshes.size()), std::move(m)});
  s.materials.push_back(mat);
  s.objects.push_back({static_cast<std::uint32_t>(s.meshes.size() - 1), static_cast<std::uint32_t>(s.materials.size() - 1),
                       Mat4::Identity()});
}

// An axis-aligned rectangle [x0, x1] x [y0, y1] at depth z, facing +z (counter-clockwise seen from
// the camera unless `reversed`), in a flat emissive colour.
inline void add_quad(Scene& s, float x0, float y0, float x1, float y1, float z, const Color3& colour,
                     bool reversed = false) {
  Mesh m;
  m.positions = {Vec3(x0, y0, z), Vec3(x1, y0, z), Vec3(x1, y1, z), Vec3(x0, y1, z)};
  m.normals.assign(4, Vec3(0, 0, 1));
  m.triangles = reversed ? std::vector<std::array<std::uint32_t, 3>>{{0, 2, 1}, {0, 3, 2}}
                         : std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}};
  add_emissive(s, std::move(m), colour);
}

// A spot light straight down onto a plane seen from above (world +x to the image's right, +z down).
inline Scene projector_scene(const std::vector<std::uint8_t>& picture, int w, int h, ProjectorMode mode) {
  Scene s;
  s.meshes.push_back({"plane", make_plane(8.0f, 8.0f, 8)});
  Material m;
  m.ambient = Color3::Zero();
  m.diffuse = Color3(0.9f, 0.9f, 0.9f);
  m.specular = Color3(0.3f, 0.3f, 0.3f);
  m.shininess = 8;
  s.materials.push_back(m);
  s.objects.push_back({0, 0, Mat4::Identity()});
  s.camera.eye = Vec3(0, 6, 0.001f);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.up = Vec3(0, 0, -1);
  s.camera.vertical_fov_deg = 60;
  s.global_ambient = Color3::Zero();
  Light spot;
  spot.type = LightType::spot;
  spot.position = Vec3(0, 2, 0);
  spot.direction = Vec3(0, -1, 0);
  spot.spot_cutoff_deg = 45;  // the picture spans x, z in [-2, 2] on the plane
  spot.diffuse = Color3(1, 0.8f, 0.6f);
  s.lights.push_back(spot);
  TextureOptions o{TextureFilter::nearest, TextureWrap::clamp};
  o.encoding = TextureEncoding::linear;
  s.textures.push_back(*make_texture("picture", w, h, picture, o));
  s.lights[0].projector.texture = 0;
  s.lights[0].projector.mode = mode;
  return s;
}

}  // namespace facet::test
