// Content drawn as its authors meant it (issue "content as authored"): double-sided blended objects
// drawn back faces first, BLEND materials that are opaque everywhere drawn opaque.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "facet/facet.hpp"
#include "gltf_builder.hpp"
#include "render_support.hpp"

namespace facet {
namespace {

// One double-sided, alpha-blended object of two quads facing the camera's way: a near one (red,
// front-facing) listed first, a far one (green, wound clockwise: back-facing) second. Lit by the
// ambient light alone (vertex colours as albedo).
Scene two_layers(bool double_sided) {
  Scene s = test::camera_scene();
  s.global_ambient = Color3(1, 1, 1);
  s.transparent_order = TransparentOrder::back_to_front;
  Mesh m;
  m.positions = {Vec3(-5, -5, -2), Vec3(5, -5, -2), Vec3(5, 5, -2), Vec3(-5, 5, -2),   // near, counter-clockwise
                 Vec3(-5, -5, -3), Vec3(-5, 5, -3), Vec3(5, 5, -3), Vec3(5, -5, -3)};  // far, clockwise
  for (int i = 0; i < 8; ++i) m.normals.push_back(Vec3(0, 0, i < 4 ? 1.0f : -1.0f));
  for (int i = 0; i < 8; ++i) m.colors.push_back(i < 4 ? Color3(1, 0, 0) : Color3(0, 1, 0));
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  s.meshes.push_back({"layers", m});
  Material mat;
  mat.ambient = mat.diffuse = Color3(1, 1, 1);
  mat.specular = Color3::Zero();
  mat.alpha = 0.5f;
  mat.blend = BlendMode::alpha;
  s.materials.push_back(mat);
  Instance inst{0, 0, Mat4::Identity()};
  inst.double_sided = double_sided;
  s.objects.push_back(inst);
  return s;
}

TEST(BlendedDoubleSided, BackFacesAreDrawnBeforeFrontFaces) {
  const Scene s = two_layers(true);
  RenderOptions o = test::gl_options();
  o.clear_color = {0, 0, 1, 1};
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
      o.shading = mode;
      o.path = path;
      test::Canvas c(8, 8);
      Renderer r;
      ASSERT_TRUE(r.render(s, o, c.view()).ok());
      // Far green over blue, then near red over that: (0.5, 0.25, 0.25).
      EXPECT_NEAR(c.byte(4, 4, 0), 128, 1) << to_string(mode);
      EXPECT_NEAR(c.byte(4, 4, 1), 64, 1) << to_string(mode);
      EXPECT_NEAR(c.byte(4, 4, 2), 64, 1) << to_string(mode);
    }
  }
  // In submission order nothing is reordered: the triangles' own order, red first, green over it.
  Scene submitted = s;
  submitted.transparent_order = TransparentOrder::submission;
  test::Canvas c(8, 8);
  ASSERT_TRUE(Renderer().render(submitted, o, c.view()).ok());
  EXPECT_NEAR(c.byte(4, 4, 0), 64, 1);
  EXPECT_NEAR(c.byte(4, 4, 1), 128, 1);
  // A one-sided object draws its front faces only.
  test::Canvas one(8, 8);
  ASSERT_TRUE(Renderer().render(two_layers(false), o, one.view()).ok());
  EXPECT_NEAR(one.byte(4, 4, 0), 128, 1);
  EXPECT_NEAR(one.byte(4, 4, 1), 0, 1);
  EXPECT_NEAR(one.byte(4, 4, 2), 128, 1);
}

TEST(BlendedDoubleSided, SameBytesForAnyThreadCount) {
  Scene s = two_layers(true);
  s.meshes[0].mesh = make_uv_sphere(1.5f, 64, 32);
  s.meshes[0].mesh.colors.assign(s.meshes[0].mesh.vertex_count(), Color3(0.2f, 0.6f, 0.9f));
  s.objects[0].model = Mat4::Identity();
  s.objects[0].model(2, 3) = -4.0f;
  Light l;
  l.type = LightType::directional;
  l.direction = Vec3(-0.3f, -0.5f, -1.0f).normalized();
  s.lights = {l};
  s.global_ambient = Color3::Constant(0.1f);
  std::vector<std::uint8_t> first;
  for (int threads : {1, 2, 3}) {
    RenderOptions o;
    o.threads = threads;
    o.tile_size = 16;
    test::Canvas c(64, 48);
    ASSERT_TRUE(Renderer().render(s, o, c.view()).ok());
    if (first.empty()) first = c.pixels();
    EXPECT_EQ(c.pixels(), first) << threads << " threads";
  }
}

// A glTF quad with a BLEND material of base colour alpha `alpha`, and with `texel_alpha` a 2x1
// base colour texture whose second texel has that alpha; returns the file's path.
std::string blend_quad(const test::TempDir& dir, double alpha, int texel_alpha = -1) {
  test::GltfBuilder b = test::quad();
  nlohmann::json mat = {{"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 1.0, 1.0, alpha}}}}};
  if (texel_alpha >= 0) {
    std::uint8_t rgba[8] = {255, 255, 255, 255, 255, 255, 255, static_cast<std::uint8_t>(texel_alpha)};
    EXPECT_TRUE(write_png(dir / "t.png", ImageView{rgba, 2, 1, 8, PixelFormat::rgba8, false}).ok());
    b.add("images", {{"uri", "t.png"}});
    b.add("textures", {{"source", 0}});
    mat["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = b.vec2({0, 0, 1, 0, 1, 1, 0, 1});
  }
  b.add("materials", mat);
  b.doc["meshes"][0]["primitives"][0]["material"] = 0;
  const std::string path = dir / ("q" + std::to_string(texel_alpha) + "_" + std::to_string(int(alpha * 100)) + ".gltf");
  test::write_text(path, b.embedded());
  return path;
}

TEST(BlendedDoubleSided, BlendWithAlphaOneEverywhereIsDrawnOpaque) {
  test::TempDir dir;
  Result<Model> opaque = load_model(blend_quad(dir, 1.0));
  ASSERT_TRUE(opaque.ok()) << opaque.status().message();
  EXPECT_EQ(opaque->scene.materials[0].blend, BlendMode::opaque);
  ASSERT_FALSE(opaque->warnings.empty());
  EXPECT_NE(opaque->warnings.back().find("materials[0].alphaMode: BLEND with alpha 1 everywhere; drawn opaque"), std::string::npos);
  Result<Model> half = load_model(blend_quad(dir, 0.5));
  ASSERT_TRUE(half.ok());
  EXPECT_EQ(half->scene.materials[0].blend, BlendMode::alpha);
  Result<Model> textured = load_model(blend_quad(dir, 1.0, 128));
  ASSERT_TRUE(textured.ok()) << textured.status().message();
  EXPECT_EQ(textured->scene.materials[0].blend, BlendMode::alpha);  // a texel of alpha 128
  Result<Model> solid = load_model(blend_quad(dir, 1.0, 255));
  ASSERT_TRUE(solid.ok()) << solid.status().message();
  EXPECT_EQ(solid->scene.materials[0].blend, BlendMode::opaque);
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// The OBJ of one polygon in z = 0 (corners in order, counter-clockwise seen from +z).
std::string polygon_obj(const std::vector<Vec2>& corners) {
  std::string text;
  for (const Vec2& c : corners) text += "v " + std::to_string(c.x()) + " " + std::to_string(c.y()) + " 0\n";
  text += "f";
  for (std::size_t i = 1; i <= corners.size(); ++i) text += " " + std::to_string(i);
  return text + "\n";
}

// Twice the signed area of the polygon (shoelace) and of each of the mesh's triangles in z = 0.
double shoelace(const std::vector<Vec2>& c) {
  double a = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const Vec2& p = c[i];
    const Vec2& q = c[(i + 1) % c.size()];
    a += double(p.x()) * double(q.y()) - double(q.x()) * double(p.y());
  }
  return a;
}

void expect_tiled(const std::vector<Vec2>& corners, const char* name) {
  Result<Mesh> m = parse_obj(polygon_obj(corners), name);
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->triangles.size(), corners.size() - 2) << name;
  double sum = 0.0;
  for (const auto& t : m->triangles) {
    const Vec3& a = m->positions[t[0]];
    const Vec3& b = m->positions[t[1]];
    const Vec3& c = m->positions[t[2]];
    const double area2 = (double(b.x()) - a.x()) * (double(c.y()) - a.y()) - (double(b.y()) - a.y()) * (double(c.x()) - a.x());
    EXPECT_GE(area2, 0.0) << name << ": a triangle winds the other way (it lies outside the polygon)";
    sum += area2;
  }
  // The triangles, all wound as the polygon, cover exactly its area: none overlaps or sticks out.
  EXPECT_NEAR(sum, shoelace(corners), 1e-4) << name;
}

TEST(ObjPolygons, ConcavePolygonsAreEarClipped) {
  expect_tiled({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L.obj");
  std::vector<Vec2> star;
  for (int k = 0; k < 10; ++k) {
    const double angle = k * std::numbers::pi / 5, r = k % 2 ? 0.4 : 1.0;
    star.emplace_back(float(r * std::cos(angle)), float(r * std::sin(angle)));
  }
  expect_tiled(star, "star.obj");
  // A ring as one polygon (as LightWave and assimp write it): the outer circle counter-clockwise,
  // a bridge in, the inner circle clockwise, the bridge out.
  std::vector<Vec2> ring;
  const int n = 24;
  for (int k = 0; k <= n; ++k) ring.emplace_back(float(2 * std::cos(2 * std::numbers::pi * k / n)), float(2 * std::sin(2 * std::numbers::pi * k / n)));
  for (int k = n; k >= 0; --k) ring.emplace_back(float(std::cos(2 * std::numbers::pi * k / n)), float(std::sin(2 * std::numbers::pi * k / n)));
  expect_tiled(ring, "ring.obj");
  // A convex polygon keeps its fan from the first corner.
  Result<Mesh> hex = parse_obj(polygon_obj({{1, 0}, {0.5f, 0.8f}, {-0.5f, 0.8f}, {-1, 0}, {-0.5f, -0.8f}, {0.5f, -0.8f}}), "hex.obj");
  ASSERT_TRUE(hex.ok());
  for (std::uint32_t k = 0; k < 4; ++k) EXPECT_EQ(hex->triangles[k], (std::array<std::uint32_t, 3>{0, k + 1, k + 2}));
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

void write_grey_png(const std::string& path) {
  std::uint8_t rgba[16];
  for (int i = 0; i < 16; ++i) rgba[i] = i % 4 == 3 ? 255 : 128;
  ASSERT_TRUE(write_png(path, ImageView{rgba, 2, 2, 8, PixelFormat::rgba8, false}).ok());
}

const char* kQuadObj = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";

TEST(MissingFiles, AMissingMaterialLibraryIsAWarningUnlessStrict) {
  test::TempDir dir;
  test::write_text(dir / "a.obj", std::string("mtllib gone.mtl\n") + kQuadObj);
  Result<Model> m = load_model(dir / "a.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_FALSE(m->warnings.empty());
  EXPECT_NE(m->warnings[0].find("gone.mtl"), std::string::npos) << m->warnings[0];
  EXPECT_EQ(m->scene.materials.size(), 1u);  // facet's default for usemtl m
  ModelOptions strict;
  strict.allow_missing = false;
  Result<Model> refused = load_model(dir / "a.obj", strict);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("gone.mtl"), std::string::npos);
  EXPECT_NE(refused.status().message().find("--strict"), std::string::npos) << refused.status().message();
  // A texture that is not an image is a warning too, and an error when strict.
  test::write_text(dir / "b.mtl", "newmtl m\nmap_Kd notes.png\n");
  test::write_text(dir / "notes.png", "this is not a picture");
  test::write_text(dir / "b.obj", std::string("mtllib b.mtl\n") + kQuadObj);
  Result<Model> b = load_model(dir / "b.obj");
  ASSERT_TRUE(b.ok()) << b.status().message();
  EXPECT_EQ(b->scene.materials[0].diffuse_texture, kNoTexture);
  EXPECT_FALSE(load_model(dir / "b.obj", strict).ok());
}

TEST(MissingFiles, TextureNamesFromAnotherMachineFallBackToTheirBaseName) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "model");
  write_grey_png(dir / "model/tex.png");
  write_grey_png(dir / "outside.png");  // beside the model's folder: never read
  for (const char* name : {"D:\\models\\spider\\tex.png", "..\\LWO\\tex.png", "C:tex.png", "textures/tex.png"}) {
    test::write_text(dir / "model/m.mtl", std::string("newmtl m\nmap_Kd ") + name + "\n");
    test::write_text(dir / "model/m.obj", std::string("mtllib m.mtl\n") + kQuadObj);
    ModelOptions strict;
    strict.allow_missing = false;  // found by its base name: not even a missing file
    Result<Model> m = load_model(dir / "model/m.obj", strict);
    ASSERT_TRUE(m.ok()) << name << ": " << m.status().message();
    EXPECT_EQ(m->scene.materials[0].diffuse_texture, 0) << name;
    ASSERT_FALSE(m->warnings.empty()) << name;
    EXPECT_NE(m->warnings.back().find("base name"), std::string::npos) << m->warnings.back();
  }
  // The base name is looked for in the model's folder only.
  test::write_text(dir / "model/m.mtl", "newmtl m\nmap_Kd ..\\outside.png\n");
  std::filesystem::remove(dir / "model/tex.png");
  Result<Model> m = load_model(dir / "model/m.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->scene.materials[0].diffuse_texture, kNoTexture);
}

TEST(MissingFiles, GltfOneIsSaidToBeUnsupported) {
  const char* files[] = {R"({"asset": {"version": 1}, "scenes": {}})",
                         R"({"asset": {"version": "1.0"}, "buffers": {"b": {"uri": "x.bin"}}})",
                         R"({"buffers": {"b": {"uri": "x.bin"}}, "shaders": {}, "techniques": {}})"};
  for (const char* text : files) {
    const std::string t(text);
    Result<Model> m = parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(t.data()), t.size()), "old.gltf", "");
    ASSERT_FALSE(m.ok()) << text;
    EXPECT_EQ(m.status().code(), ErrorCode::unsupported) << m.status().message();
    EXPECT_NE(m.status().message().find("glTF 1.0 and older are not supported"), std::string::npos) << m.status().message();
  }
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

TEST(GltfInstancing, EveryInstanceIsDrawnAtItsPlace) {
  test::GltfBuilder b = test::quad();
  const int t = b.vec3({0, 0, 0, 2, 0, 0, 4, 0, 0});
  const int r = b.vec4({0, 0, 0, 1, 0, 0, 0.7071068f, 0.7071068f, 0, 0, 0, 1});
  const int s = b.vec3({1, 1, 1, 1, 1, 1, 2, 2, 2});
  b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  b.doc["nodes"][0]["translation"] = {0.0, 10.0, 0.0};
  b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = {{"TRANSLATION", t}, {"ROTATION", r}, {"SCALE", s}};
  const std::string text = b.embedded();
  auto parse = [](const std::string& x) {
    return parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(x.data()), x.size()), "i.gltf", "");
  };
  Result<Model> m = parse(text);
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->scene.objects.size(), 3u);
  for (const std::string& w : m->warnings) EXPECT_EQ(w.find("EXT_mesh_gpu_instancing"), std::string::npos) << w;
  // The node's translation, then each instance's T x R x S.
  auto world = [&](std::size_t i, Vec3 p) { return Vec3((m->scene.objects[i].model * p.homogeneous()).head<3>()); };
  EXPECT_TRUE(world(0, Vec3(1, 1, 0)).isApprox(Vec3(1, 11, 0)));
  EXPECT_TRUE(world(1, Vec3(1, 0, 0)).isApprox(Vec3(2, 11, 0), 1e-5f));  // a quarter turn about z
  EXPECT_TRUE(world(2, Vec3(1, 1, 0)).isApprox(Vec3(6, 12, 0)));
  // Attributes of different counts are refused, naming the attribute.
  b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] = b.vec3({1, 1, 1});
  Result<Model> bad = parse(b.embedded());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("EXT_mesh_gpu_instancing.attributes.SCALE"), std::string::npos) << bad.status().message();
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// Blender's own exports with lights in its units (tests/data/blender, made by
// tools/data/make_blender_exports.py with Blender 3.4): with no option, each shows its subject
// neither black nor clipped: most covered pixels between 10 % and 95 % of white (the issue's
// acceptance), where GL's reading of their intensities drew white silhouettes.
TEST(BlenderExports, EveryExportShowsItsSubjectNeitherBlackNorClipped) {
  const std::filesystem::path folder = std::filesystem::path(test::data_dir()) / "blender";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".glb") continue;
    ++files;
    Result<Model> m = load_model(entry.path().string());
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_TRUE(m->has_camera && m->has_lights) << entry.path();
    test::Canvas c(160, 90);
    Renderer r;
    RenderOptions o;
    o.shading = ShadingMode::phong;  // as facet render draws a model: lit per pixel
    ASSERT_TRUE(r.render(m->scene, o, c.view()).ok()) << entry.path();
    int covered = 0, in_range = 0, clipped = 0;
    for (int y = 0; y < 90; ++y) {
      for (int x = 0; x < 160; ++x) {
        const int top = std::max({c.byte(x, y, 0), c.byte(x, y, 1), c.byte(x, y, 2)});
        if (top == 0) continue;  // the black background
        ++covered;
        in_range += top >= 26 && top <= 242;
        clipped += top == 255;
      }
    }
    EXPECT_GT(covered, 160 * 90 / 8) << entry.path() << ": the subject and its lit floor show";
    EXPECT_GT(2 * in_range, covered) << entry.path() << ": " << in_range << " of " << covered << " covered pixels in 10-95 % of white";
    EXPECT_LT(10 * clipped, covered) << entry.path() << ": " << clipped << " of " << covered << " covered pixels clipped";
    std::printf("%s: %d of %d covered pixels in 10-95 %% of white, %d clipped\n", entry.path().filename().c_str(), in_range,
                covered, clipped);
  }
  EXPECT_EQ(files, 10);
}

// A surface that names no material (an OBJ without a .mtl, a glTF primitive without "material")
// is lit by the ambient light as its diffuse grey, as three.js and Blender light it: GL's ambient
// 0.2 left its unlit side near black under the default rig where viewers show it grey.
TEST(DefaultMaterial, AmbientIsTheDiffuseGreyForObjAndGltf) {
  test::TempDir dir;
  test::write_text(dir / "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  test::write_text(dir / "q.gltf", test::quad().embedded());
  for (const std::string name : {"a.obj", "q.gltf"}) {
    Result<Model> m = load_model(dir / name);
    ASSERT_TRUE(m.ok()) << m.status().message();
    ASSERT_EQ(m->scene.objects.size(), 1u) << name;
    const Material& mat = m->scene.materials[m->scene.objects[0].material];
    EXPECT_EQ(mat.name, "default") << name;
    EXPECT_EQ(mat.diffuse, Color3::Constant(0.8f)) << name;
    EXPECT_EQ(mat.ambient, mat.diffuse) << name;
    EXPECT_EQ(mat.specular, Color3::Zero()) << name;
  }
}

}  // namespace
}  // namespace facet
