// Baked light (facet/bake.hpp): lightmap texels as patches, direct light with shadow rays, and
// progressive-refinement radiosity with ray-cast form factors, all through one Embree scene.
// This file: the options, the charts and patches, the ray scene, burial probes, small texels
// merged, and the result; bake_light.cpp: the light.
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
#include "bake/baker.hpp"


namespace facet {
namespace bake_internal {
namespace {

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

}  // namespace

void bake_error(void* user, RTCError code, const char* message) {
  auto* b = static_cast<Baker*>(user);
  if (b->error_code_ == 0) b->error_code_ = static_cast<int>(code), b->error_ = message ? message : "";
}

Status Baker::checkpoint(double done) {
  last_check_ = elapsed();
  const bool radiosity = std::string_view(phase_) == "radiosity";
  if (o_.max_seconds > 0 && last_check_ >= o_.max_seconds && !radiosity) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.0f %%", 100.0 * std::clamp(done, 0.0, 1.0));
    return {ErrorCode::cancelled, "max_seconds",
            "max_seconds: the time limit of " + format_number(o_.max_seconds) + " s ran out while " + phase_ + " (" + buf +
                " of it done), before any light was shot; allow more time, or bake fewer texels, subdivisions or probe rays"};
  }
  if (o_.progress) {
    const double whole = std::max(last_done_, std::min(1.0, (phase_index_ + std::clamp(done, 0.0, 1.0)) / phase_count_));
    last_done_ = whole;
    if (!o_.progress(whole)) return {ErrorCode::cancelled, "", std::string("bake: cancelled while ") + phase_};
  }
  return {};
}

Status Baker::charge(std::uint64_t bytes, const char* what) {
  used_bytes_ += bytes;
  if (o_.memory_budget_bytes != 0 && used_bytes_ > o_.memory_budget_bytes) {
    return {ErrorCode::out_of_memory, "memory_budget_bytes",
            std::string("memory_budget_bytes: the bake needs more than ") + format_bytes(used_bytes_) + " (" + what + ", " +
                std::to_string(stats_.texels) + " texels at " + format_number(o_.charts.texels_per_unit) +
                " texels per unit, " + std::to_string(o_.subdivisions) + " x " + std::to_string(o_.subdivisions) +
                " pieces a texel), over the budget of " + format_bytes(o_.memory_budget_bytes) +
                "; use fewer texels per unit or subdivisions, or a larger budget"};
  }
  return {};
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
    const std::size_t object_texels = static_cast<std::size_t>(s.unwrap.width) * static_cast<std::size_t>(s.unwrap.height);
    texels += object_texels;
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
    // Per texel: its patch, its light, area and dilation flag in the result, its footprint sum,
    // and a patch (most texels are covered).
    stats_.texels = texels;
    FACET_TRY(charge(std::uint64_t(object_texels) * (sizeof(std::int32_t) + sizeof(Color3) + sizeof(float) + 1 + sizeof(double) +
                                                     sizeof(Patch)), "the lightmaps' texels"));
    FACET_TRY(checkpoint(double(k + 1) / double(scene_.objects.size())));
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
    std::size_t charged = 0;
    // Each piece lives in pieces_ (with its growth), in this object's list and its sort's buffer
    // while they are made, then in a regroup's copy and the per-piece light.
    constexpr std::uint64_t kBytesPerPiece = 3 * sizeof(Piece) + sizeof(V3) + 1;
    for (std::size_t t = 0; t < u.triangles.size(); ++t) {
      if (object_pieces.size() - charged >= 4096) {
        FACET_TRY(charge(std::uint64_t(object_pieces.size() - charged) * kBytesPerPiece, "footprint pieces"));
        charged = object_pieces.size();
      }
      if (t % 64 == 0) FACET_TRY(maybe_checkpoint((double(obj) + double(t) / double(u.triangles.size())) / double(surfaces_.size())));
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
    FACET_TRY(charge(std::uint64_t(object_pieces.size() - charged) * kBytesPerPiece, "footprint pieces"));
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

Status Baker::drop_buried_pieces() {
  const int n = o_.burial_rays;
  if (n == 0 || pieces_.empty()) return {};
  const int side = std::max(1, static_cast<int>(std::sqrt(double(n))));
  std::vector<std::uint8_t> buried(pieces_.size(), 0);
  FACET_TRY(in_slices(pieces_.size(), 64, [&](const tbb::blocked_range<std::size_t>& r, int) {
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
  }));
  stats_.rays += pieces_.size() * static_cast<std::size_t>(n);
  for (const std::uint8_t b : buried) stats_.buried += b;
  if (stats_.buried == 0) return {};  // nothing to regroup
  std::vector<std::int64_t> same(patches_.size());
  for (std::size_t p = 0; p < same.size(); ++p) same[p] = static_cast<std::int64_t>(p);
  regroup(same, buried);
  return {};
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

Result<BakeResult> Baker::run() {
  phase_count_ = 3 + (o_.burial_rays > 0) + o_.direct + o_.gather_emitters;  // charts, patches, radiosity and those that run
  begin_phase("cutting charts");
  FACET_TRY(make_surfaces());
  begin_phase("cutting texels into pieces");
  FACET_TRY(make_patches());
  FACET_TRY(build_rays());
  if (o_.burial_rays > 0) {
    begin_phase("probing for buried pieces");
    FACET_TRY(drop_buried_pieces());
  }
  merge_small_patches();
  if (o_.direct) {
    begin_phase("lighting the pieces directly");
    FACET_TRY(direct_light());
  }
  if (o_.gather_emitters) {
    begin_phase("gathering light from emissive surfaces");
    FACET_TRY(emitter_light());
  }
  begin_phase("radiosity");
  FACET_TRY(radiosity());
  FACET_TRY(checkpoint(1.0));
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

}  // namespace bake_internal

using bake_internal::Baker;
using bake_internal::check_options;

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
  // Every object gets a lightmap: one that could not draw with it is refused now, not after the
  // bake (where apply_lightmaps, or a baked scene file, would refuse it).
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (Status s = check_lightmap_object(scene, i); !s.ok()) {
      return Status{s.code(), s.field(), "cannot bake: " + s.message()};
    }
  }
  try {
    Baker baker(scene, options);
    return baker.run();
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", "bake: out of memory"};
  }
}

}  // namespace facet
