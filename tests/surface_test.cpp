// Surfaces (issue 15): textures with GL's texture environments, vertex colours, blending, alpha
// test, depth writes and fog, checked against values computed here from GL 2.1's formulas, and
// the pictures' determinism (threads, ISAs) and scalar/SIMD agreement.
#include <cmath>
#include <cstring>

#include "io/srgb.hpp"
#include "texture/sampler.hpp"
#include "render_support.hpp"
#include "surface_support.hpp"

namespace facet {
namespace {

// result, on every path and shading mode.
TEST(Surfaces, TextureEnvironmentsFollowGL) {
  const Color3 e(0.8f, 0.4f, 0.2f);
  const std::array<std::uint8_t, 4> t = {128, 255, 64, 102};  // alpha 0.4
  const double T[4] = {128 / 255.0, 1.0, 64 / 255.0, 102 / 255.0};
  const double A = 0.5;
  for (TextureMode mode : {TextureMode::modulate, TextureMode::replace, TextureMode::decal, TextureMode::add}) {
    Scene s = test::camera_scene();
    s.textures.push_back(texture_from(1, 1, TextureFilter::bilinear, [&](int, int) { return t; }));
    test::add_quad(s, -5, -5, 5, 5, -3, e);
    add_uvs(s);
    s.materials.back().diffuse_texture = 0;
    s.materials.back().texture_mode = mode;
    s.materials.back().alpha = static_cast<float>(A);
    double c[4] = {};
    for (int k = 0; k < 3; ++k) {
      const double ek = e[k];
      switch (mode) {
        case TextureMode::modulate: c[k] = ek * T[k]; break;
        case TextureMode::replace: c[k] = T[k]; break;
        case TextureMode::decal: c[k] = ek * (1 - T[3]) + T[k] * T[3]; break;
        case TextureMode::add: c[k] = std::min(1.0, ek + T[k]); break;
      }
    }
    c[3] = mode == TextureMode::replace ? T[3] : mode == TextureMode::decal ? A : A * T[3];
    for (auto [path, isa] : every_path()) {
      for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
        SCOPED_TRACE(std::string(to_string(mode)) + " " + to_string(path) + " " + to_string(isa) + " " + to_string(shading));
        const Pixel p = render_centre(s, path, shading, isa);
        EXPECT_PIXEL_NEAR(p, step(c[0]), step(c[1]), step(c[2]), step(c[3]));
      }
    }
  }
}

// Separate specular: the texture modulates emission + ambient + diffuse; the specular is added
// after it, so a black texture still shows the highlight (GL_SEPARATE_SPECULAR_COLOR).
TEST(Surfaces, SpecularIsAddedAfterTheTexture) {
  Scene s = test::camera_scene();
  s.textures.push_back(texture_from(1, 1, TextureFilter::nearest, [](int, int) {
    return std::array<std::uint8_t, 4>{0, 0, 0, 255};
  }));
  test::add_quad(s, -5, -5, 5, 5, -3, Color3(0.5f, 0.5f, 0.5f));
  add_uvs(s);
  Material& m = s.materials.back();
  m.diffuse_texture = 0;
  m.diffuse = Color3(1, 1, 1);
  m.specular = Color3(0.25f, 0.5f, 0.75f);
  m.shininess = 0;  // n.h^0 = 1 wherever n.l > 0
  Light l;  // towards the camera: n.l = 1
  l.direction = Vec3(0, 0, -1);
  s.lights.push_back(l);
  for (auto [path, isa] : every_path()) {
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      SCOPED_TRACE(std::string(to_string(path)) + " " + to_string(isa) + " " + to_string(shading));
      const Pixel p = render_centre(s, path, shading, isa);
      EXPECT_PIXEL_NEAR(p, step(0.25), step(0.5), step(0.75), 255);
    }
  }
}

// Vertex colours replace the material's ambient and diffuse: a mesh whose vertices all carry c
// renders as the same mesh with ambient = diffuse = c.
TEST(Surfaces, VertexColoursActAsTheMaterialColour) {
  Scene a = make_default_scene();
  Scene b = a;
  const Color3 c(0.9f, 0.3f, 0.5f);
  for (std::size_t o = 0; o < a.objects.size(); ++o) {
    Mesh& mesh = a.meshes[a.objects[o].mesh].mesh;
    mesh.colors.assign(mesh.vertex_count(), c);
    b.materials[b.objects[o].material].ambient = c;
    b.materials[b.objects[o].material].diffuse = c;
  }
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (auto [path, isa] : every_path()) {
      SCOPED_TRACE(std::string(to_string(path)) + " " + to_string(isa) + " " + to_string(shading));
      Canvas ca(160, 120), cb(160, 120);
      RenderOptions o = test::gl_options();
      o.path = path;
      o.isa = isa;
      o.shading = shading;
      Renderer r;
      ASSERT_TRUE(r.render(a, o, ca.view()).ok());
      ASSERT_TRUE(r.render(b, o, cb.view()).ok());
      const auto pa = ca.pixels(), pb = cb.pixels();
      int worst = 0;
      for (std::size_t i = 0; i < pa.size(); ++i) worst = std::max(worst, std::abs(int(pa[i]) - int(pb[i])));
      EXPECT_LE(worst, 1);
    }
  }
}

// Blending over an opaque red quad, every mode against its GL formula.
TEST(Surfaces, BlendModesFollowGL) {
  const Color3 dst(0.8f, 0.2f, 0.4f), src(0.3f, 0.6f, 0.9f);
  const double As = 0.25, Ad = 1.0;
  for (BlendMode mode : {BlendMode::alpha, BlendMode::premultiplied, BlendMode::add, BlendMode::multiply, BlendMode::subtract}) {
    Scene s = test::camera_scene();
    test::add_quad(s, -5, -5, 5, 5, -4, dst);
    test::add_quad(s, -5, -5, 5, 5, -3, src);
    s.materials.back().blend = mode;
    s.materials.back().alpha = static_cast<float>(As);
    double out[4] = {};
    for (int k = 0; k < 4; ++k) {
      const double cs = k < 3 ? src[k] : As, cd = k < 3 ? dst[k] : Ad;
      switch (mode) {
        case BlendMode::alpha: out[k] = cs * As + cd * (1 - As); break;
        case BlendMode::premultiplied: out[k] = cs + cd * (1 - As); break;
        case BlendMode::add: out[k] = cs + cd; break;
        case BlendMode::multiply: out[k] = cs * cd; break;
        case BlendMode::subtract: out[k] = cd - cs; break;
        case BlendMode::opaque: out[k] = cs; break;
      }
    }
    for (auto [path, isa] : every_path()) {
      for (ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
        SCOPED_TRACE(std::string(to_string(mode)) + " " + to_string(path) + " " + to_string(isa) + " " + to_string(shading));
        const Pixel p = render_centre(s, path, shading, isa);
        EXPECT_PIXEL_NEAR(p, step(out[0]), step(out[1]), step(out[2]), step(out[3]));
      }
    }
  }
}

// Blended geometry tests depth but does not write it (by default): an opaque quad behind it drawn
// afterwards still covers the pixel. With depth_write on, it hides the later quad.
TEST(Surfaces, BlendedGeometryDoesNotWriteDepthByDefault) {
  for (DepthWrite dw : {DepthWrite::automatic, DepthWrite::on}) {
    Scene s = test::camera_scene();
    test::add_quad(s, -5, -5, 5, 5, -3, Color3(1, 1, 1));
    s.materials.back().blend = BlendMode::alpha;
    s.materials.back().alpha = 0.5f;
    s.materials.back().depth_write = dw;
    test::add_quad(s, -5, -5, 5, 5, -4, Color3(0, 1, 0));  // behind, submitted after
    for (auto [path, isa] : every_path()) {
      SCOPED_TRACE(std::string(to_string(dw)) + " " + to_string(path) + " " + to_string(isa));
      const Pixel p = render_centre(s, path, ShadingMode::gouraud, isa);
      if (dw == DepthWrite::automatic) {
        EXPECT_PIXEL_NEAR(p, 0, 255, 0, 255);
      } else {  // white at 0.5 over the clear colour (0.25, 0.5, 0.75, 1)
        EXPECT_PIXEL_NEAR(p, step(0.625), step(0.75), step(0.875), step(0.75));
      }
    }
  }
}

// The alpha test keeps fragments with alpha >= cutoff: exactly at the cutoff is kept.
TEST(Surfaces, AlphaTestKeepsAlphaAtTheCutoff) {
  const std::uint8_t a8 = 128;
  const float a = a8 / 255.0f;
  for (float cutoff : {a, std::nextafter(a, 1.0f)}) {
    Scene s = test::camera_scene();
    s.textures.push_back(texture_from(1, 1, TextureFilter::nearest, [&](int, int) {
      return std::array<std::uint8_t, 4>{255, 255, 255, a8};
    }));
    test::add_quad(s, -5, -5, 5, 5, -3, Color3(1, 0, 0));
    add_uvs(s);
    s.materials.back().diffuse_texture = 0;
    s.materials.back().alpha_cutoff = cutoff;
    for (auto [path, isa] : every_path()) {
      for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
        SCOPED_TRACE(std::to_string(cutoff) + " " + to_string(path) + " " + to_string(isa) + " " + to_string(shading));
        const Pixel p = render_centre(s, path, shading, isa);
        if (cutoff == a) {
          EXPECT_PIXEL_NEAR(p, 255, 0, 0, a8);
        } else {
          EXPECT_PIXEL_NEAR(p, step(0.25), step(0.5), step(0.75), 255);  // the clear colour
        }
      }
    }
  }
}

// Fog at a known eye depth (3): linear, exp and exp2 against their formulas; start = end is a step;
// density 0 is no fog.
TEST(Surfaces, FogFollowsGL) {
  struct Case {
    FogMode mode;
    float start, end, density;
    double f;
  };
  const double z = 3.0;
  const Case cases[] = {{FogMode::linear, 1, 5, 1, (5 - z) / 4},  {FogMode::linear, 3.5, 3.5, 1, 1.0},
                        {FogMode::linear, 2.5, 2.5, 1, 0.0},      {FogMode::exp, 0, 1, 0.3f, std::exp(-0.3 * z)},
                        {FogMode::exp2, 0, 1, 0.3f, std::exp(-(0.3 * z) * (0.3 * z))}, {FogMode::exp, 0, 1, 0, 1.0}};
  const Color3 e(0.9f, 0.1f, 0.5f), fog(0.2f, 0.6f, 1.0f);
  for (const Case& c : cases) {
    Scene s = test::camera_scene();
    test::add_quad(s, -5, -5, 5, 5, -static_cast<float>(z), e);
    s.fog.mode = c.mode;
    s.fog.color = fog;
    s.fog.start = c.start, s.fog.end = c.end, s.fog.density = c.density;
    // Untextured, and through a one-texel texture t (modulate): a Phong draw then carries the
    // texel beside the fog factor from before lighting to the fog stage.
    const std::array<std::uint8_t, 4> t = {153, 255, 204, 255};
    for (const bool textured : {false, true}) {
      if (textured) {
        add_uvs(s);
        s.textures = {texture_from(1, 1, TextureFilter::nearest, [&](int, int) { return t; })};
        s.materials.back().diffuse_texture = 0;
      }
      double want[3];
      for (int k = 0; k < 3; ++k) want[k] = c.f * e[k] * (textured ? t[k] / 255.0 : 1.0) + (1 - c.f) * fog[k];
      for (auto [path, isa] : every_path()) {
        for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
          SCOPED_TRACE(std::string(to_string(c.mode)) + " " + std::to_string(c.start) + " " + to_string(path) + " " +
                       to_string(isa) + " " + to_string(shading) + (textured ? " textured" : ""));
          const Pixel p = render_centre(s, path, shading, isa);
          EXPECT_PIXEL_NEAR(p, step(want[0]), step(want[1]), step(want[2]), 255);
        }
      }
    }
  }
}

TEST(Surfaces, DoneWhenSceneUsesEveryFeature) {
  const Scene s = surfaces_scene();
  ASSERT_TRUE(validate_scene(s).ok()) << validate_scene(s).message();
  int textured = 0, blended = 0;
  for (const Instance& inst : s.objects) {
    textured += s.materials[inst.material].diffuse_texture != kNoTexture;
    blended += s.materials[inst.material].blend != BlendMode::opaque;
  }
  EXPECT_GE(textured, 2);
  EXPECT_GE(blended, 1);
}

TEST(Surfaces, ByteIdenticalForAnyThreadCount) {
  const Scene s = surfaces_scene();
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
      RenderOptions o = test::gl_options();
      o.shading = shading;
      o.path = path;
      o.tile_size = 32;  // many tiles over the threads
      o.threads = 1;
      const auto one = render_pixels(s, o);
      for (int threads : {2, 8}) {
        o.threads = threads;
        EXPECT_TRUE(render_pixels(s, o) == one) << to_string(shading) << " " << to_string(path) << " threads " << threads;
      }
    }
    // Every ISA within a step of the others: the raster kernels do the same IEEE operations, but
    // the lighting kernels contract a*b+c with FMA on avx2 and avx512 (shade_simd.hpp), which moves
    // a few vertex colours by an ulp and so a few pixels by a step.
    std::vector<std::uint8_t> first;
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      if (!isa_supported(isa)) continue;
      RenderOptions o = test::gl_options();
      o.shading = shading;
      o.isa = isa;
      const auto pixels = render_pixels(s, o);
      if (first.empty()) {
        first = pixels;
      } else {
        int worst = 0;
        for (std::size_t i = 0; i < pixels.size(); ++i) worst = std::max(worst, std::abs(int(pixels[i]) - int(first[i])));
        EXPECT_LE(worst, 1) << to_string(shading) << " " << to_string(isa);
      }
    }
  }
}

// Scalar and SIMD rasterizers run the same pixel program on the same planes: within a step, and
// almost every pixel identical, in either tier (the 16-bit tier's fixed-point sampler has a scalar
// twin of the same bytes; the step is the lighting's, see ByteIdenticalForAnyThreadCount). The
// fast tier is not the exact one: its textured pixels differ (within 2 steps).
TEST(Surfaces, SimdMatchesScalar) {
  const Scene s = surfaces_scene();
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    std::vector<std::uint8_t> scalar_exact;
    for (PixelPrecision precision : {PixelPrecision::exact, PixelPrecision::fast}) {
      RenderOptions a = test::gl_options(), b = test::gl_options();
      a.shading = b.shading = shading;
      a.path = LightingPath::scalar;
      b.path = LightingPath::simd;
      a.pixel_precision = b.pixel_precision = precision;
      const auto pa = render_pixels(s, a), pb = render_pixels(s, b);
      int worst = 0;
      std::size_t differ = 0;
      for (std::size_t i = 0; i < pa.size(); ++i) {
        const int d = std::abs(int(pa[i]) - int(pb[i]));
        worst = std::max(worst, d);
        differ += d != 0;
      }
      EXPECT_LE(worst, 1) << to_string(shading) << " " << to_string(precision);
      EXPECT_LE(differ, pa.size() / 100) << to_string(shading) << " " << to_string(precision);
      if (precision == PixelPrecision::exact) {
        scalar_exact = pa;
      } else {
        int from_exact = 0;
        for (std::size_t i = 0; i < pa.size(); ++i) from_exact = std::max(from_exact, std::abs(int(pa[i]) - int(scalar_exact[i])));
        EXPECT_LE(from_exact, 2) << to_string(shading);
        EXPECT_FALSE(pa == scalar_exact) << to_string(shading) << ": the scalar path ran the exact tier";
      }
    }
  }
}

// Multisampled surfaces: the SIMD programs shade each pixel once and store, blend and alpha-test
// into each sample (the textured ones a batch at a time); the scalar path runs the stages once per
// sample. Textures, blending, fog and an alpha-tested ground, every shading mode, 4 and 16 samples.
TEST(Surfaces, MultisampledSimdMatchesScalar) {
  Scene s = surfaces_scene();
  // The ground alpha-tested against a checker of transparent and opaque squares.
  s.textures.push_back(texture_from(16, 16, TextureFilter::nearest, [](int i, int j) {
    return std::array<std::uint8_t, 4>{200, 180, 90, static_cast<std::uint8_t>((i / 2 + j / 2) % 2 ? 255 : 0)};
  }));
  for (const Instance& inst : s.objects) {
    Material& m = s.materials[inst.material];
    if (m.diffuse_texture == 0) m.diffuse_texture = static_cast<std::int32_t>(s.textures.size() - 1), m.alpha_cutoff = 0.5f;
  }
  for (int samples : {4, 16}) {
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      RenderOptions a = test::gl_options(), b = test::gl_options();
      a.shading = b.shading = shading;
      a.samples = b.samples = samples;
      a.path = LightingPath::scalar;
      b.path = LightingPath::simd;
      const auto pa = render_pixels(s, a, 160, 120), pb = render_pixels(s, b, 160, 120);
      int worst = 0;
      std::size_t differ = 0, far = 0;
      for (std::size_t i = 0; i < pa.size(); ++i) {
        const int d = std::abs(int(pa[i]) - int(pb[i]));
        worst = std::max(worst, d);
        differ += d != 0;
        far += d > 2;
      }
      // Depth interpolated from planes (SIMD) or barycentrics (scalar) can order two surfaces that
      // meet differently at a sample: at most one sample's share of a pixel, at few pixels
      // (measured: one pixel, 7 steps, at 16 samples).
      EXPECT_LE(worst, 2 + 255 / samples) << samples << " samples, " << to_string(shading);
      EXPECT_LE(far, pa.size() / 1000) << samples << " samples, " << to_string(shading);
      EXPECT_LE(differ, pa.size() / 100) << samples << " samples, " << to_string(shading);
    }
  }
}

// The SIMD kernels run opaque GL_MODULATE textured Gouraud draws without fog through a specialised
// program (raster_simd.hpp, modulate_batch). Fog whose factor is exactly 1 everywhere (a linear
// step at 1e6: f = 1, so c * 1 + fog * 0 = c) sends the same draws through the general program;
// the pictures must be the same bytes, on every ISA and for every texture filter.
// The specialised program (modulate_fast in raster_simd.hpp) against the general one, which an
// alpha test that every fragment passes forces (the textures are opaque, the textured materials'
// alpha is 1): the same bits, with each fog mode and none.
TEST(Surfaces, SpecialisedModulateProgramEqualsTheGeneralOne) {
  for (TextureFilter filter : {TextureFilter::nearest, TextureFilter::bilinear, TextureFilter::trilinear}) {
    for (FogMode fog : {FogMode::none, FogMode::linear, FogMode::exp, FogMode::exp2}) {
      Scene fast = surfaces_scene();
      fast.fog.mode = fog;
      fast.fog.density = 0.05f;
      if (filter != TextureFilter::trilinear) {  // every texture single-level (the last one is bilinear)
        Texture single = fast.textures.back();
        single.filter = filter;
        for (Texture& t : fast.textures) t = single;
      }
      Scene general = fast;
      int textured = 0;
      for (Material& m : general.materials) {
        if (m.diffuse_texture == kNoTexture) continue;
        ASSERT_EQ(m.alpha, 1.0f);
        m.alpha_cutoff = 1e-6f;
        ++textured;
      }
      ASSERT_GE(textured, 2);
      for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
        if (!isa_supported(isa)) continue;
        RenderOptions o = test::gl_options();
        o.shading = ShadingMode::gouraud;
        o.path = LightingPath::simd;
        o.isa = isa;
        o.pixel_precision = PixelPrecision::exact;  // the float tier's programs (the 16-bit tier has no general twin)
        const auto a = render_pixels(fast, o), b = render_pixels(general, o);
        EXPECT_TRUE(a == b) << to_string(isa) << " " << to_string(filter) << " " << to_string(fog);
      }
    }
  }
}

// The fused blended programs (BlendProgram in pixel/programs_simd.hpp: Gouraud, untextured, alpha,
// premultiplied or additive blending) against the general program, which an alpha test every
// fragment passes forces: the same bytes on every ISA and for 3 threads, with the layers
// overlapping each other, an opaque backdrop and an opaque quad hiding part of them, some writing
// depth and some not.
TEST(Surfaces, FusedBlendProgramsEqualTheGeneralOne) {
  for (BlendMode mode : {BlendMode::alpha, BlendMode::premultiplied, BlendMode::add}) {
    Scene fused = test::camera_scene();
    test::add_quad(fused, -3, -3, 3, 3, -4, Color3(0.2f, 0.4f, 0.6f));  // opaque backdrop
    test::add_quad(fused, 0.5f, 0.5f, 3, 3, -3.0f, Color3(0.7f, 0.7f, 0.1f));  // hides the far layers' corner
    for (int i = 0; i < 4; ++i) {
      const float o = 0.4f * static_cast<float>(i);
      test::add_quad(fused, -1.5f + o, -1.2f + o * 0.5f, 0.8f + o, 1.0f + o * 0.3f, -3.5f + 0.3f * static_cast<float>(i),
                     Color3(0.9f - 0.2f * static_cast<float>(i), 0.3f + 0.15f * static_cast<float>(i), 0.5f));
      Material& m = fused.materials.back();
      m.diffuse = Color3(0.5f, 0.6f, 0.7f);  // lit by the point light: colours vary across each quad
      m.blend = mode;
      m.alpha = 0.3f + 0.15f * static_cast<float>(i);
      m.depth_write = i % 2 == 0 ? DepthWrite::on : DepthWrite::automatic;
    }
    Light l;
    l.type = LightType::point;
    l.position = Vec3(0.5f, 0.3f, -2.0f);
    fused.lights.push_back(l);
    Scene general = fused;
    for (Material& m : general.materials) {
      if (m.blend != BlendMode::opaque) m.alpha_cutoff = 1e-6f;
    }
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      if (!isa_supported(isa)) continue;
      RenderOptions o = test::gl_options();
      o.shading = ShadingMode::gouraud;
      o.path = LightingPath::simd;
      o.isa = isa;
      const auto a = render_pixels(fused, o), b = render_pixels(general, o);
      EXPECT_TRUE(a == b) << to_string(isa) << " " << to_string(mode);
      o.threads = 3;
      EXPECT_TRUE(render_pixels(fused, o) == a) << to_string(isa) << " " << to_string(mode) << " threads 3";
    }
  }
}

// The 16-bit tier (RenderOptions::pixel_precision fast): the surfaces
// scene's textured draws (the fused modulate programs and the general program's blended,
// alpha-tested and other-environment draws), with each filter and fog mode, are the same bytes
// for 1, 2 and 8 threads; within 2 steps of the exact tier (its sampler's contract under colours <= 1) and not
// the same picture (the tier ran); with sRGB textures, which it leaves to the float programs,
// the same bytes as the exact tier.
TEST(Surfaces, FastPixelTierHoldsItsContract) {
  for (TextureFilter filter : {TextureFilter::nearest, TextureFilter::bilinear, TextureFilter::trilinear}) {
    for (FogMode fog : {FogMode::none, FogMode::linear}) {
      Scene s = surfaces_scene();
      s.fog.mode = fog;
      if (filter != TextureFilter::trilinear) {
        Texture single = s.textures.back();
        single.filter = filter;
        for (Texture& t : s.textures) t = single;
      }
      RenderOptions o = test::gl_options();
      o.shading = ShadingMode::gouraud;
      o.pixel_precision = PixelPrecision::fast;
      o.tile_size = 32;
      o.threads = 1;
      const auto fast = render_pixels(s, o);
      for (int threads : {2, 8}) {
        o.threads = threads;
        EXPECT_TRUE(render_pixels(s, o) == fast) << to_string(filter) << " threads " << threads;
      }
      o.pixel_precision = PixelPrecision::exact;
      const auto exact = render_pixels(s, o);
      int worst = 0;
      for (std::size_t i = 0; i < fast.size(); ++i) worst = std::max(worst, std::abs(int(fast[i]) - int(exact[i])));
      std::printf("fast pixel tier, %s, fog %s: largest difference from the exact tier %d steps\n", to_string(filter),
                  to_string(fog), worst);
      EXPECT_LE(worst, 2) << to_string(filter) << " " << to_string(fog);
      if (filter != TextureFilter::nearest) {
        EXPECT_FALSE(fast == exact) << to_string(filter) << ": the tier did not run";
      }
      for (Texture& t : s.textures) t.encoding = TextureEncoding::srgb;
      o.pixel_precision = PixelPrecision::fast;
      const auto srgb_fast = render_pixels(s, o);
      o.pixel_precision = PixelPrecision::exact;
      EXPECT_TRUE(srgb_fast == render_pixels(s, o)) << to_string(filter) << ": sRGB textures stay exact";
    }
  }
}

// Emission after the texture (Material::emission_after_texture, glTF's rule): a quad lit by one
// light towards the camera (n.l = 1, so the lit colour is the diffuse D plus the scene's ambient
// times the material's), under a one-texel diffuse texture T and emission E, times a one-texel
// emissive texture Te where there is one. GL's rule modulates the emission with T; glTF's adds it
// after T; each on every path and shading mode.
TEST(Surfaces, EmissionAfterTheTextureFollowsGltf) {
  const Color3 E(0.3f, 0.1f, 0.05f), D(0.5f, 0.25f, 0.75f);
  const std::array<std::uint8_t, 4> t = {128, 255, 64, 255}, te = {255, 128, 0, 51};
  const double T[3] = {128 / 255.0, 1.0, 64 / 255.0}, Te[3] = {1.0, 128 / 255.0, 0.0};
  struct Case {
    const char* name;
    bool diffuse_texture, emissive_texture, after;
  };
  for (const Case k : {Case{"gl", true, false, false}, Case{"after", true, false, true}, Case{"both textures", true, true, true},
                       Case{"emissive texture alone", false, true, false}}) {
    Scene s = test::camera_scene();
    s.textures.push_back(texture_from(1, 1, TextureFilter::bilinear, [&](int, int) { return t; }));
    s.textures.push_back(texture_from(1, 1, TextureFilter::nearest, [&](int, int) { return te; }));
    test::add_quad(s, -5, -5, 5, 5, -3, E);
    add_uvs(s);
    Material& m = s.materials.back();
    m.ambient = Color3::Zero();
    m.diffuse = D;
    m.diffuse_texture = k.diffuse_texture ? 0 : kNoTexture;
    m.emissive_texture = k.emissive_texture ? 1 : kNoTexture;
    m.emission_after_texture = k.after;
    Light l;  // towards the camera: n.l = 1
    l.direction = Vec3(0, 0, -1);
    s.lights.push_back(l);
    double c[3];
    for (int ch = 0; ch < 3; ++ch) {
      const double t_ch = k.diffuse_texture ? T[ch] : 1.0, e_ch = E[ch] * (k.emissive_texture ? Te[ch] : 1.0);
      c[ch] = k.after || k.emissive_texture ? std::min(1.0, D[ch] * t_ch + e_ch) : (E[ch] + D[ch]) * t_ch;
    }
    for (auto [path, isa] : every_path()) {
      for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
        SCOPED_TRACE(std::string(k.name) + " " + to_string(path) + " " + to_string(isa) + " " + to_string(shading));
        const Pixel p = render_centre(s, path, shading, isa);
        EXPECT_PIXEL_NEAR(p, step(c[0]), step(c[1]), step(c[2]), 255);  // the emissive texel's alpha is not read
      }
    }
  }
}

// Without a texture, emission after the texture is emission in the lighting: the same bytes (the
// frame plan adds no stage), and no emission at all adds none either.
TEST(Surfaces, EmissionStageOnlyWhereItChangesSomething) {
  Scene gl = make_default_scene();
  for (Material& m : gl.materials) {
    m.emissive = Color3(0.1f, 0.2f, 0.05f);
    m.diffuse_texture = kNoTexture;
  }
  Scene after = gl;
  for (Material& m : after.materials) m.emission_after_texture = true;
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    RenderOptions o = test::gl_options();
    o.shading = shading;
    EXPECT_TRUE(render_pixels(gl, o) == render_pixels(after, o)) << to_string(shading);
  }
}

// The done-when scene with emissive textures: on the textured ground (after its checker), on the
// blended sphere (no diffuse texture) and on a plain sphere under emission_after_texture alone.
Scene emissive_scene() {
  Scene s = surfaces_scene();
  s.textures.push_back(texture_from(16, 16, TextureFilter::trilinear, [](int i, int j) {
    const bool lit = (i % 4 == 0) || (j % 4 == 0);
    return std::array<std::uint8_t, 4>{static_cast<std::uint8_t>(lit ? 255 : 0), static_cast<std::uint8_t>(lit ? 180 : 0),
                                       static_cast<std::uint8_t>(lit ? 40 : 0), 255};
  }));
  const auto glow = static_cast<std::int32_t>(s.textures.size() - 1);
  for (std::size_t o = 0; o < s.objects.size(); ++o) {
    Material& m = s.materials[s.objects[o].material];
    if (m.diffuse_texture == 0) {  // the ground
      m.emissive = Color3(0.6f, 0.5f, 0.4f);
      m.emissive_texture = glow;
    } else if (m.blend != BlendMode::opaque) {
      m.emissive = Color3(1.0f, 1.0f, 1.0f);
      m.emissive_texture = glow;
    } else if (m.diffuse_texture == 1) {
      m.emissive = Color3(0.2f, 0.1f, 0.1f);
      m.emission_after_texture = true;
    }
  }
  return s;
}

TEST(Surfaces, EmissiveTexturesSameBytesForAllThreadsAndEveryPath) {
  const Scene s = emissive_scene();
  ASSERT_TRUE(validate_scene(s).ok()) << validate_scene(s).message();
  for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    RenderOptions o = test::gl_options();
    o.shading = shading;
    o.tile_size = 32;
    std::vector<std::uint8_t> scalar;
    for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
      o.path = path;
      o.threads = 1;
      const auto one = render_pixels(s, o);
      for (int threads : {2, 8}) {
        o.threads = threads;
        EXPECT_TRUE(render_pixels(s, o) == one) << to_string(shading) << " " << to_string(path) << " threads " << threads;
      }
      if (path == LightingPath::scalar) {
        scalar = one;
        continue;
      }
      int worst = 0;
      std::size_t differ = 0;
      for (std::size_t i = 0; i < one.size(); ++i) {
        const int d = std::abs(int(one[i]) - int(scalar[i]));
        worst = std::max(worst, d);
        differ += d != 0;
      }
      EXPECT_LE(worst, 2) << to_string(shading);
      EXPECT_LE(differ, one.size() / 100) << to_string(shading);
    }
    // The emission shows: the picture is not the one without it.
    EXPECT_FALSE(render_pixels(s, o) == render_pixels(surfaces_scene(), o)) << to_string(shading);
  }
}

TEST(Surfaces, BadSurfaceInputIsRefusedWithItsField) {
  auto expect_field = [](const Scene& s, const std::string& field) {
    const Status st = validate_scene(s);
    EXPECT_FALSE(st.ok()) << field;
    EXPECT_EQ(st.field(), field) << st.message();
  };
  Scene base = test::camera_scene();
  test::add_quad(base, -1, -1, 1, 1, -3, Color3(1, 1, 1));
  add_uvs(base);
  base.textures.push_back(texture_from(2, 2, TextureFilter::nearest, [](int, int) {
    return std::array<std::uint8_t, 4>{1, 2, 3, 4};
  }));
  ASSERT_TRUE(validate_scene(base).ok());
  Scene s = base;
  s.materials[0].uv_scale = Vec2(0, 1);
  expect_field(s, "materials[0].uv_scale");
  s = base;
  s.materials[0].uv_scale = Vec2(1, std::nanf(""));
  expect_field(s, "materials[0].uv_scale");
  s = base;
  s.materials[0].diffuse_texture = 1;
  expect_field(s, "materials[0].diffuse_texture");
  s = base;
  s.materials[0].diffuse_texture = 0;
  s.meshes[0].mesh.uvs.clear();
  expect_field(s, "objects[0].material");
  s = base;
  s.materials[0].emissive_texture = 1;
  expect_field(s, "materials[0].emissive_texture");
  s = base;
  s.materials[0].emissive_texture = -2;
  expect_field(s, "materials[0].emissive_texture");
  s = base;
  s.materials[0].emissive_texture = 0;
  s.meshes[0].mesh.uvs.clear();
  expect_field(s, "objects[0].material");
  s = base;
  s.materials[0].alpha_cutoff = 1.5f;
  expect_field(s, "materials[0].alpha_cutoff");
  s = base;
  s.fog.mode = FogMode::linear;
  s.fog.start = 5, s.fog.end = 4;
  expect_field(s, "fog.end");
  s = base;
  s.fog.density = -1;
  expect_field(s, "fog.density");
  s = base;
  s.materials[0].blend = static_cast<BlendMode>(9);
  expect_field(s, "materials[0].blend");
  // Nothing is drawn: render refuses before touching a pixel.
  s = base;
  s.materials[0].diffuse_texture = 3;
  Canvas c(16, 16);
  Renderer r;
  EXPECT_FALSE(r.render(s, test::gl_options(), c.view()).ok());
  EXPECT_TRUE(c.untouched());
}

}  // namespace
}  // namespace facet
