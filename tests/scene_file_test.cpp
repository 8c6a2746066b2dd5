// JSON scene files: a complete example, the defaults, and malformed files. Every error must name
// the file, the line and the field.
#include <algorithm>
#include <filesystem>

#include "test_support.hpp"

namespace facet {
namespace {

Result<Scene> parse(const std::string& text) { return parse_scene_json(text, "inline.json", test::data_dir()); }

// Parses `text`, expects failure, and checks that the message has `file:line:` and mentions all of `parts`.
void expect_error(const std::string& text, int line, const std::string& field,
                  const std::vector<std::string>& parts) {
  const Result<Scene> s = parse(text);
  ASSERT_FALSE(s.ok()) << "accepted:\n" << text;
  const std::string msg = s.status().message();
  EXPECT_EQ(msg.rfind("inline.json:" + std::to_string(line) + ":", 0), 0u) << msg;
  if (!field.empty()) {
    EXPECT_NE(msg.find(field), std::string::npos) << msg;
  }
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
}

TEST(SceneFile, CompleteExampleLoads) {
  const std::string path = test::data_dir() + "/scenes/example.json";
  Result<Scene> s = load_scene_file(path, test::scene_options());
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_EQ(s->meshes.size(), 5u);
  EXPECT_EQ(s->materials.size(), 4u);  // three named + the default for the object without one
  EXPECT_EQ(s->objects.size(), 5u);
  ASSERT_EQ(s->lights.size(), 5u);
  EXPECT_EQ(s->camera.eye, (Vec3(0, 2.5f, 7)));
  EXPECT_EQ(s->materials[0].specular, Color3(0.6f, 0.6f, 0.6f));  // grey shorthand
  EXPECT_FLOAT_EQ(s->materials[0].shininess, 48);
  EXPECT_EQ(s->lights[1].type, LightType::point);
  EXPECT_FLOAT_EQ(s->lights[1].quadratic_attenuation, 0.02f);
  EXPECT_FLOAT_EQ(s->lights[1].range, 12);
  EXPECT_EQ(s->lights[2].spot_shape, SpotShape::cutoff_exponent);
  EXPECT_EQ(s->lights[3].spot_shape, SpotShape::smooth_cone);
  EXPECT_FALSE(s->lights[4].enabled);
  EXPECT_EQ(s->meshes[4].mesh.triangle_count(), 4u);  // the OBJ, resolved next to the scene file
  EXPECT_EQ(s->meshes[4].mesh.vertex_count(), 12u);   // 30 deg crease: every corner is hard
  EXPECT_EQ(s->objects[4].material, 3u);
  EXPECT_EQ(s->materials[3].name, "default");
  // rotate_deg [90, 0, 0] then uniform scale 1.5: y goes to z.
  const Mat4& ring = s->objects[3].model;
  EXPECT_NEAR((ring.topLeftCorner<3, 3>() * Vec3(0, 1, 0) - Vec3(0, 0, 1.5f)).norm(), 0.0f, 1e-6f);
  EXPECT_EQ(Vec3(ring.block<3, 1>(0, 3)), Vec3(0, 1.5f, -1));
  EXPECT_TRUE(validate_scene(*s).ok());
}

TEST(SceneFile, EmptyObjectGivesGlDefaults) {
  Result<Scene> s = parse("{}");
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Scene defaults;
  EXPECT_EQ(s->global_ambient, defaults.global_ambient);
  EXPECT_EQ(s->camera.eye, defaults.camera.eye);
  EXPECT_EQ(s->viewer, ViewerMode::local);
  EXPECT_EQ(s->transparent_order, TransparentOrder::submission);
  EXPECT_TRUE(s->lights.empty());
}

bool same_mesh(const Mesh& a, const Mesh& b) {
  return a.positions == b.positions && a.normals == b.normals && a.triangles == b.triangles && a.uvs == b.uvs;
}

// Every field a scene file may leave out takes the documented default (docs/scene-format.md): the
// procedural shapes, each one with nothing but its "shape", then with each field given.
TEST(SceneFile, ShapeDefaultsAreTheDocumentedOnes) {
  Result<Scene> s = parse(R"({"meshes": [{"name": "a", "shape": "sphere"}, {"name": "b", "shape": "cube"},
                                         {"name": "c", "shape": "plane"}, {"name": "d", "shape": "torus"},
                                         {"name": "e", "shape": "disc"}]})");
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_TRUE(same_mesh(s->meshes[4].mesh, make_disc(1.0f, 64)));
  EXPECT_TRUE(same_mesh(s->meshes[0].mesh, make_uv_sphere(1.0f, 48, 24)));
  EXPECT_TRUE(same_mesh(s->meshes[1].mesh, make_cube(1.0f, 1)));
  EXPECT_TRUE(same_mesh(s->meshes[2].mesh, make_plane(10.0f, 10.0f, 1)));
  EXPECT_TRUE(same_mesh(s->meshes[3].mesh, make_torus(1.0f, 0.25f, 48, 24)));
  // Each field given is the one used (a field read into the wrong variable shows here).
  s = parse(R"({"meshes": [{"name": "a", "shape": "sphere", "radius": 2, "segments": 5, "rings": 3},
                           {"name": "b", "shape": "cube", "size": 3, "subdivisions": 2},
                           {"name": "c", "shape": "plane", "size_x": 4, "size_z": 6, "subdivisions": 3},
                           {"name": "d", "shape": "torus", "major_radius": 2, "minor_radius": 0.5, "segments": 7, "sides": 5},
                           {"name": "e", "shape": "disc", "radius": 0.5, "segments": 9}]})");
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_TRUE(same_mesh(s->meshes[4].mesh, make_disc(0.5f, 9)));
  EXPECT_TRUE(same_mesh(s->meshes[0].mesh, make_uv_sphere(2.0f, 5, 3)));
  EXPECT_TRUE(same_mesh(s->meshes[1].mesh, make_cube(3.0f, 2)));
  EXPECT_TRUE(same_mesh(s->meshes[2].mesh, make_plane(4.0f, 6.0f, 3)));
  EXPECT_TRUE(same_mesh(s->meshes[3].mesh, make_torus(2.0f, 0.5f, 7, 5)));
}

// Objects, materials and lights with nothing but what they must have are the C++ defaults (which
// are GL's), field by field.
TEST(SceneFile, ObjectMaterialAndLightDefaultsAreTheCppOnes) {
  Result<Scene> s = parse(R"({"meshes": [{"name": "m", "shape": "cube"}], "materials": [{"name": "x"}],
                              "objects": [{"mesh": "m", "material": "x"}],
                              "lights": [{"type": "directional"}, {"type": "point"}, {"type": "spot"}]})");
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Instance io;
  const Instance& o = s->objects[0];
  EXPECT_EQ(o.model, io.model);
  EXPECT_EQ(o.mesh_materials, io.mesh_materials);
  EXPECT_EQ(o.cast_shadows, io.cast_shadows);
  EXPECT_EQ(o.receive_shadows, io.receive_shadows);
  EXPECT_EQ(o.double_sided, io.double_sided);
  const Material mo;
  const Material& m = s->materials[0];
  EXPECT_EQ(m.emissive, mo.emissive);
  EXPECT_EQ(m.ambient, mo.ambient);
  EXPECT_EQ(m.diffuse, mo.diffuse);
  EXPECT_EQ(m.specular, mo.specular);
  EXPECT_EQ(m.shininess, mo.shininess);
  EXPECT_EQ(m.alpha, mo.alpha);
  EXPECT_EQ(m.alpha_cutoff, mo.alpha_cutoff);
  EXPECT_EQ(m.blend, mo.blend);
  EXPECT_EQ(m.texture_mode, mo.texture_mode);
  EXPECT_EQ(m.uv_scale, mo.uv_scale);
  EXPECT_EQ(m.emission_after_texture, mo.emission_after_texture);
  for (std::size_t i = 0; i < 3; ++i) {
    Light lo;
    lo.type = s->lights[i].type;
    const Light& l = s->lights[i];
    EXPECT_EQ(l.position, lo.position) << i;
    EXPECT_EQ(l.direction, lo.direction) << i;
    EXPECT_EQ(l.ambient, lo.ambient) << i;
    EXPECT_EQ(l.diffuse, lo.diffuse) << i;
    EXPECT_EQ(l.specular, lo.specular) << i;
    EXPECT_EQ(l.constant_attenuation, lo.constant_attenuation) << i;
    EXPECT_EQ(l.linear_attenuation, lo.linear_attenuation) << i;
    EXPECT_EQ(l.quadratic_attenuation, lo.quadratic_attenuation) << i;
    EXPECT_EQ(l.range, lo.range) << i;
    EXPECT_EQ(l.spot_cutoff_deg, lo.spot_cutoff_deg) << i;
    EXPECT_EQ(l.spot_exponent, lo.spot_exponent) << i;
    EXPECT_EQ(l.enabled, lo.enabled) << i;
    EXPECT_EQ(l.shadow.method, lo.shadow.method) << i;
  }
}

TEST(SceneFile, AnInfiniteFarPlane) {
  Result<Scene> s = parse(R"({"camera": {"near": 0.05, "far": "infinite"}})");
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_TRUE(std::isinf(s->camera.far) && s->camera.far > 0.0f);
  expect_error(R"({"camera": {"far": "far"}})", 1, "camera.far", {"infinite"});
}

TEST(SceneFile, TransparentOrderIsReadAndItsErrorsNamed) {
  for (auto [text, order] : {std::pair{"submission", TransparentOrder::submission},
                             std::pair{"back_to_front", TransparentOrder::back_to_front}}) {
    Result<Scene> s = parse(std::string("{ \"transparent_order\": \"") + text + "\" }");
    ASSERT_TRUE(s.ok()) << s.status().message();
    EXPECT_EQ(s->transparent_order, order);
    EXPECT_STREQ(to_string(order), text);  // the library's name is the file's (the CLI parses through it)
  }
  expect_error("{\n  \"two_sided\": true,\n  \"transparent_order\": \"sorted\"\n}", 3, "transparent_order",
               {"submission", "back_to_front", "sorted"});
  expect_error("{\n  \"transparent_order\": true\n}", 2, "transparent_order", {});
}

TEST(SceneFile, NotJson) {
  expect_error("{\n  \"camera\": {\n    \"eye\": [0, 1, 2,]\n  }\n}\n", 3, "", {"invalid JSON"});
  expect_error("{\n  \"lights\": [\n", 3, "", {"invalid JSON"});
}

TEST(SceneFile, EmptyFile) { expect_error("  \n", 1, "", {"empty file"}); }

TEST(SceneFile, TopLevelMustBeAnObject) { expect_error("[1, 2]", 1, "top level", {"expected an object"}); }

TEST(SceneFile, WrongType) {
  expect_error("{\n  \"lights\": [\n    { \"type\": \"point\",\n      \"position\": \"up there\" }\n  ]\n}", 4,
               "lights[0].position", {"expected an array of 3 numbers", "found string 'up there'"});
}

TEST(SceneFile, WrongArrayLength) {
  expect_error("{\n\"camera\": {\"eye\": [1, 2]}\n}", 2, "camera.eye", {"found an array of 2 elements"});
}

TEST(SceneFile, UnknownFieldSuggestsTheRightOne) {
  expect_error("{\n  \"lights\": [\n    { \"type\": \"point\",\n      \"positon\": [0, 1, 0] }\n  ]\n}", 4,
               "lights[0]", {"unknown field 'positon'", "did you mean 'position'?"});
  expect_error("{ \"camra\": {} }", 1, "top level", {"unknown field 'camra'", "did you mean 'camera'?"});
}

TEST(SceneFile, NaNWrittenAsAString) {
  expect_error("{\"materials\": [\n {\"shininess\": \"NaN\"}\n]}", 2, "materials[0].shininess",
               {"expected a number", "found string 'NaN'"});
}

TEST(SceneFile, NumberOutOfFloatRange) {
  expect_error("{\"materials\": [\n {\"shininess\": 1e300}\n]}", 2, "materials[0].shininess",
               {"finite number within float range"});
}

TEST(SceneFile, NegativeAndHugeShininess) {
  expect_error("{\"materials\": [\n {\"name\": \"a\"},\n {\"name\": \"b\",\n  \"shininess\": -3}\n]}", 4,
               "materials[1].shininess", {"expected a number in [0, 4096", "found -3"});
  expect_error("{\"materials\": [\n {\"shininess\": 1e9}\n]}", 2, "materials[0].shininess", {"found 1e+09"});
}

TEST(SceneFile, ZeroLengthDirection) {
  expect_error("{\"lights\": [\n {\"type\": \"directional\",\n  \"direction\": [0, 0, 0]}\n]}", 3,
               "lights[0].direction", {"non-zero direction"});
}

TEST(SceneFile, SpotConeOver90Degrees) {
  expect_error("{\"lights\": [{\"type\": \"spot\",\n  \"spot\": {\"cutoff_deg\": 200}}]}", 2,
               "lights[0].spot.cutoff_deg", {"[0, 90", "found 200"});
  expect_error("{\"lights\": [{\"type\": \"spot\",\n  \"spot\": {\"inner_deg\": 50, \"outer_deg\": 40}}]}", 2,
               "lights[0].spot.inner_deg", {"found 50"});
}

TEST(SceneFile, SpotFieldsOfBothShapes) {
  expect_error("{\"lights\": [{\"type\": \"spot\",\n  \"spot\": {\"cutoff_deg\": 20, \"outer_deg\": 40}}]}", 2,
               "lights[0].spot", {"not both"});
}

TEST(SceneFile, LinearRangeAttenuationAndPhongLobe) {
  Result<Scene> s = parse(R"({"lights": [{"type": "point", "attenuation": {"model": "linear_range", "min": 1, "max": 8}}],
    "materials": [{"name": "m", "specular_model": "phong"}, {"name": "n"}]})");
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_EQ(s->lights[0].attenuation_model, AttenuationModel::linear_range);
  EXPECT_EQ(s->lights[0].range_min, 1.0f);
  EXPECT_EQ(s->lights[0].range_max, 8.0f);
  EXPECT_EQ(s->materials[0].specular_model, SpecularModel::phong);
  EXPECT_EQ(s->materials[1].specular_model, SpecularModel::blinn);  // the default
  expect_error("{\"lights\": [{\"type\": \"point\",\n \"attenuation\": {\"model\": \"linear_range\", \"min\": 1}}]}", 2,
               "lights[0].attenuation.max", {"missing"});
  expect_error("{\"lights\": [{\"type\": \"point\",\n \"attenuation\": {\"model\": \"linear_range\", \"min\": 9, \"max\": 8}}]}", 2,
               "lights[0].attenuation.min", {"[0, 8]", "found 9"});
  expect_error("{\"lights\": [{\"type\": \"point\",\n \"attenuation\": {\"model\": \"linear_range\", \"max\": 0}}]}", 2,
               "lights[0].attenuation.max", {"(0, 1e+30]", "found 0"});
  expect_error("{\"lights\": [{\"type\": \"point\",\n \"attenuation\": {\"model\": \"linear_range\", \"max\": 4, \"quadratic\": 1}}]}", 2,
               "lights[0].attenuation.quadratic", {"not GL's coefficients"});
  expect_error("{\"lights\": [{\"type\": \"point\",\n \"attenuation\": {\"max\": 4}}]}", 2,
               "lights[0].attenuation.max", {"only the linear_range model"});
  expect_error("{\"materials\": [\n {\"specular_model\": \"cook-torrance\"}]}", 2, "materials[0].specular_model",
               {"one of \"blinn, phong\""});
}

TEST(SceneFile, UnknownLightType) {
  expect_error("{\"lights\": [\n{\"type\": \"lamp\"}]}", 2, "lights[0].type",
               {"one of \"directional, point, spot\"", "found string 'lamp'"});
}

TEST(SceneFile, UnknownMeshNameListsTheDefinedOnes) {
  expect_error("{\"meshes\": [{\"name\": \"ball\", \"shape\": \"sphere\"}],\n \"objects\": [\n  {\"mesh\": \"bal\"}]}", 3,
               "objects[0].mesh", {"no mesh named 'bal'", "defined: 'ball'"});
}

TEST(SceneFile, MissingObjFileNamesThePathTried) {
  const Result<Scene> s = parse("{\"meshes\": [\n {\"name\": \"m\",\n  \"obj\": \"nowhere/missing.obj\"}]}");
  ASSERT_FALSE(s.ok());
  const std::string msg = s.status().message();
  EXPECT_EQ(msg.rfind("inline.json:3:", 0), 0u) << msg;
  EXPECT_NE(msg.find("meshes[0].obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find(test::data_dir() + "/nowhere/missing.obj"), std::string::npos) << msg;
}

TEST(SceneFile, MalformedObjNamesBothFiles) {
  const Result<Scene> s = parse("{\"meshes\": [{\"obj\": \"scenes/example.json\"}]}");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("inline.json:1: meshes[0].obj:"), std::string::npos) << s.status().message();
  EXPECT_NE(s.status().message().find("example.json:1: not an OBJ file: its first statement is not an OBJ statement"), std::string::npos) << s.status().message();
}

TEST(SceneFile, IntegerExpected) {
  expect_error("{\"meshes\": [{\"shape\": \"sphere\",\n \"segments\": 2.5}]}", 2, "meshes[0].segments",
               {"expected an integer"});
  expect_error("{\"meshes\": [{\"shape\": \"sphere\",\n \"segments\": 100000}]}", 2, "meshes[0].segments",
               {"[3, 4096]"});
}

TEST(SceneFile, NegativeSize) {
  expect_error("{\"meshes\": [{\"shape\": \"cube\",\n \"size\": -1}]}", 2, "meshes[0].size", {"a number > 0"});
}

TEST(SceneFile, DuplicateKey) {
  expect_error("{\"camera\": {\"near\": 1,\n \"near\": 2}}", 2, "", {"duplicate key 'near' in camera"});
}

TEST(SceneFile, DeepNestingIsRefused) {
  const std::string deep = "{\"camera\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  expect_error(deep, 1, "", {"nesting deeper than 64 levels"});
}

TEST(SceneFile, CameraProblemsFoundByValidation) {
  expect_error("{\"camera\": {\"eye\": [0, 0, 5],\n \"target\": [0, 0, 5]}}", 2, "camera.target",
               {"must differ from camera.eye"});
  expect_error("{\"camera\": {\n \"near\": 10, \"far\": 1}}", 2, "camera.far", {"> camera.near"});
}

TEST(SceneFile, MissingAndDirectoryPaths) {
  const Result<Scene> missing = load_scene_file("/nonexistent/scene.json");
  EXPECT_EQ(missing.status().code(), ErrorCode::io_error);
  EXPECT_NE(missing.status().message().find("'/nonexistent/scene.json'"), std::string::npos);
  EXPECT_EQ(load_scene_file(test::data_dir()).status().code(), ErrorCode::io_error);
}

TEST(SceneFile, ObjectWithMatrixAndTranslateIsAmbiguous) {
  expect_error("{\"meshes\": [{\"name\": \"c\", \"shape\": \"cube\"}],\n\"objects\": [{\"mesh\": \"c\",\n"
               " \"translate\": [1, 2, 3], \"matrix\": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]}",
               2, "objects[0]", {"cannot be combined"});
}

TEST(SceneFile, SingularMatrixIsRejected) {
  expect_error("{\"meshes\": [{\"name\": \"c\", \"shape\": \"cube\"}],\n\"objects\": [\n{\"mesh\": \"c\",\n"
               " \"matrix\": [1,0,0,0, 0,0,0,0, 0,0,1,0, 0,0,0,1]}]}",
               3, "objects[0].transform", {"invertible"});
}


// --- Surfaces: textures, material surface fields and fog.

TEST(SceneFile, SurfacesSceneLoads) {
  Result<Scene> s = load_scene_file(test::data_dir() + "/scenes/surfaces.json", test::scene_options());
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->textures.size(), 2u);
  EXPECT_EQ(s->textures[0].name, "stone");
  EXPECT_EQ(s->textures[0].filter, TextureFilter::trilinear);
  EXPECT_EQ(s->textures[1].wrap, TextureWrap::mirror);
  EXPECT_EQ(s->textures[0].levels[0].width, 64);
  EXPECT_EQ(s->materials[0].diffuse_texture, 0);
  EXPECT_EQ(s->materials[0].uv_scale, Vec2(8, 8));
  EXPECT_EQ(s->materials[1].diffuse_texture, 1);
  EXPECT_EQ(s->materials[2].blend, BlendMode::alpha);
  EXPECT_EQ(s->materials[2].depth_write, DepthWrite::automatic);
  EXPECT_EQ(s->materials[3].diffuse_texture, kNoTexture);
  EXPECT_EQ(s->fog.mode, FogMode::linear);
  EXPECT_EQ(s->fog.end, 28.0f);
}

TEST(SceneFile, SurfaceFieldsAndTheirErrors) {
  const std::string tex = R"("textures": [ { "name": "t", "file": "textures/checker.png" } ],)";
  const std::string mesh = R"("meshes": [ { "name": "q", "shape": "plane" } ], "objects": [ { "mesh": "q", "material": "m" } ])";
  auto scene = [&](const std::string& material, const std::string& extra = "") {
    return "{\n" + tex + "\n\"materials\": [\n" + material + "\n],\n" + extra + mesh + "\n}";
  };
  Result<Scene> ok = parse(scene(R"({ "name": "m", "diffuse_texture": "t", "texture_mode": "decal", "uv_scale": 2,
    "alpha_cutoff": 0.5, "blend": "premultiplied", "depth_write": true })", R"("fog": { "mode": "exp2", "density": 0.1 },)"));
  ASSERT_TRUE(ok.ok()) << ok.status().message();
  EXPECT_EQ(ok->materials[0].texture_mode, TextureMode::decal);
  EXPECT_EQ(ok->materials[0].uv_scale, Vec2(2, 2));
  EXPECT_EQ(ok->materials[0].alpha_cutoff, 0.5f);
  EXPECT_EQ(ok->materials[0].blend, BlendMode::premultiplied);
  EXPECT_EQ(ok->materials[0].depth_write, DepthWrite::on);
  EXPECT_EQ(ok->fog.mode, FogMode::exp2);
  EXPECT_EQ(ok->fog.density, 0.1f);
  EXPECT_EQ(ok->materials[0].emissive_texture, kNoTexture);
  EXPECT_FALSE(ok->materials[0].emission_after_texture);
  Result<Scene> glow = parse(scene(R"({ "name": "m", "emissive": [1, 0.5, 0], "emissive_texture": "t" })"));
  ASSERT_TRUE(glow.ok()) << glow.status().message();
  EXPECT_EQ(glow->materials[0].emissive_texture, 0);
  glow = parse(scene(R"({ "name": "m", "diffuse_texture": "t", "emission_after_texture": true })"));
  ASSERT_TRUE(glow.ok()) << glow.status().message();
  EXPECT_TRUE(glow->materials[0].emission_after_texture);
  EXPECT_FALSE(ok->materials[0].alpha_to_coverage);
  Result<Scene> a2c = parse(scene(R"({ "name": "m", "alpha_to_coverage": true })"));
  ASSERT_TRUE(a2c.ok()) << a2c.status().message();
  EXPECT_TRUE(a2c->materials[0].alpha_to_coverage);
  expect_error(scene(R"({ "name": "m", "alpha_to_coverage": "yes" })"), 4, "materials[0].alpha_to_coverage", {"true or false"});
  // Each bad field: its line (3: the material) and its name.
  expect_error(scene(R"({ "name": "m", "emissive_texture": "nope" })"), 4, "materials[0].emissive_texture", {"no texture named"});
  expect_error(scene(R"({ "name": "m", "emission_after_texture": 1 })"), 4, "materials[0].emission_after_texture",
               {"true or false"});
  expect_error(scene(R"({ "name": "m", "diffuse_texture": "nope" })"), 4, "materials[0].diffuse_texture", {"no texture named"});
  expect_error(scene(R"({ "name": "m", "uv_scale": [0, 1] })"), 4, "materials[0].uv_scale", {"non-zero"});
  expect_error(scene(R"({ "name": "m", "blend": "screen" })"), 4, "materials[0].blend", {"premultiplied"});
  expect_error(scene(R"({ "name": "m", "texture_mode": "blend" })"), 4, "materials[0].texture_mode", {"modulate"});
  expect_error(scene(R"({ "name": "m", "alpha_cutoff": 2 })"), 4, "materials[0].alpha_cutoff", {"[0, 1]"});
  expect_error(scene(R"({ "name": "m" })", R"("fog": { "mode": "linear", "start": 5, "end": 1 },)" "\n"), 6, "fog.end", {});
  expect_error(scene(R"({ "name": "m" })", R"("fog": { "start": 5 },)" "\n"), 6, "fog.mode", {"missing"});
  // Environment maps: a sphere map, a cube of six faces, and their errors (line 4: the material).
  Result<Scene> env = parse(scene(R"({ "name": "m", "environment": { "mode": "sphere", "texture": "t", "strength": 0.5,
    "blend": "mix" } })"));
  ASSERT_TRUE(env.ok()) << env.status().message();
  EXPECT_EQ(env->materials[0].environment.mode, EnvironmentMode::sphere);
  EXPECT_EQ(env->materials[0].environment.maps[0], 0);
  EXPECT_EQ(env->materials[0].environment.maps[1], kNoTexture);
  EXPECT_EQ(env->materials[0].environment.strength, 0.5f);
  EXPECT_EQ(env->materials[0].environment.blend, EnvironmentBlend::mix);
  env = parse(scene(R"({ "name": "m", "environment": { "mode": "cube", "faces": ["t", "t", "t", "t", "t", "t"] } })"));
  ASSERT_TRUE(env.ok()) << env.status().message();
  EXPECT_EQ(env->materials[0].environment.mode, EnvironmentMode::cube);
  EXPECT_EQ(env->materials[0].environment.maps[5], 0);
  EXPECT_EQ(env->materials[0].environment.blend, EnvironmentBlend::add);
  env = parse(scene(R"({ "name": "m", "environment": { "mode": "cube", "dynamic": true, "resolution": 64 } })"));
  ASSERT_TRUE(env.ok()) << env.status().message();
  EXPECT_TRUE(env->materials[0].environment.dynamic);
  EXPECT_EQ(env->materials[0].environment.resolution, 64);
  EXPECT_EQ(env->materials[0].environment.maps[0], kNoTexture);
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "sphere", "texture": "t", "dynamic": true } })"), 4,
               "materials[0].environment.dynamic", {"only a cube"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "dynamic": true, "resolution": 0 } })"), 4,
               "materials[0].environment.resolution", {"4096"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "faces": ["t", "t", "t", "t", "t", "t"], "resolution": 8 } })"),
               4, "materials[0].environment.resolution", {"only a dynamic"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "dynamic": true, "faces": ["t", "t", "t", "t", "t", "t"] } })"),
               4, "materials[0].environment.faces", {"rendered, not read"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "faces": ["t", "t", "t", "t", "t"] } })"), 4,
               "materials[0].environment.faces", {"six texture names"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "faces": ["t", "t", "t", "t", "t", "x"] } })"), 4,
               "materials[0].environment.faces[5]", {"no texture named"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "sphere" } })"), 4, "materials[0].environment.texture",
               {"missing"});
  // A cube from one equirectangular picture: six faces appended once per picture and size.
  Result<Scene> pano = parse(scene(R"({ "name": "m", "environment": { "mode": "cube", "texture": "t", "face_size": 8 } },
{ "name": "n", "environment": { "mode": "cube", "texture": "t", "face_size": 8 } },
{ "name": "o", "environment": { "mode": "cube", "texture": "t" } })"));
  ASSERT_TRUE(pano.ok()) << pano.status().message();
  ASSERT_EQ(pano->textures.size(), 13u);  // the picture, then two conversions of six faces
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(pano->materials[0].environment.maps[k], 1 + k);
    EXPECT_EQ(pano->materials[1].environment.maps[k], 1 + k);
    EXPECT_EQ(pano->materials[2].environment.maps[k], 7 + k);
  }
  EXPECT_EQ(pano->textures[1].width(), 8);
  EXPECT_EQ(pano->textures[7].width(), std::max(1, pano->textures[0].width() / 4));
  EXPECT_EQ(pano->textures[12].wrap, TextureWrap::clamp);
  EXPECT_TRUE(validate_scene(*pano).ok());
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "texture": "t", "faces": ["t", "t", "t", "t", "t", "t"] } })"),
               4, "materials[0].environment.faces", {"not both"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "sphere", "texture": "t", "face_size": 8 } })"), 4,
               "materials[0].environment.face_size", {"equirectangular"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "texture": "t", "face_size": 0 } })"), 4,
               "materials[0].environment.face_size", {"4096"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "cube", "texture": "x" } })"), 4,
               "materials[0].environment.texture", {"no texture named"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "mirror", "texture": "t" } })"), 4,
               "materials[0].environment.mode", {"sphere"});
  expect_error(scene(R"({ "name": "m", "environment": { "texture": "t" } })"), 4, "materials[0].environment.mode", {"missing"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "normal", "texture": "t", "strength": 2 } })"), 4,
               "materials[0].environment.strength", {"[0, 1]"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "sphere", "texture": "t", "blend": "screen" } })"), 4,
               "materials[0].environment.blend", {"mix"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "sphere", "texture": "t", "faces": [] } })"), 4,
               "materials[0].environment.faces", {"only a cube"});
  expect_error(scene(R"({ "name": "m", "environment": { "mode": "sphere", "texture": "t", "mirror": 1 } })"), 4,
               "materials[0].environment", {"unknown field"});
  // A texture file that is missing or not an image: the scene file's line, the field and the image's path.
  expect_error(R"({ "textures": [ { "name": "t", "file": "textures/absent.png" } ] })", 1, "textures[0].file",
               {"absent.png"});
  expect_error(R"({ "textures": [ { "name": "t", "file": "obj/tetrahedron.obj" } ] })", 1, "textures[0].file",
               {"tetrahedron.obj"});
  expect_error(R"({ "textures": [ { "name": "t", "file": "textures/checker.png", "filter": "cubic" } ] })", 1,
               "textures[0].filter", {"trilinear"});
}


TEST(SceneFile, MeshMaterialsComeFromTheObjGroups) {
  const std::string text = R"({
  "materials": [ { "name": "red", "emissive": [1, 0, 0] }, { "name": "green", "emissive": [0, 1, 0] } ],
  "meshes": [ { "name": "q", "obj": "obj/two_materials.obj" } ],
  "objects": [ { "mesh": "q", "mesh_materials": true } ]
})";
  Result<Scene> s = parse(text);
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->meshes[0].mesh.groups.size(), 2u);
  EXPECT_TRUE(s->objects[0].mesh_materials);
  std::string missing = text;
  missing.replace(missing.find(R"("green")"), 7, R"("lime")");
  expect_error(missing, 4, "objects[0].mesh_materials", {"'green'", "does not define"});
  std::string both = text;
  both.replace(both.find(R"("mesh_materials": true)"), 22, R"("mesh_materials": true, "material": "red")");
  expect_error(both, 4, "objects[0].material", {"mesh_materials"});
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

TEST(SceneFile, ShadowsAreRead) {
  const Result<Scene> s = parse(R"({
    "meshes": [ { "name": "m", "shape": "cube" } ],
    "objects": [ { "mesh": "m", "cast_shadows": false }, { "mesh": "m", "receive_shadows": false } ],
    "lights": [ { "type": "directional", "shadow": { "method": "raycast", "bias": { "normal": 0.01 } } },
                { "type": "point", "shadow": { "method": "none", "resolution": 512, "filter": "pcf5x5",
                                               "bias": { "constant": 0.001, "slope": 2 } } },
                { "type": "point" } ] })");
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_FALSE(s->objects[0].cast_shadows);
  EXPECT_TRUE(s->objects[0].receive_shadows);
  EXPECT_TRUE(s->objects[1].cast_shadows);
  EXPECT_FALSE(s->objects[1].receive_shadows);
  EXPECT_EQ(s->lights[0].shadow.method, ShadowMethod::raycast);
  EXPECT_FLOAT_EQ(s->lights[0].shadow.bias.normal, 0.01f);
  EXPECT_EQ(s->lights[1].shadow.method, ShadowMethod::none);
  EXPECT_EQ(s->lights[1].shadow.resolution, 512);
  EXPECT_EQ(s->lights[1].shadow.filter, ShadowFilter::pcf5x5);
  EXPECT_FLOAT_EQ(s->lights[1].shadow.bias.constant, 0.001f);
  EXPECT_FLOAT_EQ(s->lights[1].shadow.bias.slope, 2.0f);
  EXPECT_EQ(s->lights[2].shadow.method, ShadowMethod::none);  // the default: no shadows
  EXPECT_EQ(s->lights[2].shadow.resolution, 2048);
  EXPECT_EQ(s->lights[2].shadow.filter, ShadowFilter::pcf3x3);
}

TEST(SceneFile, BadShadowsNameTheField) {
  expect_error(R"({ "lights": [ { "type": "point", "shadow": { "method": "stencil" } } ] })", 1, "lights[0].shadow.method",
               {"raycast"});
  expect_error(R"({ "lights": [ { "type": "point", "shadow": { "resolution": 64 } } ] })", 1, "lights[0].shadow.method",
               {"missing"});
  expect_error(R"({ "lights": [ { "type": "point", "shadow": { "method": "raycast", "resolution": 8 } } ] })", 1,
               "lights[0].shadow.resolution", {"16"});
  expect_error(R"({ "lights": [ { "type": "point", "shadow": { "method": "raycast", "filter": "pcf4x4" } } ] })", 1,
               "lights[0].shadow.filter", {"pcf3x3"});
  expect_error(R"({ "lights": [ { "type": "point", "shadow": { "method": "raycast", "bias": { "normal": -1 } } } ] })",
               1, "lights[0].shadow.bias.normal", {"[0, 10000]"});
  expect_error(R"({ "lights": [ { "type": "point", "shadow": { "method": "raycast", "blur": 1 } } ] })", 1,
               "lights[0].shadow", {"blur"});
  expect_error(R"({ "meshes": [ { "name": "m", "shape": "cube" } ],
                    "objects": [ { "mesh": "m", "cast_shadows": 1 } ] })", 2, "objects[0].cast_shadows", {"true or false"});
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// An object's "lightmap": with "uv": "generate" the object gets its own copy of the mesh, split
// along the charts unwrap_lightmap cuts from the mesh placed in the world, with those coordinates.
TEST(SceneFile, LightmapGeneratesTheBakesCharts) {
  const std::string text = R"({
    "textures": [{"name": "lm", "file": "textures/checker.png", "filter": "bilinear", "wrap": "clamp", "encoding": "linear"}],
    "meshes": [{"name": "box", "shape": "cube", "size": 2, "subdivisions": 2}],
    "objects": [{"mesh": "box", "translate": [1, 2, 3], "scale": 0.5,
                 "lightmap": {"texture": "lm", "scale": 2.5, "mode": "replace", "texels_per_unit": 8, "padding": 3}}]
  })";
  const Result<Scene> s = parse(text);
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->meshes.size(), 2u);
  const Instance& inst = s->objects[0];
  EXPECT_EQ(inst.mesh, 1u);
  EXPECT_EQ(inst.lightmap, 0);
  EXPECT_EQ(inst.lightmap_scale, 2.5f);
  EXPECT_EQ(inst.lightmap_mode, LightmapMode::replace);
  LightmapUvOptions o;
  o.texels_per_unit = 8, o.padding = 3;
  const Result<LightmapUnwrap> u = unwrap_lightmap(world_space_mesh(s->meshes[0].mesh, inst.model), o);
  ASSERT_TRUE(u.ok());
  const Mesh& split = s->meshes[1].mesh;
  EXPECT_EQ(split.lightmap_uvs, u->uvs);
  EXPECT_EQ(split.triangles, u->triangles);
  for (std::size_t v = 0; v < split.positions.size(); ++v) EXPECT_EQ(split.positions[v], s->meshes[0].mesh.positions[u->source_vertex[v]]);
  EXPECT_TRUE(validate_scene(*s).ok()) << validate_scene(*s).message();
}

TEST(SceneFile, LightmapErrorsNameTheirField) {
  const std::string head = R"({"textures": [{"name": "lm", "file": "textures/checker.png"}], "meshes": [{"name": "b", "shape": "cube"}],
"objects": [{"mesh": "b", "lightmap": )";
  expect_error(head + R"({"texture": "nope", "texels_per_unit": 4}}]})", 2, "objects[0].lightmap.texture", {"no texture named"});
  expect_error(head + R"({"texture": "lm"}}]})", 2, "objects[0].lightmap.texels_per_unit", {"missing"});
  expect_error(head + R"({"texture": "lm", "texels_per_unit": 4, "mode": "bright"}}]})", 2, "objects[0].lightmap.mode", {"diffuse"});
  expect_error(head + R"({"texture": "lm", "texels_per_unit": 4, "scale": 0}}]})", 2, "objects[0].lightmap.scale", {"> 0"});
  expect_error(head + R"({"texture": "lm", "uv": "mesh", "padding": 2}}]})", 2, "objects[0].lightmap.padding", {"generate"});
  expect_error(head + R"({"texture": "lm", "texels_per_unit": 1e9}}]})", 2, "objects[0].lightmap.texels_per_unit", {"would fit"});
  expect_error(head + R"({"texture": "lm", "texels_per_unit": 4, "shade": 1}}]})", 2, "objects[0].lightmap", {"unknown field"});
}

}  // namespace
}  // namespace facet
