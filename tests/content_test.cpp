// glTF import (model.hpp): what is read, how it maps onto facet's scene, and the errors for
// malformed files. Files are written by the tests (gltf_builder.hpp). OBJ + MTL: obj_import_test.cpp.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "content/import.hpp"
#include "content_support.hpp"
#include "facet/facet.hpp"
#include "gltf_builder.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

using test::GltfBuilder;
namespace fs = std::filesystem;

// {"primitives": [primitive]} for a primitive of the given attributes (and indices, material, mode when >= 0).
nlohmann::json mesh_of(nlohmann::json attributes, int indices = -1, int material = -1, int mode = -1) {
  nlohmann::json prim = nlohmann::json::object();
  prim["attributes"] = std::move(attributes);
  if (indices >= 0) prim["indices"] = indices;
  if (material >= 0) prim["material"] = material;
  if (mode >= 0) prim["mode"] = mode;
  nlohmann::json mesh = nlohmann::json::object();
  mesh["primitives"] = nlohmann::json::array({prim});
  return mesh;
}

const std::vector<float> kQuadPositions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
const std::vector<float> kQuadNormals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
const std::vector<float> kQuadUvs = {0, 1, 1, 1, 1, 0, 0, 0};  // glTF: v down from the top
const std::vector<std::uint16_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

// A textured quad facing +z, a camera at z = 3 and a directional light along -z; `image` says how
// the texture is stored: "uri" (an external file), "view" (in the buffer), or "" (no texture).
GltfBuilder textured_quad(const std::string& png_bytes, const std::string& image) {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions), nrm = b.vec3(kQuadNormals), uv = b.vec2(kQuadUvs);
  const int idx = b.indices16(kQuadIndices);
  nlohmann::json prim = {{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}}, {"indices", idx}, {"material", 0}};
  b.add("meshes", {{"name", "quad"}, {"primitives", {prim}}});
  nlohmann::json pbr = {{"baseColorFactor", {0.8, 0.6, 0.4, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}};
  if (!image.empty()) {
    pbr["baseColorTexture"] = {{"index", 0}};
    b.add("samplers", {{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}});
    if (image == "uri") {
      b.add("images", {{"uri", "tex.png"}});
    } else {
      const int v = b.view(png_bytes.data(), png_bytes.size());
      b.add("images", {{"bufferView", v}, {"mimeType", "image/png"}});
    }
    b.add("textures", {{"sampler", 0}, {"source", 0}});
  }
  b.add("materials", {{"name", "paint"}, {"pbrMetallicRoughness", pbr}});
  b.add("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.5}, {"zfar", 10.0}}}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "directional"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 2.0}}}}}}};
  b.add("nodes", {{"mesh", 0}});
  b.add("nodes", {{"camera", 0}, {"translation", {0.0, 0.0, 3.0}}});
  b.add("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.add("scenes", {{"nodes", {0, 1, 2}}});
  b.doc["scene"] = 0;
  return b;
}

// The facet scene the textured quad should become, built by hand from docs/content.md.
Scene expected_quad_scene(const std::string& texture_path) {
  Scene s;
  Mesh m;
  for (int i = 0; i < 4; ++i) {
    m.positions.emplace_back(kQuadPositions[3 * i], kQuadPositions[3 * i + 1], kQuadPositions[3 * i + 2]);
    m.normals.emplace_back(0.0f, 0.0f, 1.0f);
    m.uvs.emplace_back(kQuadUvs[2 * i], 1.0f - kQuadUvs[2 * i + 1]);
  }
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.meshes.push_back({"quad", m});
  TextureOptions to;
  to.filter = TextureFilter::nearest;
  to.wrap = TextureWrap::clamp;
  to.encoding = TextureEncoding::srgb;  // base colour (and emissive) textures are sRGB in glTF
  Result<Texture> t = load_texture(texture_path, "tex.png", to);
  EXPECT_TRUE(t.ok());
  s.textures.push_back(*t);
  Material mat;
  mat.name = "paint";
  const PbrMapping pbr = map_metallic_roughness(Color3(0.8f, 0.6f, 0.4f), 0.0f, 0.5f);
  mat.diffuse = mat.ambient = pbr.diffuse;
  mat.specular = pbr.specular;
  mat.shininess = pbr.shininess;
  mat.model = MaterialModel::pbr;  // the glTF BRDF itself (the GL colours above stay for --gl-materials)
  mat.base_color = Color3(0.8f, 0.6f, 0.4f);
  mat.metallic = 0.0f;
  mat.roughness = 0.5f;
  mat.diffuse_texture = 0;
  mat.emission_after_texture = true;  // glTF adds the emission after the base colour
  s.materials.push_back(mat);
  s.objects.push_back(Instance{0, 0, Mat4::Identity()});
  s.camera.eye = Vec3(0, 0, 3);
  s.camera.target = Vec3(0, 0, 2);
  s.camera.up = Vec3(0, 1, 0);
  s.camera.vertical_fov_deg = float(0.8 * 180.0 / std::numbers::pi);
  s.camera.near = 0.5f;
  s.camera.far = 10.0f;
  Light l;
  l.type = LightType::directional;
  l.direction = Vec3(0, 0, -1);
  // 2 lx of (1, 0.5, 0.25): colour x intensity / pi (docs/color.md).
  l.diffuse = l.specular = Color3(float(2.0 / std::numbers::pi), float(1.0 / std::numbers::pi), float(0.5 / std::numbers::pi));
  s.lights.push_back(l);
  // A model with lights in physical units: metered, the neutral operator.
  s.display.automatic = true;
  s.display.tone_mapping = ToneMapping::neutral;
  return s;
}

TEST(GltfImport, TexturedQuadIsTheSceneDocsDescribe) {
  TempDir dir;
  const std::string png = write_test_png(dir / "tex.png");
  const GltfBuilder b = textured_quad(png, "uri");
  test::write_text(dir / "quad.bin", b.bin);
  test::write_text(dir / "quad.gltf", b.external("quad.bin"));
  Result<Model> m = load_model(dir / "quad.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_TRUE(m->has_camera);
  EXPECT_TRUE(m->has_lights);
  ASSERT_EQ(m->scene.meshes.size(), 1u);
  ASSERT_EQ(m->scene.textures.size(), 1u);
  EXPECT_EQ(m->scene.textures[0].filter, TextureFilter::nearest);
  EXPECT_EQ(m->scene.textures[0].wrap, TextureWrap::clamp);
  EXPECT_EQ(m->scene.meshes[0].mesh.uvs[0], Vec2(0.0f, 0.0f));  // glTF (0, 1) is the bottom-left corner
  ASSERT_EQ(m->scene.lights.size(), 1u);
  EXPECT_EQ(m->scene.lights[0].diffuse, Color3(float(2.0 / std::numbers::pi), float(1.0 / std::numbers::pi), float(0.5 / std::numbers::pi)));
  EXPECT_TRUE(m->scene.lights[0].direction.isApprox(Vec3(0, 0, -1)));
  EXPECT_TRUE(m->warnings.empty()) << m->warnings[0];
  Scene expected = expected_quad_scene(dir / "tex.png");
  EXPECT_EQ(render_rgba(m->scene), render_rgba(expected));
  // ModelOptions::gl_materials: the same material lit by GL's model, as before the glTF BRDF.
  ModelOptions gl;
  gl.gl_materials = true;
  Result<Model> as_gl = load_model(dir / "quad.gltf", gl);
  ASSERT_TRUE(as_gl.ok()) << as_gl.status().message();
  EXPECT_EQ(as_gl->scene.materials[0].model, MaterialModel::gl);
  expected.materials[0].model = MaterialModel::gl;
  EXPECT_EQ(render_rgba(as_gl->scene), render_rgba(expected));
  EXPECT_NE(render_rgba(m->scene), render_rgba(expected));
  expected.materials[0].model = MaterialModel::pbr;
  // The picture is the texture's: the top-left pixel of the quad's image area is red-ish.
}

// emissiveFactor x emissiveTexture is added after the base colour's texture (glTF's rule), the
// same picture as the facet scene docs/content.md describes; KHR_materials_unlit ignores it.
// normalTexture: a linear texture (the same image as the sRGB base colour is a second facet
// texture), its scale; TANGENT read as given (w snapped within 1e-3), generated (MikkTSpace) when
// absent or when a w is neither +1 nor -1, with a warning naming the element.
// TEXCOORD_1 becomes the mesh's lightmap coordinates (v flipped as TEXCOORD_0's), kept through
// the normals facet computes for a primitive without NORMAL (which split vertices at creases).
TEST(GltfImport, SecondUvSetIsTheLightmapsCoordinates) {
  TempDir dir;
  for (bool normals : {true, false}) {
    GltfBuilder b;
    const std::vector<float> lightmap = {0.1f, 0.9f, 0.4f, 0.9f, 0.4f, 0.6f, 0.1f, 0.6f};
    const int pos = b.vec3(kQuadPositions), nrm = b.vec3(kQuadNormals), uv = b.vec2(kQuadUvs), uv1 = b.vec2(lightmap);
    nlohmann::json attributes = {{"POSITION", pos}, {"TEXCOORD_0", uv}, {"TEXCOORD_1", uv1}};
    if (normals) attributes["NORMAL"] = nrm;
    b.add("meshes", mesh_of(attributes, b.indices16(kQuadIndices)));
    b.add("nodes", {{"mesh", 0}});
    b.add("scenes", {{"nodes", {0}}});
    b.doc["scene"] = 0;
    test::write_text(dir / "lm.bin", b.bin);
    test::write_text(dir / "lm.gltf", b.external("lm.bin"));
    Result<Model> m = load_model(dir / "lm.gltf");
    ASSERT_TRUE(m.ok()) << m.status().message();
    const Mesh& mesh = m->scene.meshes[0].mesh;
    ASSERT_EQ(mesh.lightmap_uvs.size(), mesh.positions.size()) << normals;
    ASSERT_TRUE(validate_mesh(mesh).ok());
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_FLOAT_EQ(mesh.lightmap_uvs[i].x(), lightmap[2 * i]) << normals;
      EXPECT_FLOAT_EQ(mesh.lightmap_uvs[i].y(), 1.0f - lightmap[2 * i + 1]) << normals;
    }
    for (const auto& w : m->warnings) EXPECT_EQ(w.find("TEXCOORD_1"), std::string::npos) << w;
  }
}

// A glTF's TEXCOORD_1 through a bake: a scene file imports the quad; bake_lightmaps bakes over
// the model's own coordinates (no charts generated); a scene file naming the baked lightmap in
// the import's "lightmaps" with "uv": "mesh" draws it over those coordinates; a list of the wrong
// length is refused with its field named.
TEST(GltfImport, SecondUvSetIsBakedOverAndDrawnFromAScene) {
  TempDir dir;
  GltfBuilder b;
  const std::vector<float> lightmap = {0.1f, 0.9f, 0.4f, 0.9f, 0.4f, 0.6f, 0.1f, 0.6f};
  const int pos = b.vec3(kQuadPositions), nrm = b.vec3(kQuadNormals), uv1 = b.vec2(lightmap);
  b.add("meshes", mesh_of({{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_1", uv1}}, b.indices16(kQuadIndices)));
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  b.doc["scene"] = 0;
  test::write_text(dir / "lm.bin", b.bin);
  test::write_text(dir / "lm.gltf", b.external("lm.bin"));
  const std::string lights = R"("lights": [ { "type": "directional", "direction": [0, 0, -1], "diffuse": 0.8 } ])";
  test::write_text(dir / "scene.json", "{ " + lights + R"(, "imports": [ { "file": "lm.gltf", "gl_materials": true } ] })");
  Result<Scene> scene = load_scene_file(dir / "scene.json");
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  BakeOptions o;
  o.charts.texels_per_unit = 16;
  o.radiosity = false;
  const Result<BakeResult> baked = bake_lightmaps(*scene, o);
  ASSERT_TRUE(baked.ok()) << baked.status().message();
  ASSERT_EQ(baked->lightmaps.size(), 1u);
  EXPECT_TRUE(baked->lightmaps[0].mesh_uvs);
  EXPECT_EQ(baked->lightmaps[0].unwrap.uvs, scene->meshes[0].mesh.lightmap_uvs);

  // The baked light, written as the lightmap texture a scene names.
  write_test_png(dir / "lightmap.png");
  const std::string textures = R"("textures": [ { "name": "lm", "file": "lightmap.png", "encoding": "linear" } ])";
  test::write_text(dir / "baked.json", "{ " + lights + ", " + textures +
                                           R"(, "imports": [ { "file": "lm.gltf", "gl_materials": true, "lightmaps": [ { "texture": "lm", "scale": 0.5, "uv": "mesh" } ] } ] })");
  Result<Scene> drawn = load_scene_file(dir / "baked.json");
  ASSERT_TRUE(drawn.ok()) << drawn.status().message();
  EXPECT_EQ(drawn->objects[0].lightmap, 0);
  EXPECT_FLOAT_EQ(drawn->objects[0].lightmap_scale, 0.5f);
  EXPECT_EQ(drawn->meshes[drawn->objects[0].mesh].mesh.lightmap_uvs, scene->meshes[0].mesh.lightmap_uvs);

  test::write_text(dir / "wrong.json", "{ " + textures + R"(, "imports": [ { "file": "lm.gltf", "lightmaps": [ null, null ] } ] })");
  Result<Scene> wrong = load_scene_file(dir / "wrong.json");
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.status().message().find("imports[0].lightmaps"), std::string::npos) << wrong.status().message();
  EXPECT_NE(wrong.status().message().find("one entry per object the model adds (1), found 2"), std::string::npos)
      << wrong.status().message();
}

TEST(GltfImport, NormalTexturesAndTangents) {
  TempDir dir;
  const std::string png = write_test_png(dir / "tex.png");
  auto load = [&](GltfBuilder& b) {
    test::write_text(dir / "quad.bin", b.bin);
    test::write_text(dir / "quad.gltf", b.external("quad.bin"));
    return load_model(dir / "quad.gltf");
  };
  GltfBuilder b = textured_quad(png, "uri");
  b.doc["materials"][0]["normalTexture"] = {{"index", 0}, {"scale", 0.75}};
  b.doc["materials"][0]["occlusionTexture"] = {{"index", 0}, {"strength", 0.4}};
  Result<Model> m = load(b);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_TRUE(m->warnings.empty()) << m->warnings[0];
  const Material& mat = m->scene.materials[0];
  ASSERT_NE(mat.occlusion_texture, kNoTexture);
  EXPECT_EQ(mat.occlusion_texture, mat.normal_texture) << "one linear texture for both slots";
  EXPECT_EQ(mat.occlusion_strength, 0.4f);
  ASSERT_NE(mat.normal_texture, kNoTexture);
  EXPECT_NE(mat.normal_texture, mat.diffuse_texture);
  EXPECT_EQ(m->scene.textures[std::size_t(mat.normal_texture)].encoding, TextureEncoding::linear);
  EXPECT_EQ(m->scene.textures[std::size_t(mat.diffuse_texture)].encoding, TextureEncoding::srgb);
  EXPECT_EQ(mat.normal_scale, 0.75f);
  Mesh generated = m->scene.meshes[0].mesh;
  ASSERT_EQ(generated.tangents.size(), 4u);
  Mesh expected = generated;
  ASSERT_TRUE(generate_tangents(expected).ok());
  EXPECT_EQ(generated.tangents, expected.tangents);
  EXPECT_GT(generated.tangents[0].x(), 0.99f);  // u runs along +x

  const std::vector<float> given = {0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, -1.0005f, 0, 1, 0, 1};
  b.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = b.vec4(given);
  m = load(b);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_TRUE(m->warnings.empty()) << m->warnings[0];
  EXPECT_EQ(m->scene.meshes[0].mesh.tangents[0], Vec4(0, 1, 0, 1));
  EXPECT_EQ(m->scene.meshes[0].mesh.tangents[2], Vec4(0, 1, 0, -1));

  GltfBuilder c = textured_quad(png, "uri");
  c.doc["materials"][0]["normalTexture"] = {{"index", 0}};
  c.doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = c.vec4({0, 1, 0, 1, 0, 1, 0, 0.5f, 0, 1, 0, 1, 0, 1, 0, 1});
  m = load(c);
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->warnings.size(), 1u);
  EXPECT_NE(m->warnings[0].find("TANGENT: element 1 has w = 0.5"), std::string::npos) << m->warnings[0];
  EXPECT_EQ(m->scene.meshes[0].mesh.tangents, expected.tangents);
}

TEST(GltfImport, EmissiveTexturesAreAddedAfterTheBaseColour) {
  TempDir dir;
  const std::string png = write_test_png(dir / "tex.png");
  GltfBuilder b = textured_quad(png, "uri");
  b.doc["materials"][0]["emissiveFactor"] = {0.5, 0.25, 1.0};
  b.doc["materials"][0]["emissiveTexture"] = {{"index", 0}};
  test::write_text(dir / "quad.bin", b.bin);
  test::write_text(dir / "quad.gltf", b.external("quad.bin"));
  Result<Model> m = load_model(dir / "quad.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_TRUE(m->warnings.empty()) << m->warnings[0];
  ASSERT_EQ(m->scene.materials.size(), 1u);
  EXPECT_EQ(m->scene.materials[0].emissive_texture, 0);
  EXPECT_EQ(m->scene.materials[0].emissive, Color3(0.5f, 0.25f, 1.0f));
  Scene expected = expected_quad_scene(dir / "tex.png");
  expected.materials[0].emissive = Color3(0.5f, 0.25f, 1.0f);
  expected.materials[0].emissive_texture = 0;
  const auto picture = render_rgba(m->scene);
  EXPECT_EQ(picture, render_rgba(expected));
  expected.materials[0].emissive_texture = kNoTexture;  // the emission is the texture's, not flat
  EXPECT_NE(picture, render_rgba(expected));

  b.doc["extensionsUsed"].push_back("KHR_materials_unlit");
  b.doc["materials"][0]["extensions"] = {{"KHR_materials_unlit", nlohmann::json::object()}};
  test::write_text(dir / "unlit.gltf", b.external("quad.bin"));
  m = load_model(dir / "unlit.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->scene.materials[0].emissive_texture, kNoTexture);
  EXPECT_TRUE(std::any_of(m->warnings.begin(), m->warnings.end(), [](const std::string& w) {
    return w.find("materials[0].emissiveTexture: ignored by KHR_materials_unlit") != std::string::npos;
  })) << (m->warnings.empty() ? "no warning" : m->warnings[0]);
}

TEST(GltfImport, GlbAndEmbeddedTwinsGiveTheSameImage) {
  TempDir dir;
  const std::string png = write_test_png(dir / "tex.png");
  const GltfBuilder ext = textured_quad(png, "uri");
  test::write_text(dir / "quad.bin", ext.bin);
  test::write_text(dir / "quad.gltf", ext.external("quad.bin"));
  const GltfBuilder inside = textured_quad(png, "view");
  test::write_text(dir / "quad.glb", inside.glb());
  test::write_text(dir / "embedded.gltf", inside.embedded());
  Result<Model> a = load_model(dir / "quad.gltf"), b = load_model(dir / "quad.glb"), c = load_model(dir / "embedded.gltf");
  ASSERT_TRUE(a.ok()) << a.status().message();
  ASSERT_TRUE(b.ok()) << b.status().message();
  ASSERT_TRUE(c.ok()) << c.status().message();
  const auto image = render_rgba(a->scene);
  EXPECT_EQ(render_rgba(b->scene), image);
  EXPECT_EQ(render_rgba(c->scene), image);
  // The texture is really used: without it the image differs.
  const GltfBuilder plain = textured_quad(png, "");
  test::write_text(dir / "plain.gltf", plain.embedded());
  Result<Model> d = load_model(dir / "plain.gltf");
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_NE(render_rgba(d->scene), image);
}

TEST(GltfImport, SameBytesForAnyThreadCount) {
  TempDir dir;
  const std::string png = write_test_png(dir / "tex.png");
  test::write_text(dir / "quad.glb", textured_quad(png, "view").glb());
  Result<Model> m = load_model(dir / "quad.glb");
  ASSERT_TRUE(m.ok()) << m.status().message();
  const auto one = render_rgba(m->scene, 256, 192, 1);
  EXPECT_EQ(render_rgba(m->scene, 256, 192, 2), one);
  EXPECT_EQ(render_rgba(m->scene, 256, 192, 8), one);
}

// A vertex-coloured triangle pair with neither camera nor lights, like the Khronos BoxVertexColors.
GltfBuilder coloured_quad(int color_type, bool normalized_ubyte) {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions);
  int col = 0;
  if (normalized_ubyte) {
    const std::vector<std::uint8_t> c = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 0, 255};
    col = b.accessor(b.view(c.data(), c.size()), 5121, 4, "VEC4", true);
  } else {
    col = b.floats({1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0}, "VEC3", 3);
  }
  (void)color_type;
  b.add("meshes", mesh_of({{"POSITION", pos}, {"COLOR_0", col}}, b.indices16(kQuadIndices)));
  b.add("nodes", {{"mesh", 0}, {"translation", {10.0, 20.0, -30.0}}, {"scale", {2.0, 2.0, 2.0}}});
  b.add("scenes", {{"nodes", {0}}});
  return b;
}

TEST(GltfImport, VertexColoursWithoutCameraOrLightsAreFramedAndLit) {
  for (bool ubyte : {false, true}) {
    TempDir dir;
    test::write_text(dir / "c.gltf", coloured_quad(0, ubyte).embedded());
    Result<Model> m = load_model(dir / "c.gltf");
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_FALSE(m->has_camera);
    EXPECT_FALSE(m->has_lights);
    const Mesh& mesh = m->scene.meshes[0].mesh;
    ASSERT_EQ(mesh.colors.size(), 4u);
    // No material: facet's default (diffuse 0.8), and the vertex colours replace it unscaled.
    EXPECT_EQ(mesh.colors[0], Color3(1, 0, 0));
    // No normals: flat normals (+z for this quad).
    EXPECT_TRUE(mesh.normals[0].isApprox(Vec3(0, 0, 1)));
    Scene& s = m->scene;
    const Bounds bounds = scene_bounds(s);
    EXPECT_TRUE(bounds.min.isApprox(Vec3(8, 18, -30)));
    EXPECT_TRUE(bounds.max.isApprox(Vec3(12, 22, -30)));
    // Before framing, the default camera sees nothing, and says why.
    Renderer r;
    std::vector<std::uint8_t> px(64 * 48 * 4);
    const ImageView view{px.data(), 64, 48, 256, PixelFormat::rgba8, false};
    FrameStats stats;
    ASSERT_TRUE(r.render(s, test::gl_options(), view, nullptr, &stats).ok());
    EXPECT_EQ(stats.pixels_filled, 0u);
    EXPECT_NE(explain_empty_frame(stats).find("outside the view"), std::string::npos) << explain_empty_frame(stats);
    s.camera = *frame_scene(s, 64.0f / 48.0f);
    add_default_lights(s);
    ASSERT_TRUE(r.render(s, test::gl_options(), view, nullptr, &stats).ok());
    EXPECT_GT(stats.pixels_filled, 64u * 48u / 10);
    EXPECT_EQ(explain_empty_frame(stats), "");
    // The bottom-left corner's pixels are red: the colours arrive.
    int red = 0;
    for (std::size_t i = 0; i < px.size(); i += 4) red += px[i] > 100 && px[i + 1] < 40 && px[i + 2] < 40;
    EXPECT_GT(red, 10);
  }
}

TEST(GltfImport, FramingKeepsTheWholeModelInView) {
  for (float aspect : {0.25f, 1.0f, 4.0f}) {
    Bounds b;
    b.min = Vec3(-3, 5, 100);
    b.max = Vec3(7, 6, 140);
    const Camera c = *frame_bounds(b, aspect);
    const Mat4 vp = projection_matrix(c, aspect) * view_matrix(c);
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p((corner & 1) ? b.max.x() : b.min.x(), (corner & 2) ? b.max.y() : b.min.y(), (corner & 4) ? b.max.z() : b.min.z());
      const Eigen::Vector4f clip = vp * Eigen::Vector4f(p.x(), p.y(), p.z(), 1.0f);
      for (int k = 0; k < 3; ++k) {
        EXPECT_LE(std::abs(clip[k]), clip.w()) << "aspect " << aspect << " corner " << corner << " axis " << k;
      }
    }
  }
}

TEST(GltfImport, NodeHierarchyTrsMatrixAndMirroring) {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions);
  b.add("meshes", mesh_of({{"POSITION", pos}}, b.indices16(kQuadIndices)));
  // Parent: translate (1, 2, 3) and rotate 90 degrees about y; child: scale -1 in x (a mirror) by a matrix.
  const double s = std::sqrt(0.5);
  b.add("nodes", {{"translation", {1.0, 2.0, 3.0}}, {"rotation", {0.0, s, 0.0, s}}, {"children", {1}}});
  b.add("nodes", {{"mesh", 0}, {"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}});
  b.add("scenes", {{"nodes", {0}}});
  const std::string text = b.embedded();
  Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "mem.gltf", "");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->scene.objects.size(), 1u);
  const Mat4& w = m->scene.objects[0].model;
  // x -> -x, then rotate about y by 90 degrees (x -> -z), then translate.
  const Eigen::Vector4f p = w * Eigen::Vector4f(1, 0, 0, 1);
  EXPECT_TRUE(p.head<3>().isApprox(Vec3(1, 2, 4), 1e-5f)) << p.transpose();
  EXPECT_LT((w.topLeftCorner<3, 3>().determinant()), 0.0f);
}

TEST(GltfImport, AnimationsAreListed) {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions);
  b.add("meshes", mesh_of({{"POSITION", pos}}, b.indices16(kQuadIndices)));
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  const int times = b.floats({0.0f, 1.0f}, "SCALAR", 1);
  const int turns = b.floats({0, 0, 0, 1, 0, 1, 0, 0}, "VEC4", 4);
  b.add("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}}}},
                       {"samplers", {{{"input", times}, {"output", turns}}}}});
  const std::string text = b.embedded();
  Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "anim.gltf", "");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->motion.animations.size(), 1u);
  EXPECT_EQ(m->motion.animations[0].name, "animations[0]");
  EXPECT_EQ(m->motion.animations[0].end_s, 1.0);
  EXPECT_EQ(m->motion.animations[0].channels, 1u);
  for (const auto& w : m->warnings) EXPECT_EQ(w.find("animations"), std::string::npos) << w;
}

TEST(GltfImport, StripsAndFansBecomeTriangles) {
  for (int mode : {5, 6}) {
    GltfBuilder b;
    const int pos = mode == 5 ? b.vec3({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0})
                              : b.vec3({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0});
    b.add("meshes", mesh_of({{"POSITION", pos}}, -1, -1, mode));
    b.add("nodes", {{"mesh", 0}});
    b.add("scenes", {{"nodes", {0}}});
    const std::string text = b.embedded();
    Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "mem.gltf", "");
    ASSERT_TRUE(m.ok()) << m.status().message();
    // Flat normals split the vertices: compare the corners' positions.
    const Mesh& mesh = m->scene.meshes[0].mesh;
    ASSERT_EQ(mesh.triangles.size(), 3u);
    auto corner = [&](std::size_t t, int k) { return mesh.positions[mesh.triangles[t][std::size_t(k)]]; };
    if (mode == 5) {  // strip: (0 1 2) (1 3 2) (2 3 4): every triangle wound like the first
      EXPECT_EQ(corner(1, 0), Vec3(1, 0, 0));
      EXPECT_EQ(corner(1, 1), Vec3(1, 1, 0));
      EXPECT_EQ(corner(1, 2), Vec3(0, 1, 0));
    } else {  // fan: (1 2 0) (2 3 0) (3 4 0)
      EXPECT_EQ(corner(2, 0), Vec3(0, 1, 0));
      EXPECT_EQ(corner(2, 1), Vec3(-1, 1, 0));
      EXPECT_EQ(corner(2, 2), Vec3(0, 0, 0));
    }
    // Every triangle faces +z, as the first does.
    for (std::size_t t = 0; t < 3; ++t) EXPECT_GT((corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0)).z(), 0.0f);
  }
}

TEST(GltfImport, SparseAccessorsAndStridesAreRead) {
  GltfBuilder b;
  // Interleaved positions and padding (stride 16), and a sparse override of vertex 2.
  std::vector<float> interleaved = {0, 0, 0, 9, 1, 0, 0, 9, 0, 1, 0, 9};
  const int v = b.view(interleaved.data(), interleaved.size() * 4, 16);
  const int pos = b.accessor(v, 5126, 3, "VEC3");
  const std::vector<std::uint8_t> which = {2};
  const std::vector<float> value = {0, 5, 0};
  const int iv = b.view(which.data(), 1), vv = b.view(value.data(), 12);
  b.doc["accessors"][pos]["sparse"] = {{"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", 5121}}}, {"values", {{"bufferView", vv}}}};
  b.add("meshes", mesh_of({{"POSITION", pos}}));
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  const std::string text = b.embedded();
  Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "mem.gltf", "");
  ASSERT_TRUE(m.ok()) << m.status().message();
  const auto& p = m->scene.meshes[0].mesh.positions;
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[1], Vec3(1, 0, 0));
  EXPECT_EQ(p[2], Vec3(0, 5, 0));
}

// The error for a glTF document changed by `edit`, which must name `path`.
void expect_error(const std::function<void(GltfBuilder&)>& edit, const std::string& path, ErrorCode code = ErrorCode::parse_error) {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions);
  b.add("meshes", mesh_of({{"POSITION", pos}}, b.indices16(kQuadIndices)));
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  edit(b);
  const std::string text = b.embedded();
  Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "bad.gltf", "");
  ASSERT_FALSE(m.ok()) << "expected an error naming " << path;
  EXPECT_NE(m.status().message().find(path), std::string::npos) << m.status().message();
  EXPECT_NE(m.status().message().find("bad.gltf"), std::string::npos) << m.status().message();
  EXPECT_EQ(m.status().code(), code) << m.status().message();
}

TEST(GltfImport, MalformedFilesNameTheJsonPath) {
  expect_error([](GltfBuilder& b) { b.doc["accessors"][1]["count"] = 7; }, "accessors[1]");  // indices beyond their view
  expect_error([](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["indices"] = 9; }, "meshes[0].primitives[0].indices");
  expect_error([](GltfBuilder& b) {
    const std::vector<std::uint16_t> bad = {0, 1, 7};
    b.doc["meshes"][0]["primitives"][0]["indices"] = b.indices16(bad);
  }, "meshes[0].primitives[0].indices");  // index 7 of 4 vertices
  expect_error([](GltfBuilder& b) { b.doc["bufferViews"][0]["byteLength"] = 100000; }, "bufferViews[0]");
  expect_error([](GltfBuilder& b) { b.doc["accessors"][0]["bufferView"] = 99; }, "accessors[0].bufferView");
  expect_error([](GltfBuilder& b) { b.doc["bufferViews"][0]["byteStride"] = 4; }, "accessors[0]");  // stride < a vec3
  expect_error([](GltfBuilder& b) { b.doc["nodes"][0]["children"] = {0}; }, "nodes[0]");  // a cycle
  expect_error([](GltfBuilder& b) {
    b.add("nodes", {{"children", {0}}});
    b.doc["scenes"][0]["nodes"] = {0, 1};
  }, "nodes[0] is reached twice");  // two parents
  expect_error([](GltfBuilder& b) { b.doc["scenes"][0]["nodes"] = {5}; }, "scenes[0].nodes[0]");
  expect_error([](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["mode"] = 7; }, "meshes[0].primitives[0].mode");
  expect_error([](GltfBuilder& b) { b.doc["extensionsRequired"] = {"EXT_texture_webp"}; b.doc["extensionsUsed"] = {"EXT_texture_webp"}; },
               "EXT_texture_webp", ErrorCode::unsupported);
  expect_error([](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["material"] = 3; }, "meshes[0].primitives[0].material");
  expect_error([](GltfBuilder& b) { b.doc["nodes"][0]["rotation"] = {0, 0, 0, 0}; }, "nodes[0].rotation");
  expect_error([](GltfBuilder& b) {
    const std::vector<float> nan = {std::nanf(""), 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = b.vec3(nan);
  }, "accessors[2]");
}

TEST(GltfImport, BuffersShorterThanDeclaredNameTheBuffer) {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions);
  b.add("meshes", mesh_of({{"POSITION", pos}}));
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  for (const bool glb : {false, true}) {
    nlohmann::json d = b.with_buffer(glb ? "" : "data:application/octet-stream;base64," + test::base64(b.bin));
    d["buffers"][0]["byteLength"] = b.bin.size() + 100;
    std::string text;
    if (glb) {
      text = GltfBuilder::glb_of(d.dump(), b.bin);
    } else {
      text = d.dump();
    }
    Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "short.gltf", "");
    ASSERT_FALSE(m.ok()) << (glb ? "glb" : "gltf");
    EXPECT_NE(m.status().message().find("buffers[0]: holds"), std::string::npos) << m.status().message();
  }
}

TEST(GltfImport, NotGltfAtAllIsAParseError) {
  for (const std::string& text : {std::string(""), std::string("{"), std::string("glTF\x02\0\0\0", 8), std::string("[1, 2]")}) {
    Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "junk.gltf", "");
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.status().message().find("junk.gltf"), std::string::npos) << m.status().message();
  }
}

TEST(GltfImport, MissingImageIsAnErrorUnlessAllowed) {
  TempDir dir;
  const std::string png = write_test_png(dir / "tex.png");
  const GltfBuilder b = textured_quad(png, "uri");
  test::write_text(dir / "quad.gltf", b.embedded());
  fs::remove(dir / "tex.png");
  ModelOptions strict;
  strict.allow_missing = false;
  Result<Model> m = load_model(dir / "quad.gltf", strict);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("images[0]"), std::string::npos) << m.status().message();
  EXPECT_NE(m.status().message().find("tex.png"), std::string::npos) << m.status().message();
  ModelOptions o;  // by default: a warning, drawn untextured
  m = load_model(dir / "quad.gltf", o);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->scene.materials[0].diffuse_texture, kNoTexture);
  bool warned = false;
  for (const auto& w : m->warnings) warned |= w.find("images[0]") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(GltfImport, MemoryBudgetIsHonoured) {
  GltfBuilder b;
  std::vector<float> many(3 * 200000, 0.5f);
  const int pos = b.vec3(many);
  b.add("meshes", mesh_of({{"POSITION", pos}}));
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  const std::string text = b.glb();
  ModelOptions o;
  o.memory_budget_bytes = 4 << 20;
  Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "big.glb", "", o);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.status().code(), ErrorCode::out_of_memory) << m.status().message();
}

TEST(GltfImport, AMillionNodesAreWalkedWithoutRecursion) {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions);
  b.add("meshes", mesh_of({{"POSITION", pos}}, b.indices16(kQuadIndices)));
  const int n = 1000000;
  nlohmann::json nodes = nlohmann::json::array();
  for (int i = 0; i < n; ++i) {
    nlohmann::json node = nlohmann::json::object();
    if (i + 1 < n) node["children"] = {i + 1};
    else node["mesh"] = 0;
    nodes.push_back(std::move(node));
  }
  b.doc["nodes"] = std::move(nodes);
  b.add("scenes", {{"nodes", {0}}});
  const std::string text = b.glb();
  Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "deep.glb", "");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->scene.objects.size(), 1u);
}

TEST(GltfImport, PunctualLightsFollowTheExtension) {
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {
      {{"type", "spot"}, {"intensity", 10.0}, {"range", 5.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
      {{"type", "point"}, {"color", {0.5, 0.5, 1.0}}}}}}}};
  b.add("nodes", {{"translation", {1.0, 2.0, 3.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.add("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  b.add("scenes", {{"nodes", {0, 1}}});
  const std::string text = b.embedded();
  Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "l.gltf", "");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->scene.lights.size(), 2u);
  const Light& spot = m->scene.lights[0];
  EXPECT_EQ(spot.type, LightType::spot);
  EXPECT_EQ(spot.position, Vec3(1, 2, 3));
  EXPECT_TRUE(spot.direction.isApprox(Vec3(0, 0, -1)));
  EXPECT_EQ(spot.spot_shape, SpotShape::smooth_cone);
  EXPECT_NEAR(spot.spot_inner_deg, 0.2 * 180 / std::numbers::pi, 1e-4);
  EXPECT_NEAR(spot.spot_outer_deg, 0.6 * 180 / std::numbers::pi, 1e-4);
  EXPECT_EQ(spot.range, 5.0f);
  EXPECT_EQ(spot.quadratic_attenuation, 1.0f);
  EXPECT_EQ(spot.constant_attenuation, 0.0f);
  // candela / pi: glTF's Lambert term is albedo / pi times the irradiance, GL's albedo times the colour.
  EXPECT_EQ(spot.diffuse, Color3::Constant(float(10.0 / std::numbers::pi)));
  EXPECT_EQ(m->scene.lights[1].diffuse, Color3(float(0.5 / std::numbers::pi), float(0.5 / std::numbers::pi), float(1.0 / std::numbers::pi)));
  // Lights in physical units: metered, and the neutral operator (docs/color.md).
  EXPECT_TRUE(m->scene.display.automatic);
  EXPECT_EQ(m->scene.display.tone_mapping, ToneMapping::neutral);

  // facet's smooth cone with falloff 2 is glTF's spot formula: light one vertex at angles across
  // the cone with the reference path and compare with saturate(cd scale + offset)^2 / d^2.
  Scene s = test::eye_space_scene();
  s.materials[0].diffuse = Color3(1, 1, 1);
  Light l = spot;
  l.position = Vec3(0, 0, 0);
  l.direction = Vec3(0, 0, -1);
  l.range = 0.0f;
  l.diffuse = Color3(1, 1, 1);
  l.specular = Color3(0, 0, 0);
  s.lights = {l};
  const double scale = 1.0 / std::max(0.001, std::cos(0.2) - std::cos(0.6)), offset = -std::cos(0.6) * scale;
  for (double angle = 0.0; angle < 0.7; angle += 0.01) {
    const Vec3 p(float(2.0 * std::sin(angle)), 0.0f, float(-2.0 * std::cos(angle)));
    test::set_single_vertex(s, p, (-p).normalized());
    VertexColors out;
    LightingOptions lo;
    lo.path = LightingPath::reference;
    ASSERT_TRUE(light_instance(s, 0, lo, out).ok());
    const double cd = std::cos(angle);
    const double att = std::pow(std::clamp(cd * scale + offset, 0.0, 1.0), 2.0) / 4.0;
    EXPECT_NEAR(out.front[0].x(), att, 1e-5) << "angle " << angle;
  }
}

TEST(GltfImport, MetallicRoughnessMapping) {
  // A dielectric keeps its base colour as diffuse and gets a white 4% highlight.
  PbrMapping d = map_metallic_roughness(Color3(0.5f, 0.25f, 1.0f), 0.0f, 0.0f);
  EXPECT_EQ(d.diffuse, Color3(0.5f, 0.25f, 1.0f));
  EXPECT_TRUE(d.specular.isApprox(Color3::Constant(0.04f)));
  EXPECT_EQ(d.shininess, kMaxShininess);
  // A polished metal only reflects, in its colour.
  PbrMapping m = map_metallic_roughness(Color3(0.9f, 0.6f, 0.2f), 1.0f, 0.0f);
  EXPECT_EQ(m.diffuse, Color3::Zero());
  EXPECT_TRUE(m.specular.isApprox(Color3(0.9f, 0.6f, 0.2f)));
  // A rough metal scatters like a diffuse surface of its colour.
  PbrMapping r = map_metallic_roughness(Color3(0.9f, 0.6f, 0.2f), 1.0f, 1.0f);
  EXPECT_EQ(r.diffuse, Color3(0.9f, 0.6f, 0.2f));
  EXPECT_EQ(r.specular, Color3::Zero());
  EXPECT_EQ(r.shininess, 1.0f);
  // Shininess from roughness: a = r^2, 2 / a^2 - 2.
  EXPECT_NEAR(map_metallic_roughness(Color3::Ones(), 0.0f, 0.5f).shininess, 30.0f, 1e-3f);
}

TEST(GltfImport, DoubleSidedMaterialsDrawBackFaces) {
  for (bool double_sided : {false, true}) {
    GltfBuilder b;
    const int pos = b.vec3(kQuadPositions);
    b.add("materials", {{"doubleSided", double_sided}, {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}});
    b.add("meshes", mesh_of({{"POSITION", pos}}, b.indices16(kQuadIndices), 0));
    b.add("nodes", {{"mesh", 0}});
    b.add("scenes", {{"nodes", {0}}});
    const std::string text = b.embedded();
    Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "d.gltf", "");
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_EQ(m->scene.objects[0].double_sided, double_sided);
    Scene& s = m->scene;
    s.camera.eye = Vec3(0, 0, -3);  // behind the quad
    s.camera.target = Vec3(0, 0, 0);
    Light l;
    l.direction = Vec3(0, 0, 1);  // lights the back
    s.lights = {l};
    for (ShadingMode shading : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      std::vector<std::uint8_t> px(32 * 32 * 4);
      const ImageView view{px.data(), 32, 32, 128, PixelFormat::rgba8, false};
      RenderOptions o = test::gl_options();
      o.shading = shading;
      FrameStats stats;
      Renderer r;
      ASSERT_TRUE(r.render(s, o, view, nullptr, &stats).ok());
      if (!double_sided) {
        EXPECT_EQ(stats.pixels_filled, 0u);
        continue;
      }
      EXPECT_GT(stats.pixels_filled, 100u);
      // Lit from behind with the negated normal: bright, not the ambient-only grey.
      const std::size_t centre = (16 * 32 + 16) * 4;
      EXPECT_GT(px[centre], 150) << to_string(shading);
    }
  }
}

}  // namespace
}  // namespace facet
