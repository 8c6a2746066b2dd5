// The field table (facet/fields.hpp): every material and light field is checked, read from a
// scene file, set and read through C and listed in the docs from the one entry that describes it.
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "facet/facet.h"
#include "test_support.hpp"

namespace facet {
namespace {

// A value of field `f` other than its default, inside its range (component c).
template <class T>
double other_value(const FieldSpec<T>& f, const T& fresh, int c) {
  const double d = f.get(fresh, c);
  switch (f.type) {
    case FieldType::boolean: return d != 0.0 ? 0.0 : 1.0;
    case FieldType::choice: return d == 0.0 ? double(f.choices.size() - 1) : 0.0;
    case FieldType::texture: return c == 0 || f.components == 1 ? 0.0 : double(c % 2);
    case FieldType::colour: return 0.25 * (c + 1);
    case FieldType::vector: return d == 0.5 * (c + 1) ? -2.0 : 0.5 * (c + 1);
    case FieldType::number:
    case FieldType::integer: {
      const double mid = f.hi > 1e6 ? f.lo + 3.0 : std::floor((f.lo + f.hi) / 2.0);
      return mid == d ? mid + 1.0 : mid;
    }
  }
  return d;
}

// A value of component c that the field refuses, if its C++ type can hold one.
template <class T>
bool bad_value(const FieldSpec<T>& f, double& out) {
  switch (f.type) {
    case FieldType::boolean: return false;  // a bool holds only good values
    case FieldType::choice: out = double(f.choices.size()); return true;
    case FieldType::texture: out = -2.0; return true;
    case FieldType::colour: out = -1.0; return true;
    case FieldType::vector: out = std::nan(""); return true;
    case FieldType::integer: out = f.hi + 1.0; return true;
    case FieldType::number: out = f.lo > -1e6 ? f.lo - 1.0 : std::nan(""); return true;
  }
  return false;
}

template <class T>
void expect_unique_names(std::span<const FieldSpec<T>> table) {
  std::map<std::string, int> seen;
  for (const auto& f : table) {
    EXPECT_EQ(seen[f.name]++, 0) << f.name;
    EXPECT_GE(f.components, 1) << f.name;
    EXPECT_GT(std::strlen(f.doc), 10u) << f.name;
    EXPECT_EQ(f.type == FieldType::choice, !f.choices.empty()) << f.name;
  }
}

TEST(FieldTable, NamesAreUniqueAndEveryDefaultIsValid) {
  expect_unique_names(material_fields());
  expect_unique_names(light_fields());
  EXPECT_TRUE(validate_material(Material{}, 0).ok());
  Light spot;
  spot.type = LightType::spot;
  EXPECT_TRUE(validate_light(spot, 0).ok());
  for (const auto& f : material_fields()) EXPECT_TRUE(is_default(f, Material{})) << f.name;
  for (const auto& f : light_fields()) EXPECT_TRUE(is_default(f, Light{})) << f.name;
}

// The choices are the enums' names in the enums' order (the to_string functions agree).
TEST(FieldTable, ChoicesFollowTheEnums) {
  auto names = [](const char* field) {
    const MaterialField* m = find_material_field(field);
    const LightField* l = find_light_field(field);
    return m ? m->choices : l->choices;
  };
  for (int i = 0; i < 6; ++i) EXPECT_STREQ(names("blend")[i], to_string(BlendMode(i)));
  for (int i = 0; i < 4; ++i) EXPECT_STREQ(names("texture_mode")[i], to_string(TextureMode(i)));
  for (int i = 0; i < 3; ++i) EXPECT_STREQ(names("depth_write")[i], to_string(DepthWrite(i)));
  for (int i = 0; i < 2; ++i) EXPECT_STREQ(names("specular_model")[i], to_string(SpecularModel(i)));
  for (int i = 0; i < 4; ++i) EXPECT_STREQ(names("environment.mode")[i], to_string(EnvironmentMode(i)));
  for (int i = 0; i < 3; ++i) EXPECT_STREQ(names("environment.blend")[i], to_string(EnvironmentBlend(i)));
  for (int i = 0; i < 4; ++i) EXPECT_STREQ(names("shadow.method")[i], to_string(ShadowMethod(i)));
  for (int i = 0; i < 4; ++i) EXPECT_STREQ(names("shadow.filter")[i], to_string(ShadowFilter(i)));
  EXPECT_EQ(names("type").size(), 3u);
  EXPECT_STREQ(names("type")[int(LightType::spot)], "spot");
  EXPECT_STREQ(names("attenuation.model")[int(AttenuationModel::linear_range)], "linear_range");
  EXPECT_STREQ(names("spot.shape")[int(SpotShape::smooth_cone)], "smooth_cone");
  EXPECT_STREQ(names("projector.mode")[int(ProjectorMode::gobo)], "gobo");
}

// Validation refuses a bad value of every field by the field's table entry, naming it.
TEST(FieldTable, ValidationRefusesEveryFieldOutOfItsRange) {
  int refused = 0;
  for (const auto& f : material_fields()) {
    Material m;
    double bad = 0;
    if (!bad_value(f, bad)) continue;
    const int c = f.components - 1;
    f.set(m, c, bad);
    const Status s = validate_material(m, 3);
    ASSERT_FALSE(s.ok()) << f.name;
    const std::string expected = "materials[3]." + std::string(f.name) + (f.type == FieldType::texture && f.components > 1 ? "[" + std::to_string(c) + "]" : "");
    EXPECT_EQ(s.field(), expected) << s.message();
    ++refused;
  }
  for (const auto& f : light_fields()) {
    Light l;
    l.type = LightType::spot;
    double bad = 0;
    if (!bad_value(f, bad)) continue;
    f.set(l, f.components - 1, bad);
    const Status s = validate_light(l, 1);
    ASSERT_FALSE(s.ok()) << f.name;
    EXPECT_EQ(s.field(), "lights[1]." + std::string(f.name)) << s.message();
    ++refused;
  }
  EXPECT_GE(refused, 45);
  // The one value outside a range a field also takes: a GL cone of 180 degrees (no cone).
  Light l;
  l.type = LightType::spot;
  l.spot_cutoff_deg = 180;
  EXPECT_TRUE(validate_light(l, 0).ok());
  l.spot_cutoff_deg = 179;
  EXPECT_EQ(validate_light(l, 0).field(), "lights[0].spot.cutoff_deg");
}

TEST(FieldTable, SetFieldChecksEveryValueBeforeStoringAny) {
  const MaterialField& diffuse = *find_material_field("diffuse");
  Material m;
  const double half_bad[] = {0.5, -1.0, 0.5};
  EXPECT_EQ(set_field(diffuse, m, half_bad, "m.diffuse").field(), "m.diffuse");
  EXPECT_EQ(m.diffuse, Material{}.diffuse);
  const double two[] = {0.5, 0.5};
  EXPECT_FALSE(set_field(diffuse, m, two, "m.diffuse").ok());
  const double good[] = {0.5, 0.25, 1.0};
  ASSERT_TRUE(set_field(diffuse, m, good, "m.diffuse").ok());
  EXPECT_EQ(m.diffuse, Color3(0.5f, 0.25f, 1.0f));
  EXPECT_EQ(format_field(diffuse, m), "[0.5, 0.25, 1]");
  EXPECT_EQ(format_field(*find_material_field("blend"), m), "\"opaque\"");
  EXPECT_FALSE(is_default(diffuse, m));
}

// The scene-file text of value v of field f (a texture by its name in the test scene).
template <class T>
std::string json_value(const FieldSpec<T>& f, const T& object) {
  auto one = [&](int c) -> std::string {
    const double v = f.get(object, c);
    if (f.type == FieldType::choice) return "\"" + std::string(f.choices[std::size_t(v)]) + "\"";
    if (f.type == FieldType::boolean) return v != 0.0 ? "true" : "false";
    if (f.type == FieldType::texture) return "\"tex" + std::to_string(int(v)) + "\"";
    std::ostringstream s;
    s.precision(9);
    s << v;
    return s.str();
  };
  if (f.components == 1) return one(0);
  std::string s = "[";
  for (int c = 0; c < f.components; ++c) s += (c ? ", " : "") + one(c);
  return s + "]";
}

constexpr const char* kTextures =
    R"("textures": [{"name": "tex0", "file": "textures/checker.png"}, {"name": "tex1", "file": "textures/stripes.png"}])";

// Every material field a scene file names at its top level is read from its table entry.
TEST(FieldTable, SceneFilesReadEveryMaterialField) {
  int read = 0;
  for (const auto& f : material_fields()) {
    if (std::strchr(f.name, '.')) continue;  // the environment's fields: read by its own rules (EnvironmentMaps.*)
    Material want;
    for (int c = 0; c < f.components; ++c) f.set(want, c, other_value(f, Material{}, c));
    const std::string text = std::string("{") + kTextures + R"(, "meshes": [{"name": "q", "shape": "plane"}], "materials": [{")" +
                             f.name + "\": " + json_value(f, want) + "}]}";
    Result<Scene> s = parse_scene_json(text, "inline.json", test::data_dir());
    ASSERT_TRUE(s.ok()) << text << "\n" << s.status().message();
    for (int c = 0; c < f.components; ++c) EXPECT_EQ(f.get(s->materials[0], c), f.get(want, c)) << f.name << " " << text;
    ++read;
  }
  EXPECT_GE(read, 22);
}

// Every light field, by its dotted name as nested objects ("shadow.bias.slope": {"shadow": {"bias":
// {"slope": ...}}}), with what the rules between fields need beside it.
TEST(FieldTable, SceneFilesReadEveryLightField) {
  for (const auto& f : light_fields()) {
    Light want;
    want.type = LightType::spot;
    for (int c = 0; c < f.components; ++c) f.set(want, c, other_value(f, Light{}, c));
    const std::string name = f.name;
    std::string inner = json_value(f, want);
    std::string path = name;
    // Nested keys from the dotted name, innermost first.
    std::string extra;
    if (name.rfind("shadow.", 0) == 0 && name != "shadow.method") extra = R"("method": "map", )";
    if (name == "attenuation.min" || name == "attenuation.max") {
      extra = name == "attenuation.min" ? R"("model": "linear_range", "max": 100, )" : R"("model": "linear_range", )";
    }
    if (name == "attenuation.model") extra = R"("max": 100, )";
    if (name == "projector.mode") extra = R"("texture": "tex0", )";
    std::string value = inner;
    for (std::size_t dot = path.rfind('.'); dot != std::string::npos; dot = path.rfind('.')) {
      value = "{" + (path.find('.') == dot ? extra : std::string()) + "\"" + path.substr(dot + 1) + "\": " + value + "}";
      path.resize(dot);
    }
    const std::string type = name == "type" ? std::string() : R"("type": "spot", )";
    const std::string text = std::string("{") + kTextures + R"(, "lights": [{)" + type + "\"" + path + "\": " + value + "}]}";
    Result<Scene> s = parse_scene_json(text, "inline.json", test::data_dir());
    ASSERT_TRUE(s.ok()) << text << "\n" << s.status().message();
    for (int c = 0; c < f.components; ++c) EXPECT_EQ(f.get(s->lights[0], c), f.get(want, c)) << name << " " << text;
  }
}

TEST(FieldTable, TheCApiSetsAndReadsEveryField) {
  facet_scene* scene = facet_scene_create();
  ASSERT_NE(scene, nullptr);
  const facet_material material = facet_material_default();
  const facet_light light = facet_light_default();
  uint32_t id = 0;
  ASSERT_EQ(facet_scene_add_material(scene, &material, &id), FACET_OK);
  ASSERT_EQ(facet_scene_add_material(scene, &material, &id), FACET_OK);
  ASSERT_EQ(id, 1u);
  ASSERT_EQ(facet_scene_add_light(scene, &light, &id), FACET_OK);
  ASSERT_EQ(id, 0u);
  ASSERT_EQ(facet_material_field_count(), material_fields().size());
  ASSERT_EQ(facet_light_field_count(), light_fields().size());
  for (std::size_t i = 0; i < facet_material_field_count(); ++i) {
    facet_field_info info{};
    ASSERT_EQ(facet_material_field_info(i, &info), FACET_OK);
    const MaterialField& f = material_fields()[i];
    EXPECT_STREQ(info.name, f.name);
    if (std::strchr(f.name, '.')) continue;  // (environment fields need the rules between them; below)
    std::vector<double> v(std::size_t(f.components)), back(v.size());
    for (int c = 0; c < f.components; ++c) v[std::size_t(c)] = other_value(f, Material{}, c);
    if (f.type == FieldType::texture) continue;  // the default scene has no textures: below
    ASSERT_EQ(facet_scene_set_material_field(scene, 1, f.name, v.data(), v.size()), FACET_OK) << f.name << ": " << facet_scene_last_error(scene);
    ASSERT_EQ(facet_scene_get_material_field(scene, 1, f.name, back.data(), back.size()), FACET_OK);
    for (std::size_t c = 0; c < v.size(); ++c) EXPECT_EQ(float(back[c]), float(v[c])) << f.name;
  }
  // The loop made material 1 a pbr material, which GL's environment mapping refuses.
  const double sphere[] = {1}, gl[] = {0};
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "environment.mode", sphere, 1), FACET_INVALID_ARGUMENT);
  EXPECT_NE(std::string(facet_scene_last_error(scene)).find("materials[1].environment.mode: a pbr material"), std::string::npos)
      << facet_scene_last_error(scene);
  ASSERT_EQ(facet_scene_set_material_field(scene, 1, "model", gl, 1), FACET_OK);
  const double cube[] = {2};  // "cube" needs six faces: refused, nothing changed
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "environment.mode", cube, 1), FACET_INVALID_ARGUMENT);
  EXPECT_NE(std::string(facet_scene_last_error(scene)).find("materials[1].environment.maps[0]"), std::string::npos) << facet_scene_last_error(scene);
  double mode = -1;
  ASSERT_EQ(facet_scene_get_material_field(scene, 1, "environment.mode", &mode, 1), FACET_OK);
  EXPECT_EQ(mode, 0);
  const double strength[] = {0.25}, too_strong[] = {1.5};
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "environment.strength", strength, 1), FACET_OK);
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "environment.strength", too_strong, 1), FACET_INVALID_ARGUMENT);
  EXPECT_NE(std::string(facet_scene_last_error(scene)).find("materials[1].environment.strength: expected a number in [0, 1]"), std::string::npos);
  const double texture[] = {0};
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "diffuse_texture", texture, 1), FACET_INVALID_ARGUMENT);  // no textures
  // Indices an int32 cannot hold are refused before they are stored (never converted: undefined).
  for (const double huge : {1e30, 4294967296.0, -2.0, 0.5, std::nan("")}) {
    EXPECT_EQ(facet_scene_set_material_field(scene, 1, "diffuse_texture", &huge, 1), FACET_INVALID_ARGUMENT) << huge;
    EXPECT_EQ(facet_scene_set_light_field(scene, 0, "shadow.resolution", &huge, 1), FACET_INVALID_ARGUMENT) << huge;
  }
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "no_such\x1b[2J", strength, 1), FACET_INVALID_ARGUMENT);
  EXPECT_EQ(std::string(facet_scene_last_error(scene)).find('\x1b'), std::string::npos);  // the caller's bytes, escaped
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "diffuse", strength, 1), FACET_INVALID_ARGUMENT);  // 3 values
  EXPECT_EQ(facet_scene_set_material_field(scene, 99, "alpha", strength, 1), FACET_INVALID_ARGUMENT);

  for (std::size_t i = 0; i < facet_light_field_count(); ++i) {
    const LightField& f = light_fields()[i];
    if (f.type == FieldType::texture || std::string(f.name) == "type" || std::string(f.name).rfind("attenuation", 0) == 0 ||
        std::string(f.name) == "range" || std::string(f.name).rfind("spot", 0) == 0) {
      continue;  // rules between fields (a directional light has no range or cone): below
    }
    std::vector<double> v(std::size_t(f.components)), back(v.size());
    for (int c = 0; c < f.components; ++c) v[std::size_t(c)] = other_value(f, Light{}, c);
    ASSERT_EQ(facet_scene_set_light_field(scene, 0, f.name, v.data(), v.size()), FACET_OK) << f.name << ": " << facet_scene_last_error(scene);
    ASSERT_EQ(facet_scene_get_light_field(scene, 0, f.name, back.data(), back.size()), FACET_OK);
    for (std::size_t c = 0; c < v.size(); ++c) EXPECT_EQ(float(back[c]), float(v[c])) << f.name;
  }
  const double twelve[] = {12};
  EXPECT_EQ(facet_scene_set_light_field(scene, 0, "range", twelve, 1), FACET_INVALID_ARGUMENT);  // directional
  EXPECT_NE(std::string(facet_scene_last_error(scene)).find("only point and spot lights have a range"), std::string::npos);
  const double spot[] = {2};
  ASSERT_EQ(facet_scene_set_light_field(scene, 0, "type", spot, 1), FACET_OK);
  EXPECT_EQ(facet_scene_set_light_field(scene, 0, "range", twelve, 1), FACET_OK);
  // A texture on a material an object without uvs draws: the material alone is valid, the scene
  // with it is not (the mesh has no texture coordinates), and the material stays as it was.
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t indices[] = {0, 1, 2};
  uint32_t mesh = 0, object = 0, tex = 0;
  const uint8_t texel[4] = {255, 255, 255, 255};
  ASSERT_EQ(facet_scene_add_mesh(scene, positions, 3, nullptr, indices, 1, &mesh), FACET_OK) << facet_scene_last_error(scene);
  ASSERT_EQ(facet_scene_add_object(scene, mesh, 1, nullptr, &object), FACET_OK) << facet_scene_last_error(scene);
  ASSERT_EQ(facet_scene_add_texture_rgba8(scene, texel, 1, 1, FACET_NEAREST, FACET_WRAP_REPEAT, &tex), FACET_OK);
  const double first[] = {double(tex)};
  EXPECT_EQ(facet_scene_set_material_field(scene, 1, "diffuse_texture", first, 1), FACET_INVALID_ARGUMENT);
  double now = 0;
  ASSERT_EQ(facet_scene_get_material_field(scene, 1, "diffuse_texture", &now, 1), FACET_OK);
  EXPECT_EQ(now, -1);
  EXPECT_EQ(facet_scene_set_material_field(scene, 0, "diffuse_texture", first, 1), FACET_OK);  // material 0: drawn by nothing
  facet_scene_destroy(scene);
}

// The docs' field tables are the tables' own text (name, type, accepted values, default, what).
template <class T>
std::string markdown(std::span<const FieldSpec<T>> table) {
  const T fresh{};
  std::string s = "| field | type | accepts | default | |\n|---|---|---|---|---|\n";
  for (const auto& f : table) {
    std::string range = describe_range(f), def = format_field(f, fresh);
    for (std::string* cell : {&range, &def}) {
      for (std::size_t at = cell->find('|'); at != std::string::npos; at = cell->find('|', at + 2)) cell->replace(at, 1, "\\|");
    }
    s += "| `" + std::string(f.name) + "` | " + to_string(f.type) + " | " + range + " | " + def + " | " + f.doc + " |\n";
  }
  return s;
}

std::string section(const std::string& doc, const std::string& marker) {
  const std::string begin = "<!-- " + marker + ": generated from the field table; tests/fields_test.cpp checks it -->\n";
  const std::size_t a = doc.find(begin);
  if (a == std::string::npos) return "(no marker '" + begin + "')";
  const std::size_t b = doc.find("<!-- end " + marker + " -->", a);
  return b == std::string::npos ? "(no end marker)" : doc.substr(a + begin.size(), b - a - begin.size());
}

TEST(FieldTable, TheDocsListEveryFieldAsTheTableDescribesIt) {
  std::ifstream in(std::string(FACET_SOURCE_DIR) + "/docs/scene-format.md");
  ASSERT_TRUE(in) << "docs/scene-format.md";
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string doc = ss.str();
  EXPECT_EQ(section(doc, "material fields"), markdown(material_fields())) << "paste the text above into docs/scene-format.md";
  EXPECT_EQ(section(doc, "light fields"), markdown(light_fields())) << "paste the text above into docs/scene-format.md";
}

}  // namespace
}  // namespace facet
