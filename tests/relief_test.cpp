// Relief: tangent-space normal maps against the geometry they stand for, and the tangents
// generate_tangents makes (MikkTSpace) against their definition.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "render_support.hpp"

namespace facet {
namespace {

// The byte that encodes component v of a normal map, and what the renderer decodes from it.
std::uint8_t encode(double v) { return static_cast<std::uint8_t>(std::lround((v * 0.5 + 0.5) * 255.0)); }
double decode(std::uint8_t b) { return 2.0 * b / 255.0 - 1.0; }

// A 3 x 3 quad grid in the xz plane facing +y (uvs: u along +x, v along -z), seen from above by
// a camera looking down, lit by a point light and a directional one, with a local viewer.
Scene plane_scene() {
  Scene s;
  Mesh m = make_plane(4.0f, 4.0f, 3);
  s.meshes.push_back({"plane", m});
  Material mat;
  mat.ambient = Color3(0.1f, 0.1f, 0.1f);
  mat.diffuse = Color3(0.6f, 0.5f, 0.4f);
  mat.specular = Color3(0.5f, 0.5f, 0.5f);
  mat.shininess = 20;
  s.materials.push_back(mat);
  s.objects.push_back({0, 0, Mat4::Identity()});
  s.camera.eye = Vec3(0.3f, 5.0f, 0.4f);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.up = Vec3(0, 0, -1);
  s.camera.vertical_fov_deg = 40;
  Light point;
  point.type = LightType::point;
  point.position = Vec3(1.5f, 2.0f, 1.0f);
  s.lights.push_back(point);
  Light sun;
  sun.direction = Vec3(-0.5f, -1.0f, 0.3f);
  sun.diffuse = Color3(0.4f, 0.4f, 0.5f);
  s.lights.push_back(sun);
  return s;
}

// A 1 x 1 normal map of tangent-space normal m (each component encoded as a byte).
std::int32_t add_normal_map(Scene& s, const std::uint8_t (&rgb)[3]) {
  TextureOptions o{TextureFilter::nearest, TextureWrap::repeat};
  o.encoding = TextureEncoding::linear;
  const std::vector<std::uint8_t> texel = {rgb[0], rgb[1], rgb[2], 255};
  Result<Texture> t = make_texture("normal", 1, 1, texel, o);
  EXPECT_TRUE(t.ok());
  s.textures.push_back(*t);
  return static_cast<std::int32_t>(s.textures.size() - 1);
}

std::vector<std::uint8_t> render(const Scene& s, LightingPath path, Isa isa = Isa::best,
                                 ShadingMode shading = ShadingMode::phong, bool vertex_relief = false) {
  test::Canvas c(96, 96);
  RenderOptions o = test::gl_options();
  o.shading = shading;
  o.vertex_relief = vertex_relief;
  o.path = path;
  o.isa = isa;
  const Status st = Renderer(o).render(s, c.view());
  EXPECT_TRUE(st.ok()) << st.message();
  return c.pixels();
}

int largest_difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  int worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
  return worst;
}

// A plane whose normal map holds one tilted normal m shades as the same plane whose vertex normals
// are m in its tangent frame (t, b = w cross(n, t), n): on every path and ISA, within one step
// (the two differ by float rounding of the normal). With u mirrored (w = -1), with a mirroring
// model matrix, and with the map's x and y scaled, the frame follows.
// A map pointing below the surface (m.z < 0) is lit as that normal too, with no NaN.
TEST(NormalMaps, AConstantMapShadesAsTheTiltedNormal) {
  for (const std::array<double, 3> normal : {std::array<double, 3>{0.45, -0.3, 0.84}, std::array<double, 3>{0.6, 0.2, -0.77}}) {
  const std::uint8_t rgb[3] = {encode(normal[0]), encode(normal[1]), encode(normal[2])};
  const Eigen::Vector3d m(decode(rgb[0]), decode(rgb[1]), decode(rgb[2]));
  struct Case {
    const char* name;
    bool mirror_u, mirror_model;
    float scale;
    bool below = false;  // two-sided, seen from below: the back face, lit with the negated frame
  };
  for (const Case& k : {Case{"plain", false, false, 1.0f}, Case{"u mirrored", true, false, 1.0f},
                        Case{"model mirrored", false, true, 1.0f}, Case{"scale 0.5", false, false, 0.5f},
                        Case{"scale -1", false, false, -1.0f}, Case{"back face", false, false, 1.0f, true},
                        Case{"back face, u mirrored", true, false, 1.0f, true}}) {
    Scene mapped = plane_scene();
    if (k.below) {
      mapped.two_sided = true;
      mapped.camera.eye = Vec3(0.3f, -5.0f, 0.4f);
      mapped.lights[0].position = Vec3(1.5f, -2.0f, 1.0f);
      mapped.lights[1].direction = Vec3(-0.5f, 1.0f, 0.3f);
    }
    Mesh& mesh = mapped.meshes[0].mesh;
    if (k.mirror_u)
      for (Vec2& uv : mesh.uvs) uv.x() = 1.0f - uv.x();
    ASSERT_TRUE(generate_tangents(mesh).ok());
    if (k.mirror_model) mapped.objects[0].model.block<3, 3>(0, 0) = Eigen::Vector3f(-1, 1, 1).asDiagonal();
    Scene tilted = mapped;
    mapped.materials[0].normal_texture = add_normal_map(mapped, rgb);
    mapped.materials[0].normal_scale = k.scale;
    // The vertex normals of the tilted twin: m in each vertex's frame, in model space.
    Mesh& flat = tilted.meshes[0].mesh;
    for (std::size_t i = 0; i < flat.positions.size(); ++i) {
      const Eigen::Vector3d n = flat.normals[i].cast<double>();
      const Eigen::Vector3d t = mesh.tangents[i].head<3>().cast<double>();
      const Eigen::Vector3d b = mesh.tangents[i].w() * n.cross(t);
      flat.normals[i] = (k.scale * m.x() * t + k.scale * m.y() * b + m.z() * n).normalized().cast<float>();
    }
    flat.tangents.clear();
    for (LightingPath path : {LightingPath::simd, LightingPath::scalar}) {
      const auto a = render(mapped, path), b = render(tilted, path);
      EXPECT_LE(largest_difference(a, b), 1) << k.name << " " << to_string(path);
      Scene unmapped = mapped;
      unmapped.materials[0].normal_texture = kNoTexture;
      EXPECT_NE(a, render(unmapped, path)) << k.name << ": the map changed nothing";
    }
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      if (!isa_supported(isa)) continue;
      EXPECT_LE(largest_difference(render(mapped, LightingPath::simd, isa), render(tilted, LightingPath::simd, isa)), 1)
          << k.name << " " << to_string(isa);
    }
  }
  }
}

// Flat and Gouraud shading do not read the map (GL computes no normal per pixel there).
TEST(NormalMaps, PerVertexShadingIgnoresTheMap) {
  Scene s = plane_scene();
  ASSERT_TRUE(generate_tangents(s.meshes[0].mesh).ok());
  const std::uint8_t tilted[3] = {200, 60, 200};
  s.materials[0].normal_texture = add_normal_map(s, tilted);
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud}) {
    Scene unmapped = s;
    unmapped.materials[0].normal_texture = kNoTexture;
    test::Canvas a(64, 64), b(64, 64);
    RenderOptions o = test::gl_options();
    o.shading = mode;
    ASSERT_TRUE(Renderer(o).render(s, a.view()).ok());
    ASSERT_TRUE(Renderer(o).render(unmapped, b.view()).ok());
    EXPECT_EQ(a.pixels(), b.pixels()) << to_string(mode);
  }
}

// Per-vertex relief (RenderOptions::vertex_relief): Gouraud lights each vertex with the normal the
// maps give there. A one-texel normal map (plain, u mirrored, mirrored model, scale -1, the back
// face of a two-sided plane) and a height ramp (slope k 2/255 per texel) shade within a step of
// the plane whose vertex normals are those normals, on every path and ISA; flat shading still
// ignores the maps.
TEST(VertexRelief, MapsPerturbTheVertexNormals) {
  const std::array<double, 3> normal{0.45, -0.3, 0.84};
  const std::uint8_t rgb[3] = {encode(normal[0]), encode(normal[1]), encode(normal[2])};
  const Eigen::Vector3d m(decode(rgb[0]), decode(rgb[1]), decode(rgb[2]));
  struct Case {
    const char* name;
    bool mirror_u, mirror_model;
    float scale;
    bool below = false;
    bool bump = false;
  };
  std::vector<std::uint8_t> ramp(64 * 4);
  for (int i = 0; i < 64; ++i) ramp[4 * i] = ramp[4 * i + 1] = ramp[4 * i + 2] = static_cast<std::uint8_t>(2 * i), ramp[4 * i + 3] = 255;
  for (const Case& k : {Case{"plain", false, false, 1.0f}, Case{"u mirrored", true, false, 1.0f},
                        Case{"model mirrored", false, true, 1.0f}, Case{"scale -1", false, false, -1.0f},
                        Case{"back face", false, false, 1.0f, true}, Case{"bump ramp", false, false, 20.0f, false, true}}) {
    Scene mapped = plane_scene();
    if (k.below) {
      mapped.two_sided = true;
      mapped.camera.eye = Vec3(0.3f, -5.0f, 0.4f);
      mapped.lights[0].position = Vec3(1.5f, -2.0f, 1.0f);
      mapped.lights[1].direction = Vec3(-0.5f, 1.0f, 0.3f);
    }
    Mesh& mesh = mapped.meshes[0].mesh;
    if (k.mirror_u)
      for (Vec2& uv : mesh.uvs) uv.x() = 1.0f - uv.x();
    if (k.bump)
      for (Vec2& uv : mesh.uvs) uv = Vec2(0.25f, 0.25f) + 0.5f * uv;  // inside the ramp
    ASSERT_TRUE(generate_tangents(mesh).ok());
    if (k.mirror_model) mapped.objects[0].model.block<3, 3>(0, 0) = Eigen::Vector3f(-1, 1, 1).asDiagonal();
    Scene tilted = mapped;
    if (k.bump) {
      TextureOptions o{TextureFilter::bilinear, TextureWrap::clamp};
      o.encoding = TextureEncoding::linear;
      Result<Texture> height = make_texture("ramp", 64, 1, ramp, o);
      ASSERT_TRUE(height.ok());
      mapped.textures.push_back(*height);
      mapped.materials[0].bump_texture = 0;
      mapped.materials[0].bump_scale = k.scale;
    } else {
      mapped.materials[0].normal_texture = add_normal_map(mapped, rgb);
      mapped.materials[0].normal_scale = k.scale;
    }
    Mesh& flat = tilted.meshes[0].mesh;
    for (std::size_t i = 0; i < flat.positions.size(); ++i) {
      const Eigen::Vector3d n = flat.normals[i].cast<double>();
      const Eigen::Vector3d t = mesh.tangents[i].head<3>().cast<double>();
      const Eigen::Vector3d b = mesh.tangents[i].w() * n.cross(t);
      flat.normals[i] = (k.bump ? (-k.scale * 2.0 / 255.0 * t + n)
                                : Eigen::Vector3d(k.scale * m.x() * t + k.scale * m.y() * b + m.z() * n)).normalized().cast<float>();
    }
    flat.tangents.clear();
    for (LightingPath path : {LightingPath::simd, LightingPath::scalar, LightingPath::reference}) {
      const auto a = render(mapped, path, Isa::best, ShadingMode::gouraud, true);
      EXPECT_LE(largest_difference(a, render(tilted, path, Isa::best, ShadingMode::gouraud)), 1) << k.name << " " << to_string(path);
      EXPECT_NE(a, render(mapped, path, Isa::best, ShadingMode::gouraud)) << k.name << ": the option changed nothing";
      EXPECT_EQ(render(mapped, path, Isa::best, ShadingMode::flat, true), render(mapped, path, Isa::best, ShadingMode::flat))
          << k.name << ": flat shading reads no map";
    }
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      if (!isa_supported(isa)) continue;
      EXPECT_LE(largest_difference(render(mapped, LightingPath::simd, isa, ShadingMode::gouraud, true),
                                   render(tilted, LightingPath::simd, isa, ShadingMode::gouraud)), 1)
          << k.name << " " << to_string(isa);
    }
  }
}

// On a finer mesh per-vertex relief approaches per-pixel relief: a sphere with the domes normal
// map (trilinear), Gouraud with vertex_relief against Phong, mean difference over the image falls
// as the segments grow and ends far below plain Gouraud's; the same bytes on 1 and 3 threads.
TEST(VertexRelief, ApproachesPerPixelReliefAsTheMeshGrows) {
  TextureOptions linear;
  linear.encoding = TextureEncoding::linear;
  Result<Texture> domes = load_texture(test::data_dir() + "/textures/domes_normal.png", "domes", linear);
  ASSERT_TRUE(domes.ok()) << domes.status().message();
  auto sphere = [&](int segments) {
    Scene s;
    s.textures.push_back(*domes);
    Material mat;
    mat.diffuse = Color3(0.8f, 0.5f, 0.3f);
    mat.ambient = Color3(0.1f, 0.1f, 0.1f);
    mat.specular = Color3(0.3f, 0.3f, 0.3f);
    mat.shininess = 12;
    mat.normal_texture = 0;
    mat.uv_scale = Vec2(2, 1);
    s.materials.push_back(mat);
    s.meshes.push_back({"sphere", make_uv_sphere(1.0f, segments, segments / 2)});
    s.objects.push_back({0, 0, Mat4::Identity()});
    s.camera.eye = Vec3(0, 0.4f, 3.0f);
    Light l;
    l.direction = Vec3(-0.6f, -0.5f, -0.6f);
    s.lights.push_back(l);
    EXPECT_TRUE(generate_missing_tangents(s).ok());
    return s;
  };
  auto mean_difference = [](const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(int(a[i]) - int(b[i]));
    return sum / double(a.size());
  };
  const auto per_pixel = render(sphere(256), LightingPath::simd);
  double previous = 1e9;
  for (int segments : {16, 64, 256}) {
    const Scene s = sphere(segments);
    const auto a = render(s, LightingPath::simd, Isa::best, ShadingMode::gouraud, true);
    const double e = mean_difference(a, per_pixel);
    std::printf("vertex relief, %d segments: mean difference from per-pixel %.3f steps\n", segments, e);
    EXPECT_LT(e, previous) << segments;
    previous = e;
    if (segments == 256) {
      const double plain = mean_difference(render(s, LightingPath::simd, Isa::best, ShadingMode::gouraud), per_pixel);
      std::printf("plain Gouraud, 256 segments: %.3f steps\n", plain);
      EXPECT_LT(e, 0.5 * plain);
      for (int threads : {1, 3}) {
        test::Canvas c(96, 96);
        RenderOptions o = test::gl_options();
        o.vertex_relief = true;
        o.threads = threads;
        ASSERT_TRUE(Renderer(o).render(s, c.view()).ok());
        EXPECT_EQ(c.pixels(), a) << threads << " threads";
      }
    }
  }
}

// Relief finer than the mesh is averaged away, not point-sampled: a trilinear map whose texels
// alternate between normals tilted 37 degrees either way along the tangent, on a sphere of 16
// segments (about 8 texels between vertices), lights as the plain sphere within two steps (the
// mip levels hold the average 127.5 as the byte 128, which decodes as a tilt of 0.3 degrees);
// read at level 0 each vertex would take one tilt or the other.
TEST(VertexRelief, ReliefFinerThanTheMeshIsFilteredAway) {
  std::vector<std::uint8_t> texels(64 * 64 * 4);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      std::uint8_t* p = texels.data() + 4 * (64 * y + x);
      p[0] = (x + y) % 2 ? 230 : 25, p[1] = 128, p[2] = 230, p[3] = 255;  // (+-0.6, 0, 0.8)
    }
  TextureOptions o{TextureFilter::trilinear, TextureWrap::repeat};
  o.encoding = TextureEncoding::linear;
  Result<Texture> t = make_texture("ripples", 64, 64, texels, o);
  ASSERT_TRUE(t.ok());
  Scene s;
  s.textures.push_back(*t);
  Material mat;
  mat.normal_texture = 0;
  mat.uv_scale = Vec2(1.9f, 0.95f);  // vertices off the texel corners (where bilinear would average)
  s.materials.push_back(mat);
  s.meshes.push_back({"sphere", make_uv_sphere(1.0f, 16, 8)});
  s.objects.push_back({0, 0, Mat4::Identity()});
  s.camera.eye = Vec3(0, 0.4f, 3.0f);
  Light l;
  l.direction = Vec3(-0.6f, -0.5f, -0.6f);
  s.lights.push_back(l);
  ASSERT_TRUE(generate_missing_tangents(s).ok());
  const auto relief = render(s, LightingPath::simd, Isa::best, ShadingMode::gouraud, true);
  const auto plain = render(s, LightingPath::simd, Isa::best, ShadingMode::gouraud);
  EXPECT_LE(largest_difference(relief, plain), 2);
}

// The relief scene (normal maps on a plane, a sphere and a cube, one scaled -1; an sRGB diffuse
// texture; Phong's lobe; a linear-range light): the same bytes for any thread count on the scalar
// and SIMD paths, and every ISA and the scalar path within a step of each other.
TEST(NormalMaps, ReliefSceneIsByteIdenticalForAnyThreadCount) {
  Result<Scene> s = load_scene_file(test::data_dir() + "/scenes/relief.json", test::scene_options());
  ASSERT_TRUE(s.ok()) << s.status().message();
  std::vector<std::uint8_t> simd;
  for (LightingPath path : {LightingPath::simd, LightingPath::scalar}) {
    std::vector<std::uint8_t> one;
    for (int threads : {1, 2, 8}) {
      test::Canvas c(200, 120);
      RenderOptions o = test::gl_options();
      o.shading = ShadingMode::phong;
      o.path = path;
      o.threads = threads;
      o.tile_size = 32;
      ASSERT_TRUE(Renderer(o).render(*s, c.view()).ok());
      if (threads == 1) one = c.pixels();
      else EXPECT_TRUE(c.pixels() == one) << to_string(path) << " threads " << threads;
    }
    if (path == LightingPath::simd) simd = one;
    else EXPECT_LE(largest_difference(simd, one), 1) << "scalar against simd";
  }
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    if (!isa_supported(isa)) continue;
    test::Canvas c(200, 120);
    RenderOptions o = test::gl_options();
    o.shading = ShadingMode::phong;
    o.isa = isa;
    ASSERT_TRUE(Renderer(o).render(*s, c.view()).ok());
    EXPECT_LE(largest_difference(simd, c.pixels()), 1) << to_string(isa);
  }
}

// An occlusion map of red r and strength k shades as the same scene whose global ambient and
// lights' ambient colours are times o = 1 + k (r - 1): occlusion multiplies exactly the ambient
// terms. On every path and ISA, within a step; with vertex colours (colour material) too. Flat and
// Gouraud shading do not read the map.
TEST(OcclusionMaps, DarkenExactlyTheAmbientTerms) {
  for (const bool coloured : {false, true}) {
    for (const float strength : {1.0f, 0.6f, 0.0f}) {
      Scene mapped = plane_scene();
      mapped.global_ambient = Color3(0.5f, 0.4f, 0.3f);
      mapped.materials[0].ambient = Color3(0.9f, 0.8f, 0.7f);
      mapped.materials[0].emissive = Color3(0.05f, 0.0f, 0.1f);
      for (Light& l : mapped.lights) l.ambient = Color3(0.3f, 0.25f, 0.2f);
      if (coloured) mapped.meshes[0].mesh.colors.assign(mapped.meshes[0].mesh.positions.size(), Color3(0.7f, 0.9f, 0.5f));
      const std::uint8_t texel[3] = {77, 200, 13};  // the red channel is read
      TextureOptions o{TextureFilter::bilinear, TextureWrap::repeat};
      o.encoding = TextureEncoding::linear;
      Result<Texture> t = make_texture("ao", 1, 1, std::vector<std::uint8_t>{texel[0], texel[1], texel[2], 255}, o);
      ASSERT_TRUE(t.ok());
      Scene scaled = mapped;
      mapped.textures.push_back(*t);
      mapped.materials[0].occlusion_texture = 0;
      mapped.materials[0].occlusion_strength = strength;
      ASSERT_TRUE(validate_scene(mapped).ok()) << validate_scene(mapped).message();
      const float occ = 1.0f + strength * (77.0f / 255.0f - 1.0f);
      scaled.global_ambient *= occ;
      for (Light& l : scaled.lights) l.ambient *= occ;
      for (LightingPath path : {LightingPath::simd, LightingPath::scalar, LightingPath::reference}) {
        EXPECT_LE(largest_difference(render(mapped, path), render(scaled, path)), 1)
            << to_string(path) << " strength " << strength << (coloured ? " coloured" : "");
      }
      for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
        if (!isa_supported(isa)) continue;
        EXPECT_LE(largest_difference(render(mapped, LightingPath::simd, isa), render(scaled, LightingPath::simd, isa)), 1)
            << to_string(isa);
      }
      if (strength == 1.0f && !coloured) {
        Scene unmapped = mapped;
        unmapped.materials[0].occlusion_texture = kNoTexture;
        EXPECT_NE(render(mapped, LightingPath::simd), render(unmapped, LightingPath::simd)) << "the map changed nothing";
        for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud}) {
          test::Canvas a(64, 64), b(64, 64);
          RenderOptions ro = test::gl_options();
          ro.shading = mode;
          ASSERT_TRUE(Renderer(ro).render(mapped, a.view()).ok());
          ASSERT_TRUE(Renderer(ro).render(unmapped, b.view()).ok());
          EXPECT_EQ(a.pixels(), b.pixels()) << to_string(mode);
        }
      }
    }
  }
}

// A height map rising along u (or v) by 2/255 per texel (read bilinear, away from its edges):
// every pixel's slopes are (k 2/255, 0) (or (0, k 2/255)), so it shades as the tangent-space
// normal (-k 2/255, 0, 1) (or (0, -k 2/255, 1)), on every path and ISA, within a step. Scale 0 is
// no bump; scale 1e6 stays finite.
TEST(BumpMaps, ARampShadesAsItsSlope) {
  std::vector<std::uint8_t> ramp(64 * 4);
  for (int i = 0; i < 64; ++i) ramp[4 * i] = ramp[4 * i + 1] = ramp[4 * i + 2] = static_cast<std::uint8_t>(2 * i), ramp[4 * i + 3] = 255;
  TextureOptions o{TextureFilter::bilinear, TextureWrap::clamp};
  o.encoding = TextureEncoding::linear;
  for (const bool along_v : {false, true})
  for (const float k : {20.0f, -7.0f}) {
    // make_texture takes the top row first: a column rising upwards is the ramp reversed.
    std::vector<std::uint8_t> column(ramp.rbegin(), ramp.rend());
    for (int i = 0; i < 64; ++i) std::swap(column[4 * i], column[4 * i + 3]), std::swap(column[4 * i + 1], column[4 * i + 2]);
    Result<Texture> height = along_v ? make_texture("ramp", 1, 64, column, o) : make_texture("ramp", 64, 1, ramp, o);
    ASSERT_TRUE(height.ok());
    Scene bumped = plane_scene();
    Mesh& mesh = bumped.meshes[0].mesh;
    for (Vec2& uv : mesh.uvs) uv = Vec2(0.25f, 0.25f) + 0.5f * uv;  // inside the ramp, away from the clamped ends
    ASSERT_TRUE(generate_tangents(mesh).ok());
    Scene tilted = bumped;
    bumped.textures.push_back(*height);
    bumped.materials[0].bump_texture = 0;
    bumped.materials[0].bump_scale = k;
    const double slope = k * 2.0 / 255.0;
    Mesh& flat = tilted.meshes[0].mesh;
    for (std::size_t i = 0; i < flat.positions.size(); ++i) {
      const Eigen::Vector3d n = flat.normals[i].cast<double>(), t = mesh.tangents[i].head<3>().cast<double>();
      const Eigen::Vector3d b = mesh.tangents[i].w() * n.cross(t);
      flat.normals[i] = (-slope * (along_v ? b : t) + n).normalized().cast<float>();
    }
    flat.tangents.clear();
    for (LightingPath path : {LightingPath::simd, LightingPath::scalar}) {
      EXPECT_LE(largest_difference(render(bumped, path), render(tilted, path)), 1)
          << to_string(path) << " scale " << k << (along_v ? " along v" : " along u");
    }
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      if (!isa_supported(isa)) continue;
      EXPECT_LE(largest_difference(render(bumped, LightingPath::simd, isa), render(tilted, LightingPath::simd, isa)), 1)
          << to_string(isa);
    }
    Scene unbumped = bumped;
    unbumped.materials[0].bump_texture = kNoTexture;
    bumped.materials[0].bump_scale = 0.0f;
    EXPECT_EQ(render(bumped, LightingPath::simd), render(unbumped, LightingPath::simd)) << "scale 0";
    bumped.materials[0].bump_scale = 1e6f;
    ASSERT_TRUE(validate_scene(bumped).ok());
    EXPECT_NE(render(bumped, LightingPath::simd), render(unbumped, LightingPath::simd)) << "scale 1e6";
  }
}

// Environment-mapped bump (flat and Gouraud, a normal-mode environment map): the height's slopes
// move the environment's coordinates. On a plane facing the eye the normal mode reads (1/2, 1/2)
// everywhere; a ramp of slope k 2/255 moves that to (1/2 + k 2/255, 1/2): the colour of a
// horizontal ramp environment there. Scale 0 is no bump; scalar and SIMD agree within a step.
TEST(BumpMaps, EnvironmentBumpMovesTheLookup) {
  Scene s;
  s.camera.eye = Vec3(0, 0, 3);
  s.camera.target = Vec3(0, 0, 0);
  s.camera.vertical_fov_deg = 30;
  s.global_ambient = Color3::Zero();
  Mesh quad;
  quad.positions = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
  quad.normals.assign(4, Vec3(0, 0, 1));
  quad.uvs = {Vec2(0.25f, 0.25f), Vec2(0.75f, 0.25f), Vec2(0.75f, 0.75f), Vec2(0.25f, 0.75f)};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  ASSERT_TRUE(generate_tangents(quad).ok());
  s.meshes.push_back({"quad", quad});
  std::vector<std::uint8_t> ramp(64 * 4), env(256 * 4);
  for (int i = 0; i < 64; ++i) ramp[4 * i] = ramp[4 * i + 1] = ramp[4 * i + 2] = static_cast<std::uint8_t>(2 * i), ramp[4 * i + 3] = 255;
  for (int i = 0; i < 256; ++i) env[4 * i] = static_cast<std::uint8_t>(i), env[4 * i + 1] = env[4 * i + 2] = 0, env[4 * i + 3] = 255;
  TextureOptions o{TextureFilter::bilinear, TextureWrap::clamp};
  o.encoding = TextureEncoding::linear;
  s.textures.push_back(*make_texture("ramp", 64, 1, ramp, o));
  s.textures.push_back(*make_texture("env", 256, 1, env, o));
  Material m;
  m.ambient = m.diffuse = m.specular = Color3::Zero();
  m.environment.mode = EnvironmentMode::normal;
  m.environment.maps[0] = 1;
  m.environment.blend = EnvironmentBlend::add;
  m.bump_texture = 0;
  m.bump_scale = 12.0f;
  s.materials.push_back(m);
  s.objects.push_back({0, 0, Mat4::Identity()});
  ASSERT_TRUE(validate_scene(s).ok()) << validate_scene(s).message();
  auto draw = [&](const Scene& scene, LightingPath path) {
    test::Canvas c(32, 32);
    RenderOptions ro = test::gl_options();
    ro.shading = ShadingMode::gouraud;
    ro.path = path;
    EXPECT_TRUE(Renderer(ro).render(scene, c.view()).ok());
    return c;
  };
  test::Canvas simd = draw(s, LightingPath::simd), scalar = draw(s, LightingPath::scalar);
  EXPECT_LE(largest_difference(simd.pixels(), scalar.pixels()), 1);
  // The environment's red at s = 1/2 + 12 x 2/255, bilinear over 256 texels of value i / 255.
  const double at = (0.5 + 12.0 * 2.0 / 255.0) * 256.0 - 0.5;
  EXPECT_NEAR(simd.byte(16, 16, 0), static_cast<double>(std::lround(at)), 1.0);
  Scene flat = s;
  flat.materials[0].bump_scale = 0.0f;
  EXPECT_NEAR(draw(flat, LightingPath::simd).byte(16, 16, 0), static_cast<double>(std::lround(0.5 * 256.0 - 0.5)), 1.0);
}

using test::projector_scene;

// A one-colour picture c filters the light as the light's colours times c would (modulate), or
// times c's luminance (gobo), on every path and ISA within a step; flat and Gouraud ignore it.
TEST(Projectors, AOneColourPictureFiltersTheLight) {
  const std::vector<std::uint8_t> c = {200, 100, 40, 255};
  for (ProjectorMode mode : {ProjectorMode::modulate, ProjectorMode::gobo}) {
    const Scene projected = projector_scene(c, 1, 1, mode);
    ASSERT_TRUE(validate_scene(projected).ok()) << validate_scene(projected).message();
    Scene filtered = projected;
    filtered.lights[0].projector.texture = -1;
    const Color3 f = Color3(200, 100, 40) / 255.0f;
    const float lum = 0.2126f * f.x() + 0.7152f * f.y() + 0.0722f * f.z();
    const Color3 k = mode == ProjectorMode::modulate ? f : Color3(lum, lum, lum);
    filtered.lights[0].diffuse = filtered.lights[0].diffuse.cwiseProduct(k);
    filtered.lights[0].specular = filtered.lights[0].specular.cwiseProduct(k);
    for (LightingPath path : {LightingPath::simd, LightingPath::scalar, LightingPath::reference}) {
      EXPECT_LE(largest_difference(render(projected, path), render(filtered, path)), 1) << to_string(path);
    }
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      if (!isa_supported(isa)) continue;
      EXPECT_LE(largest_difference(render(projected, LightingPath::simd, isa), render(filtered, LightingPath::simd, isa)), 1)
          << to_string(isa);
    }
    test::Canvas a(48, 48), b(48, 48);
    RenderOptions ro = test::gl_options();
    ro.shading = ShadingMode::gouraud;
    Scene unprojected = projected;
    unprojected.lights[0].projector.texture = -1;
    ASSERT_TRUE(Renderer(ro).render(projected, a.view()).ok());
    ASSERT_TRUE(Renderer(ro).render(unprojected, b.view()).ok());
    EXPECT_EQ(a.pixels(), b.pixels());
  }
}

// A light standing on the surface it lights (points at its position and beside it, on its near
// plane): a white picture changes nothing and nothing becomes NaN.
TEST(Projectors, ALightOnTheSurfaceItLightsStaysFinite) {
  const std::vector<std::uint8_t> white = {255, 255, 255, 255};
  Scene s = projector_scene(white, 1, 1, ProjectorMode::modulate);
  s.lights[0].position = Vec3(0, 0, 0);
  s.lights[0].direction = Vec3(1, -1, 0);
  s.lights[0].spot_cutoff_deg = 80;
  Scene plain = s;
  plain.lights[0].projector.texture = -1;
  for (LightingPath path : {LightingPath::simd, LightingPath::scalar}) {
    EXPECT_LE(largest_difference(render(s, path), render(plain, path)), 1) << to_string(path);
  }
}

// The picture's orientation: a light pointing straight down has +x as its up (the vertical
// light's rule), so the picture's top (t > 1/2) falls on +x and its right (s > 1/2) on +z. Each
// quadrant of a 2 x 2 picture lands there; outside the picture's square no light arrives.
TEST(Projectors, ThePictureLandsTheRightWayRound) {
  // Top row first: top-left red, top-right green, bottom-left blue, bottom-right white.
  const std::vector<std::uint8_t> quads = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  const Scene s = projector_scene(quads, 2, 2, ProjectorMode::modulate);
  test::Canvas c(96, 96);
  RenderOptions o = test::gl_options();
  o.shading = ShadingMode::phong;
  ASSERT_TRUE(Renderer(o).render(s, c.view()).ok());
  // Image position of world (x, 0, z): +x right, +z down, 6 units away with a 60-degree view.
  auto at = [&](float x, float z, int ch) {
    const float scale = 48.0f / (6.0f * std::tan(30.0f * 3.14159265f / 180.0f));
    return c.byte(static_cast<int>(48 + x * scale), static_cast<int>(48 + z * scale), ch);
  };
  // Top (t > 1/2) on +x, right (s > 1/2) on +z: top-right green at (+x, +z), top-left red at (+x, -z).
  EXPECT_GT(at(1.0f, 1.0f, 1), 100);
  EXPECT_LT(at(1.0f, 1.0f, 0), 10);
  EXPECT_GT(at(1.0f, -1.0f, 0), 100);
  EXPECT_LT(at(1.0f, -1.0f, 1), 10);
  EXPECT_GT(at(-1.0f, -1.0f, 2), 60);  // bottom-left blue at (-x, -z)
  EXPECT_LT(at(-1.0f, -1.0f, 0), 10);
  EXPECT_GT(at(-1.0f, 1.0f, 0), 100);  // bottom-right white at (-x, +z)
  EXPECT_GT(at(-1.0f, 1.0f, 1), 80);
  EXPECT_EQ(at(2.6f, 0.0f, 0), 0);  // outside the cone: dark
}

// A glTF written for these tests (tools/data/make_relief_gltf.py): an sRGB base colour, a linear
// normal and occlusion map, tangents generated; lit per pixel the maps change the picture, and
// the picture is the same bytes on 1 and 2 threads.
TEST(NormalMaps, AGltfWithNormalOcclusionAndSrgbTextures) {
  Result<Model> m = load_model(test::data_dir() + "/gltf/relief_cube.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  EXPECT_TRUE(m->warnings.empty()) << m->warnings[0];
  Scene& s = m->scene;
  const Material& mat = s.materials[0];
  ASSERT_NE(mat.diffuse_texture, kNoTexture);
  ASSERT_NE(mat.normal_texture, kNoTexture);
  ASSERT_NE(mat.occlusion_texture, kNoTexture);
  EXPECT_EQ(s.textures[std::size_t(mat.diffuse_texture)].encoding, TextureEncoding::srgb);
  EXPECT_EQ(s.textures[std::size_t(mat.normal_texture)].encoding, TextureEncoding::linear);
  EXPECT_EQ(s.textures[std::size_t(mat.occlusion_texture)].encoding, TextureEncoding::linear);
  EXPECT_EQ(s.meshes[0].mesh.tangents.size(), s.meshes[0].mesh.positions.size());
  s.camera = *frame_scene(s, 1.0f);
  add_default_lights(s);
  std::vector<std::uint8_t> pictures[2];
  for (int threads : {1, 2}) {
    test::Canvas c(96, 96);
    RenderOptions o = test::gl_options();
    o.shading = ShadingMode::phong;
    o.threads = threads;
    o.srgb = true;
    ASSERT_TRUE(Renderer(o).render(s, c.view()).ok());
    pictures[threads - 1] = c.pixels();
  }
  EXPECT_EQ(pictures[0], pictures[1]);
  Scene flat = s;
  flat.materials[0].normal_texture = flat.materials[0].occlusion_texture = kNoTexture;
  test::Canvas c(96, 96);
  RenderOptions o = test::gl_options();
  o.shading = ShadingMode::phong;
  o.srgb = true;
  ASSERT_TRUE(Renderer(o).render(flat, c.view()).ok());
  EXPECT_NE(c.pixels(), pictures[0]);
}

// A normal map needs tangents: validation says so, and generate_missing_tangents makes them.
TEST(NormalMaps, MissingTangentsAreNamedAndGenerated) {
  Scene s = plane_scene();
  const std::uint8_t up[3] = {128, 128, 255};
  s.materials[0].normal_texture = add_normal_map(s, up);
  const Status st = validate_scene(s);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("no tangents"), std::string::npos) << st.message();
  ASSERT_TRUE(generate_missing_tangents(s).ok());
  EXPECT_EQ(s.meshes[0].mesh.tangents.size(), s.meshes[0].mesh.positions.size());
  EXPECT_TRUE(validate_scene(s).ok());
  s.materials[0].normal_scale = std::nanf("");
  EXPECT_FALSE(validate_scene(s).ok());
}

// MikkTSpace's tangent at a vertex of a smooth mesh: unit, perpendicular to the normal, along
// increasing u (positive dot with dP/du), w the sign of the uv area. On a uv sphere that is the
// direction of increasing longitude up to the tilt each triangle's diagonal gives its dP/du, which
// shrinks as the square of the faces' size (1 - |t . east| measured 0.0033 at 32 x 16 segments,
// 0.00023 at 128 x 64); with u mirrored, the opposite direction and w flipped.
TEST(Tangents, FollowIncreasingUOnASphere) {
  float first_w = 0, first_along = 0;
  for (bool mirrored : {false, true}) {
    Mesh m = make_uv_sphere(1.0f, 128, 64);
    if (mirrored)
      for (Vec2& uv : m.uvs) uv.x() = 1.0f - uv.x();
    const std::size_t before = m.positions.size();
    ASSERT_TRUE(generate_tangents(m).ok());
    EXPECT_EQ(m.positions.size(), before) << "no mixed orientation on a sphere";
    ASSERT_TRUE(validate_mesh(m).ok());
    double worst = 0;
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      const Vec3 p = m.positions[i];
      const Vec3 n = m.normals[i];
      const Vec3 t = m.tangents[i].head<3>();
      if (std::abs(p.y()) > 0.9f) continue;  // near the poles the fans' uvs shear the face tangents
      EXPECT_NEAR(t.norm(), 1.0f, 1e-5f);
      EXPECT_NEAR(t.dot(n), 0.0f, 1e-5f);
      // Longitude increases towards (-z, 0, x) or its opposite, depending on the sphere's u.
      const Vec3 east = Vec3(-p.z(), 0, p.x()).normalized();
      worst = std::max<double>(worst, 1.0 - std::abs(t.dot(east)));
      EXPECT_EQ(m.tangents[i].w(), m.tangents[0].w());
    }
    EXPECT_LT(worst, 1e-3) << "tangents along the parallels";
    std::printf("sphere tangents: largest 1 - |t . east| %.3g\n", worst);
    // Along increasing u: the mirrored sphere's tangents point the other way, its w flips.
    const std::size_t i = m.positions.size() / 2;
    const Vec3 east = Vec3(-m.positions[i].z(), 0, m.positions[i].x()).normalized();
    const float along = m.tangents[i].head<3>().dot(east);
    if (!mirrored) {
      first_w = m.tangents[0].w();
      first_along = along;
    } else {
      EXPECT_EQ(m.tangents[0].w(), -first_w);
      EXPECT_LT(along * first_along, 0.0f);
    }
  }
}

// facet's MikkTSpace against the reference implementation's tangents: Blender (which compiles
// Mikkelsen's mikktspace.c) exported Suzanne (seams, thin triangles, a few triangles with flipped UVs), a UV sphere
// (degenerate UV triangles at the poles) and a cube with one face mirrored in u, with their
// TANGENT attribute (tools/data/make_mikktspace_reference.py). Regenerated here from positions,
// normals and UVs alone, every triangle corner gets the same w and a direction within 0.1 degree
// of Blender's (its float32 output, quantised by the glTF export; facet computes in double).
TEST(Tangents, MatchTheReferenceImplementationOnBlenderMeshes) {
  Result<Model> m = load_model(test::data_dir() + "/gltf/mikktspace_reference.gltf");
  ASSERT_TRUE(m.ok()) << m.status().message();
  ASSERT_EQ(m->scene.meshes.size(), 3u);
  for (const NamedMesh& nm : m->scene.meshes) {
    const Mesh& stored = nm.mesh;
    ASSERT_EQ(stored.tangents.size(), stored.positions.size()) << nm.name << ": TANGENT read";
    Mesh mine = stored;
    mine.tangents.clear();
    ASSERT_TRUE(generate_tangents(mine).ok()) << nm.name;
    ASSERT_EQ(mine.triangles.size(), stored.triangles.size());
    double worst_deg = 0;
    std::size_t w_differs = 0, corners = 0, mirrored = 0;
    for (std::size_t t = 0; t < stored.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const Vec4& a = stored.tangents[stored.triangles[t][k]];
        const Vec4& b = mine.tangents[mine.triangles[t][k]];
        ++corners;
        mirrored += a.w() < 0;
        if (a.w() != b.w()) ++w_differs;
        const double c = std::clamp<double>(a.head<3>().normalized().dot(b.head<3>().normalized()), -1.0, 1.0);
        worst_deg = std::max(worst_deg, std::acos(c) * 180.0 / 3.14159265358979);
      }
    }
    std::printf("%s: %zu corners (%zu mirrored), largest angle to Blender's tangent %.4f deg, w differs at %zu\n",
                nm.name.c_str(), corners, mirrored, worst_deg, w_differs);
    EXPECT_EQ(w_differs, 0u) << nm.name;
    EXPECT_LT(worst_deg, 0.1) << nm.name;
    if (nm.name.find("Suzanne") != std::string::npos || nm.name.find("Cube") != std::string::npos) {
      EXPECT_GT(mirrored, 0u) << nm.name << ": the mirrored case is exercised";
    }
  }
}

// A vertex shared by triangles of both uv orientations (a mirrored seam) is split in two; a
// triangle with no uv area gets a direction perpendicular to its normal; w is +1 or -1.
TEST(Tangents, MirroredSeamsSplitAndDegenerateUvsStayFinite) {
  Mesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(5, 5, 0), Vec3(6, 5, 0), Vec3(5, 6, 0)};
  m.normals.assign(m.positions.size(), Vec3(0, 0, 1));
  // Triangles 0 and 1 share the edge 0-2; u mirrors across it. Triangle 2 has all uvs equal.
  m.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(1, 0), Vec2(0.5f, 0.5f), Vec2(0.5f, 0.5f), Vec2(0.5f, 0.5f)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
  ASSERT_TRUE(generate_tangents(m).ok());
  ASSERT_TRUE(validate_mesh(m).ok());
  EXPECT_EQ(m.positions.size(), 9u) << "vertices 0 and 2 split";
  const auto& a = m.triangles[0];
  const auto& b = m.triangles[1];
  EXPECT_EQ(m.tangents[a[0]].w(), 1.0f);
  EXPECT_EQ(m.tangents[b[0]].w(), -1.0f);
  EXPECT_NE(a[0], b[0]);
  EXPECT_GT(m.tangents[a[0]].x(), 0.99f);   // u increases along +x on the right
  EXPECT_LT(m.tangents[b[0]].x(), -0.99f);  // and along -x on the left; v along +y on both sides
  for (int k = 0; k < 3; ++k) {
    const Vec4& t = m.tangents[m.triangles[2][k]];
    EXPECT_TRUE(t.allFinite());
    EXPECT_NEAR(t.head<3>().norm(), 1.0f, 1e-6f);
    EXPECT_NEAR(t.z(), 0.0f, 1e-6f);
  }
}

}  // namespace
}  // namespace facet
