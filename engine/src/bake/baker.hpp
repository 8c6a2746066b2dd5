// Internal: the baker's data and its passes (facet/bake.hpp), shared by bake.cpp (charts,
// patches, the ray scene, burial probes, the result) and bake_light.cpp (direct light, emitters,
// radiosity).
//
// Determinism: every random number is a hash of (patch, shot, ray, dimension); rays are traced
// in parallel into per-ray slots and their results applied in ray order; the patch to shoot is
// the first with the most unshot power; the Embree hierarchy is built in a one-thread arena, so
// that a ray hitting an edge two triangles share finds the same one whatever the caller's
// thread count.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>

#include "common/parallel.hpp"
#include "facet/bake.hpp"

namespace facet::bake_internal {

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
inline double hash01(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
  std::uint64_t x = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull ^
                    (c + 0x85157AF5ull) * 0x94D049BB133111EBull ^ (d + 0x2545F4914F6CDD1Dull);
  x ^= x >> 30, x *= 0xBF58476D1CE4E5B9ull, x ^= x >> 27, x *= 0x94D049BB133111EBull, x ^= x >> 31;
  return static_cast<double>(x >> 11) * 0x1.0p-53;
}

inline void basis(const V3& n, V3& t, V3& b) {
  const V3 axis = std::abs(n.x()) <= std::abs(n.y()) && std::abs(n.x()) <= std::abs(n.z()) ? V3::UnitX()
                  : std::abs(n.y()) <= std::abs(n.z())                                      ? V3::UnitY()
                                                                                             : V3::UnitZ();
  t = axis.cross(n).normalized();
  b = n.cross(t);
}

// Ray k of a set cosine-distributed about `n`, stratified on a side x side grid of the unit
// square (cell k mod side^2), jittered in its cell by two numbers in [0, 1).
V3 stratified_cosine(const V3& n, int side, int k, double jitter_a, double jitter_b);

void bake_error(void* user, RTCError code, const char* message);

class Baker {
 public:
  Baker(const Scene& scene, const BakeOptions& o) : scene_(scene), o_(o), arena_(o.threads > 0 ? o.threads : 1 << 10) {}
  ~Baker() {
    if (rscene_) rtcReleaseScene(rscene_);
    if (device_) rtcReleaseDevice(device_);
  }
  Result<BakeResult> run();

 private:
  // Between pieces of work, on the calling thread: the time limit (max_seconds: radiosity stops
  // with its result, any earlier phase fails, having nothing whole to give), and the host's
  // progress callback, told the share of the whole bake done (phases in equal shares), which may
  // cancel. `done` is the share of the current phase.
  Status checkpoint(double done);
  // A checkpoint when the last was at least 50 ms ago (for loops of many small steps).
  Status maybe_checkpoint(double done) { return elapsed() - last_check_ >= 0.05 ? checkpoint(done) : Status{}; }
  void begin_phase(const char* name) { phase_ = name, ++phase_index_; }
  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  // `bytes` more memory for `what`, against BakeOptions::memory_budget_bytes.
  Status charge(std::uint64_t bytes, const char* what);
  // body(range, worker) over [0, n) in slices sized to take about a tenth of a second, with a
  // checkpoint after each: a long phase stops within a second of its limit or its cancel. The
  // slicing does not change the result (every item is computed on its own).
  template <class Body>
  Status in_slices(std::size_t n, std::size_t grain, const Body& body) {
    std::size_t slice = grain;
    for (std::size_t b = 0; b < n;) {
      const std::size_t e = b + std::min(slice, n - b);
      const double t0 = elapsed();
      arena_.execute([&] { arena_.parallel_for(tbb::blocked_range<std::size_t>(b, e, grain), body); });
      const double took = elapsed() - t0;
      if (took < 0.05 && slice < (std::size_t{1} << 40)) slice *= 2;
      else if (took > 0.2 && slice > grain) slice /= 2;
      b = e;
      if (Status s = checkpoint(double(b) / double(n)); !s.ok()) return s;
    }
    return {};
  }
  const Material& material_of(const Instance& inst, std::size_t triangle) const;
  Status make_surfaces();
  Status make_patches();
  Status build_rays();
  Status drop_buried_pieces();
  void merge_small_patches();
  // Rebuilds pieces_ and patches_ with each piece in patch `target[its patch]` (-1: dropped), the
  // patches in their old order; texel_patch_ and the surfaces' fallbacks follow.
  void regroup(const std::vector<std::int64_t>& target, const std::vector<std::uint8_t>& dropped_piece);
  Status direct_light();
  // Each patch's light += the area-weighted average of its pieces' light.
  void add_piece_light(const std::vector<V3>& at_piece);
  Status emitter_light();
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
  const char* phase_ = "";
  int phase_index_ = -1, phase_count_ = 1;
  double last_done_ = 0;  // the last share reported: reports only grow
  double last_check_ = 0;
  std::uint64_t used_bytes_ = 0;

  friend void bake_error(void*, RTCError, const char*);
};

}  // namespace facet::bake_internal
