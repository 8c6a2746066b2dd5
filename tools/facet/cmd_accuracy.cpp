// facet accuracy: how far every fast method is from the exact one, at three levels.
//
//  1. Vertices: 10^5 random vertices (16 random materials, shininess 0..256, some black
//     specular; 8 random lights of every type) lit by every path x ISA x pow tier, against the
//     reference path (double precision): max and mean error in 8-bit steps, the largest
//     difference after rounding to 8 bits, NaN count. Then the special inputs (n.h = 1 at high
//     shininess, light at the vertex, zero normals, L = -V, 0^0, eye at the vertex).
//  2. Pow methods: every tier on every ISA over its failure inputs (NaN, negative, 0, subnormal,
//     1 - ulp, 1, 1 + ulp, +inf, huge exponents), against double-precision pow of the clamped
//     input: where each returns NaN, leaves [0, 1], or exceeds its stated contract.
//  3. Images: a scene of spheres on a plane, ray-cast per pixel in double precision from the
//     exact geometry (not its triangles) and lit by the reference path at the exact hit point and
//     normal; then facet's flat, Gouraud and Phong images at several tessellation levels: PSNR and
//     largest error over the pixels inside the silhouettes (covered in both images, and not on an
//     edge of either).
//  4. Texture filters: nearest, bilinear and trilinear samples of a 256x256 texture at random
//     coordinates (repeat wrap, -3..4) and derivatives (level of detail -2..7), by the scalar
//     sampler and each ISA's SIMD sampler, against the double-precision reference sampler: max
//     and mean error in 8-bit steps, and samples per second on one thread.
//  5. Shadows: a sphere and a cube on a plane under one light at a time (directional, spot,
//     point), each shadow method against ray-cast shadows (exact visibility): per method x
//     resolution x filter, the share of receiver pixels (pixels the light reaches) whose colour
//     differs from the ray-cast image by more than one step, how far (in pixels) the farthest of
//     them lies from a ray-cast shadow edge, PSNR against the ray-cast image, and ms per frame.
//  6-7. Environment and bump maps per vertex and per pixel (see their functions).
//  8. Multisampling: edge pixels at 1, 4, 8 and 16 samples against a 64-sample reference.
// Output: a table, or JSON (--json FILE) and CSV (--csv FILE).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <cstring>
#include <fstream>
#include <memory>
#include <numbers>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "cli.hpp"
#include "common/format.hpp"
#include "common/look_at.hpp"
#include "lighting/point_shader.hpp"
#include "texture/sampler.hpp"
#include "raster/tile_raster.hpp"
#include "texture/sampler.hpp"

namespace facet::cli {
namespace {

// One measurement: what was measured (kind, method, case) and its numbers.
struct Row {
  std::string kind;    // "vertices", "special", "pow", "image"
  std::string method;  // e.g. "simd avx2 (pow fast)", "pow fast avx2", "phong"
  std::string item;    // e.g. "random", "light at vertex", "x=nan s=3", "segments=64"
  double max_lsb = 0;  // largest |error| in 8-bit steps
  double mean_lsb = 0;
  int max_step = 0;  // largest difference after rounding both to 8 bits
  long nans = 0;
  double psnr_db = 0;     // images
  double ms_per_frame = 0;  // images: the same frame on the default path (simd, best ISA), 1 thread
  double rate = 0;          // textures: samples per second, 1 thread
  double share = 0;         // shadows: share of receiver pixels that differ from ray-cast shadows
  double edge_px = 0;       // shadows: the farthest of them from a ray-cast shadow edge, pixels
  std::string verdict;    // "ok" or what failed
};

std::string number(double v) {
  if (std::isnan(v)) return "null";
  if (std::isinf(v)) return v > 0 ? "1e999" : "-1e999";
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

// --- 1. vertices -------------------------------------------------------------------------------

Scene random_scene(int vertex_count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  Scene s;
  s.camera.eye = Vec3(0, 0, 6);
  s.global_ambient = Color3(0.1f, 0.1f, 0.1f);
  const int objects = 16;
  for (int o = 0; o < objects; ++o) {
    Mesh m;
    const int n = vertex_count / objects / 3 * 3;
    for (int i = 0; i < n; ++i) {
      m.positions.emplace_back(2 * u(rng), 2 * u(rng), 2 * u(rng));
      Vec3 nn(u(rng), u(rng), u(rng));
      m.normals.push_back(nn.norm() > 1e-3f ? Vec3(nn.normalized()) : Vec3(0, 0, 1));
    }
    for (int i = 0; i + 2 < n; i += 3) {
      m.triangles.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1), static_cast<std::uint32_t>(i + 2)});
    }
    s.meshes.push_back({"random" + std::to_string(o), m});
    Material mat;
    mat.emissive = Color3(0.1f * u01(rng), 0.1f * u01(rng), 0.1f * u01(rng));
    mat.ambient = Color3(u01(rng), u01(rng), u01(rng)) * 0.3f;
    mat.diffuse = Color3(u01(rng), u01(rng), u01(rng)) * 0.7f;
    mat.specular = o % 5 == 0 ? Color3(0, 0, 0) : Color3(u01(rng), u01(rng), u01(rng)) * 0.6f;
    // Shininess 0..256: whole numbers, fractions, 0.
    const float s_raw = 256.0f * u01(rng) * u01(rng);
    mat.shininess = o % 4 == 0 ? std::round(s_raw) : (o % 7 == 0 ? 0.0f : s_raw);
    s.materials.push_back(mat);
    s.objects.push_back({static_cast<std::uint32_t>(o), static_cast<std::uint32_t>(o), Mat4::Identity()});
  }
  for (int i = 0; i < 8; ++i) {
    Light l;
    l.position = Vec3(4 * u(rng), 4 * u(rng), 4 * u(rng));
    l.direction = Vec3(u(rng), u(rng), -1.0f).normalized();
    l.ambient = Color3(u01(rng), u01(rng), u01(rng)) * 0.1f;
    l.diffuse = Color3(u01(rng), u01(rng), u01(rng)) * 0.5f;
    l.specular = Color3(u01(rng), u01(rng), u01(rng)) * 0.5f;
    switch (i % 4) {
      case 0: l.type = LightType::directional; break;
      case 1:
        l.type = LightType::point;
        l.linear_attenuation = 0.2f * u01(rng);
        l.quadratic_attenuation = 0.1f * u01(rng);
        break;
      case 2:
        l.type = LightType::spot;
        l.direction = (-l.position).normalized();
        l.spot_cutoff_deg = 20 + 60 * u01(rng);
        l.spot_exponent = 64 * u01(rng);
        break;
      default:
        l.type = LightType::spot;
        l.direction = (-l.position).normalized();
        l.spot_shape = SpotShape::smooth_cone;
        l.spot_inner_deg = 10 + 20 * u01(rng);
        l.spot_outer_deg = l.spot_inner_deg + 30 * u01(rng);
        break;
    }
    s.lights.push_back(l);
  }
  return s;
}

// The special inputs, one object each, named.
std::vector<std::pair<std::string, Scene>> special_scenes() {
  std::vector<std::pair<std::string, Scene>> out;
  auto base = [](float shininess) {
    Scene s;
    s.camera.eye = Vec3(0, 0, 5);
    Material m;
    m.diffuse = Color3(0.6f, 0.6f, 0.6f);
    m.specular = Color3(1, 1, 1);
    m.shininess = shininess;
    s.materials.push_back(m);
    return s;
  };
  auto one_vertex = [](Scene& s, const Vec3& p, const Vec3& n) {
    Mesh m;
    m.positions = {p, p + Vec3(1e-3f, 0, 0), p + Vec3(0, 1e-3f, 0)};
    m.normals = {n, n, n};
    m.triangles = {{0, 1, 2}};
    s.meshes.push_back({"v", m});
    s.objects.push_back({0, 0, Mat4::Identity()});
  };
  {  // n.h = 1 (light and eye both along the normal) at the largest shininess
    Scene s = base(4096);
    Light l;
    l.direction = Vec3(0, 0, -1);
    s.lights.push_back(l);
    s.viewer = ViewerMode::infinite;
    one_vertex(s, Vec3(0, 0, 0), Vec3(0, 0, 1));
    out.emplace_back("n.h = 1, shininess 4096", s);
  }
  {  // light exactly at the vertex
    Scene s = base(32);
    Light l;
    l.type = LightType::point;
    l.position = Vec3(0.5f, 0.25f, 0.125f);
    s.lights.push_back(l);
    one_vertex(s, Vec3(0.5f, 0.25f, 0.125f), Vec3(0, 0, 1));
    out.emplace_back("point light at the vertex", s);
  }
  {  // zero normal
    Scene s = base(32);
    s.lights.push_back(Light{});
    one_vertex(s, Vec3(0, 0, 0), Vec3(0, 0, 0));
    out.emplace_back("zero normal", s);
  }
  {  // L = -V: the light straight behind the vertex, seen from the eye
    Scene s = base(32);
    Light l;
    l.type = LightType::point;
    l.position = Vec3(0, 0, -5);
    s.lights.push_back(l);
    one_vertex(s, Vec3(0, 0, 0), Vec3(0, 0, 1));
    out.emplace_back("L = -V", s);
  }
  {  // 0^0: shininess 0 and n.h = 0
    Scene s = base(0);
    Light l;
    l.direction = Vec3(-1, 0, 0);  // grazing: n.l = 0 exactly
    s.lights.push_back(l);
    s.viewer = ViewerMode::infinite;
    one_vertex(s, Vec3(0, 0, 0), Vec3(0, 0, 1));
    out.emplace_back("0^0 (shininess 0, grazing light)", s);
  }
  {  // eye at the vertex (local viewer: V has no direction)
    Scene s = base(32);
    s.camera.eye = Vec3(0, 0, 0);
    s.camera.target = Vec3(0, 0, -1);
    s.lights.push_back(Light{});
    one_vertex(s, Vec3(0, 0, 0), Vec3(0, 0, 1));
    out.emplace_back("eye at the vertex", s);
  }
  return out;
}

struct Method {
  std::string name;
  LightingOptions options;
};

std::vector<Method> all_methods() {
  std::vector<Method> v;
  LightingOptions o;
  o.path = LightingPath::scalar;
  v.push_back({"scalar", o});
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    if (!isa_supported(isa)) continue;
    for (PowTier tier : {PowTier::automatic, PowTier::exact, PowTier::fast, PowTier::integer, PowTier::schlick}) {
      o.path = LightingPath::simd;
      o.isa = isa;
      o.pow_tier = tier;
      v.push_back({describe_path(LightingPath::simd, isa, tier), o});
    }
  }
  return v;
}

// Errors of `got` against `ref` over all objects' front colours.
Row compare_colours(const std::vector<VertexColors>& ref, const std::vector<VertexColors>& got) {
  Row r;
  double sum = 0;
  long count = 0;
  for (std::size_t o = 0; o < ref.size(); ++o) {
    for (std::size_t i = 0; i < ref[o].front.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        const double a = ref[o].front[i][c], b = got[o].front[i][c];
        if (std::isnan(b)) {
          ++r.nans;
          continue;
        }
        const double d = std::abs(a - b) * 255.0;
        r.max_lsb = std::max(r.max_lsb, d);
        sum += d;
        ++count;
        auto step = [](double v) { return static_cast<int>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5); };
        r.max_step = std::max(r.max_step, std::abs(step(a) - step(b)));
      }
    }
  }
  r.mean_lsb = count ? sum / double(count) : 0;
  return r;
}

// The contract of a lighting method's vertex colours against the double reference, in absolute
// float error (max_lsb / 255), with the measured value it leaves margin for (10^5 random vertices,
// 8 lights of every type, shininess 0-256; README "pow tiers"):
//   exact tier                    2e-6   (measured 0 on sse2, avx2 and avx512)
//   auto, fast and integer tiers  3e-5   (measured 1.84e-5 at most: the fast pow's 2.2e-5 contract
//                                         scaled by the specular colour, plus the float kernel)
//   scalar path                   1e-5   (measured 1.6e-6: float arithmetic, std::pow)
//   schlick                       none   (a different lobe)
// and every promised method is also within one 8-bit step. Phong's R.V lobe (every material of
// the "random, phong lobe" case) keeps the same contracts except the auto, fast and integer tiers'
// 4e-5 (measured 3.09e-5 on sse2, 2.95e-5 on avx2 and avx512: the fast pow's error where R.V's
// wider lobe puts more points).
std::string colour_verdict(const LightingOptions& o, const Row& r, bool phong_lobe = false) {
  if (r.nans) return "NaN";
  double bound = 1e-5;
  if (o.path == LightingPath::simd) {
    if (o.pow_tier == PowTier::schlick) return "ok (schlick: a different lobe, no accuracy promised)";
    bound = o.pow_tier == PowTier::exact ? 2e-6 : phong_lobe ? 4e-5 : 3e-5;
  }
  const double err = r.max_lsb / 255.0;
  if (err > bound) return "above contract (" + format_number(bound) + ", found " + format_number(err) + ")";
  if (r.max_step > 1) return "more than 1 step";
  return "ok";
}

Status vertex_accuracy(bool quick, std::vector<Row>& rows) {
  const Scene scene = random_scene(quick ? 10000 : 100000, 2026);
  LightingOptions ref_options;
  ref_options.path = LightingPath::reference;
  std::vector<VertexColors> ref, got;
  if (Status s = light_scene(scene, ref_options, ref); !s.ok()) return s;
  const auto specials = special_scenes();
  Scene phong = scene;  // the same points and lights, every material on Phong's R.V lobe
  for (Material& mat : phong.materials) mat.specular_model = SpecularModel::phong;
  std::vector<VertexColors> phong_ref;
  if (Status s = light_scene(phong, ref_options, phong_ref); !s.ok()) return s;
  for (const Method& m : all_methods()) {
    if (Status s = light_scene(scene, m.options, got); !s.ok()) return s;
    Row r = compare_colours(ref, got);
    r.kind = "vertices";
    r.method = m.name;
    r.item = "random";
    r.verdict = colour_verdict(m.options, r);
    rows.push_back(r);
    if (Status s = light_scene(phong, m.options, got); !s.ok()) return s;
    Row pr = compare_colours(phong_ref, got);
    pr.kind = "vertices";
    pr.method = m.name;
    pr.item = "random, phong lobe";
    pr.verdict = colour_verdict(m.options, pr, true);
    rows.push_back(pr);
    for (const auto& [name, special] : specials) {
      std::vector<VertexColors> sref, sgot;
      if (Status s = light_scene(special, ref_options, sref); !s.ok()) return s;
      if (Status s = light_scene(special, m.options, sgot); !s.ok()) return s;
      Row sr = compare_colours(sref, sgot);
      sr.kind = "special";
      sr.method = m.name;
      sr.item = name;
      sr.verdict = colour_verdict(m.options, sr);
      rows.push_back(sr);
    }
  }
  return {};
}

// --- 2. pow methods ----------------------------------------------------------------------------

void pow_sweep(std::vector<Row>& rows) {
  using lighting::simd::PowMethod;
  using lighting::simd::PowSpec;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float xs[] = {nan, -inf, -0.5f, -0.0f, 0.0f, 1e-40f, 1e-20f, 0.25f, 0.5f, std::nextafter(1.0f, 0.0f),
                      1.0f, std::nextafter(1.0f, 2.0f), 2.0f, inf};
  const float ss[] = {0.0f, 0.01f, 0.5f, 1.0f, 3.0f, 37.5f, 128.0f, 256.0f, 1024.0f, 4096.0f};
  struct Tier {
    const char* name;
    PowMethod method;
  };
  const Tier tiers[] = {{"exact", PowMethod::exact}, {"fast", PowMethod::fast}, {"integer", PowMethod::integer},
                        {"schlick", PowMethod::schlick}};
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    const lighting::SimdKernels* k = lighting::simd_kernels(isa);
    if (!k) continue;
    for (const Tier& tier : tiers) {
      for (float s : ss) {
        if (tier.method == PowMethod::integer && (s != std::floor(s) || s > 256)) continue;  // outside its domain
        alignas(64) float in[lighting::simd::kMaxLanes * 2] = {};
        alignas(64) float out[lighting::simd::kMaxLanes * 2] = {};
        const std::size_t n = std::size(xs);
        std::copy(std::begin(xs), std::end(xs), in);
        k->pow(PowSpec{tier.method, s, static_cast<int>(s)}, in, out, lighting::simd::kMaxLanes * 2);
        for (std::size_t i = 0; i < n; ++i) {
          const float x = xs[i];
          const double clamped = std::isnan(x) ? 0.0 : std::clamp(double(x), 0.0, 1.0);
          const double exact = (clamped == 0.0 && s == 0.0f) ? 1.0 : std::pow(clamped, double(s));
          Row r;
          r.kind = "pow";
          r.method = std::string("pow ") + tier.name + " " + to_string(isa);
          std::ostringstream item;
          item << "x=" << x << " s=" << s;
          r.item = item.str();
          const float y = out[i];
          r.nans = std::isnan(y) ? 1 : 0;
          r.max_lsb = std::isnan(y) ? 0 : std::abs(double(y) - exact) * 255.0;
          r.mean_lsb = r.max_lsb;
          // Contracts (engine/src/fastmath/pow_simd.hpp): exact 2e-6 up to s = 1024 (measured
          // 9.7e-8); fast 2.2e-5 up to s = 256 (measured 2.0e-5); integer 7.7e-6 for whole s up
          // to 256 (measured 5.0e-6); schlick promises none.
          const double err = std::isnan(y) ? INFINITY : std::abs(double(y) - exact);
          std::string verdict = "ok";
          if (std::isnan(y)) {
            verdict = "NaN";
          } else if (y < 0.0f || y > 1.0f) {
            verdict = "outside [0, 1]";
          } else if (tier.method == PowMethod::exact && s <= 1024 && err > 2e-6) {
            verdict = "above contract (2e-6)";
          } else if (tier.method == PowMethod::fast && s <= 256 && err > 2.2e-5) {
            verdict = "above contract (2.2e-5)";
          } else if (tier.method == PowMethod::integer && err > 7.7e-6) {
            verdict = "above contract (7.7e-6)";
          } else if (tier.method == PowMethod::schlick) {
            verdict = "ok (no contract)";
          } else if (s > 256 && tier.method == PowMethod::fast) {
            verdict = "ok (outside its contract's range)";
          }
          r.verdict = verdict;
          rows.push_back(r);
        }
      }
    }
  }
}

// --- 3. images ---------------------------------------------------------------------------------

struct Sphere {
  Eigen::Vector3d centre;
  double radius;
  std::uint32_t material;
};

// The reference scene: three spheres on a ground plane, two lights (directional and point).
Scene image_scene(int segments, const std::vector<Sphere>& spheres, double plane_y) {
  Scene s;
  s.camera.eye = Vec3(0, 1.2f, 5.5f);
  s.camera.target = Vec3(0, 0.5f, 0);
  s.camera.vertical_fov_deg = 40;
  s.camera.near = 0.5f;
  s.camera.far = 30;
  s.global_ambient = Color3(0.1f, 0.1f, 0.1f);
  const Color3 colours[] = {{0.8f, 0.2f, 0.2f}, {0.2f, 0.7f, 0.3f}, {0.2f, 0.3f, 0.9f}, {0.6f, 0.6f, 0.55f}};
  for (int m = 0; m < 4; ++m) {
    Material mat;
    mat.ambient = colours[m] * 0.5f;
    mat.diffuse = colours[m];
    mat.specular = m < 3 ? Color3(0.6f, 0.6f, 0.6f) : Color3(0.1f, 0.1f, 0.1f);
    mat.shininess = m == 0 ? 16.0f : (m == 1 ? 60.0f : (m == 2 ? 128.0f : 8.0f));
    s.materials.push_back(mat);
  }
  s.meshes.push_back({"sphere", make_uv_sphere(1.0f, segments, std::max(2, segments / 2))});
  for (const Sphere& sp : spheres) {
    Mat4 t = Mat4::Identity();
    t.topLeftCorner<3, 3>() *= static_cast<float>(sp.radius);
    t.block<3, 1>(0, 3) = sp.centre.cast<float>();
    s.objects.push_back({0, sp.material, t});
  }
  s.meshes.push_back({"ground", make_plane(20.0f, 20.0f, std::max(1, segments / 4))});
  Mat4 g = Mat4::Identity();
  g(1, 3) = static_cast<float>(plane_y);
  s.objects.push_back({1, 3, g});
  Light sun;
  sun.direction = Vec3(-0.4f, -1.0f, -0.5f).normalized();
  sun.diffuse = Color3(0.7f, 0.7f, 0.7f);
  sun.specular = Color3(0.7f, 0.7f, 0.7f);
  s.lights.push_back(sun);
  Light lamp;
  lamp.type = LightType::point;
  lamp.position = Vec3(2.0f, 3.0f, 2.5f);
  lamp.diffuse = Color3(0.6f, 0.55f, 0.5f);
  lamp.specular = Color3(0.8f, 0.8f, 0.8f);
  lamp.linear_attenuation = 0.05f;
  s.lights.push_back(lamp);
  return s;
}

struct Image {
  int w = 0, h = 0;
  std::vector<std::uint8_t> rgba;
  std::vector<std::uint8_t> covered;
  std::vector<int> object;  // reference only: which object the pixel shows (-1: none)
};

// Ray-cast reference: per pixel centre, the nearest exact hit (spheres and the plane, in double
// precision, eye space), lit by the reference path at the exact point and normal.
Status raycast(const Scene& scene, const std::vector<Sphere>& spheres, double plane_y, int w, int h, Image& out) {
  const Eigen::Matrix4d view = look_at_d(scene.camera);
  std::vector<lighting::PointShader> shaders(scene.materials.size());
  LightingOptions o;
  o.path = LightingPath::reference;
  o.cull_lights = false;
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    if (Status s = shaders[m].prepare(scene, view, scene.materials[m], o); !s.ok()) return s;
  }
  struct Hit {
    double t = INFINITY;
    Eigen::Vector3d n;
    std::uint32_t material = 0;
    int object = -1;
  };
  std::vector<std::pair<Eigen::Vector3d, double>> centres;  // eye space
  for (const Sphere& sp : spheres) centres.emplace_back((view * sp.centre.homogeneous()).head<3>(), sp.radius);
  const Eigen::Vector3d plane_n = view.topLeftCorner<3, 3>() * Eigen::Vector3d(0, 1, 0);
  const Eigen::Vector3d plane_p = (view * Eigen::Vector4d(0, plane_y, 0, 1)).head<3>();
  const double tan_half = std::tan(double(scene.camera.vertical_fov_deg) * M_PI / 360.0);
  const double aspect = double(w) / double(h);
  const Eigen::Matrix4d eye_to_world = view.inverse();
  out.w = w, out.h = h;
  out.rgba.assign(static_cast<std::size_t>(w * h * 4), 0);
  out.covered.assign(static_cast<std::size_t>(w * h), 0);
  out.object.assign(static_cast<std::size_t>(w * h), -1);
  lighting::SoaScratch scratch;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double ndc_x = 2.0 * (x + 0.5) / w - 1.0, ndc_y = 1.0 - 2.0 * (y + 0.5) / h;
      const Eigen::Vector3d d = Eigen::Vector3d(ndc_x * tan_half * aspect, ndc_y * tan_half, -1.0).normalized();
      Hit hit;
      for (std::size_t i = 0; i < centres.size(); ++i) {
        const Eigen::Vector3d& c = centres[i].first;
        const double r = centres[i].second;
        const double b = d.dot(c), disc = b * b - (c.squaredNorm() - r * r);
        if (disc < 0) continue;
        const double t = b - std::sqrt(disc);
        if (t > 0 && t < hit.t) hit = {t, (t * d - c) / r, spheres[i].material, static_cast<int>(i)};
      }
      const double denom = d.dot(plane_n);
      if (std::abs(denom) > 1e-12) {
        const double t = plane_p.dot(plane_n) / denom;
        const Eigen::Vector3d p = t * d;
        // The plane is a 20 x 20 square around the origin (as the mesh).
        const Eigen::Vector4d world = eye_to_world * p.homogeneous();
        if (t > 0 && t < hit.t && std::abs(world.x()) <= 10 && std::abs(world.z()) <= 10) {
          hit = {t, plane_n, 3, static_cast<int>(centres.size())};
        }
      }
      if (!std::isfinite(hit.t)) continue;
      // Beyond the far plane the rasterizer draws nothing either.
      if (hit.t * -d.z() > scene.camera.far) continue;
      const Vec3 p = (hit.t * d).cast<float>(), n = hit.n.normalized().cast<float>();
      Color3 c;
      shaders[hit.material].shade_points(1, &p, &n, &c, scratch);
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      for (int k = 0; k < 3; ++k) out.rgba[4 * i + k] = static_cast<std::uint8_t>(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
      out.rgba[4 * i + 3] = 255;
      out.covered[i] = 1;
      out.object[i] = hit.object;
    }
  }
  return {};
}

Row compare_images_inside(const Image& ref, const Image& got) {
  Row r;
  double sum = 0, sq = 0;
  long n = 0;
  // Inside a silhouette: the pixel and its 8 neighbours are covered (and, in the reference, show
  // the same object): edges, where tessellation moves the outline, are left out.
  auto interior = [&](const Image& im, int x, int y) {
    const int id = im.object.empty() ? 0 : im.object[static_cast<std::size_t>(y * im.w + x)];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= im.w || yy >= im.h) return false;
        const std::size_t j = static_cast<std::size_t>(yy * im.w + xx);
        if (!im.covered[j] || (!im.object.empty() && im.object[j] != id)) return false;
      }
    return true;
  };
  for (int y = 0; y < ref.h; ++y) {
    for (int x = 0; x < ref.w; ++x) {
      if (!interior(ref, x, y) || !interior(got, x, y)) continue;
      const std::size_t i = static_cast<std::size_t>(y * ref.w + x);
      for (int k = 0; k < 3; ++k) {
        const double d = std::abs(double(ref.rgba[4 * i + k]) - double(got.rgba[4 * i + k]));
        r.max_lsb = std::max(r.max_lsb, d);
        sum += d;
        sq += d * d;
        ++n;
      }
    }
  }
  r.mean_lsb = n ? sum / double(n) : 0;
  r.max_step = static_cast<int>(r.max_lsb);
  r.psnr_db = sq > 0 ? 10.0 * std::log10(255.0 * 255.0 / (sq / double(n))) : INFINITY;
  return r;
}

Status image_accuracy(bool quick, std::vector<Row>& rows) {
  const std::vector<Sphere> spheres = {{{-1.3, 0.6, 0.0}, 0.6, 0}, {{0.1, 0.8, -0.6}, 0.8, 1}, {{1.4, 0.45, 0.5}, 0.45, 2}};
  const double plane_y = 0.0;
  const int w = quick ? 320 : 640, h = quick ? 200 : 400;
  Image ref;
  if (Status s = raycast(image_scene(8, spheres, plane_y), spheres, plane_y, w, h, ref); !s.ok()) return s;
  std::vector<int> levels = quick ? std::vector<int>{16, 64, 256} : std::vector<int>{8, 16, 32, 64, 128, 256};
  // Every image on the reference path, the scalar path and the simd path of each ISA (auto tier):
  // each against the ray-cast spheres (Phong >= 45 dB inside the silhouettes at the finest
  // tessellation), and each non-reference image against the reference path's image of the same
  // frame: the same coverage, colours within 1 step (the project's cross-path contract).
  struct PathChoice {
    std::string name;
    LightingPath path;
    Isa isa;
  };
  std::vector<PathChoice> paths = {{"reference", LightingPath::reference, Isa::best},
                                   {"scalar", LightingPath::scalar, Isa::best}};
  for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
    if (isa_supported(isa)) paths.push_back({std::string("simd ") + to_string(isa), LightingPath::simd, isa});
  }
  for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
    for (int segments : levels) {
      const Scene scene = image_scene(segments, spheres, plane_y);
      Image reference_path;
      for (const PathChoice& choice : paths) {
        Image got;
        got.w = w, got.h = h;
        got.rgba.assign(static_cast<std::size_t>(w * h * 4), 0);
        std::vector<float> depth(static_cast<std::size_t>(w * h));
        RenderOptions o;
        o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
        o.shading = mode;
        o.path = choice.path;
        o.isa = choice.isa;
        o.clear_color = {0, 0, 0, 0};
        const ImageView view{got.rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
        const DepthView dv{depth.data(), w, h, static_cast<std::size_t>(w) * sizeof(float), false};
        Renderer r;
        if (Status s = r.render(scene, o, view, &dv); !s.ok()) return s;
        got.covered.resize(depth.size());
        for (std::size_t i = 0; i < depth.size(); ++i) got.covered[i] = depth[i] < 1.0f;
        Row row = compare_images_inside(ref, got);
        if (choice.path == LightingPath::simd && choice.isa == best_isa()) {
          // The speed side of the chart: the same frame on this path, one thread.
          RenderOptions fast = o;
          fast.threads = 1;
          Renderer timed(fast);
          (void)timed.render(scene, view);  // warm-up; the image is not used
          const int repeats = quick ? 2 : 10;
          const auto t0 = std::chrono::steady_clock::now();
          for (int i = 0; i < repeats; ++i) (void)timed.render(scene, view);
          row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
        }
        row.kind = "image";
        row.method = choice.path == LightingPath::reference ? std::string(to_string(mode))
                                                            : std::string(to_string(mode)) + " " + choice.name;
        row.item = "segments=" + std::to_string(segments);
        row.verdict = "ok";
        if (mode == ShadingMode::phong && segments == levels.back() && row.psnr_db < 45.0) row.verdict = "below 45 dB";
        if (choice.path == LightingPath::reference) {
          reference_path = got;
        } else {
          int worst = 0;
          bool same_coverage = true;
          for (std::size_t i = 0; i < got.covered.size(); ++i) {
            same_coverage &= got.covered[i] == reference_path.covered[i];
            for (int c = 0; c < 3; ++c) {
              worst = std::max(worst, std::abs(int(got.rgba[4 * i + c]) - int(reference_path.rgba[4 * i + c])));
            }
          }
          if (!same_coverage) row.verdict = "coverage differs from the reference path";
          else if (worst > 1) row.verdict = "more than 1 step from the reference path (" + std::to_string(worst) + ")";
        }
        rows.push_back(row);
      }
    }
  }
  return {};
}

// 4. Texture filters against the reference sampler (see the header).
void texture_accuracy(bool quick, std::vector<Row>& rows) {
  constexpr int kSide = 256;
  std::mt19937 rng(1234);
  std::vector<std::uint8_t> rgba(4 * kSide * kSide);
  for (std::size_t i = 0; i < rgba.size(); ++i) {  // smooth bands plus noise: every filter has work to do
    const std::size_t texel = i / 4;
    const double x = double(texel % kSide), y = double(texel / kSide);
    const double v = 127.5 + 80 * std::sin(x * 0.21 + double(i % 4)) * std::cos(y * 0.13) + double(rng() % 40) - 20;
    rgba[i] = static_cast<std::uint8_t>(std::clamp(v, 0.0, 255.0));
  }
  const std::size_t n = quick ? 16384 : 262144;
  std::vector<float> in[6];
  for (auto& v : in) v.resize(n);
  std::uniform_real_distribution<float> coord(-3.0f, 4.0f), lod(-2.0f, 7.0f), angle(0.0f, 6.2831853f);
  for (std::size_t i = 0; i < n; ++i) {
    in[0][i] = coord(rng), in[1][i] = coord(rng);
    const float scale = std::exp2(lod(rng)) / kSide, a = angle(rng);  // |d(s w, t h)| = 2^lod
    in[2][i] = scale * std::cos(a), in[3][i] = scale * std::sin(a);
    in[4][i] = -scale * std::sin(a), in[5][i] = scale * std::cos(a);
  }
  struct Filter {
    TextureFilter filter;
    const char* name;
  };
  for (const Filter f : {Filter{TextureFilter::nearest, "nearest"}, Filter{TextureFilter::bilinear, "bilinear"},
                         Filter{TextureFilter::trilinear, "trilinear"}}) {
    TextureOptions options;
    options.filter = f.filter;
    const Result<Texture> t = make_texture("accuracy", kSide, kSide, rgba, options);
    if (!t) continue;
    const texture::Sampler sampler = texture::make_sampler(*t);
    std::vector<double> ref(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const double lambda = texture::lod_reference(sampler, in[2][i], in[3][i], in[4][i], in[5][i]);
      const auto c = texture::sample_reference(sampler, in[0][i], in[1][i], lambda);
      for (int k = 0; k < 4; ++k) ref[4 * i + static_cast<std::size_t>(k)] = c[static_cast<std::size_t>(k)];
    }
    std::vector<float> out[4];
    for (auto& v : out) v.resize(n);
    float* const outs[4] = {out[0].data(), out[1].data(), out[2].data(), out[3].data()};
    const float* const ins[6] = {in[0].data(), in[1].data(), in[2].data(), in[3].data(), in[4].data(), in[5].data()};
    // run() samples every input; unpack() (untimed) leaves the samples in out as floats 0..1.
    auto measure = [&](const std::string& method, const auto& run, const auto& unpack, double max_steps) {
      run();
      unpack();
      Row r;
      r.kind = "texture";
      r.method = method;
      r.item = f.name;
      double sum = 0;
      std::size_t over_one = 0;
      for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 4; ++k) {
          const double e = std::abs(double(out[k][i]) - ref[4 * i + static_cast<std::size_t>(k)]) * 255.0;
          if (std::isnan(e)) ++r.nans;
          r.max_lsb = std::max(r.max_lsb, e);
          sum += e;
          over_one += e > 1.0;
        }
      }
      r.mean_lsb = sum / double(4 * n);
      int reps = 0;
      const auto start = std::chrono::steady_clock::now();
      double seconds = 0;
      do {
        run();
        ++reps;
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      } while (seconds < (quick ? 0.02 : 0.2));
      r.rate = double(n) * reps / seconds;
      // Contract (docs/textures.md): bilinear and trilinear within a step (the 16-bit tier's
      // fixed-point sampler: 1.5 and 2 steps); nearest picks the reference's texel but for
      // coordinates within float rounding of a texel border.
      if (r.nans) {
        r.verdict = "NaN";
      } else if (f.filter == TextureFilter::nearest) {
        r.verdict = double(over_one) <= 1e-3 * double(4 * n) ? "ok" : "nearest: too many other texels";
      } else {
        r.verdict = r.max_lsb <= max_steps ? "ok" : "over " + number(max_steps) + " steps";
      }
      rows.push_back(r);
    };
    const auto nothing = [] {};
    measure("scalar", [&] {
      for (std::size_t i = 0; i < n; ++i) {
        const float lambda = texture::lod_scalar(sampler, in[2][i], in[3][i], in[4][i], in[5][i]);
        const auto c = texture::sample_scalar(sampler, in[0][i], in[1][i], lambda);
        for (int k = 0; k < 4; ++k) out[k][i] = c[static_cast<std::size_t>(k)];
      }
    }, nothing, 1.0);
    std::vector<std::uint32_t> packed(n);
    const double fixed_steps = f.filter == TextureFilter::trilinear ? 2.0 : 1.5;
    const auto unpack = [&] {
      for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 4; ++k) out[k][i] = static_cast<float>((packed[i] >> (8 * k)) & 0xffu) / 255.0f;
      }
    };
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512}) {
      const raster::simd::Kernels* k = raster::simd_raster_kernels(isa);
      if (!k) continue;
      measure(std::string("simd ") + to_string(isa), [&] { k->sample(sampler, n, ins, outs); }, nothing, 1.0);
      measure(std::string("simd ") + to_string(isa) + " 16-bit", [&] { k->sample_fixed(sampler, n, ins, packed.data()); },
              unpack, fixed_steps);
    }
  }
}

// 5. Shadows against ray-cast shadows (see the header).
Scene shadow_scene(LightType type) {
  Scene s;
  s.meshes.push_back({"ground", make_plane(16.0f, 16.0f, 8)});
  s.meshes.push_back({"ball", make_uv_sphere(1.0f, 96, 48)});
  s.meshes.push_back({"box", make_cube(1.0f, 1)});
  Material ground, red, blue;
  ground.ambient = ground.diffuse = Color3(0.8f, 0.8f, 0.8f);
  red.ambient = red.diffuse = Color3(0.8f, 0.15f, 0.1f);
  blue.ambient = blue.diffuse = Color3(0.2f, 0.3f, 0.8f);
  for (Material* m : {&ground, &red, &blue}) m->specular = Color3(0.3f, 0.3f, 0.3f), m->shininess = 24.0f;
  s.materials = {ground, red, blue};
  s.objects.push_back(Instance{0, 0});
  Instance ball{1, 1}, box{2, 2};
  ball.model.block<3, 1>(0, 3) = Vec3(-0.8f, 1.3f, 0.0f);
  box.model = (Eigen::Translation3f(1.6f, 0.5f, 0.6f) * Eigen::AngleAxisf(0.5236f, Vec3::UnitY())).matrix();
  s.objects.push_back(ball);
  s.objects.push_back(box);
  Light l;
  l.type = type;
  l.diffuse = Color3(0.8f, 0.8f, 0.8f);
  l.specular = Color3(0.5f, 0.5f, 0.5f);
  if (type == LightType::directional) {
    l.direction = Vec3(-0.5f, -1.0f, -0.3f).normalized();
  } else if (type == LightType::spot) {
    l.position = Vec3(2.5f, 5.0f, 2.5f);
    l.direction = Vec3(-0.45f, -1.0f, -0.45f).normalized();
    l.spot_shape = SpotShape::smooth_cone;
    l.spot_inner_deg = 30.0f;
    l.spot_outer_deg = 40.0f;
  } else {
    l.position = Vec3(-2.6f, 2.2f, 1.6f);
  }
  s.lights.push_back(l);
  s.global_ambient = Color3(0.1f, 0.1f, 0.12f);
  s.camera.eye = Vec3(0.0f, 3.5f, 8.0f);
  s.camera.target = Vec3(0.0f, 0.6f, 0.0f);
  s.camera.vertical_fov_deg = 45.0f;
  s.camera.near = 0.1f;
  s.camera.far = 60.0f;
  return s;
}

// The map contract: every pixel that differs from the ray-cast image lies within this many
// pixels (of a 640-pixel-wide image) of a ray-cast shadow edge or an object's outline. A map's
// shadow edge moves by the filter's reach and the bias, a few texels, which light at grazing
// angles stretches over several pixels; and at 1024^2 and finer at most 1.5 % of the receivers
// differ.
double map_edge_contract(int resolution, int taps) { return 8.0 + (taps + 1) * 2048.0 / resolution; }

// The volume contract: differing pixels lie within this many pixels of a ray-cast shadow edge
// or an outline, at any image size (a shadow edge's own pixels may round either way in either
// method), and at most this share of the receivers differ.
constexpr double kVolumeEdgeContract = 1.0;
constexpr double kVolumeShareContract = 0.002;

Status shadow_accuracy(bool quick, std::vector<Row>& rows) {
  const int w = quick ? 320 : 640, h = quick ? 180 : 360;
  struct Kind {
    LightType type;
    const char* name;
  };
  for (const Kind kind : {Kind{LightType::directional, "directional"}, Kind{LightType::spot, "spot"},
                          Kind{LightType::point, "point"}}) {
    const Scene base = shadow_scene(kind.type);
    auto render = [&](const Scene& s, double* ms) -> Result<std::vector<std::uint8_t>> {
      std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4));
      RenderOptions o;
      o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
      o.shading = ShadingMode::phong;
      o.threads = 1;
      const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
      Renderer r(o);
      if (Status st = r.render(s, view); !st.ok()) return st;
      if (ms) {  // the same frame again, one thread: its time with this method
        const int repeats = quick ? 2 : 6;
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < repeats; ++i) (void)r.render(s, view);
        *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
      }
      return rgba;
    };
    auto with = [&](ShadowMethod method, int resolution, ShadowFilter filter) {
      Scene s = base;
      s.lights[0].shadow.method = method;
      s.lights[0].shadow.resolution = resolution;
      s.lights[0].shadow.filter = filter;
      return s;
    };
    Scene off = base;
    off.lights[0].enabled = false;
    double ray_ms = 0;
    const auto exact = render(with(ShadowMethod::raycast, 2048, ShadowFilter::none), &ray_ms);
    const auto lit = render(base, nullptr), dark = render(off, nullptr);
    if (!exact) return exact.status();
    if (!lit) return lit.status();
    if (!dark) return dark.status();
    const std::size_t n = static_cast<std::size_t>(w * h);
    auto differ = [](const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, std::size_t i, int tol) {
      for (int c = 0; c < 3; ++c) {
        if (std::abs(int(a[4 * i + c]) - int(b[4 * i + c])) > tol) return true;
      }
      return false;
    };
    // Which object each pixel shows: the scene unlit, each object glowing in its own colour.
    Scene ids = base;
    ids.lights[0].enabled = false;
    ids.global_ambient = Color3(0, 0, 0);
    for (std::size_t m = 0; m < ids.materials.size(); ++m) {
      ids.materials[m].ambient = Color3(0, 0, 0);
      ids.materials[m].emissive = Color3(m == 0 ? 1.0f : 0.0f, m == 1 ? 1.0f : 0.0f, m == 2 ? 1.0f : 0.0f);
    }
    const auto object = render(ids, nullptr);
    if (!object) return object.status();
    std::vector<std::uint8_t> receiver(n), shadowed(n);
    for (std::size_t i = 0; i < n; ++i) {
      receiver[i] = differ(*lit, *dark, i, 0);
      shadowed[i] = differ(*exact, *lit, i, 0);
    }
    // Distance (in pixels, the larger of |dx| and |dy|) to the nearest edge: a ray-cast shadow
    // edge (a pixel whose shadowed state differs from a neighbour's) or an object's outline (a
    // pixel whose object differs from a neighbour's: where a caster stands on a receiver, a
    // filtered map's shadow reaches past the caster's lit foot by the filter's width).
    std::vector<int> edge_distance(n, 1 << 20);
    std::vector<std::size_t> frontier;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y * w + x);
        auto apart = [&](std::size_t j) { return shadowed[j] != shadowed[i] || std::memcmp(&(*object)[4 * j], &(*object)[4 * i], 3) != 0; };
        const bool edge = (x + 1 < w && apart(i + 1)) || (y + 1 < h && apart(i + w)) || (x > 0 && apart(i - 1)) ||
                          (y > 0 && apart(i - w));
        if (edge) edge_distance[i] = 0, frontier.push_back(i);
      }
    }
    for (int d = 1; !frontier.empty(); ++d) {  // breadth first over the 8 neighbours
      std::vector<std::size_t> next;
      for (const std::size_t i : frontier) {
        const int x = static_cast<int>(i % static_cast<std::size_t>(w)), y = static_cast<int>(i / static_cast<std::size_t>(w));
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int u = x + dx, v = y + dy;
            if (u < 0 || v < 0 || u >= w || v >= h) continue;
            const std::size_t j = static_cast<std::size_t>(v * w + u);
            if (edge_distance[j] > d) edge_distance[j] = d, next.push_back(j);
          }
        }
      }
      frontier.swap(next);
    }
    auto measure = [&](const std::string& method, const std::string& item, const Scene& s, double edge_contract,
                       double share_contract) -> Status {
      Row r;
      r.kind = "shadow";
      r.method = method;
      r.item = std::string(kind.name) + (item.empty() ? "" : " " + item);
      const auto got = render(s, &r.ms_per_frame);
      if (!got) return got.status();
      std::size_t receivers = 0, differing = 0;
      double sq = 0;
      for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
          const double e = double((*got)[4 * i + c]) - double((*exact)[4 * i + c]);
          sq += e * e;
          r.max_step = std::max(r.max_step, static_cast<int>(std::abs(e)));
        }
        if (!receiver[i]) continue;
        ++receivers;
        if (!differ(*got, *exact, i, 1)) continue;
        ++differing;
        r.edge_px = std::max(r.edge_px, double(edge_distance[i]));
      }
      const double mse = sq / double(3 * n);
      r.psnr_db = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : INFINITY;
      r.share = receivers ? double(differing) / double(receivers) : 0.0;
      r.verdict = "ok";
      if (r.edge_px > edge_contract) {
        r.verdict = "differs " + number(r.edge_px) + " px from an edge (contract " + number(edge_contract) + ")";
      } else if (r.share > share_contract) {
        r.verdict = "too many pixels differ (contract " + number(100 * share_contract) + " %)";
      }
      rows.push_back(r);
      return {};
    };
    // Ray-cast against itself: the check that the comparison itself finds nothing.
    if (Status st = measure("raycast", "", with(ShadowMethod::raycast, 2048, ShadowFilter::none), 0.0, 0.0); !st.ok()) {
      return st;
    }
    // Volumes: exact per pixel, so only pixels next to a shadow edge or an outline may differ
    // (where the pixel's Phong position and the mask's pixel round apart, or the two methods'
    // rounding decides a grazing pixel differently), and few of them.
    if (Status st = measure("volume", "", with(ShadowMethod::volume, 2048, ShadowFilter::none), kVolumeEdgeContract,
                            kVolumeShareContract);
        !st.ok()) {
      return st;
    }
    const std::vector<int> resolutions = quick ? std::vector<int>{512, 2048} : std::vector<int>{256, 512, 1024, 2048, 4096};
    const std::vector<ShadowFilter> filters =
        quick ? std::vector<ShadowFilter>{ShadowFilter::none, ShadowFilter::pcf3x3}
              : std::vector<ShadowFilter>{ShadowFilter::none, ShadowFilter::pcf2x2, ShadowFilter::pcf3x3, ShadowFilter::pcf5x5};
    for (const int res : resolutions) {
      for (const ShadowFilter f : filters) {
        const Status st = measure(std::string("map ") + to_string(f), std::to_string(res), with(ShadowMethod::map, res, f),
                                  map_edge_contract(res, shadow_filter_width(f)) * w / 640.0, res >= 1024 ? 0.015 : 1.0);
        if (!st.ok()) return st;
      }
    }
  }
  return {};
}

// --- Environment maps: per vertex (Gouraud's texgen) against per pixel (Phong) -----------------

// A w x w face of a smooth sky (each channel affine in the unit direction) for face f of a cube
// map, top row first; GL's table 3.21 with t from the face's top.
Texture sky_face(int f, int size) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size * size) * 4);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const double sc = 2 * (i + 0.5) / size - 1, tc = 2 * (j + 0.5) / size - 1;
      const Eigen::Vector3d d[6] = {{1, -tc, -sc}, {-1, -tc, sc}, {sc, 1, tc}, {sc, -1, -tc}, {sc, -tc, 1}, {-sc, -tc, -1}};
      const Eigen::Vector3d u = d[f].normalized();
      std::uint8_t* p = &rgba[static_cast<std::size_t>(j * size + i) * 4];
      for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(std::lround(255.0 * (0.5 + 0.45 * u[c])));
      p[3] = 255;
    }
  }
  TextureOptions o;
  o.filter = TextureFilter::bilinear;
  o.wrap = TextureWrap::clamp;
  return std::move(*make_texture("sky", size, size, rgba, o));
}

// A mirror ball (radius 1, `segments` around) cube-mapped with the sky, its colour the
// environment alone, against exact reflection rays of the true sphere into the same faces (the
// reference sampler in double), over the pixels well inside its silhouette; the frame's time on
// one thread beside it.
Status environment_accuracy(bool quick, std::vector<Row>& rows) {
  const int w = quick ? 160 : 480, h = w;
  Scene s;
  s.camera.eye = Vec3(0, 0, 3.2f);
  s.camera.near = 0.5f;
  s.camera.far = 10.0f;
  s.global_ambient = Color3(0, 0, 0);
  for (int f = 0; f < 6; ++f) s.textures.push_back(sky_face(f, 32));
  Material m;
  m.ambient = m.diffuse = Color3(0, 0, 0);
  m.environment.mode = EnvironmentMode::cube;
  m.environment.blend = EnvironmentBlend::mix;
  for (int f = 0; f < 6; ++f) m.environment.maps[f] = f;
  s.materials.push_back(m);
  s.objects.push_back({});
  texture::Sampler faces[6];
  for (int f = 0; f < 6; ++f) faces[f] = texture::make_sampler(s.textures[static_cast<std::size_t>(f)]);
  const Eigen::Matrix3d to_eye = view_matrix(s.camera).cast<double>().topLeftCorner<3, 3>();
  const Eigen::Vector3d eye = s.camera.eye.cast<double>();
  const double k = std::tan(0.5 * s.camera.vertical_fov_deg * std::numbers::pi / 180.0);
  auto exact = [&](const Eigen::Vector3d& hit) {  // world space; the unit sphere's normal is hit
    const Eigen::Vector3d u = (hit - eye).normalized(), n = hit.normalized();
    const Eigen::Vector3d r = u - 2.0 * n * n.dot(u);
    return texture::sample_cube_reference(faces, r.x(), r.y(), r.z());
  };
  const std::vector<int> tessellations = quick ? std::vector<int>{24, 96} : std::vector<int>{12, 24, 48, 96, 192};
  for (const int segments : tessellations) {
    s.meshes.assign(1, {"ball", make_uv_sphere(1.0f, segments, segments / 2)});
    for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
      std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4));
      RenderOptions o;
      o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
      o.shading = shading;
      o.threads = 1;
      const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
      Renderer r(o);
      if (Status st = r.render(s, view); !st.ok()) return st;
      Row row;
      row.kind = "environment";
      row.method = shading == ShadingMode::gouraud ? "per vertex (gouraud)" : "per pixel (phong)";
      row.item = "segments=" + std::to_string(segments);
      const int repeats = quick ? 2 : 8;
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < repeats; ++i) (void)r.render(s, view);
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
      double sum = 0;
      std::size_t pixels = 0, close = 0;
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          const Eigen::Vector3d dir =
              to_eye.transpose() * Eigen::Vector3d((2.0 * (x + 0.5) / w - 1) * k, (1 - 2.0 * (y + 0.5) / h) * k, -1).normalized();
          const double b = eye.dot(dir), disc = b * b - (eye.squaredNorm() - 1.0);
          if (disc < 0.15) continue;  // near the silhouette the tessellated outline differs from the sphere's
          const auto want = exact(eye + (-b - std::sqrt(disc)) * dir);
          bool near = true;
          for (int c = 0; c < 3; ++c) {
            const double e = std::abs(double(rgba[static_cast<std::size_t>((y * w + x) * 4 + c)]) - 255.0 * want[static_cast<std::size_t>(c)]);
            sum += e;
            row.max_lsb = std::max(row.max_lsb, e);
            near = near && e <= 2.5;
          }
          ++pixels;
          close += near;
        }
      }
      row.mean_lsb = pixels ? sum / double(3 * pixels) : 0.0;
      row.max_step = static_cast<int>(std::lround(row.max_lsb));
      row.share = pixels ? double(close) / double(pixels) : 0.0;  // within 2 steps
      // The contract (tests/environment_test.cpp checks the same): finely tessellated, both
      // within half a step on average; coarse, per pixel is the better of the two.
      row.verdict = segments >= 96 && row.mean_lsb > 0.5 ? "mean over 0.5 step at 96+ segments" : "ok";
      rows.push_back(row);
    }
  }
  return {};
}

// Bump mapping per vertex (Gouraud with RenderOptions::vertex_relief) and per pixel (Phong) on a
// sphere of `segments` around, against per-pixel bump on the reference lighting path at 512
// segments, over the pixels well inside the silhouette; the frame's time on one thread beside it.
// The height map: smooth bumps h = (1 + sin 2 pi x / 16 sin 2 pi y / 16) / 2 on 64 x 64 texels,
// trilinear, four times around the sphere.
Status relief_accuracy(bool quick, std::vector<Row>& rows) {
  const int w = quick ? 160 : 480, h = w;
  std::vector<std::uint8_t> height(64 * 64 * 4);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const double v = 0.5 + 0.5 * std::sin(2 * std::numbers::pi * (x + 0.5) / 16) * std::sin(2 * std::numbers::pi * (y + 0.5) / 16);
      std::uint8_t* p = height.data() + 4 * (64 * y + x);
      p[0] = p[1] = p[2] = static_cast<std::uint8_t>(std::lround(255 * v)), p[3] = 255;
    }
  TextureOptions to;
  to.encoding = TextureEncoding::linear;
  Result<Texture> bumps = make_texture("bumps", 64, 64, height, to);
  if (!bumps) return bumps.status();
  Scene s;
  s.textures.push_back(std::move(*bumps));
  s.camera.eye = Vec3(0, 0.6f, 3.2f);
  s.camera.near = 0.5f;
  s.camera.far = 10.0f;
  Material m;
  m.diffuse = Color3(0.8f, 0.55f, 0.35f);
  m.ambient = Color3(0.1f, 0.1f, 0.1f);
  m.specular = Color3(0.4f, 0.4f, 0.4f);
  m.shininess = 24;
  m.bump_texture = 0;
  m.bump_scale = 6;
  m.uv_scale = Vec2(4, 2);
  s.materials.push_back(m);
  s.objects.push_back({});
  Light key;
  key.direction = Vec3(-0.5f, -0.4f, -0.7f);
  s.lights.push_back(key);
  auto draw = [&](int segments, ShadingMode shading, LightingPath path, std::vector<std::uint8_t>& rgba, Renderer** keep) -> Status {
    s.meshes.assign(1, {"ball", make_uv_sphere(1.0f, segments, segments / 2)});
    if (Status st = generate_missing_tangents(s); !st.ok()) return st;
    RenderOptions o;
    o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
    o.shading = shading;
    o.path = path;
    o.vertex_relief = true;
    o.threads = 1;
    rgba.assign(static_cast<std::size_t>(w * h * 4), 0);
    auto* r = new Renderer(o);
    const Status st = r->render(s, {rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false});
    if (keep) {
      *keep = r;
    } else {
      delete r;
    }
    return st;
  };
  std::vector<std::uint8_t> reference;
  if (Status st = draw(512, ShadingMode::phong, LightingPath::reference, reference, nullptr); !st.ok()) return st;
  // Inside the silhouette, away from it (the tessellated outline differs from the sphere's).
  const Eigen::Matrix3d to_eye = view_matrix(s.camera).cast<double>().topLeftCorner<3, 3>();
  const Eigen::Vector3d eye = s.camera.eye.cast<double>();
  const double k = std::tan(0.5 * s.camera.vertical_fov_deg * std::numbers::pi / 180.0);
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d dir =
          to_eye.transpose() * Eigen::Vector3d((2.0 * (x + 0.5) / w - 1) * k, (1 - 2.0 * (y + 0.5) / h) * k, -1).normalized();
      const double b = eye.dot(dir), disc = b * b - (eye.squaredNorm() - 1.0);
      inside[static_cast<std::size_t>(y * w + x)] = disc >= 0.15;
    }
  const std::vector<int> tessellations = quick ? std::vector<int>{16, 256} : std::vector<int>{16, 32, 64, 128, 256};
  for (const int segments : tessellations) {
    for (const ShadingMode shading : {ShadingMode::gouraud, ShadingMode::phong}) {
      std::vector<std::uint8_t> rgba;
      Renderer* r = nullptr;
      if (Status st = draw(segments, shading, LightingPath::simd, rgba, &r); !st.ok()) {
        delete r;
        return st;
      }
      Row row;
      row.kind = "relief";
      row.method = shading == ShadingMode::gouraud ? "bump per vertex (gouraud)" : "bump per pixel (phong)";
      row.item = "segments=" + std::to_string(segments);
      const int repeats = quick ? 2 : 8;
      const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < repeats; ++i) (void)r->render(s, view);
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
      delete r;
      double sum = 0;
      std::size_t pixels = 0, close = 0;
      for (std::size_t i = 0; i < inside.size(); ++i) {
        if (!inside[i]) continue;
        bool near = true;
        for (std::size_t c = 0; c < 3; ++c) {
          const double e = std::abs(double(rgba[4 * i + c]) - double(reference[4 * i + c]));
          sum += e;
          row.max_lsb = std::max(row.max_lsb, e);
          near = near && e <= 2;
        }
        ++pixels;
        close += near;
      }
      row.mean_lsb = pixels ? sum / double(3 * pixels) : 0.0;
      row.max_step = static_cast<int>(std::lround(row.max_lsb));
      row.share = pixels ? double(close) / double(pixels) : 0.0;
      // The contract: from 128 segments (where the facets no longer move the pixels' texture
      // coordinates by much) per pixel is within a step of the reference on average; per vertex
      // only approaches it, within 4 steps at 256 segments.
      if (segments >= 128 && shading == ShadingMode::phong && row.mean_lsb > 1.0) {
        row.verdict = "per-pixel bump mean over 1 step at 128+ segments";
      } else if (segments >= 256 && shading == ShadingMode::gouraud && row.mean_lsb > 4.0) {
        row.verdict = "per-vertex bump mean over 4 steps at 256+ segments";
      } else {
        row.verdict = "ok";
      }
      rows.push_back(row);
    }
  }
  return {};
}

// 8. Multisampling: the built-in scene at 320 x 180 with 1, 4, 8 and 16 samples a pixel against
// a 64-sample reference (the same frame at 2560 x 1440, one sample, each 8 x 8 block averaged in
// linear float): the mean and largest error in 8-bit steps over the edge pixels (those whose 64
// reference samples do not all show the same object or all the background, from a frame of flat
// object colours), and ms per frame on one thread. The reference shades every one of its
// samples, multisampling each pixel once, so part of the error is shading, not coverage.
Status msaa_accuracy(bool quick, std::vector<Row>& rows) {
  const Scene s = make_default_scene();
  constexpr int w = 320, h = 180, kUp = 8, W = w * kUp, H = h * kUp;
  std::vector<float> big(static_cast<std::size_t>(W) * H * 4);
  std::vector<std::uint8_t> ids(static_cast<std::size_t>(W) * H * 4);
  {
    RenderOptions o;
    o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
    if (Status st = Renderer(o).render(s, {big.data(), W, H, static_cast<std::size_t>(W) * 16, PixelFormat::rgba32f, false}); !st.ok()) {
      return st;
    }
    Scene flat = s;  // each object in its own flat colour: which object each sample shows
    flat.lights.clear();
    flat.fog.mode = FogMode::none;
    flat.global_ambient = Color3::Zero();
    flat.materials.clear();
    for (std::size_t k = 0; k < flat.objects.size(); ++k) {
      Material m;
      m.ambient = m.diffuse = m.specular = Color3::Zero();
      m.emissive = Color3(float(k + 1) / 255.0f, 0.0f, 0.0f);
      flat.materials.push_back(m);
      flat.objects[k].material = static_cast<std::uint32_t>(k);
      flat.objects[k].mesh_materials = false;
    }
    o.clear_color = {0.0f, 0.0f, 0.0f, 1.0f};
    if (Status st = Renderer(o).render(flat, {ids.data(), W, H, static_cast<std::size_t>(W) * 4, PixelFormat::rgba8, false}); !st.ok()) {
      return st;
    }
  }
  std::vector<double> reference(static_cast<std::size_t>(w * h * 3));
  std::vector<std::uint8_t> edge(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double sum[3] = {};
      const std::size_t first = (static_cast<std::size_t>(y * kUp) * W + static_cast<std::size_t>(x * kUp)) * 4;
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      for (int j = 0; j < kUp; ++j) {
        for (int k = 0; k < kUp; ++k) {
          const std::size_t at = (static_cast<std::size_t>(y * kUp + j) * W + static_cast<std::size_t>(x * kUp + k)) * 4;
          for (int c = 0; c < 3; ++c) sum[c] += std::clamp(double(big[at + static_cast<std::size_t>(c)]), 0.0, 1.0);
          edge[i] |= ids[at] != ids[first];
        }
      }
      for (int c = 0; c < 3; ++c) reference[3 * i + static_cast<std::size_t>(c)] = 255.0 * sum[c] / (kUp * kUp);
    }
  }
  for (const int samples : {1, 4, 8, 16}) {
    RenderOptions o;
    o.srgb = false;  // the targets are in steps of linear 8-bit output, GL's
    o.samples = samples;
    o.threads = 1;
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4));
    const ImageView view{rgba.data(), w, h, static_cast<std::size_t>(w) * 4, PixelFormat::rgba8, false};
    Renderer r(o);
    if (Status st = r.render(s, view); !st.ok()) return st;
    Row row;
    row.kind = "msaa";
    row.method = std::to_string(samples) + (samples == 1 ? " sample" : " samples");
    row.item = "built-in 320x180";
    const int repeats = quick ? 3 : 20;
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < repeats; ++k) (void)r.render(s, view);
    row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeats;
    double sum = 0;
    std::size_t pixels = 0, close = 0;
    for (std::size_t i = 0; i < edge.size(); ++i) {
      if (!edge[i]) continue;
      bool near = true;
      for (std::size_t c = 0; c < 3; ++c) {
        const double e = std::abs(double(rgba[4 * i + c]) - reference[3 * i + c]);
        sum += e;
        row.max_lsb = std::max(row.max_lsb, e);
        near = near && e <= 8;
      }
      ++pixels, close += near;
    }
    row.mean_lsb = pixels ? sum / double(3 * pixels) : 0.0;
    row.max_step = static_cast<int>(std::lround(row.max_lsb));
    row.share = pixels ? double(close) / double(pixels) : 0.0;
    rows.push_back(row);
  }
  // The contract: each count at least as close as the one below it, and 4 samples at most half
  // one sample's mean edge error.
  const std::size_t first = rows.size() - 4;
  for (std::size_t k = first; k < rows.size(); ++k) {
    Row& row = rows[k];
    row.verdict = "ok";
    if (k > first && row.mean_lsb > rows[k - 1].mean_lsb) row.verdict = "more error than fewer samples";
    if (k == first + 1 && row.mean_lsb > 0.5 * rows[first].mean_lsb) row.verdict = "4 samples not twice as close as 1";
  }
  return {};
}

// --- 9. baking: radiosity's convergence ---------------------------------------------------------
// The white furnace (a closed box of albedo 0.7 emitting 0.1 everywhere converges to
// B = 0.1 / 0.3), baked with more and more shots on 1 and 2 threads: the mean and largest error of
// each texel's radiosity in 8-bit steps, the unshot power's share (`share`) and the bake's time.
// Emission shot (not gathered, whose spikes at the box's edges would hide the convergence).
// The ambient term (on, as by default) spreads what is unshot over the box, which in a uniform
// furnace is right on average from the first shots; what stays is each texel's Monte Carlo noise
// (about 1.4 steps at 256 rays a shot). Contract: the unshot share falls as the shots grow, and
// the last bake is within 2 steps on average.
Status bake_accuracy(bool quick, std::vector<Row>& rows) {
  Scene s;
  Mesh box = make_cube(2.0f, 2);
  box.uvs.clear(), box.tangents.clear();
  for (auto& t : box.triangles) std::swap(t[1], t[2]);
  for (auto& n : box.normals) n = -n;
  s.meshes.push_back({"furnace", box});
  Material m;
  m.ambient = m.diffuse = Color3(0.7f, 0.7f, 0.7f);
  m.emissive = Color3(0.1f, 0.1f, 0.1f);
  m.specular = Color3::Zero();
  s.materials.push_back(m);
  s.objects.push_back({0, 0, Mat4::Identity()});
  const double expected = 0.1 / 0.3;
  for (const int threads : {1, 2}) {
    const std::size_t first = rows.size();
    for (const std::size_t shots : quick ? std::vector<std::size_t>{50, 400, 3200} : std::vector<std::size_t>{25, 50, 100, 200, 400, 800, 1600, 3200, 6400}) {
      BakeOptions o;
      o.charts.texels_per_unit = 4;
      o.gather_emitters = false;
      o.max_shots = shots;
      o.residual = 0;
      o.threads = threads;
      const auto t0 = std::chrono::steady_clock::now();
      const Result<BakeResult> r = bake_lightmaps(s, o);
      if (!r) return r.status();
      Row row;
      row.kind = "bake";
      row.method = threads == 1 ? "1 thread" : "2 threads";
      row.item = "furnace, " + std::to_string(shots) + " shots";
      row.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const BakedLightmap& lm = r->lightmaps[0];
      double sum = 0, area = 0;
      for (std::size_t i = 0; i < lm.light.size(); ++i) {
        if (lm.area[i] == 0) continue;
        const double b = 0.1 + 0.7 * double(lm.light[i].x());
        const double e = 255.0 * std::abs(b - expected);
        sum += e * lm.area[i], area += lm.area[i];
        row.max_lsb = std::max(row.max_lsb, e);
      }
      row.mean_lsb = sum / area;
      row.max_step = static_cast<int>(std::lround(row.max_lsb));
      row.share = r->stats.entered > 0 ? r->stats.unshot / r->stats.entered : 0.0;
      rows.push_back(row);
    }
    for (std::size_t k = first; k < rows.size(); ++k) {
      Row& row = rows[k];
      row.verdict = "ok";
      if (k > first && row.share > rows[k - 1].share) row.verdict = "more power unshot after more shots";
      if (k + 1 == rows.size() && row.mean_lsb > 2.0) row.verdict = "not within 2 steps on average";
    }
  }
  return {};
}

void write_json(std::ostream& o, const std::vector<Row>& rows) {
  o << "{\n  \"machine\": \"" << json_escape(to_string(best_isa())) << "\",\n  \"rows\": [\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    o << "    {\"kind\": \"" << r.kind << "\", \"method\": \"" << json_escape(r.method) << "\", \"item\": \""
      << json_escape(r.item) << "\", \"max_lsb\": " << number(r.max_lsb) << ", \"mean_lsb\": " << number(r.mean_lsb)
      << ", \"max_step\": " << r.max_step << ", \"nans\": " << r.nans << ", \"psnr_db\": " << number(r.psnr_db) << ", \"ms_per_frame\": " << number(r.ms_per_frame)
      << ", \"rate\": " << number(r.rate) << ", \"share\": " << number(r.share) << ", \"edge_px\": " << number(r.edge_px)
      << ", \"verdict\": \"" << json_escape(r.verdict) << "\"}" << (i + 1 < rows.size() ? "," : "") << "\n";
  }
  o << "  ]\n}\n";
}

void write_csv(std::ostream& o, const std::vector<Row>& rows) {
  o << "kind,method,item,max_lsb,mean_lsb,max_step,nans,psnr_db,ms_per_frame,rate,share,edge_px,verdict\n";
  auto q = [](const std::string& s) { return "\"" + s + "\""; };
  for (const Row& r : rows) {
    o << r.kind << "," << q(r.method) << "," << q(r.item) << "," << number(r.max_lsb) << "," << number(r.mean_lsb)
      << "," << r.max_step << "," << r.nans << "," << number(r.psnr_db) << "," << number(r.ms_per_frame) << ","
      << number(r.rate) << "," << number(r.share) << "," << number(r.edge_px) << "," << q(r.verdict) << "\n";
  }
}

}  // namespace

int accuracy(const std::string& only, bool quick, bool check, const std::string& json_path, const std::string& csv_path);

Command add_accuracy(CLI::App& facet) {
  struct State {
    std::string only, json_path, csv_path;
    bool quick = false, check = false;
  };
  auto st = std::make_shared<State>();
  CLI::App* app = facet.add_subcommand("accuracy", "every fast method against its exact reference: vertices, pow, images, textures, shadows, environment and bump maps, multisampling");
  app->footer(
      "Measures every lighting path, ISA and pow tier against the exact reference: vertex colours\n"
      "(random and special inputs), the pow methods over their failure inputs, whole images against a\n"
      "ray-cast reference of exact spheres, the texture filters against the reference sampler, and\n"
      "the shadow methods against ray-cast shadows, environment maps per vertex and per pixel against\n"
      "exact reflection rays, bump maps per vertex and per pixel against per-pixel bump on the\n"
      "reference path, multisampled edges against a 64-sample reference, and radiosity's convergence in the\n"
      "white furnace (B = E / (1 - albedo)) against the shots and time spent.");
  app->add_option("--only", st->only,
                  "vertices | pow | images | textures | shadows | environment | relief | msaa | bake (default: all nine)")
      ->check(one_of({"vertices", "pow", "images", "textures", "shadows", "environment", "relief", "msaa", "bake"}, "part"));
  app->add_flag("--quick", st->quick, "fewer vertices (10^4) and tessellation levels, for tests");
  app->add_option("--json", st->json_path, "write all results as JSON to FILE");
  app->add_option("--csv", st->csv_path, "write all results as CSV (one row per measurement) to FILE");
  app->add_flag("--check", st->check, "exit with status 1 if any measurement is outside its contract (for tests)");
  return {app, [st] { return accuracy(st->only, st->quick, st->check, st->json_path, st->csv_path); }};
}

int accuracy(const std::string& only, bool quick, bool check, const std::string& json_path, const std::string& csv_path) {
  std::vector<Row> rows;
  if (only.empty() || only == "vertices") {
    if (Status s = vertex_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "pow") pow_sweep(rows);
  if (only.empty() || only == "images") {
    if (Status s = image_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "textures") texture_accuracy(quick, rows);
  if (only.empty() || only == "shadows") {
    if (Status s = shadow_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "environment") {
    if (Status s = environment_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "relief") {
    if (Status s = relief_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "msaa") {
    if (Status s = msaa_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "bake") {
    if (Status s = bake_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }

  int failures = 0;
  // The pow sweep has hundreds of rows: print only its failures and the worst case of each method
  // (all of them with --csv or --json).
  std::map<std::string, std::size_t> worst_pow;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].kind != "pow") continue;
    auto [it, fresh] = worst_pow.emplace(rows[i].method, i);
    if (!fresh && rows[i].max_lsb > rows[it->second].max_lsb) it->second = i;
  }
  std::printf("%-9s %-28s %-36s %9s %9s %5s %5s %8s  %s\n", "kind", "method", "case", "max LSB", "mean LSB", "step",
              "NaN", "PSNR dB", "verdict");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const bool bad = r.verdict.rfind("ok", 0) != 0;
    failures += bad;
    if (r.kind == "pow" && !bad && worst_pow[r.method] != i) continue;
    std::printf("%-9s %-28s %-36s %9.3g %9.3g %5d %5ld %8s  %s", r.kind.c_str(), r.method.c_str(), r.item.c_str(),
                r.max_lsb, r.mean_lsb, r.max_step, r.nans,
                r.kind == "image" || r.kind == "shadow" ? number(r.psnr_db).c_str() : "", r.verdict.c_str());
    if (r.kind == "texture") std::printf(" (%.1f M samples/s)", r.rate / 1e6);
    if (r.kind == "environment" || r.kind == "relief") std::printf(" (%.1f %% of pixels within 2 steps; %.2f ms/frame)", 100.0 * r.share, r.ms_per_frame);
    if (r.kind == "msaa") std::printf(" (%.1f %% of edge pixels within 8 steps; %.2f ms/frame)", 100.0 * r.share, r.ms_per_frame);
    if (r.kind == "bake") std::printf(" (%.3g %% of the power unshot; %.1f ms)", 100.0 * r.share, r.ms_per_frame);
    if (r.kind == "shadow") {
      std::printf(" (%.3f %% of receivers differ, farthest %.0f px from an edge; %.2f ms/frame)", 100.0 * r.share, r.edge_px,
                  r.ms_per_frame);
    }
    std::printf("\n");
  }
  std::printf("%zu measurements, %d outside their contract%s\n", rows.size(), failures,
              failures ? " (see the verdicts above)" : "");
  if (!json_path.empty()) {
    std::ofstream f(json_path);
    write_json(f, rows);
    if (!f) return fail("cannot write " + json_path);
  }
  if (!csv_path.empty()) {
    std::ofstream f(csv_path);
    write_csv(f, rows);
    if (!f) return fail("cannot write " + csv_path);
  }
  return check && failures > 0 ? 1 : 0;
}

}  // namespace facet::cli
