// Posing glTF models (facet/animation.hpp): a node's keyframes, a two-joint skin bent by a known
// angle and a morph target at chosen weights, all against closed forms; the three pose paths;
// bad files refused by JSON path.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "facet/facet.hpp"
#include "gltf_builder.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

using test::GltfBuilder;

Result<Model> parse_rig_text(const std::string& text) {
  return parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "rig.gltf", "");
}

// A node whose quad turns about +Y from 0 to 90 degrees over 1 s, with `interpolation`, below a
// parent node 3 along +X.
GltfBuilder turning_quad(const char* interpolation) {
  GltfBuilder b = test::quad();
  b.doc["nodes"].push_back({{"children", {0}}, {"translation", {3, 0, 0}}});
  b.doc["scenes"][0]["nodes"] = {1};
  const double h = std::sqrt(0.5);
  const int times = b.floats({0.0f, 1.0f}, "SCALAR", 1);
  std::vector<float> keys = {0, 0, 0, 1, 0, float(h), 0, float(h)};
  if (std::string(interpolation) == "CUBICSPLINE") keys = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, float(h), 0, float(h), 0, 0, 0, 0};
  const int turns = b.floats(keys, "VEC4", 4);
  b.add("animations", {{"name", "turn"},
                       {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}}}},
                       {"samplers", {{{"input", times}, {"output", turns}, {"interpolation", interpolation}}}}});
  return b;
}

// The angle about +Y of an object's model matrix, in degrees.
double yaw_deg(const Instance& o) { return std::atan2(double(o.model(0, 2)), double(o.model(0, 0))) * 180.0 / std::numbers::pi; }

TEST(RigPose, ANodeTurnsAsItsKeysSay) {
  for (const char* interpolation : {"LINEAR", "STEP", "CUBICSPLINE"}) {
    SCOPED_TRACE(interpolation);
    Result<Model> m = parse_rig_text(turning_quad(interpolation).embedded());
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_NEAR(yaw_deg(m->scene.objects[0]), 0.0, 1e-9);  // loaded at rest
    Result<int> a = find_animation(*m, "turn");
    ASSERT_TRUE(a.ok());
    PoseOptions po;
    po.animation = *a;
    for (const double t : {-1.0, 0.0, 0.5, 1.0, 3.0}) {
      ASSERT_TRUE(pose_model(*m, t, po).ok());
      const double s = std::clamp(t, 0.0, 1.0);
      // LINEAR: slerp, so the angle moves evenly; STEP holds the first key until the last;
      // CUBICSPLINE with zero tangents: the Hermite blend 3s^2 - 2s^3 of the two quaternions,
      // renormalised: the angle is 2 atan(b sin45 / (a + b cos45)).
      double want = 90.0 * s;
      if (std::string(interpolation) == "STEP") want = s < 1.0 ? 0.0 : 90.0;
      if (std::string(interpolation) == "CUBICSPLINE") {
        const double bw = 3 * s * s - 2 * s * s * s, aw = 1 - bw, h = std::sqrt(0.5);
        want = 2.0 * std::atan2(bw * h, aw + bw * h) * 180.0 / std::numbers::pi;
      }
      EXPECT_NEAR(yaw_deg(m->scene.objects[0]), want, 1e-4) << "t = " << t;
      EXPECT_EQ(m->scene.objects[0].model(0, 3), 3.0f);  // the parent's translation, composed
    }
  }
}

// A strip along +Y from 0 to 2 (x in {0, 1}), joint 0 at the origin, joint 1 at y = 1 (its
// child): the rows y = 0 and y = 2 follow one joint each, the row y = 1 both by half. The
// animation turns joint 1 by 90 degrees about +Z at t = 1.
GltfBuilder bending_strip() {
  GltfBuilder b;
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0, 1, 2, 0};
  const std::vector<float> normals = {1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0};
  const std::vector<std::uint16_t> joints = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
  const std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
  const int pos = b.vec3(positions), nrm = b.vec3(normals);
  const int jnt = b.accessor(b.view(joints.data(), joints.size() * 2), 5123, 6, "VEC4");
  const int wgt = b.vec4(weights);
  const std::vector<std::uint16_t> tris = {0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4};
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"JOINTS_0", jnt}, {"WEIGHTS_0", wgt}}},
                                    {"indices", b.indices16(tris)}}}}});
  const std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
  const int inverse = b.floats(ibm, "MAT4", 16);
  b.add("nodes", {{"mesh", 0}, {"skin", 0}, {"translation", {5, 0, 0}}});  // ignored: skinned vertices are the joints'
  b.add("nodes", {{"children", {2}}});
  b.add("nodes", {{"translation", {0, 1, 0}}});
  b.add("skins", {{"joints", {1, 2}}, {"inverseBindMatrices", inverse}});
  b.add("scenes", {{"nodes", {0, 1}}});
  const double h = std::sqrt(0.5);
  const int times = b.floats({0.0f, 1.0f}, "SCALAR", 1);
  const int turns = b.floats({0, 0, 0, 1, 0, 0, float(h), float(h)}, "VEC4", 4);
  b.add("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}}}},
                       {"samplers", {{{"input", times}, {"output", turns}}}}});
  return b;
}

TEST(RigPose, ATwoJointSkinBendsByItsAngle) {
  Result<Model> m = parse_rig_text(bending_strip().embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->motion.skins.size(), 1u);
  EXPECT_EQ(m->motion.skins[0].joints, 2u);
  EXPECT_EQ(m->motion.skins[0].vertices, 6u);
  ASSERT_EQ(m->scene.objects.size(), 1u);
  EXPECT_TRUE(m->scene.objects[0].model.isIdentity());
  const Mesh& mesh = m->scene.meshes[m->scene.objects[0].mesh].mesh;
  // At rest the joints are where the bind matrices put them: the file's positions.
  EXPECT_EQ(mesh.positions[5], Vec3(1, 2, 0));
  for (const PosePath path : {PosePath::simd, PosePath::scalar, PosePath::reference}) {
    PoseOptions po;
    po.animation = 0;
    po.path = path;
    ASSERT_TRUE(pose_model(*m, 1.0, po).ok());
    // Joint 1 turned 90 degrees about +Z at (0, 1, 0): (x, 2) -> (-1, 1 + x); the middle row half
    // of each joint: (x, 1) -> ((x + 0) / 2, (1 + 1 + x) / 2).
    for (int x = 0; x < 2; ++x) {
      const Vec3 top = mesh.positions[std::size_t(4 + x)], middle = mesh.positions[std::size_t(2 + x)], bottom = mesh.positions[std::size_t(x)];
      EXPECT_NEAR(top.x(), -1.0, 1e-6);
      EXPECT_NEAR(top.y(), 1.0 + x, 1e-6);
      EXPECT_NEAR(middle.x(), 0.5 * x, 1e-6);
      EXPECT_NEAR(middle.y(), 1.0 + 0.5 * x, 1e-6);
      EXPECT_NEAR(bottom.x(), double(x), 1e-6);
      EXPECT_NEAR(bottom.y(), 0.0, 1e-6);
      // Normals: +X turns to +Y on joint 1's row, to (1, 1)/sqrt 2 on the shared row.
      EXPECT_NEAR(mesh.normals[std::size_t(4 + x)].y(), 1.0, 1e-6);
      EXPECT_NEAR(mesh.normals[std::size_t(2 + x)].x(), std::sqrt(0.5), 1e-6);
      EXPECT_NEAR(mesh.normals[std::size_t(2 + x)].y(), std::sqrt(0.5), 1e-6);
    }
  }
  // Half way: 45 degrees.
  PoseOptions po;
  po.animation = 0;
  ASSERT_TRUE(pose_model(*m, 0.5, po).ok());
  const double c = std::cos(std::numbers::pi / 4), s = std::sin(std::numbers::pi / 4);
  EXPECT_NEAR(mesh.positions[5].x(), c * 1 - s * 1, 1e-6);
  EXPECT_NEAR(mesh.positions[5].y(), 1 + s * 1 + c * 1, 1e-6);
}

TEST(RigPose, WeightsThatDoNotAddUpToOneAreRenormalised) {
  GltfBuilder b = bending_strip();
  // The top row's weights halved: renormalised to 1, it still follows joint 1 all the way.
  const std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0, 0};
  b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = b.vec4(weights);
  Result<Model> m = parse_rig_text(b.embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  bool warned = false;
  for (const std::string& w : m->warnings) warned |= w.find("2 vertices' weights do not add up to 1") != std::string::npos;
  EXPECT_TRUE(warned);
  PoseOptions po;
  po.animation = 0;
  ASSERT_TRUE(pose_model(*m, 1.0, po).ok());
  const Mesh& mesh = m->scene.meshes[m->scene.objects[0].mesh].mesh;
  EXPECT_NEAR(mesh.positions[4].x(), -1.0, 1e-6);
  EXPECT_NEAR(mesh.positions[4].y(), 1.0, 1e-6);
}

TEST(RigPose, AMorphedNodeScaledToNothingIsNotDrawn) {
  GltfBuilder b;
  const int pos = b.vec3(test::kQuadPositions);
  const int delta = b.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", b.indices16(test::kQuadIndices)},
                                    {"targets", {{{"POSITION", delta}}}}}}}});
  b.add("nodes", {{"mesh", 0}, {"scale", {0, 1, 1}}});
  b.add("scenes", {{"nodes", {0}}});
  Result<Model> m = parse_rig_text(b.embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_TRUE(m->scene.objects.empty());
  ASSERT_FALSE(m->warnings.empty());
  EXPECT_NE(m->warnings.back().find("singular"), std::string::npos) << m->warnings.back();
}

TEST(RigPose, AMorphTargetMovesByItsWeight) {
  GltfBuilder b;
  const int pos = b.vec3(test::kQuadPositions);
  const int delta = b.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", b.indices16(test::kQuadIndices)},
                                    {"targets", {{{"POSITION", delta}}}}}}},
                   {"weights", {0.25}}});
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  const int times = b.floats({0.0f, 1.0f}, "SCALAR", 1);
  const int weights = b.floats({0.0f, 1.0f}, "SCALAR", 1);
  b.add("animations", {{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}},
                       {"samplers", {{{"input", times}, {"output", weights}}}}});
  Result<Model> m = parse_rig_text(b.embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->motion.morphed_meshes, 1u);
  EXPECT_EQ(m->motion.morph_targets, 1u);
  const Mesh& mesh = m->scene.meshes[m->scene.objects[0].mesh].mesh;
  EXPECT_EQ(mesh.positions[2].z(), 0.25f);  // the mesh's weights at rest
  PoseOptions po;
  po.animation = 0;
  for (const double w : {0.0, 0.5, 1.0}) {
    ASSERT_TRUE(pose_model(*m, w, po).ok());
    for (const Vec3& p : mesh.positions) EXPECT_EQ(p.z(), float(w));
  }
}

TEST(RigPose, BadFilesAreRefusedByPath) {
  struct Case {
    const char* what;
    std::function<void(GltfBuilder&)> edit;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"a joint out of range", [](GltfBuilder& b) { b.doc["skins"][0]["joints"] = {1}; }, "JOINTS_0"},
      {"a joint that is no node", [](GltfBuilder& b) { b.doc["skins"][0]["joints"] = {1, 99}; }, "skins[0].joints[1]"},
      {"too many joints", [](GltfBuilder& b) { b.doc["skins"][0]["joints"] = std::vector<int>(70000, 1); }, "skins[0].joints"},
      {"times that go back",
       [](GltfBuilder& b) { b.doc["animations"][0]["samplers"][0]["input"] = b.floats({1.0f, 0.0f}, "SCALAR", 1); },
       "animations[0].samplers[0].input"},
      {"a NaN key",
       [](GltfBuilder& b) {
         b.doc["animations"][0]["samplers"][0]["output"] = b.floats({0, 0, 0, 1, 0, 0, std::nanf(""), 1}, "VEC4", 4);
       },
       "not a finite float"},
      {"a billion keys",
       [](GltfBuilder& b) { b.doc["accessors"][b.doc["animations"][0]["samplers"][0]["input"].get<int>()]["count"] = 1000000000; },
       "1000000000 keyframes"},
      {"a matrix node animated", [](GltfBuilder& b) { b.doc["nodes"][2] = {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1}}}; },
       "animations[0].channels[0].target.node"},
      {"a cycle", [](GltfBuilder& b) { b.doc["nodes"][2]["children"] = {1}; }, "nodes"},
      {"a cycle outside the scene",
       [](GltfBuilder& b) {
         b.add("nodes", {{"children", {4}}});
         b.add("nodes", {{"children", {3}}});
       },
       "nodes[3]: is in a cycle"},
      {"two parents", [](GltfBuilder& b) { b.add("nodes", {{"children", {2}}}); }, "has two parents"},
      {"a pose beyond float's range",
       [](GltfBuilder& b) {
         const std::vector<float> huge = {2e38f, 0, 0, 0, 0, 2e38f, 0, 0, 0, 0, 2e38f, 0, 0, 0, 0, 1,
                                          2e38f, 0, 0, 0, 0, 2e38f, 0, 0, 0, 0, 2e38f, 0, 0, 0, 0, 1};
         b.doc["skins"][0]["inverseBindMatrices"] = b.floats(huge, "MAT4", 16);
         b.doc["nodes"][1]["scale"] = {10, 10, 10};
       },
       "out of float's range"},
      {"an unknown path", [](GltfBuilder& b) { b.doc["animations"][0]["channels"][0]["target"]["path"] = "colour"; },
       "animations[0].channels[0].target.path"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    GltfBuilder b = bending_strip();
    c.edit(b);
    Result<Model> m = parse_rig_text(b.embedded());
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.status().message().find(c.expect), std::string::npos) << m.status().message();
  }
}

TEST(RigPose, APosedModelIsTheSameBytesForAnyThreadCount) {
  Result<Model> m = parse_rig_text(bending_strip().embedded());
  ASSERT_TRUE(m.ok());
  PoseOptions po;
  po.animation = 0;
  ASSERT_TRUE(pose_model(*m, 0.6, po).ok());
  m->scene.camera = *frame_scene(m->scene, 1.0f);
  Light sun;  // a light of its own: the studio's prefiltering would dominate the test's time
  sun.type = LightType::directional;
  sun.direction = Vec3(0.3f, -0.5f, -1.0f).normalized();
  m->scene.lights.push_back(sun);
  std::vector<std::uint8_t> pictures[3];
  for (int threads : {1, 2, 3}) {
    std::vector<std::uint8_t>& px = pictures[threads - 1];
    px.assign(96 * 96 * 4, 0);
    RenderOptions o;
    o.threads = threads;
    o.shading = ShadingMode::phong;
    Renderer r(o);
    ASSERT_TRUE(r.render(m->scene, {px.data(), 96, 96, 96 * 4, PixelFormat::rgba8, false}).ok());
  }
  EXPECT_EQ(pictures[0], pictures[1]);
  EXPECT_EQ(pictures[0], pictures[2]);
  EXPECT_NE(std::count(pictures[0].begin(), pictures[0].end(), 0), static_cast<long>(pictures[0].size()));
}

TEST(RigPose, PosingRefusesWhatIsNotThere) {
  Result<Model> m = parse_rig_text(bending_strip().embedded());
  ASSERT_TRUE(m.ok());
  PoseOptions po;
  po.animation = 1;
  EXPECT_FALSE(pose_model(*m, 0.0, po).ok());
  po.animation = 0;
  EXPECT_FALSE(pose_model(*m, std::nan(""), po).ok());
  EXPECT_FALSE(find_animation(*m, "walk").ok());
  m->scene.meshes[m->scene.objects[0].mesh].mesh.positions.pop_back();  // a host changed the scene
  EXPECT_FALSE(pose_model(*m, 0.0, po).ok());
}

TEST(RigPose, FramingCoversTheWholeAnimation) {
  Result<Model> m = parse_rig_text(bending_strip().embedded());
  ASSERT_TRUE(m.ok());
  PoseOptions po;
  po.animation = 0;
  Result<Bounds> box = animation_bounds(*m, po);
  ASSERT_TRUE(box.ok());
  EXPECT_NEAR(box->min.x(), -1.0, 1e-5);  // the bent pose reaches x = -1
  // Half way the tip reaches y = 1 + sqrt 2; 32 sampled times come within 1e-3 of it.
  EXPECT_GT(box->max.y(), 1.0 + std::sqrt(2.0) - 1e-3);
  EXPECT_LE(box->max.y(), 1.0 + std::sqrt(2.0) + 1e-6);
  EXPECT_EQ(m->pose.animation, -1);       // posed again as it was
  EXPECT_EQ(m->scene.meshes[m->scene.objects[0].mesh].mesh.positions[5], Vec3(1, 2, 0));
  // The framing of every pose's vertices: the bent poses reach x = -1, so the view is wider than
  // the rest pose's, and every sampled pose's vertices lie within it.
  Result<Camera> rest = frame_scene(m->scene, 1.0f), moving = frame_animation(*m, 1.0f, ViewOptions{}, po);
  ASSERT_TRUE(rest.ok() && moving.ok());
  EXPECT_GT((moving->eye - moving->target).norm(), (rest->eye - rest->target).norm());
  EXPECT_EQ(m->pose.animation, -1);
  const double half = std::tan(0.5 * double(moving->vertical_fov_deg) * std::numbers::pi / 180.0);
  for (const double t : animation_sample_times(m->motion.animations[0], 16)) {
    ASSERT_TRUE(pose_model(*m, t, po).ok());
    for (const Vec3& p : m->scene.meshes[m->scene.objects[0].mesh].mesh.positions) {
      // The camera looks along -z from +z (the default view): the point's slope from the axis.
      const Eigen::Vector3d rel = (p - moving->eye).cast<double>();
      const double depth = -rel.z();
      EXPECT_LE(std::abs(rel.x()) / depth, half * (1 + 1e-6));
      EXPECT_LE(std::abs(rel.y()) / depth, half * (1 + 1e-6));
    }
  }
}

// A scene file imports the model posed: "animation" by name or index, "time" in seconds.
TEST(RigPose, SceneFilesImportAPose) {
  test::TempDir dir;
  const std::string strip = test::data_dir() + "/gltf/bending_strip.gltf";
  auto load = [&](const std::string& fields) {
    test::write_text(dir / "posed.json", R"({ "imports": [ { "file": ")" + strip + "\" " + fields + " } ] }");
    LoadOptions o;
    o.assets.allowed_roots = {test::data_dir()};
    return load_scene_file(dir / "posed.json", o);
  };
  Result<Scene> rest = load(""), bent = load(R"(, "animation": "bend", "time": 1)"), by_index = load(R"(, "animation": 0, "time": 1)");
  ASSERT_TRUE(rest.ok()) << rest.status().message();
  ASSERT_TRUE(bent.ok()) << bent.status().message();
  ASSERT_TRUE(by_index.ok()) << by_index.status().message();
  const Vec3 tip = bent->meshes[0].mesh.positions.back();  // (1, 2, 0) bent about (0, 1): (-1, 2)
  EXPECT_NEAR(tip.x(), -1.0f, 1e-5f);
  EXPECT_NEAR(tip.y(), 2.0f, 1e-5f);
  EXPECT_EQ(rest->meshes[0].mesh.positions.back(), Vec3(1, 2, 0));
  EXPECT_EQ(by_index->meshes[0].mesh.positions, bent->meshes[0].mesh.positions);
  Result<Scene> wrong = load(R"(, "animation": "walk")");
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.status().message().find("imports[0].animation"), std::string::npos) << wrong.status().message();
  EXPECT_NE(wrong.status().message().find("bend"), std::string::npos) << wrong.status().message();
  Result<Scene> bad_time = load(R"(, "time": "soon")");
  ASSERT_FALSE(bad_time.ok());
  EXPECT_NE(bad_time.status().message().find("imports[0].time"), std::string::npos) << bad_time.status().message();
}

}  // namespace
}  // namespace facet
