// PBR materials and their surroundings through the interfaces: a scene file's "model": "pbr" and
// "environment_image" (a picture in the scene's folder; one outside it refused), the C API's
// environment functions, and glTF's KHR_materials_ior and KHR_materials_specular.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "facet/facet.h"
#include "facet/facet.hpp"
#include "gltf_builder.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

// A 16 x 8 Radiance picture of one grey (flat scanlines).
std::string grey_hdr() {
  std::string s = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n";
  for (int i = 0; i < 16 * 8; ++i) s += {char(128), char(128), char(128), char(128)};  // 0.50195 each
  return s;
}

TEST(PbrSceneFile, ModelPbrAndAnEnvironmentPictureInTheScenesFolder) {
  test::TempDir dir;
  test::write_text(dir / "sky.hdr", grey_hdr());
  test::write_text(dir / "scene.json", R"({
    "environment_image": { "file": "sky.hdr", "intensity": 2, "rotation_deg": 45 }, "background": "environment",
    "materials": [ { "name": "gold", "model": "pbr", "base_color": [1, 0.77, 0.34], "metallic": 1, "roughness": 0.3, "ior": 1.4 } ],
    "meshes": [ { "name": "ball", "shape": "sphere" } ], "objects": [ { "mesh": "ball", "material": "gold" } ], "lights": [] })");
  Result<Scene> s = load_scene_file(dir / "scene.json");
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_EQ(s->materials[0].model, MaterialModel::pbr);
  EXPECT_EQ(s->materials[0].metallic, 1.0f);
  EXPECT_EQ(s->materials[0].ior, 1.4f);
  EXPECT_EQ(s->environment_light.source, EnvironmentSource::image);
  EXPECT_EQ(s->environment_light.width, 16);
  EXPECT_EQ(s->environment_light.rgb[0], 128.5f / 256.0f);
  EXPECT_EQ(s->environment_light.intensity, 2.0f);
  EXPECT_EQ(s->environment_light.rotation_deg, 45.0f);
  EXPECT_EQ(s->background, Background::environment);
  // A picture outside the scene's folder is refused, naming the field.
  test::TempDir other("facet_other");
  test::write_text(other / "sky.hdr", grey_hdr());
  test::write_text(dir / "outside.json", R"({ "environment_image": { "file": ")" + (other / "sky.hdr") + R"(" } })");
  Result<Scene> outside = load_scene_file(dir / "outside.json");
  ASSERT_FALSE(outside.ok());
  EXPECT_NE(outside.status().message().find("environment_image.file"), std::string::npos) << outside.status().message();
  for (const char* bad : {R"({ "environment_image": { "source": "studio", "file": "sky.hdr" } })",
                          R"({ "environment_image": { "source": "sunset" } })",
                          R"({ "background": "sky" })",
                          R"({ "background": "environment" })",
                          R"({ "environment_image": { "source": "studio", "intensity": -1 } })",
                          R"({ "environment_image": { "file": "missing.hdr" } })",
                          R"({ "materials": [ { "model": "pbr", "base_color": [2, 0, 0] } ] })",
                          R"({ "materials": [ { "model": "pbr", "environment": { "mode": "sphere", "texture": "t" } } ],
                               "textures": [ { "name": "t", "file": "sky.hdr" } ] })"}) {
    test::write_text(dir / "bad.json", bad);
    Result<Scene> b = load_scene_file(dir / "bad.json");
    EXPECT_FALSE(b.ok()) << bad;
  }
}

TEST(PbrCApi, EnvironmentSetReadAndRefused) {
  facet_scene* scene = facet_scene_create();
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(facet_scene_set_environment(scene, FACET_SURROUNDINGS_STUDIO, 1.5f, 10.0f), FACET_OK);
  facet_surroundings source = FACET_SURROUNDINGS_NONE;
  float intensity = 0, rotation = 0;
  int w = -1, h = -1;
  EXPECT_EQ(facet_scene_get_environment(scene, &source, &w, &h, &intensity, &rotation), FACET_OK);
  EXPECT_EQ(source, FACET_SURROUNDINGS_STUDIO);
  EXPECT_EQ(intensity, 1.5f);
  EXPECT_EQ(rotation, 10.0f);
  EXPECT_EQ(facet_scene_set_environment(scene, FACET_SURROUNDINGS_IMAGE, 1.0f, 0.0f), FACET_INVALID_ARGUMENT);
  EXPECT_EQ(facet_scene_set_environment(scene, FACET_SURROUNDINGS_NONE, -1.0f, 0.0f), FACET_INVALID_ARGUMENT);
  std::vector<float> rgb(16 * 8 * 3, 0.25f);
  EXPECT_EQ(facet_scene_set_environment_pixels(scene, rgb.data(), 16, 8, 1.0f, 0.0f), FACET_OK);
  EXPECT_EQ(facet_scene_get_environment(scene, &source, &w, &h, nullptr, nullptr), FACET_OK);
  EXPECT_EQ(source, FACET_SURROUNDINGS_IMAGE);
  EXPECT_EQ(w, 16);
  EXPECT_EQ(h, 8);
  EXPECT_EQ(facet_scene_set_environment_pixels(scene, rgb.data(), 15, 8, 1.0f, 0.0f), FACET_INVALID_ARGUMENT);
  rgb[7] = std::nanf("");
  EXPECT_EQ(facet_scene_set_environment_pixels(scene, rgb.data(), 16, 8, 1.0f, 0.0f), FACET_INVALID_ARGUMENT);
  EXPECT_NE(std::string(facet_scene_last_error(scene)).find("texel 2"), std::string::npos) << facet_scene_last_error(scene);
  EXPECT_EQ(facet_scene_set_environment_pixels(scene, nullptr, 16, 8, 1.0f, 0.0f), FACET_INVALID_ARGUMENT);
  test::TempDir dir;
  test::write_text(dir / "sky.hdr", grey_hdr());
  EXPECT_EQ(facet_scene_load_environment_image(scene, (dir / "sky.hdr").c_str(), 1.0f, 0.0f, 0), FACET_OK);
  EXPECT_EQ(facet_scene_load_environment_image(scene, (dir / "none.hdr").c_str(), 1.0f, 0.0f, 0), FACET_IO_ERROR);
  facet_background background = FACET_BACKGROUND_ENVIRONMENT;
  EXPECT_EQ(facet_scene_get_background(scene, &background), FACET_OK);
  EXPECT_EQ(background, FACET_BACKGROUND_COLOUR);
  EXPECT_EQ(facet_scene_set_background(scene, FACET_BACKGROUND_ENVIRONMENT), FACET_OK);
  EXPECT_EQ(facet_scene_get_background(scene, &background), FACET_OK);
  EXPECT_EQ(background, FACET_BACKGROUND_ENVIRONMENT);
  EXPECT_EQ(facet_scene_set_background(scene, static_cast<facet_background>(7)), FACET_INVALID_ARGUMENT);
  EXPECT_NE(std::string(facet_scene_last_error(scene)).find("background"), std::string::npos);
  facet_scene_destroy(scene);
}

TEST(PbrGltf, IorAndSpecularExtensionsAreRead) {
  test::TempDir dir;
  test::GltfBuilder b = test::quad();
  b.doc["materials"] = {{{"pbrMetallicRoughness", {{"metallicFactor", 0.25}, {"roughnessFactor", 0.5}}},
                         {"extensions", {{"KHR_materials_ior", {{"ior", 1.33}}},
                                         {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.5, 0.25}}}}}}}};
  b.doc["meshes"][0]["primitives"][0]["material"] = 0;
  b.doc["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_specular"};
  test::write_text(dir / "q.gltf", b.embedded());
  Result<Model> m = load_model(dir / "q.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  const Material& mat = m->scene.materials[0];
  EXPECT_EQ(mat.model, MaterialModel::pbr);
  EXPECT_FLOAT_EQ(mat.metallic, 0.25f);
  EXPECT_FLOAT_EQ(mat.roughness, 0.5f);
  EXPECT_FLOAT_EQ(mat.ior, 1.33f);
  EXPECT_FLOAT_EQ(mat.specular_weight, 0.5f);
  EXPECT_EQ(mat.specular_color, Color3(1.0f, 0.5f, 0.25f));
  EXPECT_TRUE(m->warnings.empty()) << m->warnings[0];
  b.doc["materials"][0]["extensions"]["KHR_materials_ior"]["ior"] = 0.5;  // below the schema's minimum: warned, 1.5 used
  test::write_text(dir / "low.gltf", b.embedded());
  Result<Model> low = load_model(dir / "low.gltf");
  ASSERT_TRUE(low.ok()) << low.status().message();
  EXPECT_FLOAT_EQ(low->scene.materials[0].ior, 1.5f);
  ASSERT_EQ(low->warnings.size(), 1u);
  EXPECT_NE(low->warnings[0].find("KHR_materials_ior.ior: 0.5 is below"), std::string::npos) << low->warnings[0];
  b.doc["materials"][0]["extensions"]["KHR_materials_ior"]["ior"] = 11.0;  // beyond any material: refused by name
  test::write_text(dir / "bad.gltf", b.embedded());
  Result<Model> bad = load_model(dir / "bad.gltf");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("KHR_materials_ior"), std::string::npos) << bad.status().message();
}

}  // namespace
}  // namespace facet
