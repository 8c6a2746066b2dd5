// The pixel tiers' contract in whole frames (RenderOptions::pixel_precision, exact and fast): a
// textured quad facing the camera and reaching past the view, so that each pixel's texture
// coordinates and their derivatives are known in closed form, rendered and compared pixel by pixel
// with GL 2.1's stages computed here in double precision on the reference sampler
// (texture::sample_reference): texture environment, fog, alpha test and blending over the clear
// colour. Errors are in 8-bit steps, |byte - 255 x exact value|, so the 8-bit rounding alone is
// up to 0.5. Per filter over texture sizes (1 x 1 to 16384 x 2, each with one of the three wrap
// modes), magnification to 1024x and minification to 40 texels a pixel, and UVs offset by 0 or 37
// before the material's scale (cases where the scaled coordinate times the texture's width passes
// 65536 are left out: there a float coordinate no longer holds 1/256 texel, in either tier); per
// texture environment, blend mode, fog and alpha test; on the scalar path and every SIMD ISA.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include "texture/sampler.hpp"
#include "render_support.hpp"

namespace facet {
namespace {

using test::Canvas;

constexpr int kN = 48;  // the frame is kN x kN
constexpr float kAlpha = 0.7f;
const Color3 kColour(0.8f, 0.45f, 0.3f);                    // the quad's primary colour (emissive)
constexpr std::array<float, 4> kClear = {0.25f, 0.5f, 0.75f, 1.0f};
const Color3 kFogColour(0.2f, 0.6f, 0.9f);
constexpr float kFogStart = 1.0f, kFogEnd = 5.0f;  // the quad lies at depth 3: fog factor 1/2

Texture random_texture(int w, int h, TextureFilter filter, TextureWrap wrap, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  for (auto& b : rgba) b = static_cast<std::uint8_t>(rng() & 0xffu);
  TextureOptions o;
  o.filter = filter;
  o.wrap = wrap;
  Result<Texture> t = make_texture("random", w, h, rgba, o);
  EXPECT_TRUE(t.ok()) << t.status().message();
  return std::move(*t);
}

struct Surface {
  TextureMode env = TextureMode::modulate;
  BlendMode blend = BlendMode::opaque;
  bool fog = false;
  float cutoff = 0.0f;
  Vec2 scale{1.0f, 1.0f};  // Material::uv_scale
  float offset = 0.0f;     // added to both texture coordinates of the quad's corners
};

// The quad from (-6, -6) to (6, 6) at depth 3 in a 90-degree view: its corners project to
// -kN / 2 and 3 kN / 2, whole pixels, and its coordinates run from offset to offset + 1, so the
// pixel (x, y) (y down) has u = scale (offset + 1/2 + ndc_x / 4), v = scale (offset + 1/2 + ndc_y / 4).
Scene quad_scene(const Texture& texture, const Surface& f) {
  Scene s = test::camera_scene();
  s.textures.push_back(texture);
  test::add_quad(s, -6, -6, 6, 6, -3, kColour);
  const float o = f.offset;
  s.meshes.back().mesh.uvs = {Vec2(o, o), Vec2(o + 1, o), Vec2(o + 1, o + 1), Vec2(o, o + 1)};
  Material& m = s.materials.back();
  m.diffuse_texture = 0;
  m.texture_mode = f.env;
  m.alpha = kAlpha;
  m.blend = f.blend;
  m.alpha_cutoff = f.cutoff;
  m.uv_scale = f.scale;
  if (f.fog) {
    s.fog.mode = FogMode::linear;
    s.fog.color = kFogColour;
    s.fog.start = kFogStart, s.fog.end = kFogEnd;
  }
  return s;
}

struct Errors {
  double worst = 0, sum = 0;
  std::size_t count = 0, skipped = 0;
  void add(double d) { worst = std::max(worst, d), sum += d, ++count; }
  double mean() const { return count ? sum / double(count) : 0.0; }
  void merge(const Errors& e) { worst = std::max(worst, e.worst), sum += e.sum, count += e.count, skipped += e.skipped; }
};

// The frame against the stages in double precision, into `e`. Pixels are skipped (counted) where
// the exact answer is ambiguous at the precision of the inputs: a nearest sample within 1e-3 of a
// pixel's step from a texel border, or a fragment alpha within 3 steps of the alpha test's cutoff.
void compare(const Scene& s, const Surface& f, RenderOptions o, Errors& e) {
  Canvas c(kN, kN);
  o.clear_color = kClear;
  Renderer r;
  const Status st = r.render(s, o, c.view());
  ASSERT_TRUE(st.ok()) << st.message();
  const texture::Sampler sampler = texture::make_sampler(s.textures[0]);
  const double su = f.scale.x(), sv = f.scale.y();
  const double dudx = su / (2.0 * kN), dvdy = -sv / (2.0 * kN);
  const double lambda = texture::lod_reference(sampler, dudx, 0.0, 0.0, dvdy);
  const bool nearest = s.textures[0].filter == TextureFilter::nearest;
  for (int y = 0; y < kN; ++y) {
    for (int x = 0; x < kN; ++x) {
      const double ndc_x = (x + 0.5) / kN * 2.0 - 1.0, ndc_y = 1.0 - (y + 0.5) / kN * 2.0;
      const double u = su * (f.offset + 0.5 + ndc_x / 4.0), v = sv * (f.offset + 0.5 + ndc_y / 4.0);
      const auto t = texture::sample_reference(sampler, u, v, lambda);
      if (nearest) {
        bool border = false;
        for (double du : {-1e-3, 1e-3})
          for (double dv : {-1e-3, 1e-3}) border = border || texture::sample_reference(sampler, u + du * dudx, v + dv * dvdy, lambda) != t;
        if (border) {
          ++e.skipped;
          continue;
        }
      }
      double cf[3] = {kColour.x(), kColour.y(), kColour.z()}, c4[4];
      const double af = kAlpha;
      for (int k = 0; k < 3; ++k) {
        switch (f.env) {
          case TextureMode::modulate: c4[k] = cf[k] * t[k]; break;
          case TextureMode::replace: c4[k] = t[k]; break;
          case TextureMode::decal: c4[k] = cf[k] * (1 - t[3]) + t[k] * t[3]; break;
          case TextureMode::add: c4[k] = std::min(1.0, cf[k] + t[k]); break;
          default: c4[k] = cf[k] * t[k]; break;
        }
      }
      c4[3] = f.env == TextureMode::replace ? t[3] : f.env == TextureMode::decal ? af : af * t[3];
      if (f.fog) {
        const double fog = (double(kFogEnd) - 3.0) / (double(kFogEnd) - double(kFogStart));
        const double fc[3] = {kFogColour.x(), kFogColour.y(), kFogColour.z()};
        for (int k = 0; k < 3; ++k) c4[k] = fog * c4[k] + (1 - fog) * fc[k];
      }
      double out[4];
      for (int k = 0; k < 4; ++k) out[k] = kClear[static_cast<std::size_t>(k)];
      if (f.cutoff > 0.0f && std::abs(c4[3] - f.cutoff) < 3.0 / 255.0) {
        ++e.skipped;
        continue;
      }
      if (c4[3] >= f.cutoff) {
        const double a = c4[3];
        for (int k = 0; k < 4; ++k) {
          const double d = out[k], src = c4[k];
          double b = src;
          switch (f.blend) {
            case BlendMode::alpha: b = src * a + d * (1 - a); break;
            case BlendMode::premultiplied: b = src + d * (1 - a); break;
            case BlendMode::add: b = src + d; break;
            case BlendMode::multiply: b = src * d; break;
            case BlendMode::subtract: b = d - src; break;
            default: break;
          }
          out[k] = std::clamp(b, 0.0, 1.0);
        }
      }
      double d = 0;
      for (int k = 0; k < 4; ++k) d = std::max(d, std::abs(c.byte(x, y, k) - 255.0 * out[k]));
      e.add(d);
    }
  }
}

std::vector<std::pair<LightingPath, Isa>> paths() {
  std::vector<std::pair<LightingPath, Isa>> p = {{LightingPath::scalar, Isa::best}};
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) p.push_back({LightingPath::simd, isa});
  return p;
}

// Each filter over texture sizes, wrap modes, magnifications (0.001 to 40 texels a pixel along u)
// and coordinate offsets, in GL_MODULATE, opaque: both tiers on every path. Bounds (measured
// 2026-11-27 in brackets, the same on every path and ISA): the exact tier 1.1 steps (1.00: the
// 8-bit rounding plus the float coordinates' error at offset UVs on a random texture, whose
// texels change by up to 255 steps from one to the next); the fast tier nearest as the exact one
// (the same texel), bilinear and trilinear 2 steps (1.80, 1.51: its sampler's contract,
// TextureSampler.FixedPointContractAgainstReference, plus the same coordinate error); its mean at
// most 0.15 steps above the exact tier's (+0.07, +0.09).
TEST(PixelTiers, FiltersHoldTheirContractInFrames) {
  struct Size {
    int w, h;
  };
  const Size sizes[] = {{1, 1}, {3, 5}, {64, 32}, {256, 256}, {16384, 2}};
  const TextureWrap wraps[] = {TextureWrap::repeat, TextureWrap::mirror, TextureWrap::clamp};
  const double texels_per_pixel[] = {1.0 / 1024, 1.0 / 16, 0.7, 3.0, 40.0};
  struct Bound {
    TextureFilter filter;
    double exact_worst, fast_worst, fast_mean_above_exact;
  };
  for (const Bound bound : {Bound{TextureFilter::nearest, 1.1, 1.1, 0.0}, Bound{TextureFilter::bilinear, 1.1, 2.0, 0.15},
                            Bound{TextureFilter::trilinear, 1.1, 2.0, 0.15}}) {
    Errors tier[2];
    int n = 0;
    for (const Size size : sizes) {
      const TextureWrap wrap = wraps[n++ % 3];
      const Texture tex = random_texture(size.w, size.h, bound.filter, wrap, 11u + unsigned(n));
      for (const double t : texels_per_pixel) {
        for (const float offset : {0.0f, 37.0f}) {
          Surface f;
          // u' = scale u: t texels a pixel along u is scale = t 2 kN / w; v likewise over h,
          // isotropic for square textures.
          f.scale = Vec2(float(t * 2 * kN / size.w), float(t * 2 * kN / size.w));
          f.offset = offset;
          if (std::abs(f.scale.x() * (offset + 1.0f)) * float(size.w) > 65536.0f) continue;  // below float's sub-texel precision
          const Scene s = quad_scene(tex, f);
          for (auto [path, isa] : paths()) {
            for (int fast = 0; fast < 2; ++fast) {
              RenderOptions o = test::gl_options();
              o.path = path, o.isa = isa;
              o.pixel_precision = fast ? PixelPrecision::fast : PixelPrecision::exact;
              Errors e;
              compare(s, f, o, e);
              if (e.worst > (fast ? bound.fast_worst : bound.exact_worst)) {
                ADD_FAILURE() << to_string(bound.filter) << " " << size.w << "x" << size.h << " " << to_string(wrap)
                              << " texels/pixel " << t << " offset " << offset << " " << to_string(path) << " "
                              << to_string(isa) << " " << (fast ? "fast" : "exact") << ": largest " << e.worst;
              }
              tier[fast].merge(e);
            }
          }
        }
      }
    }
    for (int fast = 0; fast < 2; ++fast) {
      std::printf("%s tier, %s: largest %.3f, mean %.4f steps over %zu pixels (%zu on texel borders)\n",
                  fast ? "fast" : "exact", to_string(bound.filter), tier[fast].worst, tier[fast].mean(), tier[fast].count,
                  tier[fast].skipped);
    }
    EXPECT_LE(tier[1].mean(), tier[0].mean() + bound.fast_mean_above_exact) << to_string(bound.filter);
    // Enough pixels compared on every path (about 97,000 a path for nearest, whose texel borders
    // are skipped): the count scales with the ISAs this CPU has.
    EXPECT_GT(tier[0].count, 90000u * paths().size());
    if (bound.filter != TextureFilter::nearest) {
      EXPECT_GT(tier[1].worst, tier[0].worst + 0.3) << to_string(bound.filter) << ": the fast tier did not run";
    }
  }
}

// Every texture environment, blend mode, fog and alpha test, bilinear and trilinear (magnified
// and between two levels), in both tiers on the scalar path and the best ISA: the same bounds
// (measured 2026-11-27: exact 0.52, fast 1.73 bilinear and 1.79 trilinear; means 0.41 and 0.48).
TEST(PixelTiers, StagesHoldTheirContractInFrames) {
  const TextureMode envs[] = {TextureMode::modulate, TextureMode::replace, TextureMode::decal, TextureMode::add};
  const BlendMode blends[] = {BlendMode::opaque, BlendMode::alpha, BlendMode::premultiplied, BlendMode::add, BlendMode::multiply,
                              BlendMode::subtract};
  for (TextureFilter filter : {TextureFilter::bilinear, TextureFilter::trilinear}) {
    const Texture tex = random_texture(64, 32, filter, TextureWrap::repeat, 3);
    Errors tier[2];
    for (TextureMode env : envs) {
      for (BlendMode blend : blends) {
        for (bool fog : {false, true}) {
          for (float cutoff : {0.0f, 0.5f}) {
            for (double t : {0.3, 1.6}) {
              Surface f;
              f.env = env, f.blend = blend, f.fog = fog, f.cutoff = cutoff;
              f.scale = Vec2(float(t * 2 * kN / 64), float(t * 2 * kN / 64));
              f.offset = 5.0f;
              const Scene s = quad_scene(tex, f);
              for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
                for (int fast = 0; fast < 2; ++fast) {
                  RenderOptions o = test::gl_options();
                  o.path = path;
                  o.pixel_precision = fast ? PixelPrecision::fast : PixelPrecision::exact;
                  Errors e;
                  compare(s, f, o, e);
                  const double bound = fast ? 2.0 : 1.1;
                  if (e.worst > bound) {
                    ADD_FAILURE() << to_string(filter) << " " << to_string(env) << " " << to_string(blend) << " fog " << fog
                                  << " cutoff " << cutoff << " texels/pixel " << t << " " << to_string(path) << " "
                                  << (fast ? "fast" : "exact") << ": largest " << e.worst;
                  }
                  tier[fast].merge(e);
                }
              }
            }
          }
        }
      }
    }
    for (int fast = 0; fast < 2; ++fast) {
      std::printf("%s tier, %s, every environment, blend, fog and alpha test: largest %.3f, mean %.4f steps over %zu pixels (%zu at the cutoff)\n",
                  fast ? "fast" : "exact", to_string(filter), tier[fast].worst, tier[fast].mean(), tier[fast].count, tier[fast].skipped);
    }
    EXPECT_LE(tier[1].mean(), tier[0].mean() + 0.15) << to_string(filter);
    EXPECT_GT(tier[0].count, 800000u);
    EXPECT_GT(tier[1].worst, tier[0].worst + 0.5) << to_string(filter) << ": the fast tier did not run";
  }
}

}  // namespace
}  // namespace facet
