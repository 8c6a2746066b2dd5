// Baked light (facet/bake.hpp): the light of a bake: direct light with shadow rays, emissive
// surfaces gathered as area lights, and progressive-refinement radiosity (bake.cpp: the patches).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <tbb/task_arena.h>

#include "bake/baker.hpp"
#include "common/try.hpp"
#include "lighting/setup.hpp"
#include "lighting/shade.hpp"

namespace facet::bake_internal {
namespace {

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

}  // namespace

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
Status Baker::emitter_light() {
  std::vector<std::uint32_t> emitters;
  std::vector<double> cdf;
  double total = 0;
  for (std::size_t i = 0; i < patches_.size(); ++i) {
    const double power = patches_[i].emission.sum() * patches_[i].area;
    if (!(power > 0)) continue;
    emitters.push_back(static_cast<std::uint32_t>(i));
    cdf.push_back(total += power);
  }
  if (emitters.empty()) return {};
  const int n = o_.area_samples;
  std::vector<V3> at_piece(pieces_.size(), V3::Zero());
  FACET_TRY(in_slices(pieces_.size(), 64, [&](const tbb::blocked_range<std::size_t>& r, int) {
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
  }));
  stats_.rays += pieces_.size() * static_cast<std::size_t>(n);
  add_piece_light(at_piece);
  return {};
}

void Baker::add_piece_light(const std::vector<V3>& at_piece) {
  for (Patch& patch : patches_) {
    V3 sum = V3::Zero();
    for (std::uint32_t i = patch.first_piece; i < patch.first_piece + patch.piece_count; ++i) sum += at_piece[i] * pieces_[i].area;
    if (patch.area > 0) patch.light += sum / patch.area;
  }
}

Status Baker::direct_light() {
  Material white;
  white.ambient = Color3::Zero(), white.diffuse = Color3::Ones(), white.specular = Color3::Zero();
  const lighting::ShadeParams<double> sp = lighting::make_shade_params<double>(scene_, Eigen::Matrix4d::Identity(), white, false);
  if (sp.lights.empty()) return {};
  std::vector<V3> at_piece(pieces_.size(), V3::Zero());
  FACET_TRY(in_slices(pieces_.size(), 256, [&](const tbb::blocked_range<std::size_t>& r, int) {
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
  }));
  stats_.rays += pieces_.size() * sp.lights.size();
  add_piece_light(at_piece);
  return {};
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
    FACET_TRY(maybe_checkpoint(std::max(entered > 0 ? 1.0 - left / entered : 1.0,
                                        o_.max_shots > 0 ? double(shot) / double(o_.max_shots) : 1.0)));
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

}  // namespace facet::bake_internal
