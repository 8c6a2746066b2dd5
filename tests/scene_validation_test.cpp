// validate_scene on scenes built in C++: each problem is reported with its field path.
#include "test_support.hpp"

namespace facet {
namespace {

std::string field_of(const Scene& s) { return validate_scene(s).field(); }

TEST(SceneValidation, DefaultSceneIsValidAndUsesEveryLightType) {
  const Scene s = make_default_scene();
  EXPECT_TRUE(validate_scene(s).ok()) << validate_scene(s).message();
  bool directional = false, point = false, gl_spot = false, smooth_spot = false;
  for (const Light& l : s.lights) {
    directional |= l.type == LightType::directional;
    point |= l.type == LightType::point;
    gl_spot |= l.type == LightType::spot && l.spot_shape == SpotShape::cutoff_exponent;
    smooth_spot |= l.type == LightType::spot && l.spot_shape == SpotShape::smooth_cone;
  }
  EXPECT_TRUE(directional && point && gl_spot && smooth_spot);
}

TEST(SceneValidation, FieldsAreNamed) {
  const Scene good = make_default_scene();
  Scene s = good;
  s.camera.up = (s.camera.target - s.camera.eye) * 2.0f;
  EXPECT_EQ(field_of(s), "camera.up");
  s = good;
  s.camera.vertical_fov_deg = 180;
  EXPECT_EQ(field_of(s), "camera.fov_deg");
  s = good;
  s.lights[1].constant_attenuation = 0;
  s.lights[1].linear_attenuation = 0;
  s.lights[1].quadratic_attenuation = 0;
  EXPECT_EQ(field_of(s), "lights[1].attenuation");
  s = good;
  s.lights[0].range = 5;  // directional
  EXPECT_EQ(field_of(s), "lights[0].range");
  s = good;
  s.lights[2].diffuse = Color3(1, -1, 0);
  EXPECT_EQ(field_of(s), "lights[2].diffuse");
  s = good;
  s.materials[1].alpha = 2;
  EXPECT_EQ(field_of(s), "materials[1].alpha");
  s = good;
  s.objects[2].mesh = 99;
  EXPECT_EQ(field_of(s), "objects[2].mesh");
  s = good;
  s.objects[0].model(0, 0) = std::numeric_limits<float>::infinity();
  EXPECT_EQ(field_of(s), "objects[0].transform");
  s = good;
  s.meshes[0].mesh.triangles[7][1] = 1u << 30;
  EXPECT_EQ(field_of(s), "meshes[0].triangles[7]");
  s = good;
  s.meshes[1].mesh.normals.pop_back();
  EXPECT_EQ(field_of(s), "meshes[1].normals");
}

TEST(SceneValidation, NonFinitePositionsAreAllowed) {
  // The renderer drops such triangles; lighting gives them no positional light. Not an error.
  Scene s = make_default_scene();
  s.meshes[0].mesh.positions[3] = Vec3(std::numeric_limits<float>::quiet_NaN(), 0, 0);
  EXPECT_TRUE(validate_scene(s).ok());
}

}  // namespace
}  // namespace facet
