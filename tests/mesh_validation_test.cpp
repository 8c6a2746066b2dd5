// validate_scene checks every mesh with a fast test first (mesh_is_valid, run on every frame) and
// builds the field name only when it fails. The fast test must give the full check's verdict on
// every input: a mesh it passes that the full check refuses would be drawn unchecked.
#include <limits>

#include "scene/validate.hpp"
#include "render_support.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

Mesh quad_mesh() {
  Mesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  m.normals.assign(4, Vec3(0, 0, 1));
  m.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  m.colors.assign(4, Color3(0.5f, 0.25f, 1.0f));
  m.tangents.assign(4, Vec4(1, 0, 0, 1));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.groups = {{"a", 0, 1}, {"b", 1, 1}};
  return m;
}

TEST(MeshValidation, FastCheckGivesTheFullChecksVerdict) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float tiny = std::numeric_limits<float>::denorm_min(), below_one = 0.99999994f;
  std::vector<std::pair<const char*, Mesh>> cases;
  auto add = [&](const char* what, auto change) {
    Mesh m = quad_mesh();
    change(m);
    cases.emplace_back(what, std::move(m));
  };
  add("valid", [](Mesh&) {});
  add("no optional arrays", [](Mesh& m) { m.uvs.clear(), m.colors.clear(), m.tangents.clear(), m.groups.clear(); });
  add("no triangles", [](Mesh& m) { m.triangles.clear(), m.groups.clear(); });
  add("no vertices", [](Mesh& m) { m = Mesh{}; });
  add("no vertices, a triangle", [](Mesh& m) { m.positions.clear(), m.normals.clear(), m.uvs.clear(), m.colors.clear(), m.tangents.clear(); });
  add("normals short", [](Mesh& m) { m.normals.pop_back(); });
  add("uvs short", [](Mesh& m) { m.uvs.pop_back(); });
  add("colours long", [](Mesh& m) { m.colors.push_back(Color3(0, 0, 0)); });
  add("tangents short", [](Mesh& m) { m.tangents.pop_back(); });
  add("index = vertex count", [](Mesh& m) { m.triangles[1][2] = 4; });
  add("index huge", [](Mesh& m) { m.triangles[0][0] = 0xffffffffu; });
  add("index last", [](Mesh& m) { m.triangles[1][2] = 3; });
  for (float v : {inf, -inf, nan}) {
    add("uv not finite", [&](Mesh& m) { m.uvs[2].y() = v; });
    add("tangent not finite", [&](Mesh& m) { m.tangents[1].z() = v; });
    add("tangent w not finite", [&](Mesh& m) { m.tangents[3].w() = v; });
    add("colour not finite", [&](Mesh& m) { m.colors[0].x() = v; });
  }
  for (float w : {0.0f, -0.0f, 0.5f, 2.0f, -1.0f, 1.0f, below_one}) add("tangent w", [&](Mesh& m) { m.tangents[2].w() = w; });
  for (float c : {0.0f, -0.0f, 1.0f, -tiny, tiny, below_one, 1.0000001f, -1.0f, 2.0f, 1e30f}) {
    add("colour component", [&](Mesh& m) { m.colors[3].z() = c; });
  }
  add("uv large", [](Mesh& m) { m.uvs[0].x() = 1e30f; });
  add("group gap", [](Mesh& m) { m.groups[1].first_triangle = 2; });
  add("group empty", [](Mesh& m) { m.groups.push_back({"c", 2, 0}); });
  add("groups short", [](Mesh& m) { m.groups.pop_back(); });
  add("groups long", [](Mesh& m) { m.groups[1].triangle_count = 2; });
  int refused = 0;
  for (const auto& [what, m] : cases) {
    const Status full = validate_mesh(m);
    EXPECT_EQ(mesh_is_valid(m), full.ok()) << what << ": " << full.message();
    refused += !full.ok();
  }
  EXPECT_GT(refused, 20);  // the list is mostly corruptions
}

TEST(MeshValidation, RenderRefusesBadTangentsWithTheirField) {
  Scene s = test::camera_scene();
  test::add_quad(s, -1, -1, 1, 1, -3, Color3(1, 1, 1));
  Mesh& m = s.meshes[0].mesh;
  m.tangents.assign(m.positions.size(), Vec4(1, 0, 0, 1));
  ASSERT_TRUE(validate_scene(s).ok());
  m.tangents.pop_back();
  EXPECT_EQ(validate_scene(s).field(), "meshes[0].tangents");
  m.tangents.assign(m.positions.size(), Vec4(1, 0, 0, 0.5f));
  EXPECT_EQ(validate_scene(s).field(), "meshes[0].tangents[0]");
  test::Canvas c(16, 16);
  Renderer r;
  EXPECT_EQ(r.render(s, RenderOptions{}, c.view()).field(), "meshes[0].tangents[0]");
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// Functions that split vertices copy every per-vertex array, the lightmap coordinates included.
TEST(MeshValidation, SplittingVerticesKeepsLightmapCoordinates) {
  Mesh tetra;
  tetra.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  tetra.lightmap_uvs = {Vec2(0.1f, 0.1f), Vec2(0.2f, 0.1f), Vec2(0.1f, 0.2f), Vec2(0.3f, 0.3f)};
  tetra.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(1, 1)};
  compute_vertex_normals(tetra, 30.0f);  // every edge is sharper: each corner its own vertex
  ASSERT_EQ(tetra.positions.size(), 12u);
  ASSERT_EQ(tetra.lightmap_uvs.size(), 12u);
  EXPECT_TRUE(validate_mesh(tetra).ok());
  const Vec2 expected[4] = {Vec2(0.1f, 0.1f), Vec2(0.2f, 0.1f), Vec2(0.1f, 0.2f), Vec2(0.3f, 0.3f)};
  for (std::size_t v = 0; v < tetra.positions.size(); ++v) {
    for (std::size_t k = 0; k < 4; ++k) {
      if (tetra.positions[v] == Vec3(k == 1, k == 2, k == 3)) {
        EXPECT_EQ(tetra.lightmap_uvs[v], expected[k]) << v;
      }
    }
  }
  // A mirrored uv seam: generate_tangents splits the vertices on it.
  Mesh quad;
  quad.positions = {Vec3(-1, -1, 0), Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(-1, 1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0)};
  quad.normals.assign(6, Vec3(0, 0, 1));
  quad.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1), Vec2(0, 0), Vec2(0, 1)};  // the right half mirrored
  quad.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  quad.lightmap_uvs = {Vec2(0, 0), Vec2(0.5f, 0), Vec2(0.5f, 1), Vec2(0, 1), Vec2(1, 0), Vec2(1, 1)};
  ASSERT_TRUE(generate_tangents(quad).ok());
  EXPECT_GT(quad.positions.size(), 6u);
  ASSERT_EQ(quad.lightmap_uvs.size(), quad.positions.size());
  for (std::size_t v = 6; v < quad.positions.size(); ++v) EXPECT_EQ(quad.lightmap_uvs[v].x(), 0.5f) << v;  // the seam's
  EXPECT_TRUE(validate_mesh(quad).ok());
}

}  // namespace
}  // namespace facet
