// Content nobody here wrote: files a scene or model names stay in its folder (facet/assets.hpp),
// containers and images are checked before they are used, wrong JSON types are errors with their
// JSON path, and compressed or quantized glTF is read as it was meant.
#include <arpa/inet.h>
#include <unistd.h>
#include <zlib.h>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>

#include "facet/facet.hpp"
#include "gltf_builder.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

using test::GltfBuilder;
namespace fs = std::filesystem;

const std::vector<float>& kPositions = test::kQuadPositions;
const std::vector<std::uint16_t>& kIndices = test::kQuadIndices;
using test::quad;
constexpr const char* kSecret = "SECRET-BYTES-0123456789";

// A test folder with a model folder inside it and a file beside that folder which no model may read.
class Dir : public test::TempDir {
 public:
  Dir() : test::TempDir("facet_trust") {
    fs::create_directories(*this / "model");
    test::write_text(*this / "secret.bin", std::string(kSecret) + std::string(40, 'x'));
  }
};

Result<Model> parse(const std::string& text, const std::string& base = "", const ModelOptions& o = {}) {
  return parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "t.gltf",
                    base, o);
}

void expect_refused(const Result<Model>& m, const std::string& field) {
  ASSERT_FALSE(m.ok()) << "expected a refusal naming " << field;
  EXPECT_NE(m.status().message().find(field), std::string::npos) << m.status().message();
  EXPECT_EQ(m.status().message().find(kSecret), std::string::npos) << m.status().message();
  for (const char c : m.status().message()) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20) << m.status().message();
}

TEST(Trust, GltfUrisStayInTheModelsFolder) {
  Dir dir;
  const GltfBuilder b = quad();
  const std::string secret = dir / "secret.bin";
  fs::create_symlink(secret, dir / "model/link.bin");
  for (const std::string& uri : {std::string("../secret.bin"), secret, "file://" + secret, std::string("%2e%2e/secret.bin"),
                                 std::string("link.bin"), std::string("./sub/../../secret.bin")}) {
    nlohmann::json d = b.with_buffer(uri);
    d["buffers"][0]["byteLength"] = 20;
    test::write_text(dir / "model/m.gltf", d.dump());
    expect_refused(load_model(dir / "model/m.gltf"), "buffers[0].uri");
  }
  // An image uri likewise.
  nlohmann::json d = b.with_buffer("data:application/octet-stream;base64," + test::base64(b.bin));
  d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  d["textures"] = {{{"source", 0}}};
  d["images"] = {{{"uri", "../secret.bin"}}};
  d["meshes"][0]["primitives"][0]["material"] = 0;
  d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 0;
  test::write_text(dir / "model/m.gltf", d.dump());
  ModelOptions strict;
  strict.allow_missing = false;
  expect_refused(load_model(dir / "model/m.gltf", strict), "images[0].uri");
  // By default a refused image is skipped, as a missing one (nothing read): the load goes on to
  // the model's next fault (its TEXCOORD_0 is the VEC3 accessor), not the image.
  Result<Model> lenient = load_model(dir / "model/m.gltf");
  ASSERT_FALSE(lenient.ok());
  EXPECT_EQ(lenient.status().message().find("images[0]"), std::string::npos) << lenient.status().message();
  EXPECT_NE(lenient.status().message().find("TEXCOORD_0"), std::string::npos) << lenient.status().message();
  EXPECT_EQ(lenient.status().message().find(kSecret), std::string::npos) << lenient.status().message();
}

TEST(Trust, AHostWidensOrReplacesTheFileSystem) {
  Dir dir;
  const GltfBuilder b = quad();
  test::write_text(dir / "shared.bin", b.bin);
  test::write_text(dir / "model/m.gltf", b.external("../shared.bin"));
  EXPECT_FALSE(load_model(dir / "model/m.gltf").ok());
  ModelOptions o;
  o.assets.allowed_roots = {dir / ""};
  Result<Model> m = load_model(dir / "model/m.gltf", o);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->scene.meshes[0].mesh.triangle_count(), 2u);
  // A resolver: no file is opened; the names asked are the folder joined with the uri.
  std::vector<std::string> asked;
  ModelOptions r;
  r.assets.resolver = [&](const std::string& name) -> Result<std::string> {
    asked.push_back(name);
    if (name == "pack/m.gltf") return b.external("data/m.bin");
    if (name == "pack/data/m.bin") return b.bin;
    return Status{ErrorCode::io_error, "", "not in the archive"};
  };
  m = load_model("pack/m.gltf", r);
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(asked, (std::vector<std::string>{"pack/m.gltf", "pack/data/m.bin"}));
  // The same confinement holds for a resolver's names: ".." may not climb out of the model's folder.
  asked.clear();
  ModelOptions escaping;
  escaping.assets.resolver = [&](const std::string& name) -> Result<std::string> {
    asked.push_back(name);
    if (name == "pack/x.gltf") return b.external("../../etc/passwd");
    return Status{ErrorCode::io_error, "", "not in the archive"};
  };
  m = load_model("pack/x.gltf", escaping);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("leads out"), std::string::npos) << m.status().message();
  EXPECT_EQ(asked, (std::vector<std::string>{"pack/x.gltf"}));
}

TEST(Trust, ObjMtlAndSceneNamesStayInTheirFolder) {
  Dir dir;
  test::write_text(dir / "model/a.obj", "mtllib ../secret.bin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ModelOptions strict;
  strict.allow_missing = false;
  Result<Model> lenient = load_model(dir / "model/a.obj");  // a warning by default, nothing read
  ASSERT_TRUE(lenient.ok()) << lenient.status().message();
  ASSERT_FALSE(lenient->warnings.empty());
  EXPECT_NE(lenient->warnings[0].find("leads out"), std::string::npos) << lenient->warnings[0];
  EXPECT_EQ(lenient->warnings[0].find(kSecret), std::string::npos) << lenient->warnings[0];
  Result<Model> m = load_model(dir / "model/a.obj", strict);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.status().message().find(kSecret), std::string::npos) << m.status().message();
  EXPECT_NE(m.status().message().find("leads out"), std::string::npos) << m.status().message();
  // An MTL whose name escapes with control characters: quoted, never raw.
  test::write_text(dir / "model/b.obj", "mtllib \x1b[31mred\n v 0 0 0\n");
  m = load_model(dir / "model/b.obj", strict);
  ASSERT_FALSE(m.ok());
  for (const char c : m.status().message()) EXPECT_NE(c, '\x1b') << m.status().message();
  // A file that is not MTL at all is not quoted.
  test::write_text(dir / "model/c.mtl", std::string(kSecret) + ":x:0:0\n");
  test::write_text(dir / "model/c.obj", "mtllib c.mtl\nv 0 0 0\n");
  m = load_model(dir / "model/c.obj");
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.status().message().find(kSecret), std::string::npos) << m.status().message();
  // A scene's obj: no absolute path.
  test::write_text(dir / "model/s.json", "{\"meshes\": [{\"name\": \"m\", \"obj\": \"" + (dir / "secret.bin") + "\"}]}");
  Result<Scene> s = load_scene_file(dir / "model/s.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().message().find(kSecret), std::string::npos) << s.status().message();
  EXPECT_NE(s.status().message().find("meshes[0].obj"), std::string::npos) << s.status().message();
}

TEST(Trust, GlbContainersAreCheckedBeforeParsing) {
  const GltfBuilder b = quad();
  const std::string good = b.glb();
  ASSERT_TRUE(parse(good).ok());
  std::string longer = good;  // the BIN chunk claims 8 bytes more than the file holds
  const std::size_t bin_at = 20 + (std::size_t(std::uint8_t(good[12])) | std::size_t(std::uint8_t(good[13])) << 8);
  std::uint32_t len = 0;
  std::memcpy(&len, longer.data() + bin_at, 4);
  len += 8;
  std::memcpy(longer.data() + bin_at, &len, 4);
  EXPECT_FALSE(parse(longer).ok());
  for (const std::uint32_t version : {1u, 3u}) {
    std::string v = good;
    std::memcpy(v.data() + 4, &version, 4);
    Result<Model> m = parse(v);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.status().message().find("version " + std::to_string(version)), std::string::npos) << m.status().message();
  }
  // A whole (empty, unknown) chunk past the length the header states: only that length tells.
  std::string wrong_length = good + std::string("\0\0\0\0XTRA", 8);
  Result<Model> m = parse(wrong_length);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("header's length"), std::string::npos) << m.status().message();
}

TEST(Trust, DeeplyNestedJsonIsRefusedBeforeParsing) {
  const GltfBuilder b = quad();
  nlohmann::json d = b.with_buffer("data:application/octet-stream;base64," + test::base64(b.bin));
  std::string text = d.dump();
  text.insert(text.size() - 1, ", \"extras\": " + std::string(100, '[') + std::string(100, ']'));
  Result<Model> m = parse(text);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("nests deeper"), std::string::npos) << m.status().message();
  // Brackets inside strings do not count.
  text = d.dump();
  text.insert(text.size() - 1, ", \"extras\": \"" + std::string(100, '[') + "\\\"\"");
  EXPECT_TRUE(parse(text).ok()) << parse(text).status().message();
}

// Edits of a valid document that must be errors naming `path`.
TEST(Trust, WrongTypesAndRangesNameTheirJsonPath) {
  const std::vector<std::pair<std::function<void(nlohmann::json&)>, std::string>> cases = {
      {[](nlohmann::json& d) { d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1}}}}}}; d["meshes"][0]["primitives"][0]["material"] = 0; },
       "materials[0].pbrMetallicRoughness.baseColorFactor"},
      {[](nlohmann::json& d) { d["materials"] = {{{"alphaMode", "MASK"}, {"alphaCutoff", -1}}}; d["meshes"][0]["primitives"][0]["material"] = 0; },
       "materials[0].alphaCutoff"},
      {[](nlohmann::json& d) {
         d["materials"] = {{{"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", "2"}}}}}}};
         d["meshes"][0]["primitives"][0]["material"] = 0;
       },
       "emissiveStrength"},
      {[](nlohmann::json& d) { d["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; d["nodes"][0]["translation"] = {1, 2, 3}; },
       "nodes[0]"},
      {[](nlohmann::json& d) { d["nodes"][0]["mesh"] = "0"; }, "nodes[0].mesh"},
      {[](nlohmann::json& d) { d["accessors"][0]["normalized"] = true; d["accessors"][0]["componentType"] = 5125; }, "accessors[0]"},
      {[](nlohmann::json& d) { d["accessors"][0]["count"] = 100000000; }, "accessors[0]"},
      {[](nlohmann::json& d) { d.erase("asset"); }, "asset"},
      {[](nlohmann::json& d) {
         d["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 1.0}, {"zfar", 0.5}}}}};
         d["nodes"][0]["camera"] = 0;
       },
       "cameras[0].perspective.zfar"},
      {[](nlohmann::json& d) {
         d["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 1.0}, {"aspectRatio", 0}}}}};
         d["nodes"][0]["camera"] = 0;
       },
       "cameras[0].perspective.aspectRatio"},
      {[](nlohmann::json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"color", {1, 1}}}};
         d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       "lights[0].color"},
      {[](nlohmann::json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"range", 0}}};
         d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       "lights[0].range"},
      {[](nlohmann::json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "spot"}}};
         d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
       },
       "lights[0].spot"},
  };
  for (const auto& [edit, path] : cases) {
    const GltfBuilder b = quad();
    nlohmann::json d = b.with_buffer("data:application/octet-stream;base64," + test::base64(b.bin));
    edit(d);
    Result<Model> m = parse(d.dump());
    ASSERT_FALSE(m.ok()) << path;
    EXPECT_NE(m.status().message().find(path), std::string::npos) << m.status().message();
    EXPECT_NE(m.status().code(), ErrorCode::out_of_memory) << m.status().message();  // checked before any allocation
  }
}

TEST(Trust, NodeTransformsComposeTranslationRotationScale) {
  GltfBuilder b = quad();
  // A quarter turn about z after a non-uniform scale: (1, 0, 0) -> (2, 0, 0) -> (0, 2, 0).
  const double h = std::sqrt(0.5);
  b.doc["nodes"][0]["rotation"] = {0, 0, h, h};
  b.doc["nodes"][0]["scale"] = {2, 1, 1};
  b.doc["nodes"][0]["translation"] = {0, 0, 5};
  Result<Model> m = parse(b.embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  const Instance& inst = m->scene.objects[0];
  const Vec3 p = (inst.model * Vec3(1, 0, 0).homogeneous()).head<3>();
  EXPECT_LT((p - Vec3(0, 2, 5)).norm(), 1e-5f) << p.transpose();
}

TEST(Trust, BudgetsAreReportedAsGiven) {
  // A budget of one byte is "1 bytes", not rounded up to "1 MiB".
  RenderOptions o;
  o.memory_budget_bytes = 1;
  const Status s = check_render(Scene{}, o, 64, 64);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("budget of 1 bytes"), std::string::npos) << s.message();
}

// Texture memory counts against a scene file's and a model's budget: four 256x256 textures
// (349,524 bytes of texels each, with their mipmaps, and 873,812 to decode and keep) where a
// budget of 1 MiB holds one: the second is refused.
TEST(Trust, TexturesCountAgainstTheLoadBudget) {
  Dir dir;
  std::vector<std::uint8_t> px(256 * 256 * 4, 200);
  ASSERT_TRUE(write_png(dir / "model/t.png", {px.data(), 256, 256, 256 * 4, PixelFormat::rgba8, false}).ok());
  std::string textures, mtl;
  for (int i = 0; i < 4; ++i) {
    textures += std::string(i ? "," : "") + "{\"name\": \"t" + std::to_string(i) + "\", \"file\": \"t.png\"}";
    mtl += "newmtl m" + std::to_string(i) + "\nmap_Kd t.png\n";
  }
  test::write_text(dir / "model/s.json", "{\"textures\": [" + textures + "]}");
  test::write_text(dir / "model/m.mtl", mtl);
  test::write_text(dir / "model/m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl m0\nf 1/1 2/1 3/1\n");
  for (const std::uint64_t budget : {std::uint64_t{1} << 20, std::uint64_t{0}}) {
    LoadOptions lo;
    lo.memory_budget_bytes = budget;
    Result<Scene> s = load_scene_file(dir / "model/s.json", lo);
    ModelOptions mo;
    mo.memory_budget_bytes = budget;
    Result<Model> m = load_model(dir / "model/m.obj", mo);
    if (budget == 0) {  // no limit: all four
      ASSERT_TRUE(s.ok()) << s.status().message();
      EXPECT_EQ(s->textures.size(), 4u);
      ASSERT_TRUE(m.ok()) << m.status().message();
      EXPECT_EQ(m->scene.textures.size(), 4u);
      continue;
    }
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.status().code(), ErrorCode::out_of_memory);
    EXPECT_NE(s.status().message().find("textures[1]"), std::string::npos) << s.status().message();
    EXPECT_NE(s.status().message().find("1 MiB"), std::string::npos) << s.status().message();
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.status().code(), ErrorCode::out_of_memory);
    EXPECT_NE(m.status().message().find("m.mtl:4"), std::string::npos) << m.status().message();
    EXPECT_NE(m.status().message().find("textures before it"), std::string::npos) << m.status().message();
  }
}

// A camera without zfar is an infinite projection (glTF's meaning), drawn with reversed depth.
TEST(Trust, ACameraWithoutZfarIsAnInfiniteProjection) {
  GltfBuilder b = quad();
  b.add("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}});
  b.add("nodes", {{"camera", 0}, {"translation", {0.5, 0.5, 3.0}}});
  b.doc["scenes"][0]["nodes"].push_back(1);
  Result<Model> m = parse(b.embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_TRUE(m->has_camera);
  EXPECT_TRUE(std::isinf(m->scene.camera.far));
  for (const std::string& w : m->warnings) EXPECT_EQ(w.find("zfar"), std::string::npos) << w;
  Scene scene = m->scene;
  add_default_lights(scene);
  std::vector<std::uint8_t> px(32 * 32 * 4);
  std::vector<float> depth(32 * 32);
  DepthView dv{depth.data(), 32, 32, 32 * sizeof(float), false};
  FrameStats stats;
  ASSERT_TRUE(Renderer().render(scene, {px.data(), 32, 32, 128, PixelFormat::rgba8, false}, &dv, &stats).ok());
  EXPECT_GT(stats.pixels_filled, 100u);  // the unit quad, 3 units away
  EXPECT_NEAR(depth[16 * 32 + 16], 0.01f / 3.0f, 1e-6f);  // reversed: near / w
}

TEST(Trust, LinePrimitivesAreSkippedWithAWarning) {
  GltfBuilder b = quad();
  b.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 1}});
  Result<Model> m = parse(b.embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->scene.objects.size(), 1u);
  bool warned = false;
  for (const auto& w : m->warnings) warned |= w.find("meshes[0].primitives[1]") != std::string::npos && w.find("lines") != std::string::npos;
  EXPECT_TRUE(warned);
  Scene scene = m->scene;
  scene.camera = *frame_scene(scene, 1.0f);
  add_default_lights(scene);
  std::vector<std::uint8_t> px(32 * 32 * 4);
  FrameStats stats;
  ASSERT_TRUE(Renderer().render(scene, {px.data(), 32, 32, 128, PixelFormat::rgba8, false}, nullptr, &stats).ok());
  EXPECT_GT(stats.pixels_filled, 0u);
}

// The positions a model's first mesh holds, in world space.
std::vector<Vec3> world_positions(const Model& m) {
  std::vector<Vec3> out;
  const Instance& inst = m.scene.objects.at(0);
  for (const Vec3& p : m.scene.meshes.at(inst.mesh).mesh.positions) out.push_back((inst.model * p.homogeneous()).head<3>());
  return out;
}

// The model drawn from a fixed camera with the default rig, 48 x 48.
std::vector<std::uint8_t> rendered(const Model& m, const Camera& camera) {
  Scene s = m.scene;
  s.camera = camera;
  add_default_lights(s);
  std::vector<std::uint8_t> px(48 * 48 * 4);
  FrameStats stats;
  EXPECT_TRUE(Renderer().render(s, {px.data(), 48, 48, 48 * 4, PixelFormat::rgba8, false}, nullptr, &stats).ok());
  EXPECT_GT(stats.pixels_filled, 48u * 48u / 4);
  return px;
}

// How many pixels of two images differ.
int pixels_differing(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  int n = 0;
  for (std::size_t i = 0; i < a.size(); i += 4) n += std::memcmp(&a[i], &b[i], 4) != 0;
  return n;
}

TEST(Trust, QuantizedMeshoptAndDracoGltfMatchTheirPlainTwin) {
  const GltfBuilder plain = quad();
  Result<Model> reference = parse(plain.embedded());
  ASSERT_TRUE(reference.ok());
  const std::vector<Vec3> want = world_positions(*reference);
  // Each is also drawn, from the camera that frames the plain quad, and compared with it.
  const Camera camera = *frame_scene(reference->scene, 1.0f);
  const std::vector<std::uint8_t> want_px = rendered(*reference, camera);
  // KHR_mesh_quantization: normalized shorts, undone by the node's scale.
  {
    GltfBuilder b;
    std::vector<std::int16_t> q;
    for (float v : kPositions) q.push_back(std::int16_t(v * 32767.0f));
    q.resize(16);
    std::vector<std::int16_t> padded;  // VEC3 of shorts, stride 8
    for (int i = 0; i < 4; ++i) padded.insert(padded.end(), {q[3 * i], q[3 * i + 1], q[3 * i + 2], 0});
    const int pos = b.accessor(b.view(padded.data(), padded.size() * 2, 8), 5122, 4, "VEC3", true);
    b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", b.indices16(kIndices)}}}}});
    b.add("nodes", {{"mesh", 0}});
    b.add("scenes", {{"nodes", {0}}});
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    Result<Model> m = parse(b.embedded());
    ASSERT_TRUE(m.ok()) << m.status().message();
    const std::vector<Vec3> got = world_positions(*m);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_LT((got[i] - want[i]).norm(), 1e-4f);
    EXPECT_LE(pixels_differing(rendered(*m, camera), want_px), 48) << "quantized";  // edges moved by < 1e-4
  }
  // EXT_meshopt_compression: the vertex and index views encoded by meshoptimizer.
  {
    GltfBuilder b;
    std::vector<unsigned char> vbuf(meshopt_encodeVertexBufferBound(4, 12)), ibuf(meshopt_encodeIndexBufferBound(6, 4));
    vbuf.resize(meshopt_encodeVertexBuffer(vbuf.data(), vbuf.size(), kPositions.data(), 4, 12));
    const std::vector<unsigned> idx32(kIndices.begin(), kIndices.end());
    ibuf.resize(meshopt_encodeIndexBuffer(ibuf.data(), ibuf.size(), idx32.data(), 6));
    b.bin.append(reinterpret_cast<const char*>(vbuf.data()), vbuf.size());
    while (b.bin.size() % 4) b.bin.push_back('\0');
    const std::size_t iat = b.bin.size();
    b.bin.append(reinterpret_cast<const char*>(ibuf.data()), ibuf.size());
    nlohmann::json d = b.with_buffer("data:application/octet-stream;base64," + test::base64(b.bin));
    d["buffers"].push_back({{"byteLength", 72}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    d["bufferViews"] = {
        {{"buffer", 1}, {"byteLength", 48}, {"byteStride", 12},
         {"extensions", {{"EXT_meshopt_compression", {{"buffer", 0}, {"byteLength", vbuf.size()}, {"byteStride", 12}, {"count", 4}, {"mode", "ATTRIBUTES"}}}}}},
        {{"buffer", 1}, {"byteOffset", 48}, {"byteLength", 24},
         {"extensions", {{"EXT_meshopt_compression", {{"buffer", 0}, {"byteOffset", iat}, {"byteLength", ibuf.size()}, {"byteStride", 4}, {"count", 6}, {"mode", "TRIANGLES"}}}}}}};
    d["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                      {{"bufferView", 1}, {"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}};
    d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}};
    d["nodes"] = {{{"mesh", 0}}};
    d["scenes"] = {{{"nodes", {0}}}};
    d["extensionsUsed"] = d["extensionsRequired"] = {"EXT_meshopt_compression"};
    Result<Model> m = parse(d.dump());
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_EQ(world_positions(*m), want);
    EXPECT_EQ(pixels_differing(rendered(*m, camera), want_px), 0) << "meshopt";
    EXPECT_EQ(m->scene.meshes[0].mesh.triangles, reference->scene.meshes[0].mesh.triangles);
    // A corrupt stream is an error naming the view.
    std::string text = d.dump();
    d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 3;
    Result<Model> bad = parse(d.dump());
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.status().message().find("bufferViews[0]"), std::string::npos) << bad.status().message();
  }
  // KHR_draco_mesh_compression: the quad encoded by libdraco without quantization.
  {
    draco::TriangleSoupMeshBuilder builder;
    builder.Start(2);
    const int att = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    for (int t = 0; t < 2; ++t) {
      const float* p[3];
      for (int c = 0; c < 3; ++c) p[c] = &kPositions[3 * kIndices[std::size_t(3 * t + c)]];
      builder.SetAttributeValuesForFace(att, draco::FaceIndex(t), p[0], p[1], p[2]);
    }
    std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
    ASSERT_TRUE(mesh);
    draco::Encoder encoder;
    draco::EncoderBuffer out;
    ASSERT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &out).ok());
    GltfBuilder b;
    const int view = b.view(out.data(), out.size());
    nlohmann::json d = b.with_buffer("data:application/octet-stream;base64," + test::base64(b.bin));
    d["accessors"] = {{{"componentType", 5126}, {"count", 4}, {"type", "VEC3"}}, {{"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}};
    d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1},
                                     {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", mesh->attribute(att)->unique_id()}}}}}}}}}}}};
    d["nodes"] = {{{"mesh", 0}}};
    d["scenes"] = {{{"nodes", {0}}}};
    d["extensionsUsed"] = d["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    Result<Model> m = parse(d.dump());
    ASSERT_TRUE(m.ok()) << m.status().message();
    const Mesh& got = m->scene.meshes[0].mesh;
    ASSERT_EQ(got.triangle_count(), 2u);
    // Draco may renumber the vertices: compare each triangle's corners.
    for (std::size_t t = 0; t < 2; ++t)
      for (int c = 0; c < 3; ++c) {
        const Vec3 p = got.positions[got.triangles[t][std::size_t(c)]];
        bool found = false;
        for (const Vec3& w : want) found |= (p - w).norm() < 1e-6f;
        EXPECT_TRUE(found);
      }
    EXPECT_EQ(pixels_differing(rendered(*m, camera), want_px), 0) << "draco";
  }
}

TEST(Trust, TextureTransformMovesTheUvs) {
  GltfBuilder b;
  const int pos = b.vec3(kPositions), uv = b.vec2({0, 0, 1, 0, 1, 1, 0, 1});
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"indices", b.indices16(kIndices)}, {"material", 0}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  const std::vector<std::uint8_t> px = {255, 0, 0, 255};
  b.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0.25}}, {"scale", {2, 3}}}}}}}}}}});
  b.add("textures", {{"source", 0}});
  std::vector<std::uint8_t> png_px = {255, 0, 0, 255};
  std::string png;
  {
    const std::string path = (fs::temp_directory_path() / ("facet_trust_tt_" + std::to_string(::getpid()) + ".png")).string();
    ASSERT_TRUE(write_png(path, {png_px.data(), 1, 1, 4, PixelFormat::rgba8, false}).ok());
    png = test::read_bytes(path);
    fs::remove(path);
  }
  b.add("images", {{"uri", "data:image/png;base64," + test::base64(png)}});
  Result<Model> m = parse(b.embedded());
  ASSERT_TRUE(m.ok()) << m.status().message();
  const Mesh& mesh = m->scene.meshes[0].mesh;
  // glTF (1, 1) -> (2 + 0.5, 3 + 0.25) = (2.5, 3.25); facet flips v: 1 - 3.25.
  EXPECT_FLOAT_EQ(mesh.uvs[2].x(), 2.5f);
  EXPECT_FLOAT_EQ(mesh.uvs[2].y(), 1.0f - 3.25f);
}

// A PNG assembled chunk by chunk, with correct CRCs unless a test breaks one.
std::string chunk(const char* type, const std::string& data) {
  std::string out;
  const std::uint32_t n = htonl(std::uint32_t(data.size()));
  out.append(reinterpret_cast<const char*>(&n), 4);
  const std::string body = std::string(type, 4) + data;
  out += body;
  const std::uint32_t crc = htonl(std::uint32_t(::crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
  out.append(reinterpret_cast<const char*>(&crc), 4);
  return out;
}
std::string palette_png(std::uint8_t index) {
  std::string ihdr(13, '\0');
  const std::uint32_t w = htonl(2), h = htonl(1);
  std::memcpy(ihdr.data(), &w, 4);
  std::memcpy(ihdr.data() + 4, &h, 4);
  ihdr[8] = 8;  // bit depth
  ihdr[9] = 3;  // palette
  const std::string raw = std::string("\0\0", 2) + std::string(1, char(index));
  std::string z(64, '\0');
  uLongf zn = z.size();
  ::compress(reinterpret_cast<Bytef*>(z.data()), &zn, reinterpret_cast<const Bytef*>(raw.data()), raw.size());
  z.resize(zn);
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("PLTE", std::string("\xff\x00\x00", 3)) +
         chunk("IDAT", z) + chunk("IEND", "");
}

Result<Texture> decode(const std::string& bytes) {
  return decode_texture({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()}, "t.png", "t");
}

TEST(Trust, CorruptPngsAreErrors) {
  ASSERT_TRUE(decode(palette_png(0)).ok()) << decode(palette_png(0)).status().message();
  // An index past the palette: stb_image read an uninitialised palette here.
  Result<Texture> past = decode(palette_png(5));
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.status().message().find("palette entry 5"), std::string::npos) << past.status().message();
  // A broken CRC in IHDR and in IDAT; a broken Adler-32 at the end of the zlib stream.
  const std::string good = palette_png(0);
  const std::size_t ihdr_crc = 8 + 8 + 13, idat = good.find("IDAT");
  for (const std::size_t at : {ihdr_crc, idat + 4 + 2}) {
    std::string bad = good;
    bad[at] = char(bad[at] ^ 0x40);
    EXPECT_FALSE(decode(bad).ok()) << at;
  }
  std::uint32_t idat_len = 0;
  std::memcpy(&idat_len, good.data() + idat - 4, 4);
  idat_len = ntohl(idat_len);
  std::string raw = good.substr(idat + 4, idat_len);
  raw[raw.size() - 1] = char(raw[raw.size() - 1] ^ 1);  // Adler-32, with the chunk's CRC made right again
  const std::string adler = good.substr(0, idat - 4) + chunk("IDAT", raw) + chunk("IEND", "");
  EXPECT_FALSE(decode(adler).ok());
  // A header claiming 100000 x 100000: refused by size, before any allocation.
  std::string huge_hdr(13, '\0');
  const std::uint32_t big = htonl(100000);
  std::memcpy(huge_hdr.data(), &big, 4);
  std::memcpy(huge_hdr.data() + 4, &big, 4);
  huge_hdr[8] = 8, huge_hdr[9] = 6;
  Result<Texture> huge = decode(std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", huge_hdr) + chunk("IEND", ""));
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.status().message().find("100000 x 100000"), std::string::npos) << huge.status().message();
}

TEST(Trust, TgaAndBmpDecode) {
  // An uncompressed 24-bit TGA, 2 x 1, bottom-up: blue, green (BGR order).
  std::string tga(18, '\0');
  tga[2] = 2;
  tga[12] = 2, tga[14] = 1, tga[16] = 24;
  tga += std::string("\xff\x00\x00\x00\xff\x00", 6);
  Result<Texture> t = decode(tga);
  ASSERT_TRUE(t.ok()) << t.status().message();
  EXPECT_EQ(t->texels[0] & 0xffffffu, 0xff0000u);  // blue in RGBA words
  auto refused = [](const std::string& bytes, const std::string& why) {
    Result<Texture> r = decode(bytes);
    ASSERT_FALSE(r.ok()) << why;
    EXPECT_NE(r.status().message().find(why), std::string::npos) << r.status().message();
  };
  // Cut short: stb left the missing rows as the heap held them (found by fuzz_texture).
  refused(tga.substr(0, tga.size() - 1), "the TGA's pixels are cut short");
  // RLE: one run of two green pixels; cut short before the run's pixel.
  std::string rle(18, '\0');
  rle[2] = 10, rle[12] = 2, rle[14] = 1, rle[16] = 24;
  ASSERT_TRUE(decode(rle + std::string("\x81\x00\xff\x00", 4)).ok());
  EXPECT_EQ(decode(rle + std::string("\x81\x00\xff\x00", 4))->texels[1] & 0xffffffu, 0x00ff00u);
  refused(rle + std::string("\x81\x00", 2), "the TGA's pixels are cut short");
  refused(rle + std::string("\x00\x00\xff\x00", 4), "the TGA's pixels are cut short");  // one pixel of two
  // A colour-mapped TGA: two 24-bit entries, 8-bit indices; an index past the map is refused
  // (stb took it as entry 0), as is a first entry index stb would read as bytes to skip.
  auto mapped = [](std::uint8_t index, std::uint8_t first) {
    std::string m(18, '\0');
    m[1] = 1, m[2] = 1, m[3] = char(first), m[5] = 2, m[7] = 24, m[12] = 1, m[14] = 1, m[16] = 8;
    return m + std::string("\xff\x00\x00\x00\xff\x00", 6) + char(index);
  };
  Result<Texture> entry1 = decode(mapped(1, 0));
  ASSERT_TRUE(entry1.ok()) << entry1.status().message();
  EXPECT_EQ(entry1->texels[0] & 0xffffffu, 0x00ff00u);
  refused(mapped(2, 0), "colour-map entry 2 of 2");
  refused(mapped(0, 1), "first entry index");
  // Found by fuzz_texture (tests/data/fuzz/texture/): a JPEG with junk between its markers whose
  // components use quantization tables it never defines (stb_image skipped the junk and decoded it
  // with tables it never set: different texels each run; libjpeg refuses both), and a palette BMP whose pixel offset lies inside its header (stb read a palette of
  // "-14" colours: none, then used the table it never filled).
  refused(test::read_bytes(test::data_dir() + "/fuzz/texture/jpeg_without_quantization_tables.jpg"), "Corrupt JPEG data");
  refused(test::read_bytes(test::data_dir() + "/fuzz/texture/bmp_pixels_inside_the_header.bmp"), "inside its header");
  // A JPEG cut short: libjpeg would decode the rest as grey; refused.
  const std::string jpeg = test::read_bytes(std::string(FACET_SOURCE_DIR) + "/tools/fuzz/corpus/texture/seed.jpg");
  ASSERT_TRUE(decode(jpeg).ok()) << decode(jpeg).status().message();
  refused(jpeg.substr(0, jpeg.size() - 40), "cannot decode the JPEG");
  // An 8-bit palette BMP, 1 x 1, its index past its two colours: refused.
  auto bmp = [](std::uint8_t index) {
    std::string b(54 + 8 + 4, '\0');
    auto put = [&](std::size_t at, std::uint32_t v) { std::memcpy(b.data() + at, &v, 4); };
    b[0] = 'B', b[1] = 'M';
    put(2, std::uint32_t(b.size()));
    put(10, 54 + 8);
    put(14, 40);
    put(18, 1);
    put(22, 1);
    b[26] = 1, b[28] = 8;
    b[54] = char(0xff), b[58] = 0;  // two colours: blue, black
    b[62] = char(index);
    return b;
  };
  ASSERT_TRUE(decode(bmp(1)).ok()) << decode(bmp(1)).status().message();
  Result<Texture> past = decode(bmp(9));
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.status().message().find("palette entry 9"), std::string::npos) << past.status().message();
}

}  // namespace
}  // namespace facet
