// Shadows, continued from shadow_test.cpp: the SIMD shadow-map lookup against its scalar twin, a
// reused renderer, shadow volumes against the sphere's exact shadow and ray-cast shadows, and
// shadows in flat and Gouraud shading.
#include <cmath>
#include <cstring>
#include <random>

#include "tile/tile_raster.hpp"
#include "shadow/map.hpp"
#include "shadow_scenes.hpp"

namespace facet {
namespace {

// The SIMD shadow-map lookup of every ISA against its scalar twin, bit for bit: the three kinds
// of map, every filter, random depths, and points anywhere (outside the map, behind the light,
// on face borders, with zero, NaN and infinite coordinates and normals), stride 1 and 3.
TEST(ShadowMaps, SimdLookupIsTheScalarOneBitForBit) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> coord(-6.0f, 6.0f), unit(0.0f, 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  shadow::CasterBounds casters;
  casters.lo = {Eigen::Vector3d(-4, 0, -4), Eigen::Vector3d(-1, 0.5, -1)};
  casters.hi = {Eigen::Vector3d(4, 0, 4), Eigen::Vector3d(1, 2.5, 1)};
  const Scene base = sphere_over_plane();
  const Eigen::Matrix4d view = view_matrix(base.camera).cast<double>();
  const Eigen::Matrix4d projection = projection_matrix(base.camera, 1.0f).cast<double>();
  int compared = 0;
  for (const Scene& s : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    for (const ShadowFilter filter : {ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5}) {
      Light light = s.lights[0];
      light.shadow.method = ShadowMethod::map;
      light.shadow.filter = filter;
      light.shadow.resolution = 64;
      light.shadow.bias.slope = 0.5f;  // every bias term in play
      light.shadow.bias.constant = 0.25f;
      shadow::ShadowMap map;
      map.plan(light, casters, view, projection);
      ASSERT_FALSE(map.empty());
      for (int f = 0; f < map.face_count(); ++f) {
        const DepthView d = map.depth_view(f);
        for (int y = 0; y < d.height; ++y) {
          for (int x = 0; x < d.width; ++x) {  // blocks of 8 x 8 texels: casters near the light or none
            std::mt19937 block(static_cast<unsigned>(f * 4096 + (y / 8) * 64 + x / 8));
            d.data[y * d.width + x] = block() % 3 == 0 ? 1.0f : 0.1f * unit(rng);
          }
        }
      }
      constexpr std::size_t kPoints = 1000;
      std::vector<float> p(6 * kPoints);
      for (std::size_t i = 0; i < kPoints; ++i) {
        const Eigen::Vector4d world(coord(rng), coord(rng) * 0.5f + 1.5f, coord(rng), 1.0);
        const Eigen::Vector4d eye = view * world;
        for (int c = 0; c < 3; ++c) p[6 * i + c] = static_cast<float>(eye[c]), p[6 * i + 3 + c] = coord(rng);
      }
      const float odd[][6] = {{0, 0, 0, 0, 0, 0},  {nan, 0, -5, 0, 1, 0}, {0, inf, -5, 0, 1, 0}, {0, 0, -5, nan, 1, 0},
                              {1e20f, 0, -5, 0, 1, 0}, {0, 0, -5, 1e20f, 0, 0}, {0, 0, 5, 0, 1, 0}};
      for (std::size_t k = 0; k < std::size(odd); ++k) std::copy_n(odd[k], 6, &p[6 * k]);
      auto run = [&](shadow::MapVisibilityFunction kernel, bool soa) {
        map.set_kernel(kernel);
        std::vector<float> out(kPoints);
        if (soa) {
          std::vector<float> streams(6 * kPoints);
          for (std::size_t i = 0; i < kPoints; ++i) {
            for (int c = 0; c < 6; ++c) streams[static_cast<std::size_t>(c) * kPoints + i] = p[6 * i + c];
          }
          const float* q = streams.data();
          map.visibility(kPoints, q, q + kPoints, q + 2 * kPoints, q + 3 * kPoints, q + 4 * kPoints, q + 5 * kPoints, 1,
                         out.data());
        } else {
          std::vector<float> xyz(3 * kPoints), nrm(3 * kPoints);
          for (std::size_t i = 0; i < kPoints; ++i) {
            for (int c = 0; c < 3; ++c) xyz[3 * i + c] = p[6 * i + c], nrm[3 * i + c] = p[6 * i + 3 + c];
          }
          map.visibility(kPoints, xyz.data(), xyz.data() + 1, xyz.data() + 2, nrm.data(), nrm.data() + 1, nrm.data() + 2,
                         3, out.data());
        }
        return out;
      };
      const std::vector<float> scalar = run(nullptr, true);
      EXPECT_EQ(run(nullptr, false), scalar);
      int partial = 0, shadowed = 0;
      for (float v : scalar) {
        partial += v > 0.0f && v < 1.0f;
        shadowed += v == 0.0f;
      }
      EXPECT_GT(shadowed, 10);
      if (filter != ShadowFilter::none) {
        EXPECT_GT(partial, 10);
      }
      for (const Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
        const tile::simd::Kernels* k = tile::simd_raster_kernels(isa);
        if (!k) continue;
        for (const bool soa : {true, false}) {
          const std::vector<float> simd = run(k->shadow_map, soa);
          ASSERT_EQ(simd.size(), scalar.size());
          EXPECT_EQ(std::memcmp(simd.data(), scalar.data(), simd.size() * sizeof(float)), 0)
              << to_string(isa) << " " << to_string(filter) << " kind " << map.kind();
          ++compared;
        }
      }
    }
  }
  EXPECT_GE(compared, 12 * 2);
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// A renderer keeps its shadow maps from frame to frame (a tile no caster reaches is cleared once)
// and its ray-cast hierarchy while the casters do not change: frames after a moved caster, a
// moved camera, a new resolution or a new tile size are the bytes a fresh renderer draws.
TEST(ShadowMaps, AReusedRendererDrawsWhatAFreshOneDraws) {
  auto draw = [](Renderer& r, const Scene& s, int tile_size) {
    Canvas c(kSize, kSize);
    RenderOptions o = test::gl_options();
    o.shading = ShadingMode::phong;
    o.tile_size = tile_size;
    EXPECT_TRUE(r.render(s, o, c.view()).ok());
    return c.pixels();
  };
  for (const ShadowMethod method : {ShadowMethod::map, ShadowMethod::raycast, ShadowMethod::volume}) {
    for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
      Scene a = with_map(base, ShadowFilter::pcf3x3, 512);
      a.lights[0].shadow.method = method;
      Scene moved = a;
      moved.objects[1].model.block<3, 1>(0, 3) = Vec3(1.0f, 1.2f, -1.0f);
      Scene finer = moved;
      finer.lights[0].shadow.resolution = 1024;
      Scene turned = finer;  // the camera moves, the casters stay
      turned.camera.eye = Vec3(1.0f, 11.0f, 3.0f);
      Scene fewer = turned;  // a caster stops casting
      fewer.objects[1].cast_shadows = false;
      Scene reshaped = moved;  // a caster's mesh changes (its adjacency and hierarchy with it)
      for (Vec3& p : reshaped.meshes[1].mesh.positions) p = Vec3(p.x() * 1.5f, p.y() * 0.5f, p.z());
      Renderer reused;
      draw(reused, a, 64);
      for (const auto& [scene, tile] : {std::pair<const Scene*, int>{&moved, 64}, {&finer, 64}, {&turned, 64}, {&a, 32},
                                        {&moved, 128}, {&fewer, 64}, {&reshaped, 64}, {&a, 64}}) {
        Renderer fresh;
        EXPECT_EQ(draw(reused, *scene, tile), draw(fresh, *scene, tile)) << "tile " << tile << " " << to_string(method);
      }
    }
  }
}

}  // namespace
}  // namespace facet

#include "shadow/volume.hpp"

namespace facet {
namespace {

// Stencil shadow volumes (z-fail): exact hard shadows per pixel, against the sphere's analytic shadow and against ray-
// cast shadows away from their edges; determinism; the adjacency.
TEST(ShadowVolumes, MatchTheSpheresExactShadow) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    SCOPED_TRACE(static_cast<int>(base.lights[0].type));
    const auto [in_shadow, in_light] = compare_with_exact_shadow(with_volume(base), 8.0 / kSize * 2.0);
    EXPECT_GT(in_shadow, 100);
    EXPECT_GT(in_light, 500);
  }
}

TEST(ShadowVolumes, SameBytesForEveryThreadCountAndPath) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    expect_same_for_threads_and_paths(with_volume(base));
  }
}

TEST(ShadowVolumes, NothingToCastIsTheUnshadowedImage) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    expect_unshadowed_without_casters_or_receivers(with_volume(base));
  }
}

TEST(ShadowVolumes, AgreeWithRaycastBeyondAPixelOfAnEdge) {
  for (const Scene& base : {sphere_over_plane(), spot_over_sphere(), point_over_sphere()}) {
    const Agreement a = compare_with_raycast(base, 1, ShadowFilter::none, ShadowMethod::volume);
    EXPECT_GT(a.shadowed, 100);
    EXPECT_GT(a.compared, kSize * kSize / 2);
  }
}

// Two volume-shadowed lights in one frame (a sun and a lamp): each its own mask.
TEST(ShadowVolumes, SeveralLights) {
  Scene s = sphere_over_plane();
  Light lamp = point_over_sphere().lights[0];
  lamp.diffuse = Color3(0.4f, 0.3f, 0.2f);
  s.lights[0].diffuse = Color3(0.4f, 0.5f, 0.6f);
  s.lights.push_back(lamp);
  const Agreement a = compare_with_raycast(s, 1, ShadowFilter::none, ShadowMethod::volume);
  EXPECT_GT(a.shadowed, 150);
}

// The camera inside a shadow volume, its near plane cutting the volume: what z-fail is for (z-pass counting would
// invert the shadow here).
TEST(ShadowVolumes, CameraInsideTheShadow) {
  for (const Scene& base : {sphere_over_plane(), point_over_sphere()}) {
    Scene s = base;
    // On the line from the sphere's centre away from the light, between the sphere and the plane.
    const Vec3 away = base.lights[0].type == LightType::directional
                          ? base.lights[0].direction
                          : Vec3((kCentre - base.lights[0].position).normalized());
    s.camera.eye = kCentre + away * 1.3f;
    s.camera.target = s.camera.eye + Vec3(1.5f, -1.0f, 0.8f);
    s.camera.up = Vec3(0, 1, 0);
    s.camera.vertical_fov_deg = 70.0f;
    s.camera.near = 0.05f;
    SCOPED_TRACE(static_cast<int>(base.lights[0].type));
    const Agreement a = compare_with_raycast(s, 1, ShadowFilter::none, ShadowMethod::volume);
    EXPECT_GT(a.shadowed, 100);
  }
}

// An open mesh (a square, one-sided) casts from both sides, as with ray-cast shadows: facing the light or turned away
// from it, the same shadow.
TEST(ShadowVolumes, OpenMeshesCastFromBothSides) {
  for (const float turn : {0.0f, 3.14159265f}) {
    Scene s = sphere_over_plane();
    s.meshes[1] = {"square", make_plane(1.6f, 1.6f, 2)};
    s.objects[1].model =
        (Eigen::Translation3f(0.0f, 1.5f, 0.0f) * Eigen::AngleAxisf(turn + 0.3f, Vec3::UnitX())).matrix();
    const Agreement a = compare_with_raycast(s, 1, ShadowFilter::none, ShadowMethod::volume);
    EXPECT_GT(a.shadowed, 150) << turn;
  }
}

// Adjacency: shapes with split vertices (seams, creases) are closed once welded; a plane is open; a triangle turned the
// wrong way opens a mesh.
TEST(ShadowVolumes, AdjacencyWeldsSplitVertices) {
  shadow::MeshEdges e;
  for (const Mesh& closed : {make_uv_sphere(1.0f, 24, 12), make_cube(1.0f, 1), make_cube(2.0f, 3)}) {
    e.build(closed);
    EXPECT_TRUE(e.closed);
    EXPECT_TRUE(e.built_from(closed));
    std::size_t uses = 0;
    for (std::size_t k = 0; k + 1 < e.first.size(); ++k) uses += e.first[k + 1] - e.first[k];
    EXPECT_EQ(uses,
              3 * closed.triangle_count());  // no degenerate triangle in these shapes
  }
  const Mesh plane = make_plane(1.0f, 1.0f, 3);
  e.build(plane);
  EXPECT_FALSE(e.closed);
  Mesh flipped = make_cube(1.0f, 1);
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_FALSE(e.built_from(flipped));
  e.build(flipped);
  EXPECT_FALSE(e.closed);
}

}  // namespace
}  // namespace facet

namespace facet {
namespace {

// Flat and Gouraud shading with shadows (the renderer's sub-frames summed per pixel): the shadow's
// edge runs through triangles, per pixel, with every method.
struct Images {
  std::vector<std::uint8_t> shadowed, lit, dark;
};
Images flat_or_gouraud(const Scene& s, ShadingMode shading, int threads = 0) {
  Scene lit = s, dark = s;
  lit.lights[0].shadow.method = ShadowMethod::none;
  dark.lights[0].enabled = false;
  return {render(s, threads, LightingPath::simd, Isa::best, nullptr, shading),
          render(lit, threads, LightingPath::simd, Isa::best, nullptr, shading),
          render(dark, threads, LightingPath::simd, Isa::best, nullptr, shading)};
}
bool within_one_step(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, std::size_t at) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(int(a[at + static_cast<std::size_t>(c)]) - int(b[at + static_cast<std::size_t>(c)])) > 1) return false;
  }
  return true;
}

TEST(ShadowsInFlatAndGouraud, MatchTheSpheresExactShadowPerPixel) {
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    for (const ShadowMethod method : {ShadowMethod::raycast, ShadowMethod::map, ShadowMethod::volume}) {
      for (const Scene& base : {sphere_over_plane(), spot_over_sphere()}) {
        Scene s = base;
        s.lights[0].shadow.method = method;
        s.lights[0].shadow.filter = ShadowFilter::none;
        SCOPED_TRACE(std::string(to_string(shading)) + " " + to_string(method) + " light " +
                     std::to_string(static_cast<int>(s.lights[0].type)));
        const Images img = flat_or_gouraud(s, shading);
        const double margin = 8.0 / kSize * 2.0 + (method == ShadowMethod::map ? map_margin(s.lights[0]) : 0.0);
        int in_shadow = 0, in_light = 0, wrong = 0;
        for (int y = 0; y < kSize; ++y) {
          for (int x = 0; x < kSize; ++x) {
            const PlanePoint pp = plane_point(s, x, y);
            if (pp.behind_sphere || std::abs(pp.p.x()) > 3.9f || std::abs(pp.p.z()) > 3.9f) continue;
            const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
            if (within_one_step(img.lit, img.dark, at)) continue;  // the light does not reach it
            if (pp.shadow_margin < -margin) {
              ++in_shadow;
              if (!within_one_step(img.shadowed, img.dark, at) && ++wrong <= 5) ADD_FAILURE() << "lit in the shadow at " << x << ", " << y;
            } else if (pp.shadow_margin > margin) {
              ++in_light;
              if (!within_one_step(img.shadowed, img.lit, at) && ++wrong <= 5) ADD_FAILURE() << "shadowed in the light at " << x << ", " << y;
            }
          }
        }
        EXPECT_EQ(wrong, 0);
        EXPECT_GT(in_shadow, 100);
        EXPECT_GT(in_light, 500);
      }
    }
  }
}

// Per pixel, not per vertex: the plane has 4 x 4 quads, so a triangle of it holds both shadowed
// and lit pixels, which per-vertex visibility could not draw.
TEST(ShadowsInFlatAndGouraud, ATriangleHoldsBothShadowAndLight) {
  Scene s = sphere_over_plane();
  const Images img = flat_or_gouraud(s, ShadingMode::flat);
  // Flat: one colour per triangle without shadows; with them, a triangle's pixels take two values.
  // The plane's triangle under the shadow's edge at world (1.5, 0, 0): find pixels of both kinds
  // within one of its quads (x in [0, 2], z in [0, 2]).
  int shadowed = 0, lit = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const PlanePoint pp = plane_point(s, x, y);
      if (pp.behind_sphere || pp.p.x() < 0.05f || pp.p.x() > 1.95f || pp.p.z() < 0.05f || pp.p.z() > 1.95f) continue;
      const std::size_t at = static_cast<std::size_t>(y * kSize + x) * 4;
      shadowed += std::memcmp(&img.shadowed[at], &img.lit[at], 3) != 0 ? 1 : 0;
      lit += within_one_step(img.shadowed, img.lit, at) ? 1 : 0;
    }
  }
  EXPECT_GT(shadowed, 20);
  EXPECT_GT(lit, 20);
}

TEST(ShadowsInFlatAndGouraud, SameBytesForEveryThreadCount) {
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    for (const ShadowMethod method : {ShadowMethod::raycast, ShadowMethod::map, ShadowMethod::volume}) {
      Scene s = point_over_sphere();
      s.lights[0].shadow.method = method;
      const auto one = render(s, 1, LightingPath::simd, Isa::best, nullptr, shading);
      EXPECT_EQ(render(s, 2, LightingPath::simd, Isa::best, nullptr, shading), one) << to_string(method);
      EXPECT_EQ(render(s, 8, LightingPath::simd, Isa::best, nullptr, shading), one) << to_string(method);
    }
  }
}

// Nothing casting: every pixel sees the light, and the summed sub-frames are the unshadowed frame
// to within a step (the shadowed light's terms are interpolated apart from the rest).
TEST(ShadowsInFlatAndGouraud, NothingToCastIsTheUnshadowedImageWithinAStep) {
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    Scene s = spot_over_sphere();
    for (Instance& i : s.objects) i.cast_shadows = false;
    Scene none = s;
    none.lights[0].shadow.method = ShadowMethod::none;
    const auto a = render(s, 0, LightingPath::simd, Isa::best, nullptr, shading);
    const auto b = render(none, 0, LightingPath::simd, Isa::best, nullptr, shading);
    for (std::size_t at = 0; at < a.size(); at += 4) ASSERT_TRUE(within_one_step(a, b, at)) << at / 4;
  }
}

// The same with textures and emission added after them (Material::emissive_texture): the
// emission belongs to the base sub-frame alone (counted twice, or modulated, it would show).
TEST(ShadowsInFlatAndGouraud, EmissionAfterTheTextureIsCountedOnce) {
  auto checker = [](int n, std::uint8_t lo, std::uint8_t hi) {
    std::vector<std::uint8_t> rgba;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::uint8_t v = (i + j) % 2 ? hi : lo;
        rgba.insert(rgba.end(), {v, static_cast<std::uint8_t>(v / 2), static_cast<std::uint8_t>(255 - v), 255});
      }
    Result<Texture> t = make_texture("checker", n, n, rgba, TextureOptions{});
    EXPECT_TRUE(t.ok());
    return std::move(*t);
  };
  for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::flat}) {
    Scene s = spot_over_sphere();
    s.textures.push_back(checker(8, 40, 220));
    s.textures.push_back(checker(4, 0, 255));
    Material& m = s.materials[0];
    m.diffuse_texture = 0;
    m.emissive_texture = 1;
    m.emissive = Color3(0.3f, 0.2f, 0.1f);
    for (Instance& i : s.objects) i.cast_shadows = false;
    Scene none = s;
    none.lights[0].shadow.method = ShadowMethod::none;
    const auto a = render(s, 0, LightingPath::simd, Isa::best, nullptr, shading);
    const auto b = render(none, 0, LightingPath::simd, Isa::best, nullptr, shading);
    for (std::size_t at = 0; at < a.size(); at += 4) ASSERT_TRUE(within_one_step(a, b, at)) << to_string(shading) << " " << at / 4;
  }
}

}  // namespace
}  // namespace facet
