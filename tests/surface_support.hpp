// The surface tests' helpers (surface_test.cpp, surface_order_test.cpp): textures from a function,
// the centre pixel of a render, every lighting path, and the scene that uses every surface feature.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "render_support.hpp"

// In the tests' own unnamed namespace, as when they were one file; inline, so that a file
// leaving one unused is not warned.
namespace facet {
namespace {

using test::Canvas;

// A w x h texture from a function of the texel (i, j), bottom row first, RGBA8.
template <class Fn>
inline Texture texture_from(int w, int h, TextureFilter filter, Fn&& texel) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h) * 4);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::array<std::uint8_t, 4> c = texel(i, j);
      std::memcpy(&rgba[static_cast<std::size_t>(j * w + i) * 4], c.data(), 4);
    }
  TextureOptions o;
  o.filter = filter;
  Result<Texture> t = make_texture("t", w, h, rgba, o);
  EXPECT_TRUE(t.ok()) << t.status().message();
  return std::move(*t);
}

// The quad of add_quad with texture coordinates 0..1 across it.
inline void add_uvs(Scene& s) {
  s.meshes.back().mesh.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
}

struct Pixel {
  int r, g, b, a;
};
inline Pixel centre(Canvas& c) {
  const int x = c.view().width / 2, y = c.view().height / 2;
  return {c.byte(x, y, 0), c.byte(x, y, 1), c.byte(x, y, 2), c.byte(x, y, 3)};
}
inline int step(double v) { return static_cast<int>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); }

inline Pixel render_centre(const Scene& s, LightingPath path, ShadingMode mode = ShadingMode::gouraud, Isa isa = Isa::best) {
  Canvas c(32, 32);
  RenderOptions o = test::gl_options();
  o.path = path;
  o.isa = isa;
  o.shading = mode;
  o.clear_color = {0.25f, 0.5f, 0.75f, 1.0f};
  Renderer r;
  const Status st = r.render(s, o, c.view());
  EXPECT_TRUE(st.ok()) << st.message();
  return centre(c);
}

inline std::vector<std::pair<LightingPath, Isa>> every_path() {
  std::vector<std::pair<LightingPath, Isa>> p = {{LightingPath::reference, Isa::best}, {LightingPath::scalar, Isa::best}};
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) p.push_back({LightingPath::simd, isa});
  return p;
}

#define EXPECT_PIXEL_NEAR(p, er, eg, eb, ea)                                                            \
  do {                                                                                                  \
    EXPECT_NEAR((p).r, (er), 1);                                                                        \
    EXPECT_NEAR((p).g, (eg), 1);                                                                        \
    EXPECT_NEAR((p).b, (eb), 1);                                                                        \
    EXPECT_NEAR((p).a, (ea), 1);                                                                        \
  } while (0)

// An emissive quad (primary colour E, alpha A) under a one-texel texture T: each environment's

// The done-when scene: a textured ground plane and sphere, an alpha-blended sphere and fog.
inline Scene surfaces_scene() {
  Scene s = make_default_scene();
  s.textures.push_back(texture_from(64, 64, TextureFilter::trilinear, [](int i, int j) {
    const bool dark = ((i / 8) + (j / 8)) % 2 == 0;
    return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(dark ? 60 : 230), static_cast<std::uint8_t>(dark ? 90 : 220),
                                       static_cast<std::uint8_t>(dark ? 40 : 200), 255};
  }));
  s.textures.push_back(texture_from(32, 16, TextureFilter::bilinear, [](int i, int j) {
    return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(i * 8), static_cast<std::uint8_t>(j * 16), 200, 255};
  }));
  for (std::size_t o = 0; o < s.objects.size(); ++o) {
    const std::string& name = s.meshes[s.objects[o].mesh].name;
    Material& m = s.materials[s.objects[o].material];
    if (name.find("plane") != std::string::npos || name.find("ground") != std::string::npos) {
      m.diffuse_texture = 0;
      m.uv_scale = Vec2(6, 6);
    }
  }
  // One sphere textured, another blended (the built-in scene's first two spheres).
  int spheres = 0;
  for (std::size_t o = 0; o < s.objects.size(); ++o) {
    if (s.meshes[s.objects[o].mesh].name.find("sphere") == std::string::npos) continue;
    Material m = s.materials[s.objects[o].material];
    if (spheres == 0) {
      m.diffuse_texture = 1;
    } else if (spheres == 1) {
      m.blend = BlendMode::alpha;
      m.alpha = 0.45f;
    }
    s.materials.push_back(m);
    s.objects[o].material = static_cast<std::uint32_t>(s.materials.size() - 1);
    ++spheres;
  }
  s.fog.mode = FogMode::linear;
  s.fog.color = Color3(0.6f, 0.65f, 0.7f);
  s.fog.start = 4;
  s.fog.end = 30;
  return s;
}

// A w x h render of `s`; checks nothing outside the image was written.
inline std::vector<std::uint8_t> render_pixels(const Scene& s, RenderOptions o, int w = 320, int h = 240) {
  Canvas c(w, h);
  Renderer r;
  const Status st = r.render(s, o, c.view());
  EXPECT_TRUE(st.ok()) << st.message();
  EXPECT_TRUE(c.outside_pixels_untouched());
  return c.pixels();
}

}  // namespace
}  // namespace facet
