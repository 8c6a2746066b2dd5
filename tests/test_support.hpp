// Helpers shared by the tests.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "facet/facet.hpp"

namespace facet::test {

inline std::string models_dir() { return FACET_MODELS_DIR; }
inline std::string data_dir() { return FACET_TEST_DATA_DIR; }

// The repository's scene files name meshes and textures in sibling folders of tests/data/scenes
// and models in ../shared/models: both widened on purpose, as a host would (facet/assets.hpp).
inline LoadOptions scene_options() {
  LoadOptions o;
  o.assets.allowed_roots = {data_dir(), models_dir()};
  return o;
}

// GL's framebuffer: 8-bit output written linear (RenderOptions::srgb false), as the tests of GL's
// formulas and the golden images (made against llvmpipe) expect.
inline RenderOptions gl_options() {
  RenderOptions o;
  o.srgb = false;
  return o;
}

// A fresh folder for the running test, removed with everything in it at the end of the test.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "facet_test") {
    path_ = std::filesystem::temp_directory_path() /
            (prefix + "_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

// Skips the calling test when ../shared/models is not beside the checkout.
#define FACET_REQUIRE_MODELS()                                                               \
  do {                                                                                       \
    if (!std::filesystem::is_directory(::facet::test::models_dir()))                         \
      GTEST_SKIP() << "models folder not found: " << ::facet::test::models_dir();            \
  } while (0)

// A scene whose world space is eye space: camera at the origin looking down -z with +y up, no
// global ambient, one material that only has what a test sets.
inline Scene eye_space_scene() {
  Scene s;
  s.camera.eye = Vec3(0, 0, 0);
  s.camera.target = Vec3(0, 0, -1);
  s.camera.up = Vec3(0, 1, 0);
  s.global_ambient = Color3::Zero();
  Material m;
  m.ambient = Color3::Zero();
  m.diffuse = Color3::Zero();
  m.specular = Color3::Zero();
  s.materials.push_back(m);
  return s;
}

// Sets the scene's only object to one vertex at `p` with normal `n` (model space = world space).
inline void set_single_vertex(Scene& s, const Vec3& p, const Vec3& n) {
  Mesh mesh;
  mesh.positions = {p};
  mesh.normals = {n};
  s.meshes = {{"vertex", mesh}};
  s.objects = {Instance{0, 0, Mat4::Identity()}};
}

}  // namespace facet::test
