// Wavefront OBJ: the syntax variants, the five real models, and malformed files (each error names
// the file and the line).
#include <filesystem>
#include <fstream>

#include "test_support.hpp"

namespace facet {
namespace {

Result<Mesh> parse(const std::string& text) { return parse_obj(text, "test.obj"); }

void expect_error(const std::string& text, const std::string& where, const std::string& what) {
  const Result<Mesh> m = parse(text);
  ASSERT_FALSE(m.ok()) << "accepted:\n" << text;
  EXPECT_EQ(m.status().code(), ErrorCode::parse_error);
  EXPECT_NE(m.status().message().find(where), std::string::npos) << m.status().message();
  EXPECT_NE(m.status().message().find(what), std::string::npos) << m.status().message();
}

const char* kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

TEST(ObjLoader, QuadIsTriangulated) {
  Result<Mesh> m = parse(std::string(kSquare) + "f 1 2 3 4\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->triangle_count(), 2u);
  for (const auto& n : m->normals) EXPECT_LT((n - Vec3(0, 0, 1)).norm(), 1e-6f);
}

TEST(ObjLoader, IndexForms) {
  const std::string body = std::string(kSquare) + "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n";
  for (const char* face : {"f 1/1 2/2 3/3\n", "f 1//1 2//1 3//1\n", "f 1/1/1 2/2/1 3/3/1\n", "f -4 -3 -2\n",
                           "f -4/-3/-1 -3/-2/-1 -2/-1/-1\n"}) {
    Result<Mesh> m = parse(body + face);
    ASSERT_TRUE(m.ok()) << face << m.status().message();
    ASSERT_EQ(m->triangle_count(), 1u) << face;
    const auto& t = m->triangles[0];
    EXPECT_EQ(m->positions[t[0]], Vec3(0, 0, 0)) << face;
    EXPECT_EQ(m->positions[t[1]], Vec3(1, 0, 0)) << face;
    EXPECT_EQ(m->positions[t[2]], Vec3(1, 1, 0)) << face;
  }
}

TEST(ObjLoader, FileNormalsAreUsedAsGiven) {
  // The file's normal deliberately differs from the face normal: the model decides.
  Result<Mesh> m = parse(std::string(kSquare) + "vn 0 1 1\nf 1//1 2//1 3//1\n");
  ASSERT_TRUE(m.ok());
  for (const auto& n : m->normals) EXPECT_LT((n - Vec3(0, 1, 1).normalized()).norm(), 1e-6f);
}

TEST(ObjLoader, CommentsGroupsCrlfAndBlankLines) {
  Result<Mesh> m = parse("# a comment\r\no thing\r\ng part\r\n\r\nv 0 0 0 # trailing\r\nv 1 0 0\r\nv 0 1 0\r\n"
                         "s 1\r\nusemtl red\r\nmtllib none.mtl\r\nf 1 2 3\r\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->triangle_count(), 1u);
}

TEST(ObjLoader, CommentInTheMiddleOfAFaceLineEndsIt) {
  // Found by fuzzing: tinyobjloader alone would read "-9" as a (negative, out-of-range) index.
  Result<Mesh> m = parse(std::string(kSquare) + "f 1 2 3 # 4 -9\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->triangle_count(), 1u);
}

TEST(ObjLoader, PolygonWithRepeatedCornersStaysInBounds) {
  Result<Mesh> m = parse(std::string(kSquare) + "f 1 2 2 4 4 1 4\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->triangle_count(), 5u);  // a fan of 7 corners; the degenerate ones are kept, not drawn
  EXPECT_TRUE(validate_mesh(*m).ok());
}

TEST(ObjLoader, MalformedFiles) {
  expect_error(std::string(kSquare) + "f 1 2 x\n", "test.obj:5:", "bad vertex index 'x'");
  expect_error(std::string(kSquare) + "f 1 2 9\n", "test.obj:5:", "vertex index 9 is out of range (4 defined so far)");
  expect_error(std::string(kSquare) + "f 0 1 2\n", "test.obj:5:", "bad vertex index '0'");
  expect_error(std::string(kSquare) + "f -5 1 2\n", "test.obj:5:", "vertex index -5 is out of range");
  expect_error(std::string(kSquare) + "vn 0 0 1\nf 1//2 2//1 3//1\n", "test.obj:6:", "normal index 2 is out of range");
  expect_error("v 0 0 0\nhello world\n", "test.obj:2:", "unknown statement 'hello'");
  expect_error("v 0 abc 0\n", "test.obj:1:", "'v' value 2 is not a number: 'abc'");
  expect_error("v 0 0\n", "test.obj:1:", "'v' expects 3 (x y z), 4 (x y z w) or 6 (x y z r g b) numbers, found 2");
  expect_error("v 0 0 0 1 1\n", "test.obj:1:", "found 5");
  expect_error("v 0 0 0 1 1 1 1\n", "test.obj:1:", "found 7");
  // Vertex colours: every vertex or none, components in [0, 1].
  expect_error("v 0 0 0 1 0 0\nv 1 0 0\n", "test.obj:2:", "vertex 2 has no colour (r g b) but vertex 1 has one");
  expect_error("v 0 0 0\nv 1 0 0 1 0 0\n", "test.obj:2:", "vertex 2 has colour (r g b) but vertex 1 has none");
  expect_error("v 0 0 0 1 0 1.5\n", "test.obj:1:", "'v' colour value 3 is outside [0, 1]: '1.5'");
  expect_error("v 0 0 0 -0.1 0 1\n", "test.obj:1:", "'v' colour value 1 is outside [0, 1]");
  expect_error(std::string(kSquare) + "vt 0 nan\n", "test.obj:5:", "'vt' value 2 is not finite");
  expect_error(std::string(kSquare) + "vt 0 0\nf 1/2 2/1 3/1\n", "test.obj:6:", "texture coordinate index 2 is out of range");
  expect_error(std::string(kSquare) + "usemtl\nf 1 2 3\n", "test.obj:5:", "'usemtl' expects a material name");
  expect_error(std::string(kSquare) + "f + 2 3\n", "test.obj:5:", "bad vertex index '+'");
  expect_error(std::string(kSquare) + "f ++1 2 3\n", "test.obj:5:", "bad vertex index '++1'");
  expect_error("v +-1 0 0\n", "test.obj:1:", "'v' value 1 is not a number: '+-1'");
  expect_error(std::string(kSquare) + "f 1 2 3\nusemtl red\nf 1 3 4\n", "test.obj", "faces before the first 'usemtl'");
  expect_error(std::string(kSquare) + "f 1 2\n", "test.obj:5:", "a face needs at least 3 vertices");
  expect_error("", "test.obj:1:", "no faces");
  expect_error("# only a comment\n\n", "test.obj:3:", "no faces");
  expect_error(std::string(kSquare) + "f 1 2 3 \\\n 4\n", "test.obj:5:", "line continuations");
  expect_error(std::string("v 0 0 0\n\0\n", 10), "test.obj", "NUL");
}

TEST(ObjLoader, TextureCoordinatesSplitVerticesAtSeams) {
  // Two triangles share the edge 1-3 in position but not in texture coordinates at vertex 3.
  Result<Mesh> m = parse(std::string(kSquare) + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.5\nvt 0 1 7\n"
                                                "f 1/1 2/2 3/3\nf 1/1 3/4 4/5\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_TRUE(validate_mesh(*m).ok());
  ASSERT_EQ(m->uvs.size(), m->vertex_count());
  EXPECT_EQ(m->vertex_count(), 5u);  // vertex 3 twice: (1, 1) and (0.5, 0)
  const auto& t0 = m->triangles[0];
  const auto& t1 = m->triangles[1];
  EXPECT_EQ(m->uvs[t0[0]], Vec2(0, 0));
  EXPECT_EQ(m->uvs[t0[1]], Vec2(1, 0));
  EXPECT_EQ(m->uvs[t0[2]], Vec2(1, 1));
  EXPECT_EQ(m->uvs[t1[1]], Vec2(0.5f, 0.0f));  // `vt u`: v defaults to 0
  EXPECT_EQ(m->uvs[t1[2]], Vec2(0, 1));        // `vt u v w`: w is ignored
  EXPECT_EQ(m->positions[t1[1]], m->positions[t0[2]]);
  // The normals are still smooth across the seam: both copies of vertex 3 get the same one.
  EXPECT_EQ(m->normals[t1[1]], m->normals[t0[2]]);
  EXPECT_TRUE(m->colors.empty());
  EXPECT_TRUE(m->groups.empty());
}

TEST(ObjLoader, CreaseSplitKeepsTextureCoordinatesAndColours) {
  // A folded pair of triangles (90 deg): the crease splits the shared vertices; the copies keep
  // their texture coordinates and colours.
  Result<Mesh> m = parse("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 1 0.5 0.5 0.5\n"
                         "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nf 1/1 2/2 3/3\nf 2/2 1/1 4/4\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_TRUE(validate_mesh(*m).ok());
  EXPECT_EQ(m->vertex_count(), 6u);
  ASSERT_EQ(m->uvs.size(), 6u);
  ASSERT_EQ(m->colors.size(), 6u);
  const auto& t0 = m->triangles[0];
  const auto& t1 = m->triangles[1];
  EXPECT_NE(t0[0], t1[1]);  // vertex 1 split by the crease
  EXPECT_EQ(m->uvs[t1[1]], Vec2(0, 0));
  EXPECT_EQ(m->colors[t1[1]], Color3(1, 0, 0));
  EXPECT_EQ(m->uvs[t1[0]], Vec2(1, 0));
  EXPECT_EQ(m->colors[t1[0]], Color3(0, 1, 0));
  EXPECT_EQ(m->colors[t1[2]], Color3(0.5f, 0.5f, 0.5f));
}

// Written as other readers (Blender, three.js, tinyobjloader) read them: numbers with a '+',
// material names with spaces, faces whose corners mix `v` and `v/vt`.
TEST(ObjLoader, PlusSignsAreNumbers) {
  Result<Mesh> m = parse("v +1 0 +0.5\nv +.5 +2e+0 0\nv 0 0 1\nvt +0.25 +1\nvn 0 0 +1\nf +1/+1/+1 2/1/1 3/1/1\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->positions[0], Vec3(1.0f, 0.0f, 0.5f));
  EXPECT_EQ(m->positions[1], Vec3(0.5f, 2.0f, 0.0f));
  EXPECT_EQ(m->uvs[0], Vec2(0.25f, 1.0f));
}

TEST(ObjLoader, UsemtlNameIsTheRestOfTheLine) {
  Result<Mesh> m = parse(std::string(kSquare) + "usemtl My Material\nf 1 2 3\nusemtl  My  Other \nf 1 3 4\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->groups.size(), 2u);
  EXPECT_EQ(m->groups[0].material, "My Material");
  EXPECT_EQ(m->groups[1].material, "My  Other");  // inner blanks kept, as newmtl keeps them
}

TEST(ObjLoader, CornersWithoutTextureCoordinateReadZero) {
  for (const char* faces : {"f 1/1 2/2 3/2\nf 1 3 4\n", "f 1/1 2/2 3/2\nf 1//1 3//1 4//1\n", "f 1 3 4\nf 1/1 2/2 3/2\n"}) {
    Result<Mesh> m = parse(std::string(kSquare) + "vt 0.5 0.5\nvt 1 0.25\nvn 0 0 1\n" + faces);
    ASSERT_TRUE(m.ok()) << faces << m.status().message();
    ASSERT_EQ(m->uvs.size(), m->positions.size()) << faces;
    ASSERT_EQ(m->triangle_count(), 2u);
    const bool textured_first = faces[3] == '/';
    const auto& with = m->triangles[textured_first ? 0 : 1];
    const auto& without = m->triangles[textured_first ? 1 : 0];
    EXPECT_EQ(m->uvs[with[0]], Vec2(0.5f, 0.5f)) << faces;
    EXPECT_EQ(m->uvs[with[1]], Vec2(1.0f, 0.25f)) << faces;
    // Vertex 1 is in both faces: the corner without a vt is a vertex of its own, at (0, 0).
    EXPECT_NE(with[0], without[0]) << faces;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m->uvs[without[k]], Vec2(0.0f, 0.0f)) << faces;
  }
}

TEST(ObjLoader, UsemtlRunsBecomeMaterialGroups) {
  Result<Mesh> m = parse(std::string(kSquare) + "usemtl red\nf 1 2 3\nf 1 3 4\nusemtl blue\nf 1 2 4 3\n"
                                                "g other\nusemtl red\nf 2 3 4\n");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_TRUE(validate_mesh(*m).ok());
  ASSERT_EQ(m->triangle_count(), 5u);
  ASSERT_EQ(m->groups.size(), 3u);
  EXPECT_EQ(m->groups[0].material, "red");
  EXPECT_EQ(m->groups[0].first_triangle, 0u);
  EXPECT_EQ(m->groups[0].triangle_count, 2u);
  EXPECT_EQ(m->groups[1].material, "blue");
  EXPECT_EQ(m->groups[1].triangle_count, 2u);  // the quad
  EXPECT_EQ(m->groups[2].material, "red");
  EXPECT_EQ(m->groups[2].first_triangle, 4u);
  // One material for the whole file is still a group.
  Result<Mesh> one = parse(std::string(kSquare) + "usemtl red\nf 1 2 3\n");
  ASSERT_TRUE(one.ok());
  ASSERT_EQ(one->groups.size(), 1u);
}

TEST(ObjLoader, VertexColoursAndFourthCoordinate) {
  Result<Mesh> c = parse("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");
  ASSERT_TRUE(c.ok()) << c.status().message();
  ASSERT_EQ(c->colors.size(), 3u);
  EXPECT_EQ(c->colors[c->triangles[0][1]], Color3(0, 1, 0));
  Result<Mesh> w = parse("v 0 0 0 1\nv 1 0 0 2\nv 0 1 0 1\nf 1 2 3\n");  // x y z w: w ignored
  ASSERT_TRUE(w.ok()) << w.status().message();
  EXPECT_TRUE(w->colors.empty());
  EXPECT_EQ(w->positions[w->triangles[0][1]], Vec3(1, 0, 0));
}

TEST(MeshValidation, OptionalArraysAndGroups) {
  Mesh m = make_plane(1, 1, 1);
  ASSERT_TRUE(validate_mesh(m).ok());
  m.uvs.pop_back();
  EXPECT_EQ(validate_mesh(m).field(), "mesh.uvs");
  m.uvs.push_back(Vec2(std::nanf(""), 0));
  EXPECT_EQ(validate_mesh(m).field(), "mesh.uvs[3]");
  m.uvs.back() = Vec2(0, 0);
  m.colors.assign(m.vertex_count(), Color3(1, 1, 1));
  EXPECT_TRUE(validate_mesh(m).ok());
  m.colors[1] = Color3(1, 2, 1);
  EXPECT_EQ(validate_mesh(m).field(), "mesh.colors[1]");
  m.colors[1] = Color3(1, 1, 1);
  m.groups = {{"a", 0, 1}, {"b", 1, 1}};
  EXPECT_TRUE(validate_mesh(m).ok());
  m.groups = {{"a", 0, 1}, {"b", 2, 1}};
  EXPECT_EQ(validate_mesh(m).field(), "mesh.groups[1]");
  m.groups = {{"a", 0, 1}};
  EXPECT_EQ(validate_mesh(m).field(), "mesh.groups");
  m.groups = {{"a", 0, 0}, {"b", 0, 2}};
  EXPECT_EQ(validate_mesh(m).field(), "mesh.groups[0]");
}

TEST(ObjLoader, MissingFileAndDirectory) {
  const Result<Mesh> missing = load_obj("/nonexistent/facet/model.obj");
  EXPECT_EQ(missing.status().code(), ErrorCode::io_error);
  EXPECT_NE(missing.status().message().find("'/nonexistent/facet/model.obj'"), std::string::npos);
  const Result<Mesh> dir = load_obj(test::data_dir());
  EXPECT_EQ(dir.status().code(), ErrorCode::io_error);
  EXPECT_NE(dir.status().message().find("not a regular file"), std::string::npos);
}

struct ModelCase {
  const char* file;
  std::size_t triangles;  // after triangulation
  friend void PrintTo(const ModelCase& c, std::ostream* os) { *os << c.file; }
};

class RealModel : public ::testing::TestWithParam<ModelCase> {};

TEST_P(RealModel, LoadsWithUsableNormals) {
  FACET_REQUIRE_MODELS();
  const ModelCase& c = GetParam();
  Result<Mesh> m = load_obj(test::models_dir() + "/" + c.file);
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_TRUE(validate_mesh(*m).ok());
  EXPECT_EQ(m->triangle_count(), c.triangles);
  std::size_t zero = 0;
  for (const auto& n : m->normals) {
    ASSERT_TRUE(n.allFinite());
    if (n == Vec3::Zero()) ++zero;
    else ASSERT_NEAR(n.norm(), 1.0f, 1e-5f);
  }
  EXPECT_LT(zero, m->vertex_count() / 1000 + 1) << "almost every vertex must get a normal";
  // spot.obj is UV-mapped (`f v/vt`); the others have no texture coordinates.
  EXPECT_EQ(m->uvs.empty(), std::string(c.file) != "spot.obj");
  for (const Vec2& uv : m->uvs) ASSERT_TRUE(uv.allFinite());
}

// Triangle counts: the models README gives faces; suzanne's 500 faces include quads.
INSTANTIATE_TEST_SUITE_P(SharedModels, RealModel,
                         ::testing::Values(ModelCase{"stanford-bunny.obj", 69451},
                                           ModelCase{"teapot.obj", 6320},
                                           ModelCase{"suzanne.obj", 968},
                                           ModelCase{"spot.obj", 5856},
                                           ModelCase{"fandisk.obj", 12946}),
                         [](const auto& param_info) {
                           std::string name = param_info.param.file;
                           name = name.substr(0, name.find('.'));
                           std::erase(name, '-');
                           return name;
                         });

}  // namespace
}  // namespace facet
