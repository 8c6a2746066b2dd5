// Baked light (facet/bake.hpp): lightmap texels as patches, direct light with shadow rays, and
// progressive-refinement radiosity with ray-cast form factors, all through one Embree scene.
//
// Determinism: every random number is a hash of (patch, shot, ray, dimension); rays are traced
// in parallel into per-ray slots and their results applied in ray order; the patch to shoot is
// the first with the most unshot power; the Embree hierarchy is built in a one-thread arena, so
// that a ray hitting an edge two triangles share finds the same one whatever the caller's
// thread count.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <new>
#include <numbers>
#include <string>

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include "common/format.hpp"
#include "common/parallel.hpp"
#include "common/try.hpp"
#include "facet/bake.hpp"
#include "lighting/setup.hpp"
#include "lighting/shade.hpp"

namespace facet {
namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

// A piece of a texel's footprint: one sub-square clipped with one triangle.
struct Piece {
  std::uint32_t patch = 0;   // the texel, as a patch index
  std::uint32_t triangle = 0, object = 0;
  V2 square;                 // the sub-square's lower-left corner, in texels
  V3 position, face_normal, normal;  // centroid; the triangle's normal; the interpolated vertex normal
  double area = 0;           // world area
};

struct Patch {
  V3 light = V3::Zero();     // arriving light (direct + indirect), colour units
  V3 unshot = V3::Zero();    // radiosity not yet shot
  V3 albedo = V3::Zero(), emission = V3::Zero();
  double area = 0;
  std::uint32_t first_piece = 0, piece_count = 0;
  std::uint32_t object = 0, texel = 0;
};

// One object's surface in world space, with its charts.
struct Surface {
  Mesh world;             // positions and normals in world space
  LightmapUnwrap unwrap;
  std::vector<V3> face_normal;
  std::vector<std::uint32_t> fallback;  // per triangle: the patch of its largest piece
  std::uint32_t first_patch_texel = 0;  // index of texel 0 in the global texel -> patch map
  bool mesh_uvs = false;                // the atlas is over the mesh's own lightmap coordinates
};

// Counter-based random numbers: the same value for the same (a, b, c, d) on every run and thread.
double hash01(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
  std::uint64_t x = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull ^
                    (c + 0x85157AF5ull) * 0x94D049BB133111EBull ^ (d + 0x2545F4914F6CDD1Dull);
  x ^= x >> 30, x *= 0xBF58476D1CE4E5B9ull, x ^= x >> 27, x *= 0x94D049BB133111EBull, x ^= x >> 31;
  return static_cast<double>(x >> 11) * 0x1.0p-53;
}

void basis(const V3& n, V3& t, V3& b) {
  const V3 axis = std::abs(n.x()) <= std::abs(n.y()) && std::abs(n.x()) <= std::abs(n.z()) ? V3::UnitX()
                  : std::abs(n.y()) <= std::abs(n.z())                                      ? V3::UnitY()
                                                                                             : V3::UnitZ();
  t = axis.cross(n).normalized();
  b = n.cross(t);
}

// The patches' unshot power in a tournament tree: the largest (the first of equals) and the sum
// at the root, a leaf's change in O(log n). Sums are added in a fixed tree order, so the stop
// test sees the same value for any thread count.
class PowerTree {
 public:
  explicit PowerTree(std::size_t n) {
    while (size_ < n) size_ *= 2;
    best_.assign(2 * size_, -1.0);
    index_.assign(2 * size_, 0);
    sum_.assign(2 * size_, 0.0);
    for (std::size_t i = 0; i < size_; ++i) index_[size_ + i] = static_cast<std::uint32_t>(i);
  }
  // Leaves first, then every parent once: the tree of `power` without n log n work.
  void fill(const std::vector<double>& power) {
    for (std::size_t i = 0; i < power.size(); ++i) best_[size_ + i] = sum_[size_ + i] = power[i];
    for (std::size_t k = size_ - 1; k >= 1; --k) pull(k);
  }
  void set(std::size_t i, double power) {
    std::size_t k = size_ + i;
    best_[k] = sum_[k] = power;
    for (k /= 2; k >= 1; k /= 2) pull(k);
  }
  double best() const { return best_[1]; }
  std::size_t best_index() const { return index_[1]; }
  double sum() const { return sum_[1]; }

 private:
  void pull(std::size_t k) {
    const std::size_t l = 2 * k, r = l + 1;
    const bool left = best_[l] >= best_[r];
    best_[k] = left ? best_[l] : best_[r];
    index_[k] = left ? index_[l] : index_[r];
    sum_[k] = sum_[l] + sum_[r];
  }
  std::size_t size_ = 1;
  std::vector<double> best_;
  std::vector<std::uint32_t> index_;
  std::vector<double> sum_;
};

// The part of polygon `in` with coordinate `axis` on the kept side of `at`.
std::vector<V2> clip(const std::vector<V2>& in, int axis, double at, bool keep_above) {
  std::vector<V2> out;
  const std::size_t n = in.size();
  for (std::size_t i = 0; i < n; ++i) {
    const V2& a = in[i];
    const V2& b = in[(i + 1) % n];
    const double da = keep_above ? a[axis] - at : at - a[axis], db = keep_above ? b[axis] - at : at - b[axis];
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

// Area and centroid of a simple polygon (counter-clockwise: positive area).
double polygon_area(const std::vector<V2>& p, V2& centroid) {
  double a = 0;
  V2 c = V2::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const V2& u = p[i];
    const V2& v = p[(i + 1) % p.size()];
    const double cross = u.x() * v.y() - v.x() * u.y();
    a += cross;
    c += (u + v) * cross;
  }
  a *= 0.5;
  centroid = a != 0 ? V2(c / (6 * a)) : V2::Zero();
  return a;
}

Status check_options(const BakeOptions& o) {
  auto bad = [](const char* field, const std::string& what) {
    return Status{ErrorCode::invalid_argument, field, std::string(field) + ": " + what};
  };
  if (o.subdivisions < 1 || o.subdivisions > 8) return bad("subdivisions", "expected 1 to 8, found " + std::to_string(o.subdivisions));
  if (o.rays_per_shot < 1 || o.rays_per_shot > (1 << 20)) {
    return bad("rays_per_shot", "expected 1 to 1048576, found " + std::to_string(o.rays_per_shot));
  }
  if (!(o.residual >= 0 && o.residual <= 1)) return bad("residual", "expected a number in [0, 1], found " + format_number(o.residual));
  if (!(o.max_seconds >= 0 && std::isfinite(o.max_seconds))) {
    return bad("max_seconds", "expected a finite number >= 0, found " + format_number(o.max_seconds));
  }
  if (!(o.small_texel >= 0 && o.small_texel <= 1)) return bad("small_texel", "expected a number in [0, 1], found " + format_number(o.small_texel));
  if (o.burial_rays < 0 || o.burial_rays > 1024) return bad("burial_rays", "expected 0 to 1024, found " + std::to_string(o.burial_rays));
  if (o.area_samples < 1 || o.area_samples > 65536) {
    return bad("area_samples", "expected 1 to 65536, found " + std::to_string(o.area_samples));
  }
  if (o.threads < 0) return bad("threads", "expected 0 (all) or more, found " + std::to_string(o.threads));
  return {};
}

class Baker {
 public:
  Baker(const Scene& scene, const BakeOptions& o) : scene_(scene), o_(o), arena_(o.threads > 0 ? o.threads : 1 << 10) {}
  ~Baker() {
    if (rscene_) rtcReleaseScene(rscene_);
    if (device_) rtcReleaseDevice(device_);
  }
  Result<BakeResult> run();

 private:
  const Material& material_of(const Instance& inst, std::size_t triangle) const;
  Status make_surfaces();
  Status make_patches();
  Status build_rays();
  void drop_buried_pieces();
  void merge_small_patches();
  // Rebuilds pieces_ and patches_ with each piece in patch `target[its patch]` (-1: dropped), the
  // patches in their old order; texel_patch_ and the surfaces' fallbacks follow.
  void regroup(const std::vector<std::int64_t>& target, const std::vector<std::uint8_t>& dropped_piece);
  void direct_light();
  void emitter_light();
  Status radiosity();
  // The patch a ray hit (object, triangle, barycentrics), or -1.
  std::int64_t patch_at(unsigned object, unsigned triangle, float u, float v) const;
  V3 offset_origin(const Piece& p) const { return p.position + p.face_normal * epsilon_; }
  // The first surface along a ray from `origin` (geomID RTC_INVALID_GEOMETRY_ID: none).
  RTCRayHit intersect(const V3& origin, const V3& dir) const;
  // A point spread uniformly over the piece: a point of its sub-square taken if it lies in the
  // triangle (up to 16 tries from the hash sequence), else the centroid.
  V3 ray_origin(const Piece& p, std::uint64_t patch, std::uint64_t shot, std::uint64_t ray) const;

  const Scene& scene_;
  const BakeOptions& o_;
  parallel::Arena arena_;
  std::vector<Surface> surfaces_;
  std::vector<Piece> pieces_;
  std::vector<Patch> patches_;
  std::vector<std::int32_t> texel_patch_;  // all objects' texels, -1 where no triangle touches
  RTCDevice device_ = nullptr;
  RTCScene rscene_ = nullptr;
  int error_code_ = 0;
  std::string error_;
  double epsilon_ = 1e-6;
  BakeStats stats_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();

  friend void bake_error(void*, RTCError, const char*);
};

void bake_error(void* user, RTCError code, const char* message) {
  auto* b = static_cast<Baker*>(user);
  if (b->error_code_ == 0) b->error_code_ = static_cast<int>(code), b->error_ = message ? message : "";
}

const Material& Baker::material_of(const Instance& inst, std::size_t triangle) const {
  if (inst.mesh_materials) {
    for (const MaterialGroup& g : scene_.meshes[inst.mesh].mesh.groups) {
      if (triangle < g.first_triangle || triangle >= std::size_t{g.first_triangle} + g.triangle_count) continue;
      for (const Material& m : scene_.materials)
        if (m.name == g.material) return m;
    }
  }
  return scene_.materials[inst.material];
}

Status Baker::make_surfaces() {
  surfaces_.resize(scene_.objects.size());
  std::size_t texels = 0;
  Eigen::AlignedBox3d bounds;
  for (std::size_t k = 0; k < scene_.objects.size(); ++k) {
    const Instance& inst = scene_.objects[k];
    const Mesh& mesh = scene_.meshes[inst.mesh].mesh;
    Surface& s = surfaces_[k];
    s.world = world_space_mesh(mesh, inst.model);
    for (const Vec3& p : s.world.positions) {
      if (p.allFinite()) bounds.extend(p.cast<double>());
    }
    const std::string field = "objects[" + std::to_string(k) + "]";
    s.mesh_uvs = o_.use_mesh_uvs && !mesh.lightmap_uvs.empty();
    if (s.mesh_uvs) s.world.lightmap_uvs = mesh.lightmap_uvs;
    Result<LightmapUnwrap> u = s.mesh_uvs ? lightmap_from_mesh_uvs(s.world, o_.charts.texels_per_unit, o_.charts.max_size)
                                          : unwrap_lightmap(s.world, o_.charts);
    if (!u.ok()) return {u.status().code(), field + "." + u.status().field(), field + ": " + u.status().message()};
    s.unwrap = std::move(*u);
    s.first_patch_texel = static_cast<std::uint32_t>(texels);
    texels += static_cast<std::size_t>(s.unwrap.width) * static_cast<std::size_t>(s.unwrap.height);
    if (texels > o_.max_texels) {
      return {ErrorCode::out_of_memory, "max_texels",
              "max_texels: the lightmaps need more than " + std::to_string(o_.max_texels) + " texels at " +
                  format_number(o_.charts.texels_per_unit) + " texels per unit (" + field + " reaches " +
                  std::to_string(texels) + "); use fewer texels per unit or a larger budget"};
    }
    s.face_normal.resize(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const V3 a = s.world.positions[mesh.triangles[t][0]].cast<double>(), b = s.world.positions[mesh.triangles[t][1]].cast<double>(),
               c = s.world.positions[mesh.triangles[t][2]].cast<double>();
      const V3 n = (b - a).cross(c - a);
      s.face_normal[t] = n.norm() > 0 && n.allFinite() ? V3(n.normalized()) : V3::Zero();
    }
  }
  stats_.texels = texels;
  if (!bounds.isEmpty()) epsilon_ = 1e-5 * std::max(bounds.diagonal().norm(), 1e-30);
  return {};
}

Status Baker::make_patches() {
  texel_patch_.assign(stats_.texels, -1);
  const int k = o_.subdivisions;
  for (std::size_t obj = 0; obj < surfaces_.size(); ++obj) {
    Surface& s = surfaces_[obj];
    const LightmapUnwrap& u = s.unwrap;
    const Instance& inst = scene_.objects[obj];
    s.fallback.assign(u.triangles.size(), std::numeric_limits<std::uint32_t>::max());
    std::vector<Piece> object_pieces;
    for (std::size_t t = 0; t < u.triangles.size(); ++t) {
      if (s.face_normal[t] == V3::Zero()) continue;  // no area: nothing to light, nothing to hit
      std::array<V2, 3> q;
      std::array<V3, 3> p, n;
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = u.triangles[t][static_cast<std::size_t>(c)];
        q[static_cast<std::size_t>(c)] = V2(double(u.uvs[v].x()) * u.width, double(u.uvs[v].y()) * u.height);
        p[static_cast<std::size_t>(c)] = s.world.positions[u.source_vertex[v]].cast<double>();
        n[static_cast<std::size_t>(c)] = s.world.normals[u.source_vertex[v]].cast<double>();
      }
      V2 unused;
      const double uv_area = polygon_area({q[0], q[1], q[2]}, unused);
      const double world_area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
      if (!(uv_area > 0)) continue;
      const double scale = world_area / uv_area;
      const V2 lo = q[0].cwiseMin(q[1]).cwiseMin(q[2]), hi = q[0].cwiseMax(q[1]).cwiseMax(q[2]);
      const int x0 = std::max(0, static_cast<int>(std::floor(lo.x()))), x1 = std::min(u.width - 1, static_cast<int>(std::floor(hi.x())));
      const int y0 = std::max(0, static_cast<int>(std::floor(lo.y()))), y1 = std::min(u.height - 1, static_cast<int>(std::floor(hi.y())));
      double best = 0;
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          for (int sy = 0; sy < k; ++sy) {
            for (int sx = 0; sx < k; ++sx) {
              const double ax = x + double(sx) / k, bx = x + double(sx + 1) / k, ay = y + double(sy) / k, by = y + double(sy + 1) / k;
              std::vector<V2> poly = {q[0], q[1], q[2]};
              poly = clip(poly, 0, ax, true);
              poly = clip(poly, 0, bx, false);
              poly = clip(poly, 1, ay, true);
              poly = clip(poly, 1, by, false);
              if (poly.size() < 3) continue;
              V2 centroid;
              const double a = polygon_area(poly, centroid);
              if (!(a > 0)) continue;
              // Barycentrics of the centroid in the uv triangle.
              const V2 e1 = q[1] - q[0], e2 = q[2] - q[0], d = centroid - q[0];
              const double det = e1.x() * e2.y() - e1.y() * e2.x();
              const double b1 = (d.x() * e2.y() - d.y() * e2.x()) / det, b2 = (e1.x() * d.y() - e1.y() * d.x()) / det;
              Piece piece;
              const std::size_t texel = s.first_patch_texel + static_cast<std::size_t>(y) * static_cast<std::size_t>(u.width) + static_cast<std::size_t>(x);
              piece.patch = static_cast<std::uint32_t>(texel);  // a texel for now; a patch index below
              piece.position = (1 - b1 - b2) * p[0] + b1 * p[1] + b2 * p[2];
              piece.face_normal = s.face_normal[t];
              const V3 shading = (1 - b1 - b2) * n[0] + b1 * n[1] + b2 * n[2];
              piece.normal = shading.norm() > 0 ? V3(shading.normalized()) : piece.face_normal;
              piece.area = a * scale;
              piece.triangle = static_cast<std::uint32_t>(t);
              piece.object = static_cast<std::uint32_t>(obj);
              piece.square = V2(ax, ay);
              object_pieces.push_back(piece);
              if (piece.area > best) best = piece.area, s.fallback[t] = static_cast<std::uint32_t>(texel);
            }
          }
        }
      }
    }
    // Pieces grouped by texel, in (texel, creation) order.
    std::stable_sort(object_pieces.begin(), object_pieces.end(), [](const Piece& a, const Piece& b) { return a.patch < b.patch; });
    for (std::size_t i = 0; i < object_pieces.size();) {
      const std::uint32_t texel = object_pieces[i].patch;
      Patch patch;
      patch.object = static_cast<std::uint32_t>(obj);
      patch.texel = texel - s.first_patch_texel;
      patch.first_piece = static_cast<std::uint32_t>(pieces_.size());
      // The texel's albedo and emission: the material of its first piece's triangle (a texel
      // over triangles of two materials takes the first in triangle order).
      const Material& m = material_of(inst, object_pieces[i].triangle);
      patch.albedo = m.diffuse.cast<double>().cwiseMax(0.0).cwiseMin(1.0);
      patch.emission = m.emissive.cast<double>().cwiseMax(0.0);
      const auto index = static_cast<std::uint32_t>(patches_.size());
      for (; i < object_pieces.size() && object_pieces[i].patch == texel; ++i) {
        object_pieces[i].patch = index;
        patch.area += object_pieces[i].area;
        pieces_.push_back(object_pieces[i]);
        ++patch.piece_count;
      }
      texel_patch_[texel] = static_cast<std::int32_t>(index);
      patches_.push_back(patch);
    }
    // Each triangle's fallback texel as a patch (a ray whose hit rounds onto a texel without area).
    for (std::uint32_t& f : s.fallback) {
      if (f != std::numeric_limits<std::uint32_t>::max()) f = static_cast<std::uint32_t>(texel_patch_[f]);
    }
  }
  stats_.patches = patches_.size();
  stats_.pieces = pieces_.size();
  return {};
}

Status Baker::build_rays() {
  device_ = rtcNewDevice("verbose=0");
  if (!device_) return {ErrorCode::out_of_memory, "", "bake: could not create the Embree device"};
  rtcSetDeviceErrorFunction(device_, bake_error, this);
  auto failed = [this](const char* what) -> Status {
    const ErrorCode code = error_code_ == RTC_ERROR_OUT_OF_MEMORY ? ErrorCode::out_of_memory : ErrorCode::unsupported;
    return {code, "", std::string("bake: ") + what + (error_.empty() ? "" : ": " + error_)};
  };
  rscene_ = rtcNewScene(device_);
  if (!rscene_) return failed("could not create the Embree scene");
  rtcSetSceneFlags(rscene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(rscene_, RTC_BUILD_QUALITY_MEDIUM);
  for (std::size_t k = 0; k < surfaces_.size(); ++k) {
    const Mesh& m = surfaces_[k].world;
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g) return failed("could not create a geometry");
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                           std::max<std::size_t>(m.positions.size(), 1)));
    auto* t = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(std::uint32_t), m.triangles.size()));
    if (!v || (!t && !m.triangles.empty())) {
      rtcReleaseGeometry(g);
      return failed("could not allocate the scene's buffers");
    }
    for (std::size_t i = 0; i < m.positions.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const float x = m.positions[i][c];
        v[3 * i + static_cast<std::size_t>(c)] = std::isfinite(x) && std::abs(x) <= 1e18f ? x : std::numeric_limits<float>::quiet_NaN();
      }
    for (std::size_t i = 0; i < m.triangles.size(); ++i)
      for (int c = 0; c < 3; ++c) t[3 * i + static_cast<std::size_t>(c)] = m.triangles[i][static_cast<std::size_t>(c)];
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(rscene_, g, static_cast<unsigned>(k));
    rtcReleaseGeometry(g);
  }
  // One thread builds, so that the hierarchy (and which of two triangles sharing an edge a ray on
  // that edge hits) does not depend on the caller's threads.
  tbb::task_arena one(1);
  one.execute([&] { rtcCommitScene(rscene_); });
  if (error_code_ != 0) return failed("building the hierarchy failed");
  return {};
}

// Ray k of a set cosine-distributed about `n`, stratified on a side x side grid of the unit
// square (cell k mod side^2), jittered in its cell by two numbers in [0, 1).
V3 stratified_cosine(const V3& n, int side, int k, double jitter_a, double jitter_b) {
  const int cell = k % (side * side);
  const double a = (cell % side + jitter_a) / side, b = (cell / side + jitter_b) / side;
  const double radius = std::sqrt(a), phi = 2 * std::numbers::pi * b;
  V3 t, bt;
  basis(n, t, bt);
  return t * (radius * std::cos(phi)) + bt * (radius * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1 - a));
}

RTCRayHit Baker::intersect(const V3& origin, const V3& dir) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = float(origin.x()), rh.ray.org_y = float(origin.y()), rh.ray.org_z = float(origin.z());
  rh.ray.dir_x = float(dir.x()), rh.ray.dir_y = float(dir.y()), rh.ray.dir_z = float(dir.z());
  rh.ray.tnear = 0.0f, rh.ray.tfar = std::numeric_limits<float>::infinity(), rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rscene_, &context, &rh);
  return rh;
}

void Baker::drop_buried_pieces() {
  const int n = o_.burial_rays;
  if (n == 0 || pieces_.empty()) return;
  const int side = std::max(1, static_cast<int>(std::sqrt(double(n))));
  std::vector<std::uint8_t> buried(pieces_.size(), 0);
  arena_.execute([&] {
    arena_.parallel_for(tbb::blocked_range<std::size_t>(0, pieces_.size(), 256), [&](const tbb::blocked_range<std::size_t>& r, int) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const Piece& piece = pieces_[i];
        const V3 origin = offset_origin(piece);
        int back = 0;
        for (int k = 0; k < n; ++k) {
          const V3 dir = stratified_cosine(piece.face_normal, side, k, hash01(i, 0xB0B1, static_cast<std::uint64_t>(k), 1),
                                           hash01(i, 0xB0B1, static_cast<std::uint64_t>(k), 2));
          const RTCRayHit rh = intersect(origin, dir);
          if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && surfaces_[rh.hit.geomID].face_normal[rh.hit.primID].dot(dir) >= 0) ++back;
        }
        buried[i] = 2 * back > n;
      }
    });
  });
  stats_.rays += pieces_.size() * static_cast<std::size_t>(n);
  for (const std::uint8_t b : buried) stats_.buried += b;
  if (stats_.buried == 0) return;  // nothing to regroup
  std::vector<std::int64_t> same(patches_.size());
  for (std::size_t p = 0; p < same.size(); ++p) same[p] = static_cast<std::int64_t>(p);
  regroup(same, buried);
}

void Baker::regroup(const std::vector<std::int64_t>& target, const std::vector<std::uint8_t>& dropped_piece) {
  // The pieces of each new patch: those of the patches it takes in (itself and any merged into it),
  // in patch order, each in piece order (a fixed order: the same sums for any thread count).
  std::vector<std::vector<std::uint32_t>> members(patches_.size());
  for (std::size_t p = 0; p < patches_.size(); ++p) {
    if (target[p] >= 0) members[static_cast<std::size_t>(target[p])].push_back(static_cast<std::uint32_t>(p));
  }
  std::vector<Piece> pieces;
  std::vector<Patch> patches;
  std::vector<std::int64_t> renumber(patches_.size(), -1);
  pieces.reserve(pieces_.size());
  for (std::size_t p = 0; p < patches_.size(); ++p) {
    if (members[p].empty()) continue;
    Patch patch = patches_[p];
    patch.first_piece = static_cast<std::uint32_t>(pieces.size());
    patch.piece_count = 0;
    patch.area = 0;
    const auto index = static_cast<std::uint32_t>(patches.size());
    for (const std::uint32_t q : members[p]) {
      for (std::uint32_t i = patches_[q].first_piece; i < patches_[q].first_piece + patches_[q].piece_count; ++i) {
        if (dropped_piece[i]) continue;
        pieces.push_back(pieces_[i]);
        pieces.back().patch = index;
        patch.area += pieces_[i].area;
        ++patch.piece_count;
      }
    }
    if (patch.piece_count == 0) continue;
    for (const std::uint32_t q : members[p]) renumber[q] = index;
    patches.push_back(patch);
  }
  for (std::int32_t& t : texel_patch_) {
    if (t >= 0) t = static_cast<std::int32_t>(renumber[static_cast<std::size_t>(t)]);
  }
  for (Surface& s : surfaces_)
    for (std::uint32_t& f : s.fallback) {
      if (f != std::numeric_limits<std::uint32_t>::max())
        f = renumber[f] < 0 ? std::numeric_limits<std::uint32_t>::max() : static_cast<std::uint32_t>(renumber[f]);
    }
  pieces_ = std::move(pieces);
  patches_ = std::move(patches);
  stats_.patches = patches_.size();
  stats_.pieces = pieces_.size();
}

void Baker::merge_small_patches() {
  if (patches_.empty()) return;
  // Per object, a full texel's area: the median of its patches' (most texels lie inside charts).
  std::vector<double> full(surfaces_.size(), 0.0);
  {
    std::vector<std::vector<double>> areas(surfaces_.size());
    for (const Patch& p : patches_) areas[p.object].push_back(p.area);
    for (std::size_t k = 0; k < areas.size(); ++k) {
      if (areas[k].empty()) continue;
      std::nth_element(areas[k].begin(), areas[k].begin() + static_cast<std::ptrdiff_t>(areas[k].size() / 2), areas[k].end());
      full[k] = areas[k][areas[k].size() / 2];
    }
  }
  std::vector<std::int64_t> target(patches_.size());
  bool any = false;
  for (std::size_t p = 0; p < patches_.size(); ++p) {
    target[p] = static_cast<std::int64_t>(p);
    const Patch& patch = patches_[p];
    const double small = o_.small_texel * full[patch.object];
    if (!(patch.area < small)) continue;
    const Surface& s = surfaces_[patch.object];
    const int x = static_cast<int>(patch.texel % static_cast<std::uint32_t>(s.unwrap.width));
    const int y = static_cast<int>(patch.texel / static_cast<std::uint32_t>(s.unwrap.width));
    std::int64_t best = -1;
    double best_area = small;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= s.unwrap.width || ny >= s.unwrap.height) continue;
        const std::int32_t q = texel_patch_[s.first_patch_texel + static_cast<std::size_t>(ny) * static_cast<std::size_t>(s.unwrap.width) +
                                            static_cast<std::size_t>(nx)];
        // The fullest neighbour of the same material (charts are padded apart: a neighbour is
        // of the same chart); a neighbour that is itself small is not joined.
        if (q < 0 || !(patches_[static_cast<std::size_t>(q)].area >= best_area)) continue;
        if (patches_[static_cast<std::size_t>(q)].albedo != patch.albedo || patches_[static_cast<std::size_t>(q)].emission != patch.emission) continue;
        if (patches_[static_cast<std::size_t>(q)].area == best_area && best >= 0 && q > best) continue;
        best = q, best_area = patches_[static_cast<std::size_t>(q)].area;
      }
    if (best >= 0) target[p] = best, any = true, ++stats_.merged;
  }
  if (any) regroup(target, std::vector<std::uint8_t>(pieces_.size(), 0));
}

std::int64_t Baker::patch_at(unsigned object, unsigned triangle, float u, float v) const {
  const Surface& s = surfaces_[object];
  const auto& tri = s.unwrap.triangles[triangle];
  const double w0 = 1.0 - double(u) - double(v);
  const double x = (w0 * s.unwrap.uvs[tri[0]].x() + double(u) * s.unwrap.uvs[tri[1]].x() + double(v) * s.unwrap.uvs[tri[2]].x()) * s.unwrap.width;
  const double y = (w0 * s.unwrap.uvs[tri[0]].y() + double(u) * s.unwrap.uvs[tri[1]].y() + double(v) * s.unwrap.uvs[tri[2]].y()) * s.unwrap.height;
  const int ix = std::clamp(static_cast<int>(std::floor(x)), 0, s.unwrap.width - 1);
  const int iy = std::clamp(static_cast<int>(std::floor(y)), 0, s.unwrap.height - 1);
  const std::int32_t p = texel_patch_[s.first_patch_texel + static_cast<std::size_t>(iy) * static_cast<std::size_t>(s.unwrap.width) + static_cast<std::size_t>(ix)];
  if (p >= 0) return p;
  const std::uint32_t f = s.fallback[triangle];
  return f == std::numeric_limits<std::uint32_t>::max() ? -1 : static_cast<std::int64_t>(f);
}

V3 Baker::ray_origin(const Piece& p, std::uint64_t patch, std::uint64_t shot, std::uint64_t ray) const {
  const Surface& s = surfaces_[p.object];
  const auto& tri = s.unwrap.triangles[p.triangle];
  std::array<V2, 3> q;
  for (int c = 0; c < 3; ++c) {
    const Vec2& uv = s.unwrap.uvs[tri[static_cast<std::size_t>(c)]];
    q[static_cast<std::size_t>(c)] = V2(double(uv.x()) * s.unwrap.width, double(uv.y()) * s.unwrap.height);
  }
  const V2 e1 = q[1] - q[0], e2 = q[2] - q[0];
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  const double size = 1.0 / o_.subdivisions;
  for (std::uint64_t attempt = 0; attempt < 16; ++attempt) {
    const V2 d = p.square + V2(hash01(patch, shot, ray, 3 + 2 * attempt), hash01(patch, shot, ray, 4 + 2 * attempt)) * size - q[0];
    const double b1 = (d.x() * e2.y() - d.y() * e2.x()) / det, b2 = (e1.x() * d.y() - e1.y() * d.x()) / det;
    if (b1 < 0 || b2 < 0 || b1 + b2 > 1) continue;
    const Mesh& m = s.world;
    const std::uint32_t v0 = s.unwrap.source_vertex[tri[0]], v1 = s.unwrap.source_vertex[tri[1]], v2 = s.unwrap.source_vertex[tri[2]];
    return (1 - b1 - b2) * m.positions[v0].cast<double>() + b1 * m.positions[v1].cast<double>() + b2 * m.positions[v2].cast<double>();
  }
  return p.position;
}

// Light from emissive surfaces gathered as area lights: at each piece, area_samples points on
// the emitting patches (a patch chosen by its share of the emitted power, stratified; a point
// spread uniformly over it), each weighted by B cos(receiver) cos(emitter) / (pi r^2) over its
// probability and kept if a shadow ray reaches it. Soft shadows, and no shooting noise in the
// direct light; radiosity then shoots only what the surfaces reflect.
void Baker::emitter_light() {
  std::vector<std::uint32_t> emitters;
  std::vector<double> cdf;
  double total = 0;
  for (std::size_t i = 0; i < patches_.size(); ++i) {
    const double power = patches_[i].emission.sum() * patches_[i].area;
    if (!(power > 0)) continue;
    emitters.push_back(static_cast<std::uint32_t>(i));
    cdf.push_back(total += power);
  }
  if (emitters.empty()) return;
  const int n = o_.area_samples;
  std::vector<V3> at_piece(pieces_.size(), V3::Zero());
  arena_.execute([&] {
    arena_.parallel_for(tbb::blocked_range<std::size_t>(0, pieces_.size(), 64), [&](const tbb::blocked_range<std::size_t>& r, int) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const Piece& piece = pieces_[i];
        V3 sum = V3::Zero();
        for (int k = 0; k < n; ++k) {
          const V3 origin = ray_origin(piece, i, 0xE418, static_cast<std::uint64_t>(k)) + piece.face_normal * epsilon_;
          const double pick = (k + hash01(i, 0xE417, static_cast<std::uint64_t>(k), 0)) / n * total;
          const std::size_t e = std::min<std::size_t>(static_cast<std::size_t>(std::lower_bound(cdf.begin(), cdf.end(), pick) - cdf.begin()), emitters.size() - 1);
          const Patch& emitter = patches_[emitters[e]];
          if (emitters[e] == piece.patch) continue;  // a patch does not light itself (it is flat)
          // A piece of the emitter by area, then a point spread over it.
          double at = hash01(i, 0xE417, static_cast<std::uint64_t>(k), 1) * emitter.area, acc = 0;
          std::uint32_t which = emitter.first_piece;
          for (std::uint32_t q = emitter.first_piece; q < emitter.first_piece + emitter.piece_count; ++q) {
            which = q;
            if ((acc += pieces_[q].area) >= at) break;
          }
          const Piece& source = pieces_[which];
          const V3 point = ray_origin(source, i, 0xE417 + static_cast<std::uint64_t>(k), 7) + source.face_normal * epsilon_;
          const V3 d = point - origin;
          const double r2 = d.squaredNorm();
          if (!(r2 > 0)) continue;
          const V3 w = d / std::sqrt(r2);
          const double cos_r = w.dot(piece.normal), cos_e = -w.dot(source.face_normal);
          if (cos_r <= 0 || cos_e <= 0 || w.dot(piece.face_normal) <= 0) continue;
          RTCIntersectContext context;
          rtcInitIntersectContext(&context);
          RTCRay ray{};
          ray.org_x = float(origin.x()), ray.org_y = float(origin.y()), ray.org_z = float(origin.z());
          ray.dir_x = float(d.x()), ray.dir_y = float(d.y()), ray.dir_z = float(d.z());
          ray.tnear = 0.0f, ray.tfar = 1.0f - 1e-4f, ray.mask = 0xffffffffu;
          rtcOccluded1(rscene_, &context, &ray);
          if (ray.tfar == -std::numeric_limits<float>::infinity()) continue;
          // Over the point's probability density: the patch's power share over its area.
          const double density = emitter.emission.sum() / total;
          sum += emitter.emission * (cos_r * cos_e / (std::numbers::pi * r2) / density);
        }
        at_piece[i] = sum / n;
      }
    });
  });
  stats_.rays += pieces_.size() * static_cast<std::size_t>(n);
  for (Patch& patch : patches_) {
    V3 sum = V3::Zero();
    for (std::uint32_t i = patch.first_piece; i < patch.first_piece + patch.piece_count; ++i) sum += at_piece[i] * pieces_[i].area;
    if (patch.area > 0) patch.light += sum / patch.area;
  }
}

void Baker::direct_light() {
  Material white;
  white.ambient = Color3::Zero(), white.diffuse = Color3::Ones(), white.specular = Color3::Zero();
  const lighting::ShadeParams<double> sp = lighting::make_shade_params<double>(scene_, Eigen::Matrix4d::Identity(), white, false);
  if (sp.lights.empty()) return;
  std::vector<V3> at_piece(pieces_.size(), V3::Zero());
  arena_.execute([&] {
    arena_.parallel_for(tbb::blocked_range<std::size_t>(0, pieces_.size(), 256), [&](const tbb::blocked_range<std::size_t>& r, int) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const Piece& piece = pieces_[i];
        const lighting::V3<double> p{piece.position.x(), piece.position.y(), piece.position.z()};
        const lighting::V3<double> n{piece.normal.x(), piece.normal.y(), piece.normal.z()};
        V3 sum = V3::Zero();
        for (const auto& light : sp.lights) {
          lighting::EyeLight<double> L = light;
          L.ambient = {}, L.specular = {}, L.shadow = 0;
          lighting::V3<double> colour{}, specular{};
          float lit = 1.0f;
          lighting::light_contribution(sp, L, p, n, lighting::V3<double>{0, 0, 1}, colour, &specular, &lit);
          if (colour.x == 0 && colour.y == 0 && colour.z == 0) continue;
          // The same light, shadowed: one ray from the piece (off its surface) towards the light.
          const V3 origin = offset_origin(piece);
          V3 dir;
          float tfar;
          if (L.type == LightType::directional) {
            dir = V3(L.to_light.x, L.to_light.y, L.to_light.z), tfar = std::numeric_limits<float>::infinity();
          } else {
            // Up to the light, less the offset: a light lying on a surface is not shadowed by it.
            dir = V3(L.position.x, L.position.y, L.position.z) - origin;
            tfar = static_cast<float>(std::max(0.0, 1.0 - epsilon_ / std::max(dir.norm(), 1e-300)));
          }
          if (dir.dot(piece.face_normal) <= 0) continue;  // behind its own surface
          RTCIntersectContext context;
          rtcInitIntersectContext(&context);
          RTCRay ray{};
          ray.org_x = float(origin.x()), ray.org_y = float(origin.y()), ray.org_z = float(origin.z());
          ray.dir_x = float(dir.x()), ray.dir_y = float(dir.y()), ray.dir_z = float(dir.z());
          ray.tnear = 0.0f, ray.tfar = tfar, ray.mask = 0xffffffffu, ray.flags = 0;
          rtcOccluded1(rscene_, &context, &ray);
          if (ray.tfar == -std::numeric_limits<float>::infinity()) continue;  // blocked
          sum += V3(colour.x, colour.y, colour.z);
        }
        at_piece[i] = sum;
      }
    });
  });
  stats_.rays += pieces_.size() * sp.lights.size();
  for (Patch& patch : patches_) {
    V3 sum = V3::Zero();
    for (std::uint32_t i = patch.first_piece; i < patch.first_piece + patch.piece_count; ++i) sum += at_piece[i] * pieces_[i].area;
    if (patch.area > 0) patch.light += sum / patch.area;
  }
}

Status Baker::radiosity() {
  const std::size_t P = patches_.size();
  // What the patches send out: their reflected direct light, and their emission unless it was
  // gathered as area light already.
  for (Patch& patch : patches_) {
    patch.unshot = patch.albedo.cwiseProduct(patch.light) + (o_.gather_emitters ? V3(V3::Zero()) : patch.emission);
  }
  double entered = 0;
  for (const Patch& patch : patches_) entered += patch.unshot.sum() * patch.area;
  stats_.entered = entered;
  if (!o_.radiosity || P == 0) {
    stats_.unshot = entered;
    stats_.stopped_by = "no radiosity";
    return {};
  }
  const int n = o_.rays_per_shot;
  const int side = std::max(1, static_cast<int>(std::sqrt(double(n))));
  struct Hit {
    std::int64_t patch;  // -1: escaped
    bool back;
  };
  std::vector<Hit> hits(static_cast<std::size_t>(n));
  std::vector<double> cdf;
  stats_.stopped_by = "max_shots";
  auto power_of = [](const Patch& p) { return p.unshot.sum() * p.area; };
  // What the shots sent, what of it reached a front face, and what those faces reflected: the
  // scene's measured share of light that lands and its reflectance, for the ambient term.
  V3 shot_power = V3::Zero(), landed_power = V3::Zero(), reflected_power = V3::Zero();
  PowerTree tree(P);
  {
    std::vector<double> power(P);
    for (std::size_t i = 0; i < P; ++i) power[i] = power_of(patches_[i]);
    tree.fill(power);
  }
  for (std::size_t shot = 0;; ++shot) {
    // The patch with the most unshot power (the first of equals), and the power left.
    const double best = tree.best(), left = tree.sum();
    const std::size_t from = tree.best_index();
    stats_.unshot = left;
    if (!(left > o_.residual * entered) || best <= 0) {
      stats_.stopped_by = "residual";
      break;
    }
    if (shot >= o_.max_shots) break;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (o_.max_seconds > 0 && elapsed >= o_.max_seconds) {
      stats_.stopped_by = "max_seconds";
      break;
    }
    if (o_.progress && shot % 64 == 0) {
      const double done = std::max(entered > 0 ? 1.0 - left / entered : 1.0, double(shot) / double(o_.max_shots));
      if (!o_.progress(std::clamp(done, 0.0, 1.0))) return {ErrorCode::cancelled, "", "bake: cancelled"};
    }
    Patch& source = patches_[from];
    // Ray origins spread over the patch's pieces by area, directions cosine-distributed about
    // each piece's face normal (stratified on a side x side grid).
    cdf.assign(source.piece_count, 0.0);
    double total = 0;
    for (std::uint32_t k = 0; k < source.piece_count; ++k) cdf[k] = (total += pieces_[source.first_piece + k].area);
    arena_.execute([&] {
      arena_.parallel_for(tbb::blocked_range<int>(0, n, 64), [&](const tbb::blocked_range<int>& r, int) {
        for (int k = r.begin(); k != r.end(); ++k) {
          // The piece by area, independent of the direction's stratum (tying the two made rays
          // from one end of a patch all leave in one azimuth).
          const double pick = hash01(from, shot, static_cast<std::uint64_t>(k), 0) * total;
          const std::size_t which = std::min<std::size_t>(static_cast<std::size_t>(std::lower_bound(cdf.begin(), cdf.end(), pick) - cdf.begin()), source.piece_count - 1);
          const Piece& piece = pieces_[source.first_piece + which];
          const V3 dir = stratified_cosine(piece.face_normal, side, k, hash01(from, shot, static_cast<std::uint64_t>(k), 1),
                                           hash01(from, shot, static_cast<std::uint64_t>(k), 2));
          const V3 origin = ray_origin(piece, from, shot, static_cast<std::uint64_t>(k)) + piece.face_normal * epsilon_;
          const RTCRayHit rh = intersect(origin, dir);
          Hit& h = hits[static_cast<std::size_t>(k)];
          h = {-1, false};
          if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
          const V3& fn = surfaces_[rh.hit.geomID].face_normal[rh.hit.primID];
          h.back = fn.dot(dir) >= 0;
          h.patch = h.back ? -1 : patch_at(rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v);
          if (!h.back && h.patch < 0) h.back = true;  // a triangle without texels: absorbed like a back face
        }
      });
    });
    // Applied in ray order: each ray carries 1 / n of the shot's power.
    const V3 power = source.unshot * (source.area / n);
    shot_power += source.unshot * source.area;
    source.unshot = V3::Zero();
    tree.set(from, 0.0);
    for (std::size_t k = 0; k < hits.size(); ++k) {
      const Hit& h = hits[k];
      // The receivers are scattered over the patches: fetch a few rays ahead.
      if (k + 8 < hits.size() && hits[k + 8].patch >= 0) __builtin_prefetch(&patches_[static_cast<std::size_t>(hits[k + 8].patch)]);
      if (h.back) {
        stats_.back_faces += power.sum();
      } else if (h.patch < 0) {
        stats_.escaped += power.sum();
      } else {
        Patch& to = patches_[static_cast<std::size_t>(h.patch)];
        const V3 arriving = power / to.area;
        to.light += arriving;
        const V3 reflected = to.albedo.cwiseProduct(arriving);
        to.unshot += reflected;
        landed_power += power, reflected_power += reflected * to.area;
        tree.set(static_cast<std::size_t>(h.patch), power_of(to));
        stats_.absorbed += (power - reflected * to.area).sum();
      }
    }
    stats_.rays += static_cast<std::size_t>(n);
    stats_.shots = shot + 1;
  }
  if (o_.ambient_from_unshot && stats_.unshot > 0) {
    // The paper's ambient term: the area-weighted average unshot radiosity, reflected again and
    // again. The paper assumes a closed scene (all of it lands, reflected at the average albedo:
    // 1 / (1 - albedo)); measured over the shots so far, the share that lands and the share
    // reflected hold for an open scene too, and for a closed one they are the same numbers.
    V3 unshot = V3::Zero(), albedo = V3::Zero();
    double area = 0;
    for (const Patch& p : patches_) unshot += p.unshot * p.area, albedo += p.albedo * p.area, area += p.area;
    if (area > 0) {
      unshot /= area, albedo /= area;
      V3 lands = V3::Ones(), reflects = albedo;
      for (int c = 0; c < 3; ++c) {
        if (shot_power[c] > 0) lands[c] = landed_power[c] / shot_power[c], reflects[c] = reflected_power[c] / shot_power[c];
      }
      if (reflects.maxCoeff() < 1.0 - 1e-9) {
        const V3 ambient = unshot.cwiseProduct(lands).cwiseQuotient(V3::Ones() - reflects);
        for (Patch& p : patches_) p.light += ambient;
      }
    }
  }
  return {};
}

Result<BakeResult> Baker::run() {
  FACET_TRY(make_surfaces());
  FACET_TRY(make_patches());
  FACET_TRY(build_rays());
  drop_buried_pieces();
  merge_small_patches();
  if (o_.direct) direct_light();
  if (o_.gather_emitters) emitter_light();
  FACET_TRY(radiosity());
  BakeResult out;
  out.lightmaps.resize(surfaces_.size());
  // Each texel's own footprint, every object's in one pass over the pieces (a small texel merged
  // into its neighbour's patch keeps its own).
  std::vector<double> texel_area(stats_.texels, 0.0);
  for (const Piece& piece : pieces_) {
    const Surface& s = surfaces_[piece.object];
    const auto x = static_cast<std::size_t>(std::floor(piece.square.x())), y = static_cast<std::size_t>(std::floor(piece.square.y()));
    const auto w = static_cast<std::size_t>(s.unwrap.width), h = static_cast<std::size_t>(s.unwrap.height);
    if (x < w && y < h) texel_area[s.first_patch_texel + y * w + x] += piece.area;
  }
  for (std::size_t k = 0; k < surfaces_.size(); ++k) {
    BakedLightmap& lm = out.lightmaps[k];
    Surface& s = surfaces_[k];
    lm.object = static_cast<std::uint32_t>(k);
    lm.mesh_uvs = s.mesh_uvs;
    const std::size_t w = static_cast<std::size_t>(s.unwrap.width), h = static_cast<std::size_t>(s.unwrap.height);
    lm.light.assign(w * h, Color3::Zero());
    lm.area.assign(w * h, 0.0f);
    std::vector<std::uint8_t> filled(w * h, 0);
    for (std::size_t i = 0; i < w * h; ++i) {
      const std::int32_t p = texel_patch_[s.first_patch_texel + i];
      if (p < 0) continue;
      lm.light[i] = patches_[static_cast<std::size_t>(p)].light.cast<float>();
      lm.area[i] = static_cast<float>(texel_area[s.first_patch_texel + i]);
      filled[i] = 1;
    }
    // Dilation: each pass fills the empty texels next to filled ones with their average, so that
    // bilinear filtering at a chart's edge reads light, not black.
    for (int pass = 0; pass < o_.charts.padding; ++pass) {
      std::vector<std::uint8_t> next = filled;
      for (std::size_t y = 0; y < h; ++y)
        for (std::size_t x = 0; x < w; ++x) {
          if (filled[y * w + x]) continue;
          Eigen::Vector3d sum = Eigen::Vector3d::Zero();
          int count = 0;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const auto nx = static_cast<std::ptrdiff_t>(x) + dx, ny = static_cast<std::ptrdiff_t>(y) + dy;
              if (nx < 0 || ny < 0 || nx >= static_cast<std::ptrdiff_t>(w) || ny >= static_cast<std::ptrdiff_t>(h)) continue;
              const std::size_t j = static_cast<std::size_t>(ny) * w + static_cast<std::size_t>(nx);
              if (filled[j]) sum += lm.light[j].cast<double>(), ++count;
            }
          if (count) lm.light[y * w + x] = (sum / count).cast<float>(), next[y * w + x] = 1;
        }
      filled = std::move(next);
    }
    lm.unwrap = std::move(s.unwrap);
  }
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  out.stats = stats_;
  return out;
}

}  // namespace

double lightmap_scale(const BakeResult& result) {
  std::vector<float> largest;
  for (const BakedLightmap& lm : result.lightmaps)
    for (std::size_t i = 0; i < lm.light.size(); ++i)
      if (lm.area[i] > 0) largest.push_back(lm.light[i].maxCoeff());
  if (largest.empty()) return 1.0;
  const std::size_t at = std::min(largest.size() - 1, static_cast<std::size_t>(0.999 * static_cast<double>(largest.size())));
  std::nth_element(largest.begin(), largest.begin() + static_cast<std::ptrdiff_t>(at), largest.end());
  return largest[at] > 0 ? double(largest[at]) : 1.0;
}

Status apply_lightmaps(Scene& scene, const BakeResult& result, double scale, LightmapMode mode) {
  if (result.lightmaps.size() != scene.objects.size()) {
    return {ErrorCode::invalid_argument, "result",
            "result: a bake of " + std::to_string(result.lightmaps.size()) + " objects, the scene has " +
                std::to_string(scene.objects.size())};
  }
  if (!(std::isfinite(scale) && scale > 0)) return {ErrorCode::invalid_argument, "scale", "scale: expected a finite number > 0"};
  try {
    Scene out = scene;  // a failure leaves the scene as it was
    for (std::size_t k = 0; k < out.objects.size(); ++k) {
      const BakedLightmap& lm = result.lightmaps[k];
      Instance& inst = out.objects[k];
      Result<Mesh> split = with_lightmap_uvs(out.meshes[inst.mesh].mesh, lm.unwrap);
      if (!split.ok()) return {split.status().code(), "result", "objects[" + std::to_string(k) + "]: " + split.status().message()};
      const int w = lm.unwrap.width, h = lm.unwrap.height;
      std::vector<std::uint8_t> rgba(4 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          // Texture rows top first: row 0 is the lightmap's top (v = 1).
          const Color3& c = lm.light[static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
          std::uint8_t* p = rgba.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x));
          for (int ch = 0; ch < 3; ++ch) p[ch] = static_cast<std::uint8_t>(std::lround(std::clamp(double(c[ch]) / scale, 0.0, 1.0) * 255.0));
          p[3] = 255;
        }
      TextureOptions to;
      to.filter = TextureFilter::bilinear;
      to.wrap = TextureWrap::clamp;
      to.encoding = TextureEncoding::linear;
      Result<Texture> t = make_texture("lightmap_" + std::to_string(k), w, h, rgba, to);
      if (!t.ok()) return {t.status().code(), "result", "objects[" + std::to_string(k) + "]: " + t.status().message()};
      out.meshes.push_back({out.meshes[inst.mesh].name + "#lightmap" + std::to_string(k), std::move(*split)});
      inst.mesh = static_cast<std::uint32_t>(out.meshes.size() - 1);
      out.textures.push_back(std::move(*t));
      inst.lightmap = static_cast<std::int32_t>(out.textures.size() - 1);
      inst.lightmap_scale = static_cast<float>(scale);
      inst.lightmap_mode = mode;
    }
    scene = std::move(out);
    return {};
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "", "apply_lightmaps: out of memory"};
  }
}

Result<BakeResult> bake_lightmaps(const Scene& scene, const BakeOptions& options) {
  FACET_TRY(check_options(options));
  FACET_TRY(validate_scene(scene));
  try {
    Baker baker(scene, options);
    return baker.run();
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", "bake: out of memory"};
  }
}

}  // namespace facet
