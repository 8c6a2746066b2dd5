// The renderer through its public API: argument checking, pixel formats and layouts, depth,
// clipping, culling, statistics, determinism, and the classic Gouraud-versus-Phong case.
#include <cmath>
#include <limits>

#include "render_support.hpp"

namespace facet {
namespace {

using test::add_quad;
using test::camera_scene;
using test::Canvas;

const Color3 kRed(1, 0, 0), kGreen(0, 1, 0), kOrange(1, 0.5f, 0);

Status render(const Scene& s, const ImageView& view, FrameStats* stats = nullptr, RenderOptions options = {},
              const DepthView* depth = nullptr) {
  Renderer r;
  return r.render(s, options, view, depth, stats);
}

// --- Arguments are checked before anything is written.

TEST(RenderArguments, InvalidViewsAreRejectedAndNothingIsWritten) {
  Scene s = camera_scene();
  add_quad(s, -9, -9, 9, 9, -5, kRed);
  Canvas c(16, 8);
  struct Case {
    const char* field;
    ImageView view;
  };
  ImageView v = c.view();
  std::vector<Case> cases;
  cases.push_back({"image.data", [&] { ImageView x = v; x.data = nullptr; return x; }()});
  cases.push_back({"image.width", [&] { ImageView x = v; x.width = 0; return x; }()});
  cases.push_back({"image.height", [&] { ImageView x = v; x.height = -3; return x; }()});
  cases.push_back({"image.width", [&] { ImageView x = v; x.width = kMaxImageDimension + 1; return x; }()});
  cases.push_back({"image.stride_bytes", [&] { ImageView x = v; x.stride_bytes = 16 * 4 - 1; return x; }()});
  cases.push_back({"image.format", [&] { ImageView x = v; x.format = static_cast<PixelFormat>(7); return x; }()});
  for (const Case& k : cases) {
    const Status st = render(s, k.view);
    EXPECT_EQ(st.code(), ErrorCode::invalid_argument) << k.field;
    EXPECT_EQ(st.field(), k.field) << st.message();
  }
  EXPECT_TRUE(c.untouched());
}

TEST(RenderArguments, AbsurdSizeIsRefusedWithoutAllocating) {
  Scene s = camera_scene();
  std::uint8_t tiny[64];
  const ImageView huge{tiny, 100000, 100000, 400000, PixelFormat::rgba8, false};
  const Status st = render(s, huge);
  EXPECT_EQ(st.field(), "image.width");
  EXPECT_NE(st.message().find("16384"), std::string::npos) << st.message();
}

TEST(RenderArguments, DepthViewOptionsAndSceneAreChecked) {
  Scene s = camera_scene();
  add_quad(s, -9, -9, 9, 9, -5, kRed);
  Canvas c(16, 8);
  std::vector<float> depth(16 * 8, 7.0f);
  DepthView wrong{depth.data(), 8, 16, 8 * sizeof(float), false};
  Renderer r;
  EXPECT_EQ(r.render(s, {}, c.view(), &wrong).field(), "depth");
  RenderOptions bad_tile = test::gl_options();
  bad_tile.tile_size = 12;
  EXPECT_EQ(r.render(s, bad_tile, c.view()).field(), "options.tile_size");
  RenderOptions nan_clear = test::gl_options();
  nan_clear.clear_color[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(r.render(s, nan_clear, c.view()).field(), "options.clear_color");
  Scene broken = s;
  broken.meshes[0].mesh.triangles[1][2] = 99;
  EXPECT_EQ(r.render(broken, {}, c.view()).field(), "meshes[0].triangles[1]");
  EXPECT_TRUE(c.untouched());
  EXPECT_TRUE(std::all_of(depth.begin(), depth.end(), [](float d) { return d == 7.0f; }));
}

// --- Formats, orientation, strides.

TEST(RenderImage, PixelFormatsAndChannelOrder) {
  Scene s = camera_scene();
  add_quad(s, -9, -9, 9, 9, -5, kOrange);  // covers the whole view
  Canvas rgba(4, 4, PixelFormat::rgba8), bgra(4, 4, PixelFormat::bgra8), f32(4, 4, PixelFormat::rgba32f);
  ASSERT_TRUE(render(s, rgba.view()).ok());
  ASSERT_TRUE(render(s, bgra.view()).ok());
  ASSERT_TRUE(render(s, f32.view()).ok());
  // 8-bit output is sRGB-encoded by default: 0.5 is 0.7354 encoded, 187.5 + 0.5 rounds to 188.
  EXPECT_EQ(rgba.byte(2, 1, 0), 255);
  EXPECT_EQ(rgba.byte(2, 1, 1), 188);
  EXPECT_EQ(rgba.byte(2, 1, 2), 0);
  EXPECT_EQ(rgba.byte(2, 1, 3), 255);
  EXPECT_EQ(bgra.byte(2, 1, 0), 0);
  EXPECT_EQ(bgra.byte(2, 1, 1), 188);
  EXPECT_EQ(bgra.byte(2, 1, 2), 255);
  EXPECT_EQ(bgra.byte(2, 1, 3), 255);
  EXPECT_FLOAT_EQ(f32.channel_f(2, 1, 0), 1.0f);
  EXPECT_FLOAT_EQ(f32.channel_f(2, 1, 1), 0.5f);
  EXPECT_FLOAT_EQ(f32.channel_f(2, 1, 2), 0.0f);
  EXPECT_FLOAT_EQ(f32.channel_f(2, 1, 3), 1.0f);
}

TEST(RenderImage, HdrFloatOutputKeepsValuesAboveOne) {
  Scene s = camera_scene();
  add_quad(s, -9, -9, 9, 9, -5, Color3(3.0f, 0.25f, 0.0f));
  Canvas clamped(4, 4, PixelFormat::rgba32f), hdr(4, 4, PixelFormat::rgba32f);
  ASSERT_TRUE(render(s, clamped.view()).ok());
  RenderOptions o = test::gl_options();
  o.hdr = true;
  ASSERT_TRUE(render(s, hdr.view(), nullptr, o).ok());
  EXPECT_FLOAT_EQ(clamped.channel_f(1, 1, 0), 1.0f);
  EXPECT_FLOAT_EQ(hdr.channel_f(1, 1, 0), 3.0f);
  EXPECT_FLOAT_EQ(hdr.channel_f(1, 1, 1), 0.25f);
}

TEST(RenderImage, YUpFlipsRowsOnly) {
  Scene s = camera_scene();
  add_quad(s, -9, 0.5f, 9, 9, -5, kRed);  // the upper part of the view only
  Canvas down(5, 7, PixelFormat::rgba8, 0, false), up(5, 7, PixelFormat::rgba8, 0, true);
  ASSERT_TRUE(render(s, down.view()).ok());
  ASSERT_TRUE(render(s, up.view()).ok());
  EXPECT_EQ(down.byte(2, 0, 0), 255);  // y-down: memory row 0 is the top of the picture
  EXPECT_EQ(down.byte(2, 6, 0), 0);
  for (int y = 0; y < 7; ++y) EXPECT_EQ(std::memcmp(down.row(y), up.row(6 - y), 5 * 4), 0) << y;
}

TEST(RenderImage, OddSizesStridesAndTilesTouchOnlyPixels) {
  Scene s = test::camera_scene();
  add_quad(s, -3, -2, 4, 3, -5, kGreen);
  for (PixelFormat f : {PixelFormat::rgba8, PixelFormat::bgra8, PixelFormat::rgba32f}) {
    for (auto [w, h] : {std::pair{1, 1}, {1, 37}, {37, 1}, {67, 45}, {130, 129}}) {
      for (int tile : {8, 64}) {
        for (bool y_up : {false, true}) {
          Canvas c(w, h, f, 13, y_up);
          RenderOptions o = test::gl_options();
          o.tile_size = tile;
          ASSERT_TRUE(render(s, c.view(), nullptr, o).ok());
          EXPECT_TRUE(c.outside_pixels_untouched()) << to_string(f) << " " << w << "x" << h << " tile " << tile;
        }
      }
    }
  }
}

TEST(RenderImage, TileSizeDoesNotChangeAByte) {
  const Scene s = make_default_scene();
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    std::vector<std::uint8_t> first;
    for (int tile : {8, 16, 64, 256}) {
      Canvas c(161, 97);
      RenderOptions o = test::gl_options();
      o.shading = mode;
      o.tile_size = tile;
      ASSERT_TRUE(render(s, c.view(), nullptr, o).ok());
      if (first.empty()) first = c.pixels();
      else EXPECT_TRUE(c.pixels() == first) << to_string(mode) << " tile " << tile;
    }
  }
}

TEST(RenderImage, SameFrameTwiceIsIdentical) {
  const Scene s = make_default_scene();
  Renderer r;
  Canvas a(160, 120), b(160, 120);
  RenderOptions o = test::gl_options();
  o.shading = ShadingMode::phong;
  ASSERT_TRUE(r.render(s, o, a.view()).ok());
  ASSERT_TRUE(r.render(s, o, b.view()).ok());
  EXPECT_TRUE(a.pixels() == b.pixels());
}

// --- Depth.

TEST(RenderDepth, NearestWinsInEitherOrder) {
  for (bool near_first : {false, true}) {
    Scene s = camera_scene();
    if (near_first) add_quad(s, -9, -9, 9, 9, -3, kGreen);
    add_quad(s, -9, -9, 9, 9, -5, kRed);
    if (!near_first) add_quad(s, -9, -9, 9, 9, -3, kGreen);
    Canvas c(8, 8);
    ASSERT_TRUE(render(s, c.view()).ok());
    EXPECT_EQ(c.byte(3, 3, 0), 0) << near_first;
    EXPECT_EQ(c.byte(3, 3, 1), 255) << near_first;
  }
}

TEST(RenderDepth, EqualDepthKeepsTheFirstSubmitted) {
  Scene s = camera_scene();
  add_quad(s, -9, -9, 9, 9, -4, kRed);
  add_quad(s, -9, -9, 9, 9, -4, kGreen);  // same depth everywhere: LESS keeps red
  for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {  // both rasterizers' depth tests
    Canvas c(8, 8);
    RenderOptions o = test::gl_options();
    o.path = path;
    Renderer r;
    ASSERT_TRUE(r.render(s, o, c.view()).ok());
    EXPECT_EQ(c.byte(3, 3, 0), 255) << to_string(path);
    EXPECT_EQ(c.byte(3, 3, 1), 0) << to_string(path);
  }
}

TEST(RenderDepth, DepthViewHoldsWindowDepth) {
  Scene s = camera_scene();
  add_quad(s, -1, -1, 1, 1, -5, kRed);  // the middle of the view only
  Canvas c(9, 9);
  std::vector<float> depth(9 * 9, -1.0f);
  const DepthView d{depth.data(), 9, 9, 9 * sizeof(float), false};
  ASSERT_TRUE(render(s, c.view(), nullptr, {}, &d).ok());
  // gluPerspective with n = 1, f = 100 at eye z = -5: z_ndc = (f + n)/(f - n) - 2fn/((f - n) * 5).
  const double n = 1, f = 100, z_ndc = (f + n) / (f - n) - 2 * f * n / ((f - n) * 5);
  EXPECT_NEAR(depth[4 * 9 + 4], 0.5 * z_ndc + 0.5, 1e-6);
  EXPECT_EQ(depth[0], 1.0f);  // nothing drawn: the cleared far depth
}

// --- Clipping and hostile geometry.

TEST(RenderClip, GroundPlaneThroughTheNearPlane) {
  Scene s = camera_scene();
  s.camera.eye = Vec3(0, 1, 0);
  s.camera.target = Vec3(0, 1, -1);
  Mesh m;  // y = 0 from 20 behind the camera to 20 in front of it
  m.positions = {Vec3(-20, 0, 20), Vec3(20, 0, 20), Vec3(20, 0, -20), Vec3(-20, 0, -20)};
  m.normals.assign(4, Vec3(0, 1, 0));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  Material mat;
  mat.emissive = kGreen;
  s.meshes.push_back({"ground", m});
  s.materials.push_back(mat);
  s.objects.push_back({0, 0, Mat4::Identity()});
  Canvas c(32, 32);
  FrameStats st;
  ASSERT_TRUE(render(s, c.view(), &st).ok());
  EXPECT_EQ(st.triangles_clipped, 2u);
  for (int x = 0; x < 32; ++x) {
    EXPECT_EQ(c.byte(x, 31, 1), 255) << "bottom row: ground";
    EXPECT_EQ(c.byte(x, 0, 1), 0) << "top row: sky";
  }
}

Scene one_triangle(const Vec3& a, const Vec3& b, const Vec3& cc) {
  Scene s = camera_scene();
  Mesh m;
  m.positions = {a, b, cc};
  m.normals.assign(3, Vec3(0, 0, 1));
  m.triangles = {{0, 1, 2}};
  Material mat;
  mat.emissive = kRed;
  s.meshes.push_back({"t", m});
  s.materials.push_back(mat);
  s.objects.push_back({0, 0, Mat4::Identity()});
  return s;
}

TEST(RenderClip, TriangleBehindTheCameraDrawsNothing) {
  Canvas c(16, 16);
  FrameStats st;
  ASSERT_TRUE(render(one_triangle({-1, -1, 5}, {1, -1, 5}, {0, 1, 5}), c.view(), &st).ok());
  EXPECT_EQ(st.triangles_outside, 1u);
  EXPECT_EQ(st.pixels_filled, 0u);
}

TEST(RenderClip, TriangleStraddlingTheEyePlane) {
  // A floor triangle (facing up, towards the eye) running from in front of the eye to behind it,
  // so w changes sign along two of its edges.
  Canvas c(16, 16);
  FrameStats st;
  ASSERT_TRUE(render(one_triangle({-3, -1, -6}, {0, -1, 6}, {3, -1, -6}), c.view(), &st).ok());
  EXPECT_EQ(st.triangles_clipped, 1u);
  EXPECT_GT(st.pixels_filled, 0u);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) EXPECT_EQ(c.byte(x, y, 0), 0) << "the floor is below the horizon";
}

TEST(RenderClip, VertexAtOrNearWZero) {
  for (float z : {0.0f, 1e-7f, -1e-7f}) {
    Canvas c(16, 16, PixelFormat::rgba8, 8);
    FrameStats st;
    ASSERT_TRUE(render(one_triangle({-1, -1, -4}, {1, -1, -4}, {0, 1, z}), c.view(), &st).ok()) << z;
    EXPECT_TRUE(c.outside_pixels_untouched());
    EXPECT_EQ(st.triangles_in, 1u);
  }
}

TEST(RenderClip, HugeTriangleIsClippedToTheGuardBandAndCoversEverything) {
  Canvas c(40, 30);
  FrameStats st;
  ASSERT_TRUE(render(one_triangle({-1e6f, -1e6f, -5}, {1e6f, -1e6f, -5}, {0, 1e6f, -5}), c.view(), &st).ok());
  EXPECT_EQ(st.triangles_clipped, 1u);
  EXPECT_EQ(st.pixels_filled, 40u * 30u);
}

TEST(RenderClip, CoordinatesOf1e30AndNaN) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const Vec3& far_vertex : {Vec3(1e30f, 0, -5), Vec3(0, 0, -1e30f), Vec3(nan, 0, -5), Vec3(1e38f, 1e38f, 1e38f)}) {
    Canvas c(16, 16, PixelFormat::rgba32f, 4);
    FrameStats st;
    ASSERT_TRUE(render(one_triangle({-1, -1, -5}, {1, -1, -5}, far_vertex), c.view(), &st).ok());
    EXPECT_TRUE(c.outside_pixels_untouched());
    EXPECT_EQ(st.triangles_in, 1u);
    // Each case has one outcome: NaN is dropped as non-finite; the others have finite clip
    // coordinates with one vertex outside the frustum (right of the guard band, beyond the far
    // plane, behind the eye) and are clipped.
    const bool is_nan = std::isnan(far_vertex.x());
    EXPECT_EQ(st.triangles_nonfinite, is_nan ? 1u : 0u) << far_vertex.transpose();
    EXPECT_EQ(st.triangles_clipped, is_nan ? 0u : 1u) << far_vertex.transpose();
    EXPECT_EQ(st.triangles_outside, 0u) << far_vertex.transpose();
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        for (int ch = 0; ch < 4; ++ch) ASSERT_TRUE(std::isfinite(c.channel_f(x, y, ch)));
  }
  Canvas c(16, 16);
  FrameStats st;
  ASSERT_TRUE(render(one_triangle({-1, -1, -5}, {1, -1, -5}, {nan, 0, -5}), c.view(), &st).ok());
  EXPECT_EQ(st.triangles_nonfinite, 1u);
  EXPECT_EQ(st.pixels_filled, 0u);
}

// --- Culling and statistics.

TEST(RenderCull, ModesAndTwoSidedScenes) {
  for (bool reversed : {false, true}) {
    for (CullMode mode : {CullMode::none, CullMode::back, CullMode::front}) {
      Scene s = camera_scene();
      add_quad(s, -9, -9, 9, 9, -5, kRed, reversed);
      RenderOptions o = test::gl_options();
      o.cull = mode;
      Canvas c(8, 8);
      ASSERT_TRUE(render(s, c.view(), nullptr, o).ok());
      const bool front_facing = !reversed;
      const bool drawn = mode == CullMode::none || (mode == CullMode::back) == front_facing;
      EXPECT_EQ(c.byte(4, 4, 0), drawn ? 255 : 0) << "reversed " << reversed << " mode " << int(mode);
    }
  }
  // Two-sided: back faces are not culled and use their back-side lighting.
  Scene s = camera_scene();
  add_quad(s, -9, -9, 9, 9, -5, Color3::Zero(), /*reversed=*/true);
  s.two_sided = true;
  s.materials[0].diffuse = Color3(0, 0, 1);
  Light l;
  l.direction = Vec3(0, 0, -1);  // shines along -z onto the quad, whose normal (+z) faces it
  s.lights.push_back(l);
  s.meshes[0].mesh.normals.assign(4, Vec3(0, 0, -1));  // normals follow the reversed winding
  Canvas c(8, 8);
  ASSERT_TRUE(render(s, c.view()).ok());
  EXPECT_EQ(c.byte(4, 4, 2), 255) << "back face lit with -n";
}

TEST(RenderStats, CountsAddUp) {
  const Scene s = make_default_scene();
  FrameStats st;
  Canvas c(320, 240);
  ASSERT_TRUE(render(s, c.view(), &st).ok());
  std::uint64_t triangles = 0;
  for (const auto& o : s.objects) triangles += s.meshes[o.mesh].mesh.triangle_count();
  EXPECT_EQ(st.triangles_in, triangles);
  EXPECT_EQ(st.triangles_clipped, 0u);  // nothing crosses the near plane or the guard band
  EXPECT_EQ(st.triangles_in, st.triangles_drawn + st.triangles_culled + st.triangles_outside +
                                 st.triangles_degenerate + st.triangles_small + st.triangles_nonfinite);
  EXPECT_GT(st.triangles_culled, st.triangles_in / 4);
  EXPECT_LE(st.pixels_filled, st.pixels_tested);
  EXPECT_GE(st.bin_entries, st.triangles_drawn);
  EXPECT_GT(st.seconds_total, 0.0);
}

// Gouraud lights only the vertices of triangles that may be drawn, flat only those triangles; the
// image is the same bytes as with everything lit, for both, every path, cull mode, two-sided lighting, a mirrored object, a
// camera inside the scene (clipped triangles) and one looking half away (triangles off screen).
TEST(RenderStats, LightingOnlyDrawableVerticesChangesNoByte) {
  struct Variant {
    const char* name;
    CullMode cull;
    bool two_sided, mirror, inside, away, through_near = false;
  };
  const Variant variants[] = {{"back", CullMode::back, false, false, false, false},
                              {"front", CullMode::front, false, false, false, false},
                              {"none", CullMode::none, false, false, false, false},
                              {"two-sided", CullMode::back, true, false, false, false},
                              {"mirrored", CullMode::back, false, true, false, false},
                              {"inside", CullMode::back, false, false, true, false},
                              {"away", CullMode::back, false, false, false, true},
                              {"through the near plane", CullMode::back, false, false, false, false, true}};
  std::vector<std::pair<LightingPath, Isa>> paths = {{LightingPath::reference, Isa::best}, {LightingPath::scalar, Isa::best}};
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) paths.push_back({LightingPath::simd, isa});
  for (const Variant& v : variants) {
    Scene s = make_default_scene();
    s.two_sided = v.two_sided;
    if (v.mirror) {
      Mat4 flip = Mat4::Identity();
      flip(0, 0) = -1.0f;
      for (Instance& inst : s.objects) inst.model = inst.model * flip;
    }
    if (v.through_near) {  // a lit quad of its own from behind the eye to the far side: only clipped triangles
      const Vec3 e = s.camera.eye, d = (s.camera.target - s.camera.eye).normalized();
      const Vec3 side = d.cross(s.camera.up).normalized(), below = e - s.camera.up.normalized() * 0.5f;
      Mesh m;
      m.positions = {below - d * 5.0f - side * 5.0f, below - d * 5.0f + side * 5.0f, below + d * 30.0f + side * 5.0f,
                     below + d * 30.0f - side * 5.0f};
      m.normals.assign(4, s.camera.up.normalized());
      m.triangles = {{0, 1, 2}, {0, 2, 3}};
      s.meshes.push_back({"through", m});
      s.objects.push_back({static_cast<std::uint32_t>(s.meshes.size() - 1), 0, Mat4::Identity()});
    }
    if (v.inside) s.camera.eye = s.camera.target + (s.camera.eye - s.camera.target) * 0.15f;
    if (v.away) s.camera.target = s.camera.target + (s.camera.target - s.camera.eye).cross(s.camera.up).normalized() * 4.0f;
    for (const auto& [path, isa] : paths) {
      for (ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
        SCOPED_TRACE(std::string(v.name) + " " + to_string(path) + " " + to_string(isa) + " " + to_string(shading));
        RenderOptions o = test::gl_options();
        o.shading = shading;
        o.cull = v.cull;
        o.path = path;
        o.isa = isa;
        Canvas drawn_only(160, 120), every(160, 120);
        FrameStats a, b;
        ASSERT_TRUE(render(s, drawn_only.view(), &a, o).ok());
        o.light_every_vertex = true;
        ASSERT_TRUE(render(s, every.view(), &b, o).ok());
        EXPECT_TRUE(drawn_only.pixels() == every.pixels());
        EXPECT_EQ(b.vertices_skipped, 0u);
        EXPECT_EQ(a.vertices_lit + a.vertices_skipped, b.vertices_lit);
        EXPECT_EQ(a.triangles_drawn, b.triangles_drawn);
        if (v.through_near) {
          EXPECT_GT(a.triangles_clipped, 0u);
        }
        if (v.cull != CullMode::none && !v.two_sided) {
          EXPECT_GT(a.vertices_skipped, b.vertices_lit / 8);
        }
      }
    }
  }
}

// --- The classic Gouraud failure: a point light close to the middle of a large quad.

TEST(RenderShading, GouraudMissesTheHighlightPhongFindsIt) {
  Scene s = camera_scene();
  s.camera.vertical_fov_deg = 60;
  add_quad(s, -10, -10, 10, 10, -5, Color3::Zero());
  s.materials[0].diffuse = Color3(0.8f, 0.8f, 0.8f);
  Light l;
  l.type = LightType::point;
  l.position = Vec3(0, 0, -4);  // one unit in front of the quad's centre
  s.lights.push_back(l);
  // 65 x 65: the centre pixel's centre is exactly the view axis, which meets the quad at (0, 0, -5).
  Canvas gouraud(65, 65), phong(65, 65);
  RenderOptions o = test::gl_options();
  o.shading = ShadingMode::gouraud;
  ASSERT_TRUE(render(s, gouraud.view(), nullptr, o).ok());
  o.shading = ShadingMode::phong;
  ASSERT_TRUE(render(s, phong.view(), nullptr, o).ok());
  const int g = gouraud.byte(32, 32, 0), p = phong.byte(32, 32, 0);
  EXPECT_LT(g + 100, p) << "Gouraud interpolates the dim corners";

  // The reference lighting at that point: 0.8 * (n.l = 1) / (k0 = 1) = 0.8.
  Scene point = s;
  test::set_single_vertex(point, Vec3(0, 0, -5), Vec3(0, 0, 1));
  point.materials[0] = s.materials[0];
  LightingOptions ref;
  ref.path = LightingPath::reference;
  VertexColors v;
  ASSERT_TRUE(light_instance(point, 0, ref, v).ok());
  const int expected = static_cast<int>(std::lround(v.front[0].x() * 255.0f));
  EXPECT_EQ(expected, 204);
  EXPECT_LE(std::abs(p - expected), 1);
}

}  // namespace
}  // namespace facet
