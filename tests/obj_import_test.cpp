// OBJ + MTL import (model.hpp): materials, textures and groups, and the errors for malformed or
// missing files; models placed by a scene file. Files are written by the tests.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "content/import.hpp"
#include "content_support.hpp"
#include "facet/facet.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

TEST(ObjMtlImport, MaterialNamesWithSpacesAndPlusSigns) {
  TempDir dir;
  test::write_text(dir / "m.mtl", "newmtl My Red\nKd +0.9 +.1 0\nnewmtl My\nKd 0 0 1\n");
  test::write_text(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl My Red\nf 1 2 3\n");
  Result<Model> m = load_model(dir / "m.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  const Scene& s = m->scene;
  ASSERT_EQ(s.objects.size(), 1u);
  const Mesh& mesh = s.meshes[s.objects[0].mesh].mesh;
  ASSERT_EQ(mesh.groups.size(), 1u);
  EXPECT_EQ(mesh.groups[0].material, "My Red");
  const Material& red = s.materials[std::size_t(find_material(s, "My Red"))];
  EXPECT_EQ(red.diffuse, Color3(0.9f, 0.1f, 0.0f));
}

TEST(ObjMtlImport, MaterialsTexturesAndGroups) {
  TempDir dir;
  write_test_png(dir / "tex.png");
  test::write_text(dir / "m.mtl",
                   "# two materials\n"
                   "newmtl red\nKa 0.1 0 0\nKd 0.9 0.1 0.1\nKs 0.5\nNs 64\nKe 0 0 0.25\nillum 2\n"
                   "newmtl glass\nKd 1 1 1\nd 0.25\nTr 0.75\nmap_Kd -s 2 3 -clamp on tex.png\nmap_Ns n.png\n");
  test::write_text(dir / "m.obj",
                   "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                   "usemtl red\nf 1/1 2/2 3/3\nusemtl glass\nf 1/1 3/3 4/4\n");
  Result<Model> m = load_model(dir / "m.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  const Scene& s = m->scene;
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_TRUE(s.objects[0].mesh_materials);
  const Material& red = s.materials[std::size_t(find_material(s, "red"))];
  EXPECT_EQ(red.ambient, Color3(0.1f, 0, 0));
  EXPECT_EQ(red.diffuse, Color3(0.9f, 0.1f, 0.1f));
  EXPECT_EQ(red.specular, Color3(0.5f, 0.5f, 0.5f));
  EXPECT_EQ(red.emissive, Color3(0, 0, 0.25f));
  EXPECT_EQ(red.shininess, 64.0f);
  EXPECT_EQ(red.blend, BlendMode::opaque);
  const Material& glass = s.materials[std::size_t(find_material(s, "glass"))];
  EXPECT_EQ(glass.alpha, 0.25f);
  EXPECT_EQ(glass.blend, BlendMode::alpha);
  ASSERT_NE(glass.diffuse_texture, kNoTexture);
  EXPECT_EQ(glass.uv_scale, Vec2(2, 3));
  EXPECT_EQ(s.textures[std::size_t(glass.diffuse_texture)].wrap, TextureWrap::clamp);
  bool bump_warned = false;
  for (const auto& w : m->warnings) bump_warned |= w.find("map_Ns") != std::string::npos && w.find("m.mtl") != std::string::npos;
  EXPECT_TRUE(bump_warned);
  EXPECT_GT(render_rgba([&] {
              Scene r = s;
              r.camera = *frame_scene(r, 64.0f / 48.0f);
              add_default_lights(r);
              return r;
            }())
                .size(),
            0u);
}

// map_Ke: the emissive texture times Ke (1 without Ke), added after the diffuse texture; a
// missing file is an error naming the line.
TEST(ObjMtlImport, EmissiveTexturesFromMapKe) {
  TempDir dir;
  write_test_png(dir / "tex.png");
  test::write_text(dir / "m.mtl",
                   "newmtl lamp\nKd 0 0 0\nKa 0 0 0\nmap_Ke tex.png\n"
                   "newmtl sign\nKd 1 1 1\nKe 0.5 0.25 1\nmap_Kd -s 2 2 tex.png\nmap_Ke -s 3 3 tex.png\n"
                   "newmtl broken\nmap_Ke absent.png\n");
  test::write_text(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                  "usemtl lamp\nf 1/1 2/2 3/3\nusemtl sign\nf 1/1 2/2 3/3\n");
  ModelOptions strict;
  strict.allow_missing = false;
  Result<Model> m = load_model(dir / "m.obj", strict);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("m.mtl:11: texture 'absent.png'"), std::string::npos) << m.status().message();
  test::write_text(dir / "m.mtl",
                   "newmtl lamp\nKd 0 0 0\nKa 0 0 0\nmap_Ke tex.png\n"
                   "newmtl sign\nKd 1 1 1\nKe 0.5 0.25 1\nmap_Kd -s 2 2 tex.png\nmap_Ke -s 3 3 tex.png\n");
  m = load_model(dir / "m.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  const Scene& s = m->scene;
  const Material& lamp = s.materials[std::size_t(find_material(s, "lamp"))];
  ASSERT_NE(lamp.emissive_texture, kNoTexture);
  EXPECT_EQ(lamp.diffuse_texture, kNoTexture);
  EXPECT_EQ(lamp.emissive, Color3(1, 1, 1));
  const Material& sign = s.materials[std::size_t(find_material(s, "sign"))];
  ASSERT_NE(sign.emissive_texture, kNoTexture);
  ASSERT_NE(sign.diffuse_texture, kNoTexture);
  EXPECT_EQ(sign.emissive, Color3(0.5f, 0.25f, 1.0f));
  EXPECT_EQ(sign.uv_scale, Vec2(2, 2));
  bool scale_warned = false;
  for (const auto& w : m->warnings) scale_warned |= w.find("m.mtl:9: map_Ke -s differs") != std::string::npos;
  EXPECT_TRUE(scale_warned);
  for (const auto& w : m->warnings) EXPECT_EQ(w.find("map_Ke: ignored"), std::string::npos) << w;
  Scene r = s;
  r.camera = *frame_scene(r, 64.0f / 48.0f);
  EXPECT_TRUE(validate_scene(r).ok()) << validate_scene(r).message();
}

// norm: a tangent-space normal map (linear) with -bm as its scale; the mesh gets tangents.
TEST(ObjMtlImport, NormalMapsFromNorm) {
  TempDir dir;
  write_test_png(dir / "tex.png");
  test::write_text(dir / "m.mtl", "newmtl bumpy\nKd 1 1 1\nmap_Kd tex.png\nnorm -bm 0.5 tex.png\nmap_Bump -bm 3 tex.png\n");
  test::write_text(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                  "usemtl bumpy\nf 1/1 2/2 3/3\n");
  Result<Model> m = load_model(dir / "m.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  for (const auto& w : m->warnings) EXPECT_EQ(w.find("norm"), std::string::npos) << w;
  const Material& mat = m->scene.materials[std::size_t(find_material(m->scene, "bumpy"))];
  ASSERT_NE(mat.normal_texture, kNoTexture);
  EXPECT_EQ(mat.normal_scale, 0.5f);
  EXPECT_EQ(m->scene.textures[std::size_t(mat.normal_texture)].encoding, TextureEncoding::linear);
  ASSERT_NE(mat.bump_texture, kNoTexture);
  EXPECT_EQ(mat.bump_scale, 3.0f);
  const Mesh& mesh = m->scene.meshes[0].mesh;
  ASSERT_EQ(mesh.tangents.size(), mesh.positions.size());
  EXPECT_GT(mesh.tangents[0].x(), 0.99f);
  test::write_text(dir / "m.mtl", "newmtl bumpy\nnorm -bm x tex.png\n");
  m = load_model(dir / "m.obj");
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("m.mtl:2: norm -bm"), std::string::npos) << m.status().message();
}

TEST(ObjMtlImport, MissingFilesAreErrorsUnlessAllowed) {
  TempDir dir;
  test::write_text(dir / "a.obj", "mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
  ModelOptions strict;
  strict.allow_missing = false;
  Result<Model> m = load_model(dir / "a.obj", strict);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("a.obj:1"), std::string::npos) << m.status().message();
  EXPECT_NE(m.status().message().find("none.mtl"), std::string::npos) << m.status().message();
  ModelOptions o;
  o.allow_missing = true;
  m = load_model(dir / "a.obj", o);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_FALSE(m->warnings.empty());

  test::write_text(dir / "b.mtl", "newmtl x\nKd 1 0 0\nmap_Kd missing.png\n");
  test::write_text(dir / "b.obj", "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl x\nf 1/1 2/1 3/1\n");
  m = load_model(dir / "b.obj", strict);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("b.mtl:3"), std::string::npos) << m.status().message();
  EXPECT_NE(m.status().message().find("missing.png"), std::string::npos) << m.status().message();
  m = load_model(dir / "b.obj", o);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->scene.materials[std::size_t(find_material(m->scene, "x"))].diffuse_texture, kNoTexture);

  // usemtl naming a material no library has.
  test::write_text(dir / "c.obj", "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl nope\nf 1 2 3\n");
  test::write_text(dir / "b.mtl", "newmtl x\nKd 1 0 0\n");
  m = load_model(dir / "c.obj", strict);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("nope"), std::string::npos) << m.status().message();
}

TEST(ObjMtlImport, MalformedMtlNamesTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"Kd 1 0 0\n", ":1:"},                         // before newmtl
      {"newmtl a\nKd 1 zero 0\n", ":2:"},            // not a number
      {"newmtl a\nKd -1 0 0\n", ":2:"},              // negative
      {"newmtl a\nd 1.5\n", ":2:"},                  // alpha out of range
      {"newmtl a\nNs\n", ":2:"},                     // missing value
      {"newmtl a\n\nKd spectral x.rfl\n", ":3:"},    // unsupported form
      {"newmtl a\nmap_Kd -s\n", ":2:"},              // option without values
      {"newmtl a\nmap_Kd -zz 1 t.png\n", ":2:"},     // unknown option
      {"newmtl\n", ":1:"},                           // no name
  };
  for (const auto& [text, where] : cases) {
    Scene s;
    std::vector<std::string> warnings;
    const Status st = parse_mtl(text, "bad.mtl", "", ModelOptions{}, s, warnings);
    ASSERT_FALSE(st.ok()) << text;
    EXPECT_NE(st.message().find(std::string("bad.mtl") + where), std::string::npos) << st.message();
  }
  // illum 0 and 1.
  Scene s;
  std::vector<std::string> warnings;
  ASSERT_TRUE(parse_mtl("newmtl a\nKd 0.5 0.5 0.5\nKs 1 1 1\nillum 0\nnewmtl b\nKs 1 1 1\nillum 1\nfoo 1\n", "ok.mtl", "",
                        ModelOptions{}, s, warnings).ok());
  EXPECT_EQ(s.materials[0].emissive, Color3(0.5f, 0.5f, 0.5f));
  EXPECT_EQ(s.materials[0].diffuse, Color3::Zero());
  EXPECT_EQ(s.materials[1].specular, Color3::Zero());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("foo"), std::string::npos) << warnings[0];
}

TEST(ModelImport, UnknownExtensionIsRefused) {
  Result<Model> m = load_model("scene.fbx");
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.status().code(), ErrorCode::unsupported);
  EXPECT_NE(m.status().message().find(".fbx"), std::string::npos);
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

TEST(SceneFileImports, ModelsArePlacedPrefixedAndWarned) {
  TempDir dir;
  test::write_text(dir / "m.mtl", "newmtl red\nKd 1 0 0\nmap_Ks b.png\n");
  test::write_text(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
  test::write_text(dir / "s.json", R"({
    "imports": [{"file": "m.obj", "translate": [5, 0, 0]}],
    "objects": [{"mesh": "m.obj:m", "material": "m.obj:red", "double_sided": true}]
  })");
  std::vector<std::string> warnings;
  LoadOptions o;
  o.warning = [&](const std::string& w) { warnings.push_back(w); };
  Result<Scene> s = load_scene_file(dir / "s.json", o);
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->objects.size(), 2u);
  EXPECT_TRUE(s->objects[0].mesh_materials);
  EXPECT_EQ(s->objects[0].model(0, 3), 5.0f);
  EXPECT_TRUE(s->objects[1].double_sided);
  EXPECT_FALSE(s->objects[0].double_sided);
  EXPECT_GE(find_material(*s, "m.obj:red"), 0);
  EXPECT_EQ(s->meshes[0].mesh.groups[0].material, "m.obj:red");
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_NE(warnings[0].find("imports[0]"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("map_Ks"), std::string::npos) << warnings[0];
  // No camera and no lights of its own: framed and lit as `facet render MODEL` would.
  EXPECT_NE(warnings[1].find("no \"camera\""), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[2].find("no \"lights\""), std::string::npos) << warnings[2];
  Result<Camera> framed = frame_scene(*s, LoadOptions{}.frame_aspect);
  ASSERT_TRUE(framed.ok());
  EXPECT_EQ(s->camera.eye, framed->eye);
  ASSERT_EQ(s->lights.size(), 2u);
  EXPECT_EQ(s->lights[0].name, "headlight");
  // With a camera or lights of the scene's own, neither is added.
  test::write_text(dir / "own.json", R"({
    "camera": {"eye": [0, 0, 9]}, "lights": [],
    "imports": [{"file": "m.obj"}]
  })");
  Result<Scene> own = load_scene_file(dir / "own.json");
  ASSERT_TRUE(own.ok()) << own.status().message();
  EXPECT_EQ(own->camera.eye, Vec3(0, 0, 9));
  EXPECT_TRUE(own->lights.empty());
  // Errors name the import's line and field.
  test::write_text(dir / "bad.json", "{\n  \"imports\": [{\"file\": \"none.gltf\"}]\n}\n");
  Result<Scene> bad = load_scene_file(dir / "bad.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("bad.json:2"), std::string::npos) << bad.status().message();
  EXPECT_NE(bad.status().message().find("imports[0].file"), std::string::npos) << bad.status().message();
  test::write_text(dir / "cam.json", R"({"camera": {}, "imports": [{"file": "m.obj", "camera": true}]})");
  EXPECT_FALSE(load_scene_file(dir / "cam.json").ok());
}

}  // namespace
}  // namespace facet
