// Golden images of the built-in scene (160 x 120), one per shading mode, and renders of the real
// models and of a 16-light scene. The golden files are regenerated with tools/regen-golden when a
// change to the pictures is intended.
//
// Tolerance: 1 step of 8-bit output per channel. Coverage is exact integer arithmetic, so a
// silhouette that moves fails this; what passes is lighting that differs by an ulp (another libm
// or compiler) and flips a rounding.
#include <filesystem>

#include "render_support.hpp"

namespace facet {
namespace {

Rgba8Image render_rgba8(const Scene& scene, int w, int h, ShadingMode mode, FrameStats* stats = nullptr,
                        LightingPath path = LightingPath::simd) {
  test::Canvas c(w, h);
  RenderOptions o = test::gl_options();
  o.shading = mode;
  o.path = path;
  Renderer r;
  const Status s = r.render(scene, o, c.view(), nullptr, stats);
  EXPECT_TRUE(s.ok()) << s.message();
  Rgba8Image img;
  img.width = w;
  img.height = h;
  img.pixels = c.pixels();
  return img;
}

class Golden : public ::testing::TestWithParam<ShadingMode> {};

void expect_matches_golden(ShadingMode mode, LightingPath path, Isa isa) {
  const std::string name = std::string("default_") + to_string(mode) + ".png";
  const Result<Rgba8Image> golden = read_png(test::data_dir() + "/golden/" + name);
  ASSERT_TRUE(golden.ok()) << golden.status().message();
  test::Canvas c(160, 120);
  RenderOptions o = test::gl_options();
  o.shading = mode;
  o.path = path;
  o.isa = isa;
  Renderer r;
  ASSERT_TRUE(r.render(make_default_scene(), o, c.view()).ok());
  Rgba8Image actual;
  actual.width = 160;
  actual.height = 120;
  actual.pixels = c.pixels();
  const Result<ImageDifference> d = compare_images(*golden, actual);
  ASSERT_TRUE(d.ok()) << d.status().message();
  if (d->max_channel_difference > 1) {
    const std::string out = (std::filesystem::temp_directory_path() / ("facet_actual_" + name)).string();
    ImageView view{const_cast<std::uint8_t*>(actual.pixels.data()), actual.width, actual.height,
                   static_cast<std::size_t>(actual.width) * 4, PixelFormat::rgba8, false};
    (void)write_png(out, view);
    ADD_FAILURE() << name << ": largest difference " << d->max_channel_difference << ", " << d->differing_pixels
                  << " pixels differ, PSNR " << d->psnr_db << " dB. This render: " << out
                  << ". If the change is intended, run tools/regen-golden and commit the new images.";
  }
}

// The golden files were rendered on the scalar path; every SIMD ISA must match them within the
// same step (the cross-path contract), with the same coverage.
TEST_P(Golden, DefaultSceneMatches) { expect_matches_golden(GetParam(), LightingPath::scalar, Isa::best); }

TEST_P(Golden, DefaultSceneMatchesOnEverySimdIsa) {
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    if (!isa_supported(isa)) continue;
    SCOPED_TRACE(to_string(isa));
    expect_matches_golden(GetParam(), LightingPath::simd, isa);
  }
}

INSTANTIATE_TEST_SUITE_P(Shading, Golden, ::testing::Values(ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong),
                         [](const auto& param_info) { return std::string(to_string(param_info.param)); });

// The model scene files name their OBJ as ../../../../shared/models/..., beside the checkout.
class ModelScene : public ::testing::TestWithParam<const char*> {};

TEST_P(ModelScene, RendersTheModel) {
  FACET_REQUIRE_MODELS();
  const Result<Scene> scene = load_scene_file(test::data_dir() + "/scenes/" + GetParam() + ".json", test::scene_options());
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  FrameStats st;
  const Rgba8Image img = render_rgba8(*scene, 160, 120, ShadingMode::phong, &st);
  EXPECT_GT(st.triangles_drawn, 100u);
  EXPECT_GT(st.pixels_filled, 160u * 120u / 20) << "the model covers a visible part of the frame";
  EXPECT_EQ(st.triangles_nonfinite, 0u);
}

INSTANTIATE_TEST_SUITE_P(Models, ModelScene, ::testing::Values("bunny", "teapot", "suzanne", "spot", "fandisk"));

TEST(ManyLights, SixteenLightsSceneRenders) {
  const Result<Scene> scene = load_scene_file(test::data_dir() + "/scenes/sixteen_lights.json", test::scene_options());
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  EXPECT_EQ(scene->lights.size(), 16u);
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    FrameStats st;
    const Rgba8Image img = render_rgba8(*scene, 160, 120, mode, &st);
    EXPECT_GT(st.pixels_filled, 160u * 120u / 4);
    // Lit: the brightest pixel is well above the ambient level.
    int brightest = 0;
    for (std::size_t i = 0; i < img.pixels.size(); i += 4) brightest = std::max<int>(brightest, img.pixels[i]);
    EXPECT_GT(brightest, 150) << to_string(mode);
  }
}

}  // namespace
}  // namespace facet
