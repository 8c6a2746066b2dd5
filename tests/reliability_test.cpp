// Regression tests for what a trusted library must never do: misread input in silence (OBJ
// polygons, numbers and normals), block on or half-write a file, hide out-of-memory behind
// another error, run past its budget or past a cancel, disagree with `facet check` about a limit,
// or echo untrusted text raw into a message.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "render_support.hpp"
#include "test_support.hpp"

namespace facet {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the test's working directory, removed at the end.
struct ScratchDir {
  fs::path path;
  ScratchDir() {
    path = fs::temp_directory_path() / ("facet_rel_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  static int& counter() {
    static int n = 0;
    return n;
  }
  std::string file(const std::string& name, const std::string& text = {}) const {
    const std::string p = (path / name).string();
    if (!text.empty()) std::ofstream(p, std::ios::binary) << text;
    return p;
  }
};

// ---- 2. OBJ: polygons of any size, numbers, normals ------------------------------------------

// A convex polygon of `corners` corners, then a triangle after it: the fan from corner 1 and the
// triangle must both come out exactly (tinyobjloader's unsigned char corner count once corrupted
// every face after a polygon of 256 or more corners).
std::string polygon_obj(int corners) {
  std::string obj;
  for (int i = 0; i < corners; ++i) {
    const double a = 2 * 3.14159265358979 * i / corners;
    obj += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0\n";
  }
  obj += "v 5 5 0\nv 6 5 0\nv 5 6 0\nf";
  for (int i = 1; i <= corners; ++i) obj += " " + std::to_string(i);
  obj += "\nf " + std::to_string(corners + 1) + " " + std::to_string(corners + 2) + " " + std::to_string(corners + 3) + "\n";
  return obj;
}

TEST(ObjPolygons, FacesOfAnyCornerCountAreFannedExactly) {
  for (int corners : {3, 254, 255, 256, 257, 300, 509, 1000}) {
    const Result<Mesh> m = parse_obj(polygon_obj(corners), "poly.obj");
    ASSERT_TRUE(m.ok()) << corners << ": " << m.status().message();
    ASSERT_EQ(m->triangle_count(), static_cast<std::size_t>(corners - 2 + 1)) << corners;
    // Vertices keep file order (all are used), so fan triangle k is (0, k+1, k+2).
    for (int k = 0; k < corners - 2; ++k) {
      const auto& t = m->triangles[static_cast<std::size_t>(k)];
      ASSERT_EQ(t[0], 0u) << corners << " corners, triangle " << k;
      ASSERT_EQ(t[1], static_cast<std::uint32_t>(k + 1)) << corners << " corners, triangle " << k;
      ASSERT_EQ(t[2], static_cast<std::uint32_t>(k + 2)) << corners << " corners, triangle " << k;
    }
    const auto& last = m->triangles.back();
    const auto c = static_cast<std::uint32_t>(corners);
    EXPECT_EQ(last, (std::array<std::uint32_t, 3>{c, c + 1, c + 2})) << corners;
    EXPECT_EQ(m->positions[c], Vec3(5, 5, 0)) << corners;
  }
}

TEST(ObjNumbers, NonFiniteAndUnrepresentableNumbersAreErrorsNamingTheLine) {
  const std::string huge_mantissa = "1" + std::string(400, '0') + "e-400";
  struct Case {
    std::string token, why;
  };
  for (const Case& c : {Case{"nan", "not finite"}, Case{"NaN", "not finite"}, Case{"inf", "not finite"},
                        Case{"-inf", "not finite"}, Case{"infinity", "not finite"}, Case{"1e39", "range of a float"},
                        Case{"-3.5e38", "range of a float"}, Case{"1e-50", "range of a float"},
                        Case{"0x1p3", "not a number"}, Case{"1.5.2", "not a number"}}) {
    const std::string obj = "v 0 0 0\nv 1 0 0\n# a comment\nv 0 " + c.token + " 0\nf 1 2 3\n";
    const Result<Mesh> m = parse_obj(obj, "numbers.obj");
    ASSERT_FALSE(m.ok()) << c.token << " was read";
    EXPECT_EQ(m.status().code(), ErrorCode::parse_error);
    EXPECT_NE(m.status().message().find("numbers.obj:4:"), std::string::npos) << m.status().message();
    EXPECT_NE(m.status().message().find(c.why), std::string::npos) << m.status().message();
  }
  // Long mantissas are read correctly rounded (tinyobjloader read this one as 0 or inf).
  const Result<Mesh> m = parse_obj("v 0 0 0\nv " + huge_mantissa + " 0 0\nv 0 0.1e1 0\nf 1 2 3\n", "long.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->positions[1].x(), 1.0f);
  EXPECT_EQ(m->positions[2].y(), 1.0f);
  // Subnormal floats are representable, so they are read.
  const Result<Mesh> sub = parse_obj("v 0 0 0\nv 1e-40 0 0\nv 0 1 0\nf 1 2 3\n", "sub.obj");
  ASSERT_TRUE(sub.ok()) << sub.status().message();
  EXPECT_EQ(sub->positions[1].x(), 1e-40f);
}

TEST(ObjNumbers, FileNumbersAreFacetsNotTinyobjloaders) {
  // 0.1 has no exact float; the correctly rounded float of each token must come through.
  const Result<Mesh> m =
      parse_obj("v 0.1 0.2 0.3\nv 16777217 -0.0000001 3.4028234e38\nv 1.17549435e-38 2 3\nf 1 2 3\n", "r.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_EQ(m->positions[0], Vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(m->positions[1], Vec3(16777216.0f, -0.0000001f, 3.4028234e38f));
  EXPECT_EQ(m->positions[2], Vec3(1.17549435e-38f, 2.0f, 3.0f));
}

TEST(ObjNormals, HugeAndTinyNormalsAreNormalisedWithoutOverflow) {
  const Result<Mesh> m = parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1e30\nvn 3e38 3e38 0\nvn 1e-30 0 0\nf 1//1 2//2 3//3\n", "n.obj");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_NEAR((m->normals[0] - Vec3(0, 0, 1)).norm(), 0.0f, 1e-7f);
  EXPECT_NEAR((m->normals[1] - Vec3(1, 1, 0).normalized()).norm(), 0.0f, 1e-7f);
  EXPECT_NEAR((m->normals[2] - Vec3(1, 0, 0)).norm(), 0.0f, 1e-7f);
}

TEST(ObjMessages, EveryErrorNamesTheFileAndTheRealLine) {
  // Blank lines and comments before the error: the line is the file's, not the checked text's.
  const Result<Mesh> m = parse_obj("# header\n\nv 0 0 0\n\n# more\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "lines.obj");
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("lines.obj:8:"), std::string::npos) << m.status().message();
}

// ---- 4. Files: regular files only, whole reads, atomic writes --------------------------------

TEST(FileAccess, FifoIsRefusedWithoutBlocking) {
  ScratchDir dir;
  const std::string fifo = (dir.path / "pipe.json").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const Result<Scene> scene = load_scene_file(fifo);
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.status().code(), ErrorCode::io_error);
  EXPECT_NE(scene.status().message().find("not a regular file"), std::string::npos) << scene.status().message();
  const Result<Mesh> mesh = load_obj(fifo);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find("not a regular file"), std::string::npos);
  const Result<Rgba8Image> png = read_png(fifo);
  ASSERT_FALSE(png.ok());
  EXPECT_NE(png.status().message().find("not a regular file"), std::string::npos);
  const Result<Scene> dir_scene = load_scene_file(dir.path.string());
  EXPECT_NE(dir_scene.status().message().find("not a regular file"), std::string::npos);
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(FileAccess, WriteIntoMissingDirectoryFailsAndCreatesNothing) {
  ScratchDir dir;
  std::vector<std::uint8_t> px(4 * 4 * 4, 200);
  const ImageView img{px.data(), 4, 4, 16, PixelFormat::rgba8, false};
  const std::string target = (dir.path / "missing" / "out.png").string();
  const Status s = write_png(target, img);
  EXPECT_EQ(s.code(), ErrorCode::io_error);
  EXPECT_FALSE(fs::exists(dir.path / "missing"));
}

// A write that fails part-way (here: the file-size limit of `ulimit -f`, in a child process so
// the limit does not reach the test runner) keeps the old file byte for byte and leaves no
// temporary file behind.
TEST(FileAccess, FailedWriteKeepsTheOldFile) {
  for (const char* name : {"old.png", "old.pfm"}) {
    ScratchDir dir;
    const std::string target = dir.file(name, std::string("the old output, intact"));
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      std::signal(SIGXFSZ, SIG_IGN);
      const rlimit limit{4096, 4096};
      ::setrlimit(RLIMIT_FSIZE, &limit);
      // Pseudo-random bytes: the PNG cannot compress them below the 4 KiB limit (about 256 KiB).
      std::vector<float> px(256 * 256 * 4);
      std::uint32_t state = 12345;
      for (float& v : px) {
        state = state * 1664525u + 1013904223u;
        v = static_cast<float>(state >> 24) / 255.0f;
      }
      const ImageView img{px.data(), 256, 256, 256 * 16, PixelFormat::rgba32f, false};
      const Status s = std::string(name).ends_with(".png") ? write_png(target, img) : write_pfm(target, img);
      ::_exit(!s.ok() && s.code() == ErrorCode::io_error ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status)) << name;
    EXPECT_EQ(WEXITSTATUS(status), 0) << name << ": the write did not fail with an i/o error";
    EXPECT_EQ(read_all(target), "the old output, intact") << name;
    std::size_t files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path)) ++files;
    EXPECT_EQ(files, 1u) << name << ": a temporary file was left behind";
  }
}

// ---- 4. Budgets, limits, cancellation, out-of-memory codes -----------------------------------

// A scene file of four spheres of `segments` x `segments`, one per line after the first.
std::string spheres_json(int segments) {
  std::string json = "{\"meshes\": [\n";
  for (int i = 0; i < 4; ++i) {
    json += std::string(i ? ",\n" : "") + "{\"name\": \"s" + std::to_string(i) +
            "\", \"shape\": \"sphere\", \"segments\": " + std::to_string(segments) +
            ", \"rings\": " + std::to_string(segments) + "}";
  }
  return json + "]}";
}

TEST(MemoryBudget, SceneFileThatWouldTakeGigabytesIsRefusedBeforeAllocating) {
  // 4096 x 4096 spheres: 805 MB each (16.8 M vertices, 33.5 M triangles), refused at the first
  // (the check runs before a mesh is generated: scene_file.cpp, reserve_mesh).
  const std::string json = spheres_json(4096);
  LoadOptions small;
  small.memory_budget_bytes = std::uint64_t{512} << 20;
  const Result<Scene> s = parse_scene_json(json, "big.json", "", small);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), ErrorCode::out_of_memory);
  EXPECT_NE(s.status().message().find("big.json:2: meshes[0]"), std::string::npos) << s.status().message();
  EXPECT_NE(s.status().message().find("memory budget of 512 MiB"), std::string::npos) << s.status().message();
}

TEST(MemoryBudget, BudgetCountsEveryMeshOfTheScene) {
  // 512 x 512 spheres: 263,169 vertices and 524,288 triangles, 12.3 MiB each: the third crosses 30 MiB.
  const std::string json = spheres_json(512);
  LoadOptions o;
  o.memory_budget_bytes = std::uint64_t{30} << 20;
  const Result<Scene> s = parse_scene_json(json, "three.json", "", o);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), ErrorCode::out_of_memory);
  EXPECT_NE(s.status().message().find("three.json:4: meshes[2]"), std::string::npos) << s.status().message();
  o.memory_budget_bytes = std::uint64_t{50} << 20;
  EXPECT_TRUE(parse_scene_json(json, "three.json", "", o).ok());
}

TEST(MemoryBudget, FileLargerThanTheBudgetIsNotRead) {
  ScratchDir dir;
  const std::string path = dir.file("big.obj", std::string(1 << 20, '#'));
  ObjOptions o;
  o.memory_budget_bytes = 1000;
  const Result<Mesh> m = load_obj(path, o);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.status().code(), ErrorCode::out_of_memory);
  EXPECT_NE(m.status().message().find("over the limit of 1000 bytes"), std::string::npos) << m.status().message();
}

TEST(MemoryBudget, FrameOverItsBudgetIsRefusedBeforeAnyPixel) {
  Scene scene = test::camera_scene();
  scene.meshes.push_back({"ball", make_uv_sphere(1.0f, 512, 256)});
  scene.materials.push_back(Material{});
  scene.objects.push_back({0, 0, Mat4::Identity()});
  RenderOptions o;
  o.memory_budget_bytes = std::uint64_t{16} << 20;
  const std::uint64_t need = estimate_frame_bytes(scene, o, 64, 48);
  EXPECT_GT(need, o.memory_budget_bytes);
  test::Canvas c(64, 48);
  Renderer r;
  const Status s = r.render(scene, o, c.view());
  EXPECT_EQ(s.code(), ErrorCode::out_of_memory);
  EXPECT_NE(s.message().find("memory_budget_bytes"), std::string::npos) << s.message();
  EXPECT_TRUE(c.untouched());
  EXPECT_EQ(check_render(scene, o, 64, 48).message(), s.message());
  o.memory_budget_bytes = 0;  // no limit
  EXPECT_TRUE(r.render(scene, o, c.view()).ok());
}

TEST(FrameLimits, RangeLimitIsOneMessageForRenderAndCheck) {
  Scene scene = test::camera_scene();
  scene.meshes.push_back({"tri", *mesh_from_arrays(std::vector<float>{0, 0, -5, 1, 0, -5, 0, 1, -5}, {},
                                                   std::vector<std::uint32_t>{0, 1, 2})});
  scene.materials.push_back(Material{});
  scene.objects.assign(65536, Instance{0, 0, Mat4::Identity()});
  RenderOptions o;
  EXPECT_TRUE(check_render(scene, o, 16, 16).ok());  // exactly at the limit
  scene.objects.push_back(Instance{0, 0, Mat4::Identity()});
  const Status checked = check_render(scene, o, 16, 16);
  EXPECT_EQ(checked.code(), ErrorCode::unsupported);
  EXPECT_NE(checked.message().find("65537 set-up ranges"), std::string::npos) << checked.message();
  EXPECT_NE(checked.message().find("at most 65536 objects"), std::string::npos) << checked.message();
  test::Canvas c(16, 16);
  Renderer r;
  const Status rendered = r.render(scene, o, c.view());
  EXPECT_EQ(rendered.message(), checked.message());
  EXPECT_TRUE(c.untouched());
}

Scene many_lights_scene(int lights) {
  Scene scene = make_default_scene();
  for (int i = 0; i < lights; ++i) {
    Light l;
    l.type = LightType::point;
    l.position = Vec3(static_cast<float>(i % 100) * 0.1f - 5.0f, 2.0f, static_cast<float>(i / 100) * 0.01f - 5.0f);
    l.diffuse = Color3(1e-4f, 1e-4f, 1e-4f);
    scene.lights.push_back(l);
  }
  return scene;
}

// Cancelled during set-up (Gouraud: lighting 20,000 lights per vertex chunk) and during the tiles
// (Phong: 20,000 lights per pixel, 8-pixel tiles), where every report is far apart. (The cost of
// this test under ASan is the frame set-up, which grows with the lights: 100,000 took 100 s.)
TEST(RenderCancel, FrameWithTwentyThousandLightsIsCancelled) {
  const Scene scene = many_lights_scene(20000);
  for (int threads : {1, 2}) {
    for (ShadingMode mode : {ShadingMode::gouraud, ShadingMode::phong}) {
      std::atomic<int> calls{0}, after_stop{0};
      std::atomic<bool> stopped{false};
      RenderOptions o;
      o.threads = threads;
      o.shading = mode;
      o.cull_lights = false;
      o.tile_size = 8;
      o.progress = [&](double done) {
        ++calls;
        if (stopped) ++after_stop;
        // Gouraud: stop at the second report; Phong: at the first past 30 % (in the tile loop).
        const bool stop = mode == ShadingMode::gouraud ? calls >= 2 : done >= 0.3;
        if (stop) stopped = true;
        return !stop;
      };
      test::Canvas c(96, 64);
      Renderer r;
      const Status s = r.render(scene, o, c.view());
      EXPECT_EQ(s.code(), ErrorCode::cancelled) << s.message();
      EXPECT_TRUE(stopped.load());
      EXPECT_EQ(after_stop.load(), 0) << "a report came after the one that said stop";
      if (mode == ShadingMode::gouraud) {
        EXPECT_TRUE(c.untouched()) << "cancelled in set-up: no pixel written";
      }
      EXPECT_TRUE(c.outside_pixels_untouched());
    }
  }
}

TEST(RenderCancel, ProgressOnlyGrowsAndTheFrameIsUnchanged) {
  const Scene scene = make_default_scene();
  test::Canvas plain(160, 100), watched(160, 100);
  RenderOptions o;
  o.threads = 2;
  Renderer r;
  ASSERT_TRUE(r.render(scene, o, plain.view()).ok());
  std::vector<double> seen;
  o.progress = [&](double done) {
    seen.push_back(done);
    return true;
  };
  ASSERT_TRUE(r.render(scene, o, watched.view()).ok());
  ASSERT_FALSE(seen.empty());
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);
  EXPECT_GT(seen.front(), 0.0);
  EXPECT_LE(seen.back(), 1.0);
  EXPECT_TRUE(plain.pixels() == watched.pixels());
}

TEST(SceneLoadCancel, ProgressCanStopALoad) {
  LoadOptions o;
  int calls = 0;
  o.progress = [&](double) { return ++calls < 2; };
  const Result<Scene> s = parse_scene_json(
      "{\"meshes\": [{\"name\": \"a\", \"shape\": \"cube\"}, {\"name\": \"b\", \"shape\": \"cube\"}, "
      "{\"name\": \"c\", \"shape\": \"cube\"}]}",
      "three.json", "", o);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), ErrorCode::cancelled);
  EXPECT_EQ(calls, 2);
}

// ---- 6. Untrusted text in messages ------------------------------------------------------------

TEST(UntrustedText, NonObjFileIsNotQuotedWhole) {
  ScratchDir dir;
  const std::string secret = "root:x:0:0:root:/root:/bin/bash-with-a-long-tail-of-secrets\nsecond line\n";
  const std::string path = dir.file("passwd", secret);
  const Result<Mesh> m = load_obj(path);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("not an OBJ file"), std::string::npos) << m.status().message();
  EXPECT_EQ(m.status().message().find("/bin/bash"), std::string::npos) << m.status().message();
  EXPECT_EQ(m.status().message().find("second line"), std::string::npos) << m.status().message();
}

TEST(UntrustedText, ControlCharactersAndNulAreEscaped) {
  const std::string name = std::string("evil\x1b[31mred\nnext") + '\0' + "after-nul";
  const std::string json = "{\"meshes\": [{\"name\": \"ok\", \"shape\": \"cube\"}], \"objects\": [{\"mesh\": \"" +
                           std::string("evil\\u001b[31mred\\nnext\\u0000after-nul") + "\"}]}";
  const Result<Scene> s = parse_scene_json(json, "names.json", "");
  ASSERT_FALSE(s.ok());
  const std::string& msg = s.status().message();
  EXPECT_EQ(msg.find('\x1b'), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\0'), std::string::npos) << msg;
  EXPECT_NE(msg.find("evil\\x1b[31mred\\nnext\\x00after-nul"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(defined: 'ok')"), std::string::npos) << msg;  // the message goes on after the NUL
  // Unknown keys and OBJ tokens too.
  const Result<Scene> k = parse_scene_json("{\"camera\": {\"e\\u001bye\": 1}}", "keys.json", "");
  EXPECT_NE(k.status().message().find("'e\\x1bye'"), std::string::npos) << k.status().message();
  const Result<Mesh> o = parse_obj("v 0 0 0\nv 1 0 0\nv 0 \x1b[2J 0\nf 1 2 3\n", "tok.obj");
  EXPECT_EQ(o.status().message().find('\x1b'), std::string::npos) << o.status().message();
  EXPECT_NE(o.status().message().find("\\x1b[2J"), std::string::npos) << o.status().message();
}

}  // namespace
}  // namespace facet
