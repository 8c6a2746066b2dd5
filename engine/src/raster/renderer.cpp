// The frame pipeline, on the renderer's own task arena: per object, light or transform the
// vertices (parallel batches), assemble triangles in parallel fixed ranges (drop non-finite and
// out-of-frustum ones, clip, project, snap, cull, set up, bin), merge the ranges' bin entries in
// order; then rasterize every tile from its bin and resolve it into the caller's image, one task
// per tile.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <new>
#include <span>

#include <tbb/blocked_range.h>
#include <tbb/info.h>

#include "common/format.hpp"
#include "common/look_at.hpp"
#include "common/parallel.hpp"
#include "facet/render.hpp"
#include "geometry/clip.hpp"
#include "geometry/project.hpp"
#include "io/srgb.hpp"
#include "lighting/point_shader.hpp"
#include "lighting/setup.hpp"
#include "raster/assemble.hpp"
#include "shadow/frame.hpp"
#include "shadow/map.hpp"
#include "shadow/raycast.hpp"
#include "raster/bins.hpp"
#include "raster/pass.hpp"
#include "raster/tile_raster.hpp"
#include "raster/triangle_setup.hpp"
#include "raster/varyings.hpp"
#include "scene/order.hpp"
#include "texture/sampler.hpp"

namespace facet {

const char* to_string(ShadingMode mode) noexcept {
  switch (mode) {
    case ShadingMode::flat: return "flat";
    case ShadingMode::gouraud: return "gouraud";
    case ShadingMode::phong: return "phong";
  }
  return "unknown";
}

DepthMode depth_mode_for(const Camera& camera, DepthMode mode) noexcept {
  if (mode != DepthMode::automatic) return mode;
  const bool reversed = !std::isfinite(camera.far) || double(camera.far) > 1e5 * double(camera.near);
  return reversed ? DepthMode::reversed : DepthMode::gl;
}

const char* to_string(DepthMode mode) noexcept {
  switch (mode) {
    case DepthMode::automatic: return "auto";
    case DepthMode::gl: return "gl";
    case DepthMode::reversed: return "reversed";
  }
  return "unknown";
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Status check_options(const RenderOptions& o) {
  auto bad = [](const char* field, const std::string& what) {
    return Status{ErrorCode::invalid_argument, field, std::string(field) + ": " + what};
  };
  if (o.shading != ShadingMode::flat && o.shading != ShadingMode::gouraud && o.shading != ShadingMode::phong) {
    return bad("options.shading", "unknown shading mode");
  }
  if (o.path != LightingPath::reference && o.path != LightingPath::scalar && o.path != LightingPath::simd) {
    return bad("options.path", "unknown lighting path");
  }
  if (o.isa != Isa::best && o.isa != Isa::sse2 && o.isa != Isa::avx2 && o.isa != Isa::avx512) {
    return bad("options.isa", "unknown instruction set");
  }
  if (o.pow_tier != PowTier::automatic && o.pow_tier != PowTier::exact && o.pow_tier != PowTier::fast &&
      o.pow_tier != PowTier::integer && o.pow_tier != PowTier::schlick) {
    return bad("options.pow_tier", "unknown pow tier");
  }
  if (o.path == LightingPath::simd && !isa_supported(o.isa)) {
    return {ErrorCode::unsupported, "options.isa",
            std::string("options.isa: this CPU has no ") + to_string(o.isa) + " (best available: " +
                to_string(best_isa()) + ")"};
  }
  if (o.cull != CullMode::none && o.cull != CullMode::back && o.cull != CullMode::front) {
    return bad("options.cull", "unknown cull mode");
  }
  if (o.depth != DepthMode::automatic && o.depth != DepthMode::gl && o.depth != DepthMode::reversed) {
    return bad("options.depth", "unknown depth mode");
  }
  if (o.tile_size < 8 || o.tile_size > 256 || o.tile_size % 8 != 0) {
    return bad("options.tile_size", "expected a multiple of 8 in [8, 256], found " + std::to_string(o.tile_size));
  }
  if (o.threads < 0 || o.threads > 256) {
    return bad("options.threads", "expected 0 (all cores) or 1..256, found " + std::to_string(o.threads));
  }
  for (float c : o.clear_color) {
    if (!std::isfinite(c)) return bad("options.clear_color", "expected finite components");
  }
  return {};
}

}  // namespace

// What each worker thread needs for itself, kept from frame to frame.
struct WorkerScratch {
  raster::TileBuffers tile;
  lighting::SoaScratch soa;
};

// Vertices per parallel lighting task and triangles per parallel set-up range. Fixed, so the split
// (and so every bin) is the same for any thread count. Small enough to spread a single 2-6k-triangle
// object over 2 cores (2 threads, 1280x720: spot 1.36 -> 1.0 ms, fandisk 1.9 -> 1.5-1.65 ms, teapot
// 1.4-1.5 -> 1.1-1.4 ms against 4096 and 8192); a range's clipped pieces fit the 16-bit index of a
// bin entry (raster_kernels.hpp), and at most kMaxRanges ranges fit its other 16 bits.
constexpr std::size_t kVertexChunk = 1024;
constexpr std::size_t kTriangleRange = 2048;
constexpr std::size_t kMaxRanges = std::size_t{1} << (32 - raster::kRangeShift);
// Objects at most this large are set up whole by one task, side by side with other such objects.
constexpr std::size_t kSmallObjectVertices = 4096;
constexpr std::size_t kSmallObjectTriangles = 8192;

namespace {
std::size_t ranges_of(std::size_t triangles) { return (triangles + kTriangleRange - 1) / kTriangleRange; }

// The set-up ranges an object takes: one per kTriangleRange triangles of each of its draws.
std::size_t object_ranges(const Scene& scene, const Instance& inst) {
  const Mesh& mesh = scene.meshes[inst.mesh].mesh;
  if (!inst.mesh_materials) return ranges_of(mesh.triangle_count());
  std::size_t n = 0;
  for (const MaterialGroup& g : mesh.groups) n += ranges_of(g.triangle_count);
  return n;
}
}  // namespace

// One draw of the frame: a whole object, or one material group of an object drawn with its mesh's
// materials (Instance::mesh_materials). Its triangles [first_triangle, end_triangle) use only the
// vertices [first_vertex, end_vertex), the only ones it transforms and lights.
struct DrawUnit {
  std::uint32_t object = 0, material = 0;
  std::size_t first_triangle = 0, end_triangle = 0, first_vertex = 0, end_vertex = 0;
  std::size_t triangles() const { return end_triangle - first_triangle; }
  std::size_t vertices() const { return end_vertex - first_vertex; }
  std::size_t ranges() const { return ranges_of(triangles()); }
};

namespace {
// The frame's draws, in object order and, within an object, group order (`units` keeps its
// capacity); a shadow map's pass draws only the objects that cast shadows, the camera's depth pass
// only the draws that write depth.
bool writes_depth(const Material& m) {
  return m.depth_write == DepthWrite::on || (m.depth_write == DepthWrite::automatic && m.blend == BlendMode::opaque);
}
// A colour pass of a back_to_front scene draws its objects in scene_order's order (`keys` keeps
// its capacity); depth passes need no order.
void plan_units(const Scene& scene, const raster::RenderPass& p, std::vector<DrawUnit>& units,
                std::vector<scene_order::ObjectKey>& keys, bool depth_writers_only = false) {
  units.clear();
  const bool casters_only = p.depth_only && p.casters_only;
  const bool depth_writers = (p.depth_only && !p.casters_only) || depth_writers_only;
  const bool sorted = !p.depth_only && scene.transparent_order == TransparentOrder::back_to_front &&
                      scene_order::order_objects(scene, p.view, keys);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const std::size_t o = sorted ? keys[k].object : k;
    const Instance& inst = scene.objects[o];
    if (casters_only && !inst.cast_shadows) continue;
    if (depth_writers && !inst.mesh_materials && !writes_depth(scene.materials[inst.material])) continue;
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    if (!inst.mesh_materials) {
      units.push_back({static_cast<std::uint32_t>(o), inst.material, 0, mesh.triangle_count(), 0, mesh.vertex_count()});
      continue;
    }
    for (const MaterialGroup& g : mesh.groups) {  // validated: every name is a scene material
      DrawUnit u{static_cast<std::uint32_t>(o), static_cast<std::uint32_t>(find_material(scene, g.material)),
                 g.first_triangle, std::size_t{g.first_triangle} + g.triangle_count, mesh.vertex_count(), 0};
      if (depth_writers && !writes_depth(scene.materials[u.material])) continue;
      for (std::size_t t = u.first_triangle; t < u.end_triangle; ++t) {
        for (std::uint32_t v : mesh.triangles[t]) {
          u.first_vertex = std::min<std::size_t>(u.first_vertex, v);
          u.end_vertex = std::max<std::size_t>(u.end_vertex, std::size_t{v} + 1);
        }
      }
      if (u.end_vertex < u.first_vertex) u.first_vertex = u.end_vertex = 0;  // no triangles
      units.push_back(u);
    }
  }
}

std::string mib(std::uint64_t bytes) {
  return std::to_string((bytes + (std::uint64_t{1} << 20) - 1) >> 20) + " MiB";
}

// The one check of the frame's limits, shared by render() and check_render().
Status check_frame_limits(const Scene& scene, const RenderOptions& options, int width, int height) {
  std::size_t ranges = 0;
  for (const Instance& inst : scene.objects) ranges += object_ranges(scene, inst);
  if (ranges > kMaxRanges) {
    return {ErrorCode::unsupported, "objects",
            "objects: the frame needs " + std::to_string(ranges) + " set-up ranges, at most " +
                std::to_string(kMaxRanges) + " fit in one frame (each object, or material group, takes one range per " +
                std::to_string(kTriangleRange) + " triangles, at least one: at most " + std::to_string(kMaxRanges) +
                " objects and " + std::to_string(kMaxRanges * kTriangleRange) + " triangles)"};
  }
  const std::uint64_t need = estimate_frame_bytes(scene, options, width, height);
  if (options.memory_budget_bytes != 0 && need > options.memory_budget_bytes) {
    return {ErrorCode::out_of_memory, "options.memory_budget_bytes",
            "options.memory_budget_bytes: the frame needs about " + mib(need) + " of scratch memory, over its budget of " +
                format_bytes(options.memory_budget_bytes) +
                " (raise RenderOptions::memory_budget_bytes, or facet render --memory-budget-mb)"};
  }
  return {};
}
}  // namespace

struct Renderer::Impl {
  // Threads: this renderer's own arena, rebuilt only when the thread count changes.
  std::unique_ptr<parallel::Arena> arena;
  int arena_threads = 0;
  // Ray-cast shadows: the frame's casters (built in the arena when a light casts ray-cast shadows).
  shadow::RayCaster caster;
  const shadow::RayCaster* frame_caster = nullptr;  // this frame's, or null
  bool has_shadows = false;  // some light is shadowed this frame (frame_shadows applies)
  // Shadow maps: one per scene light (planned and drawn when the light has one), the casters'
  // bounds they are fitted to, the depth views their passes write, and what the lighting reads.
  std::vector<shadow::ShadowMap> maps;
  std::vector<const shadow::ShadowMap*> frame_maps;  // per scene light: its map this frame, or null
  std::vector<DepthView> map_views;
  shadow::CasterBounds caster_bounds;
  // Shadow volumes: the camera's depth (drawn by a depth-only pass first) and each volume
  // light's mask.
  shadow::ShadowVolumes volumes;
  DepthView volume_depth;
  shadow::FrameShadows frame_shadows;
  Status frame_status;  // a failure inside the arena (the casters' build)
  // One per arena slot (tbb::this_task_arena::current_thread_index()), sized on the calling
  // thread before any parallel loop, so that no task ever allocates.
  std::vector<WorkerScratch> workers;
  WorkerScratch& worker(int slot) { return workers[static_cast<std::size_t>(slot)]; }
  std::vector<raster::RasterCounters> tile_counters;
  // Frame-wide state, reused from frame to frame (capacity is kept).
  std::vector<std::vector<raster::ScreenTriangle>> range_triangles;
  std::vector<raster::RangeBinning> range_binning;
  std::vector<raster::PendingTriangles> range_pending;  // per range: between the assembly phases
  std::vector<const raster::ScreenTriangle*> range_data;
  std::size_t range_count = 0;
  std::vector<std::vector<std::uint32_t>> bins;
  // Each pass's draws (objects, or their material groups), planned once per pass (plan_units),
  // kept with their capacity; `units` is the running pass's.
  std::vector<std::vector<DrawUnit>> pass_units;
  std::span<const DrawUnit> units;
  std::vector<lighting::PointShader> shaders;  // one per draw
  std::vector<raster::simd::Draw> draws;               // one per draw: its varyings and pixel program
  std::vector<lighting::LightingFeatures> features;  // one per draw: what its lighting takes and gives
  std::vector<char> draw_two_sided;  // one per draw: both faces drawn and lit (the pass's rule, or Instance::double_sided)
  std::vector<texture::Sampler> samplers;        // one per scene texture
  raster::simd::Fog fog;
  SrgbTable srgb;  // made once per renderer (RenderOptions::srgb)
  Impl() { make_srgb_table(srgb); }
  // Per vertex: outcodes, and for vertices inside the guard band the snapped screen position,
  // computed once instead of once per triangle that uses the vertex.
  using ScreenVertex = geometry::ScreenVertex;
  // What one object's set-up needs between its lighting and its assembly. One per arena slot:
  // small objects are set up whole by one task each, on that task's slot's scratch; large ones one
  // at a time, with their vertices and ranges spread over the threads, on slot 0's.
  struct ObjectScratch {
    std::vector<std::array<float, 4>> clip;
    std::vector<ScreenVertex> screen;
    std::vector<Color3> front, back;
    std::vector<Color3> front_spec, back_spec, flat_albedo;  // textured: specular apart; flat: mean vertex colour
    std::vector<Vec3> eye_p, eye_n, centroid, face_normal;
    // Gouraud: 1 for a vertex of a triangle that may be drawn (or clipped; marked by
    // raster::place_range), and per vertex chunk the list of those vertices.
    std::vector<std::uint8_t> drawn;
    std::vector<std::uint32_t> lit_index;
    // The object's model matrix has a negative determinant (a mirror): its triangles wind the
    // other way on screen, so front and back swap (as in glTF, Direct3D and GL's glFrontFace).
    bool mirrored = false;
    // Capacity for any object of up to `vertices` vertices and `triangles` triangles in this
    // shading mode, so that whichever object a slot gets, set-up allocates nothing.
    void reserve(std::size_t vertices, std::size_t triangles, ShadingMode mode, bool both_faces, bool surfaces);
  };
  std::vector<ObjectScratch> object_scratch;
  // Per object: its first set-up range (ranges are numbered in object order, so bins do not
  // depend on which objects ran in parallel) and its counters, added up in object order.
  struct ObjectCounts {
    std::uint64_t vertices_lit = 0, vertices_skipped = 0, pairs_evaluated = 0, pairs_skipped = 0;
    double seconds_lighting = 0, seconds_geometry = 0;
  };
  std::vector<std::size_t> first_range;
  std::vector<ObjectCounts> object_counts;

  // The frame plan: its passes, run in order (capacity is kept), and the one running.
  std::vector<raster::RenderPass> passes;
  const raster::RenderPass* pass = nullptr;
  bool simd_raster = true;  // the simd path rasterizes with the SIMD kernels
  const raster::simd::Kernels* simd_kernels = nullptr;  // its ISA's, when simd_raster
  bool light_every_vertex = false;  // RenderOptions::light_every_vertex
  FrameStats stats;
  FrameStats last_stats;  // of the last successful render
  // Progress and cancellation (RenderOptions::progress): work units are vertex chunks, set-up
  // ranges and tiles; loops skip their remaining units once `cancelled` is set.
  const std::function<bool(double)>* progress = nullptr;
  std::atomic<std::uint64_t> work_done{0};
  std::uint64_t work_total = 1;
  std::atomic<bool> cancelled{false};
  std::mutex progress_mutex;  // one callback at a time; a busy thread skips its report
  double progress_reported = 0;  // under progress_mutex
  void unit_done();
  RenderOptions config;   // for render(scene, color, ...)

  void render(const Scene& scene, const RenderOptions& options, const ImageView& color, const DepthView* depth);
  // Flat and Gouraud shading with shadows: a frame of sub-frames summed per pixel (see below).
  void render_composite(const Scene& scene, const RenderOptions& options, const ImageView& color,
                        const DepthView* depth);
  // What a sub-frame of render_composite changes: a visibility sub-frame (Phong, plain surfaces,
  // each pixel's visibility of three shadowed lights as its colour), or a part (the lights,
  // ambient and fog the shaders see come from `part_lighting`; emission left out when asked).
  enum class SubFrame { none, visibility, part };
  SubFrame sub_frame = SubFrame::none;
  std::size_t visibility_lights[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX};
  const Scene* part_lighting = nullptr;
  bool part_without_emission = false;
  std::vector<float> composite_base, composite_part, composite_visibility;
  Scene composite_lights;  // lights, ambient and fog of a part (no meshes)
  void run_pass(const Scene& scene, const RenderOptions& options, const raster::RenderPass& p,
                std::span<const DrawUnit> pass_draws);
  void plan_draws(const Scene& scene, const RenderOptions& options, const raster::RenderPass& p);
  // Progress units of a pass with these draws: its tiles, set-up ranges and vertex chunks.
  std::uint64_t pass_work(const Scene& scene, const raster::RenderPass& p, std::span<const DrawUnit> pass_draws) const;
  std::vector<scene_order::ObjectKey> order_keys;  // plan_units' scratch (TransparentOrder::back_to_front)
  // Runs body(range, slot) over [begin, end) in chunks of `grain`: spread over the arena's threads
  // when `slot` < 0, else all on the calling task's slot.
  template <class Body>
  void for_chunks(std::size_t begin, std::size_t end, std::size_t grain, int slot, const Body& body);
  void set_up_object(const Scene& scene, std::uint32_t object, const Eigen::Matrix4d& view,
                     const Eigen::Matrix4d& proj, const LightingOptions& lighting, ObjectScratch& os, int slot);
  void prepare_object(const Scene& scene, const Instance& inst, const Eigen::Matrix4d& view,
                      const Eigen::Matrix4d& proj, const LightingOptions& lighting, std::uint32_t object,
                      ObjectScratch& os, int slot);
  // The first phase of assembly over the object's ranges (raster::place_range): its triangles
  // that can be drawn, in range_pending, and (Gouraud) their vertices marked in `drawn`.
  void place_object(const Mesh& mesh, std::uint32_t object, const ObjectScratch& os, std::uint8_t* drawn, int slot);
  void assemble_object(const Mesh& mesh, std::uint32_t object, float alpha, const ObjectScratch& os, int slot);
};

Status check_render_options(const RenderOptions& options) noexcept {
  try {
    return check_options(options);
  } catch (const std::exception&) {
    return {ErrorCode::out_of_memory, "options", "out of memory while checking the options"};
  }
}

// Whether some enabled light of `scene` casts ray-cast shadows; whether one casts shadows from a map.
static bool casts_raycast_shadows(const Scene& scene) {
  return std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
           return l.enabled && l.shadow.method == ShadowMethod::raycast;
         });
}
static bool casts_volume_shadows(const Scene& scene) {
  return std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
    return l.enabled && l.shadow.method == ShadowMethod::volume;
  });
}
static bool casts_map_shadows(const Scene& scene) {
  return std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
           return l.enabled && l.shadow.method == ShadowMethod::map;
         });
}

// World-space boxes of the objects that cast shadows (their finite vertices' model-space boxes,
// corners through the model matrix).
static void bound_casters(const Scene& scene, shadow::CasterBounds& out) {
  out.lo.clear();
  out.hi.clear();
  for (const Instance& inst : scene.objects) {
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    Eigen::Vector3d lo, hi;
    if (!inst.cast_shadows || mesh.triangles.empty() || !lighting::finite_box(mesh.positions, lo, hi)) continue;
    const Eigen::Matrix4d model = inst.model.cast<double>();
    Eigen::AlignedBox3d box;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d c((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
      box.extend((model * c.homogeneous()).head<3>());
    }
    if (!box.min().allFinite() || !box.max().allFinite()) continue;
    out.lo.push_back(box.min());
    out.hi.push_back(box.max());
  }
}

std::uint64_t estimate_frame_bytes(const Scene& scene, const RenderOptions& options, int width, int height) noexcept {
  using U = std::uint64_t;
  const auto sat_add = [](U a, U b) { return a > ~U{0} - b ? ~U{0} : a + b; };
  const auto sat_mul = [](U a, U b) { return b != 0 && a > ~U{0} / b ? ~U{0} : a * b; };
  // Per vertex: clip position, screen vertex, front and back colour, eye position and normal.
  const U per_vertex = 16 + 24 + 2 * 12 + 2 * 12;
  // Per triangle: its record, its entry between the set-up's two phases (4 + 1 bytes) and its
  // bin entries (one tile each, for unclipped small triangles); for flat shading also its
  // centroid, face normal and two colours (4 x 12 bytes).
  U bytes = 0, max_vertices = 0, max_triangles = 0;
  for (const Instance& inst : scene.objects) {
    if (inst.mesh >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    bytes = sat_add(bytes, sat_mul(mesh.triangle_count(), sizeof(raster::ScreenTriangle) + 5 + 3 * 4));
    max_vertices = std::max<U>(max_vertices, mesh.vertex_count());
    max_triangles = std::max<U>(max_triangles, mesh.triangle_count());
  }
  const U slots = static_cast<U>(
      parallel::usable_threads(options.threads > 0 ? std::min(options.threads, 256) : tbb::info::default_concurrency()));
  // Slot 0 holds the largest object; the others at most a small object each.
  bytes = sat_add(bytes, sat_add(sat_mul(max_vertices, per_vertex), sat_mul(max_triangles, 4 * 12)));
  bytes = sat_add(bytes, sat_mul(slots, kSmallObjectVertices * per_vertex + kSmallObjectTriangles * 4 * 12));
  // Per object: its shader's copy of the lights.
  bytes = sat_add(bytes, sat_mul(sat_mul(scene.objects.size(), scene.lights.size()), 512));
  // Per thread: tile planes and SoA lighting scratch; per tile: its bin.
  const U tile = static_cast<U>(std::clamp(options.tile_size, 8, 256));
  bytes = sat_add(bytes, sat_mul(slots, 5 * tile * tile * 4 + 64 * 1024));
  const U tiles = (static_cast<U>(std::max(width, 1)) / tile + 1) * (static_cast<U>(std::max(height, 1)) / tile + 1);
  bytes = sat_add(bytes, sat_mul(tiles, 64));
  // Ray-cast shadows: Embree's copy of the casters (12 bytes a vertex and a triangle's indices)
  // and its hierarchy (allowed 96 bytes a triangle), and the per-thread visibility scratch.
  const bool raycast = casts_raycast_shadows(scene);
  if (raycast) {
    for (const Instance& inst : scene.objects) {
      if (inst.mesh >= scene.meshes.size() || !inst.cast_shadows) continue;
      const Mesh& mesh = scene.meshes[inst.mesh].mesh;
      bytes = sat_add(bytes, sat_add(sat_mul(mesh.vertex_count(), 12), sat_mul(mesh.triangle_count(), 12 + 96)));
    }
  }
  // Shadow maps: their depth images (every face) and their passes' bins; and the per-thread
  // visibility scratch of every shadowed light.
  bool maps = false;
  for (const Light& l : scene.lights) {
    if (!l.enabled || l.shadow.method != ShadowMethod::map) continue;
    maps = true;
    const U texels = static_cast<U>(shadow::ShadowMap::bytes(l)) / 4;
    bytes = sat_add(bytes, sat_add(texels * 4, (texels / (tile * tile) + 6) * 64));
  }
  // Shadow volumes: the camera's depth, the masks, the volumes' triangles, the casters' adjacency.
  std::size_t volume_lights = 0, casters = 0;
  for (const Light& l : scene.lights) volume_lights += l.enabled && l.shadow.method == ShadowMethod::volume;
  if (volume_lights > 0) {
    for (const Instance& inst : scene.objects) {
      if (inst.mesh < scene.meshes.size() && inst.cast_shadows) casters += scene.meshes[inst.mesh].mesh.triangle_count();
    }
    bytes = sat_add(bytes, shadow::ShadowVolumes::bytes(width, height, volume_lights, casters));
  }
  // Flat and Gouraud shadows: three float frames and a visibility per shadowed light
  // (render_composite).
  std::size_t shadowed = 0;
  for (const Light& l : scene.lights) shadowed += l.enabled && l.shadow.method != ShadowMethod::none;
  if (shadowed > 0 && options.shading != ShadingMode::phong) {
    const U pixels = static_cast<U>(std::max(width, 1)) * static_cast<U>(std::max(height, 1));
    bytes = sat_add(bytes, sat_mul(pixels, 3 * 16 + 4 * U(shadowed)));
  }
  if (raycast || maps || volume_lights > 0) {
    bytes = sat_add(bytes, sat_mul(slots, U(kMaxShadowedLights) * (kVertexChunk + kTriangleRange) * 8));
  }
  return bytes;
}

Status check_render(const Scene& scene, const RenderOptions& options, int width, int height) noexcept {
  try {
    if (width < 1 || height < 1 || width > kMaxImageDimension || height > kMaxImageDimension) {
      return {ErrorCode::invalid_argument, "image",
              "image: expected a size of 1.." + std::to_string(kMaxImageDimension) + " per side"};
    }
    if (Status s = check_options(options); !s.ok()) return s;
    if (Status s = validate_scene(scene); !s.ok()) return s;
    // Flat and Gouraud shadows sum sub-frames per pixel (render_composite): only for materials
    // whose colour is linear in the lighting.
    const bool shadowed = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
      return l.enabled && l.shadow.method != ShadowMethod::none;
    });
    if (shadowed && options.shading != ShadingMode::phong) {
      for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& mat = scene.materials[m];
        const bool textured = mat.diffuse_texture != kNoTexture;
        const std::string field = "materials[" + std::to_string(m) + "]";
        if (textured && mat.texture_mode != TextureMode::modulate) {
          return {ErrorCode::unsupported, field + ".texture_mode",
                  field + ".texture_mode: with shadows in flat or Gouraud shading, textures modulate the lighting "
                          "(\"modulate\"), or draw in Phong shading (--shading phong)"};
        }
        if (mat.blend != BlendMode::opaque && mat.blend != BlendMode::alpha && mat.blend != BlendMode::premultiplied) {
          return {ErrorCode::unsupported, field + ".blend",
                  field + ".blend: with shadows in flat or Gouraud shading, blending is opaque, alpha or "
                          "premultiplied, or draw in Phong shading (--shading phong)"};
        }
      }
    }
    return check_frame_limits(scene, options, width, height);
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "scene", "out of memory while checking the scene"};
  }
}

std::uint64_t Renderer::Impl::pass_work(const Scene& scene, const raster::RenderPass& p,
                                        std::span<const DrawUnit> pass_draws) const {
  std::uint64_t work = static_cast<std::uint64_t>(p.tile_count());
  const bool placed = !p.depth_only && p.shading != ShadingMode::phong && !light_every_vertex;
  for (const DrawUnit& u : pass_draws) {  // ranges, clip chunks, then lighting or centroid chunks
    work += u.ranges() + (u.vertices() + kVertexChunk - 1) / kVertexChunk;
    if (!p.depth_only) {
      work += (u.vertices() + kVertexChunk - 1) / kVertexChunk +
              (u.triangles() + kVertexChunk - 1) / kVertexChunk *
                  (p.two_sided() || scene.objects[u.object].double_sided ? 2 : 1);
    }
    if (placed) work += u.ranges();  // the placing phase
  }
  return work;
}

void Renderer::Impl::unit_done() {
  const std::uint64_t done = work_done.fetch_add(1, std::memory_order_relaxed) + 1;
  if (!progress || cancelled.load(std::memory_order_relaxed)) return;
  std::unique_lock<std::mutex> lock(progress_mutex, std::try_to_lock);
  // After a report that said stop, no other report follows.
  if (!lock.owns_lock() || cancelled.load(std::memory_order_relaxed)) return;
  // Reports never go backwards, whichever thread's count arrives first.
  progress_reported = std::max(progress_reported, std::min(1.0, static_cast<double>(done) / static_cast<double>(work_total)));
  if (!(*progress)(progress_reported)) cancelled.store(true, std::memory_order_relaxed);
}

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::Renderer(const RenderOptions& config) : impl_(std::make_unique<Impl>()) { impl_->config = config; }

const RenderOptions& Renderer::config() const noexcept {
  static const RenderOptions kDefaults;  // immutable; for a moved-from renderer
  return impl_ ? impl_->config : kDefaults;
}

void Renderer::set_config(const RenderOptions& config) noexcept {
  if (impl_) impl_->config = config;
}

Status Renderer::render(const Scene& scene, const ImageView& color, const DepthView* depth,
                        FrameStats* stats) noexcept {
  if (!impl_) return {ErrorCode::invalid_argument, "renderer", "renderer: used after being moved from"};
  return render(scene, impl_->config, color, depth, stats);
}

FrameStats Renderer::last_stats() const noexcept { return impl_ ? impl_->last_stats : FrameStats{}; }
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Status Renderer::render(const Scene& scene, const RenderOptions& options, const ImageView& color,
                        const DepthView* depth, FrameStats* stats) noexcept {
  try {
    if (!impl_) return {ErrorCode::invalid_argument, "renderer", "renderer: used after being moved from"};
    if (Status s = validate_image_view(color); !s.ok()) return s;
    if (depth) {
      if (Status s = validate_depth_view(*depth, color.width, color.height); !s.ok()) return s;
    }
    if (Status s = check_render(scene, options, color.width, color.height); !s.ok()) return s;
    const int threads = parallel::usable_threads(options.threads > 0 ? options.threads : tbb::info::default_concurrency());
    if (!impl_->arena || impl_->arena_threads != threads) {
      impl_->arena = std::make_unique<parallel::Arena>(threads);
      impl_->arena_threads = impl_->arena->threads();
      impl_->workers.clear();
      impl_->workers.resize(static_cast<std::size_t>(impl_->arena_threads));
    }
    impl_->progress = options.progress ? &options.progress : nullptr;
    impl_->cancelled.store(false);
    impl_->work_done.store(0);
    impl_->progress_reported = 0;
    impl_->frame_status = {};
    const bool composite = options.shading != ShadingMode::phong &&
                           std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
                             return l.enabled && l.shadow.method != ShadowMethod::none;
                           });
    impl_->arena->execute([&] {
      if (composite) {
        impl_->render_composite(scene, options, color, depth);
      } else {
        impl_->render(scene, options, color, depth);
      }
    });
    if (!impl_->frame_status.ok()) return impl_->frame_status;
    if (impl_->cancelled.load()) {
      return {ErrorCode::cancelled, "options.progress", "options.progress: the frame was cancelled"};
    }
    impl_->last_stats = impl_->stats;
    if (stats) *stats = impl_->stats;
    return {};
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "scene", "out of memory while rendering"};
  } catch (const std::exception& e) {
    return {ErrorCode::invalid_argument, "scene", std::string("render failed: ") + e.what()};
  }
}

void Renderer::Impl::render(const Scene& scene, const RenderOptions& options, const ImageView& color,
                            const DepthView* depth) {
  const auto frame_start = Clock::now();
  stats = FrameStats{};
  stats.threads = arena_threads;
  for (WorkerScratch& w : workers) {  // grows only when the tile size or the chunk size grows
    w.tile.resize(options.tile_size);
    // The most points one lighting call takes: a vertex chunk, or a set-up range's triangles (flat).
    w.soa.reserve_padded(std::max(kVertexChunk, kTriangleRange));
  }
  // A part of a flat or Gouraud frame with shadows is drawn without them (render_composite).
  const bool shadows = sub_frame != SubFrame::part;
  const bool raycast = shadows && casts_raycast_shadows(scene), map_shadows = shadows && casts_map_shadows(scene);
  if (raycast || map_shadows || (shadows && casts_volume_shadows(scene))) {  // the shadowed lights' visibility of a lighting call's points, and its padded copies
    const std::size_t points = lighting::simd::padded(std::max(kVertexChunk, kTriangleRange));
    for (WorkerScratch& w : workers) {
      if (w.soa.visibility.size() < 2 * kMaxShadowedLights * points) w.soa.visibility.resize(2 * kMaxShadowedLights * points);
    }
  }
  light_every_vertex = options.light_every_vertex;
  simd_raster = options.path == LightingPath::simd;
  simd_kernels = simd_raster ? raster::simd_raster_kernels(options.isa) : nullptr;
  passes.clear();
  raster::RenderPass camera = raster::camera_pass(scene, options, color, depth);
  camera.assembly.place = simd_kernels ? simd_kernels->place : nullptr;
  // Shadow maps: fitted to the casters and the camera, then one depth-only pass per face, before
  // the camera's pass.
  frame_maps.assign(scene.lights.size(), nullptr);
  bool any_map = false;
  if (map_shadows) {
    const auto start = Clock::now();
    bound_casters(scene, caster_bounds);
    if (maps.size() < scene.lights.size()) maps.resize(scene.lights.size());
    map_views.clear();
    map_views.reserve(6 * kMaxShadowedLights);  // validated: the passes' pointers stay put
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
      const Light& light = scene.lights[l];
      if (!light.enabled || light.shadow.method != ShadowMethod::map || map_views.size() + 6 > map_views.capacity()) continue;
      shadow::ShadowMap& map = maps[l];
      map.plan(light, caster_bounds, camera.view, camera.projection);
      if (map.empty()) continue;  // nothing can shade a visible point: the light is not shadowed
      map.set_kernel(simd_kernels ? simd_kernels->shadow_map : nullptr);
      frame_maps[l] = &map;
      any_map = true;
      for (int f = 0; f < map.face_count(); ++f) {
        map_views.push_back(map.depth_view(f));
        passes.push_back(raster::depth_pass(map.face_view(f), map.face_projection(f), map_views.back(), options.tile_size));
        passes.back().depth_dirty = map.dirty_tiles(f, options.tile_size);
        passes.back().assembly.place = camera.assembly.place;
        stats.shadow_map_texels += static_cast<std::uint64_t>(map.resolution()) * static_cast<std::uint64_t>(map.resolution());
      }
    }
    for (const Instance& inst : scene.objects) {
      if (inst.cast_shadows) stats.shadow_casters += scene.meshes[inst.mesh].mesh.triangle_count();
    }
    stats.seconds_shadows += seconds_since(start);
  }
  // Shadow volumes: the camera's depth alone, then (after that pass) the volumes' masks.
  if (shadows) {
    volumes.plan(scene, camera.width(), camera.height());
  } else {
    volumes.disable();
  }
  if (volumes.active()) {
    volume_depth = volumes.depth_view();
    raster::RenderPass d = camera;  // the same view, culling and triangles
    d.shading = ShadingMode::flat;
    d.depth_only = true;
    d.casters_only = false;
    d.color = nullptr;
    d.depth = &volume_depth;
    d.depth_dirty = volumes.dirty_tiles(options.tile_size);
    passes.push_back(d);
    for (const Instance& inst : scene.objects) {
      if (inst.cast_shadows && !map_shadows) stats.shadow_casters += scene.meshes[inst.mesh].mesh.triangle_count();
    }
  }
  passes.push_back(camera);
  // Ray-cast shadows: the casters as Embree sees them, built here, in this renderer's arena.
  frame_caster = nullptr;
  if (raycast) {
    const auto start = Clock::now();
    frame_status = caster.build(scene, camera.view);
    stats.seconds_shadows += seconds_since(start);
    stats.shadow_casters = caster.triangle_count();
    if (!frame_status.ok()) return;
    frame_caster = &caster;
  }
  frame_shadows = {frame_caster, frame_maps, volumes.active() ? &volumes : nullptr};
  has_shadows = frame_caster || any_map || volumes.active();
  work_total = 0;
  if (pass_units.size() < passes.size()) pass_units.resize(passes.size());
  for (std::size_t k = 0; k < passes.size(); ++k) {
    plan_units(scene, passes[k], pass_units[k], order_keys, sub_frame == SubFrame::visibility);
    work_total += pass_work(scene, passes[k], pass_units[k]);
  }
  work_total = std::max<std::uint64_t>(work_total, 1);
  for (std::size_t k = 0; k < passes.size(); ++k) {
    const raster::RenderPass& p = passes[k];
    const auto start = Clock::now();
    run_pass(scene, options, p, pass_units[k]);
    if (p.depth_only && !p.casters_only && !cancelled.load(std::memory_order_relaxed)) {
      volumes.build(scene, camera.view, camera.projection, *arena);  // the camera's depth is drawn
    }
    if (p.depth_only) stats.seconds_shadows += seconds_since(start);
    if (cancelled.load(std::memory_order_relaxed)) break;
  }
  pass = nullptr;
  units = {};
  stats.seconds_total = seconds_since(frame_start);
}

// Flat and Gouraud shading with shadows. Each shadowed light's diffuse and specular terms are
// drawn apart from the rest, so that every pixel can take its own visibility of that light (the
// shadow's edge runs through triangles, not along them):
//   1. visibility: a Phong sub-frame of the same view finds each pixel's visibility of three
//      shadowed lights at a time with the lights' own methods (the point and normal the pixel
//      shows; plain surfaces: no texture, vertex colour or blending; only depth-writing draws);
//   2. the base: the frame in the options' shading with the shadowed lights' diffuse and specular
//      terms left out (their ambient terms stay), into floats, with the caller's depth;
//   3. one part per shadowed light: its diffuse and specular terms alone (no emission, no
//      ambient light, black fog and background), in the same shading;
//   4. per pixel, base + sum of part x visibility, clamped unless the output is HDR floats, stored
//      as the tiles store pixels.
// Every step is linear in the lighting for the materials check_render admits (modulate textures;
// opaque, alpha or premultiplied blending), so a frame whose lights all see everything is the
// unshadowed frame up to rounding (one step). Sub-frames are deterministic, so the frame is too.
// Progress is reported by the last part alone.
void Renderer::Impl::render_composite(const Scene& scene, const RenderOptions& options, const ImageView& color,
                                      const DepthView* depth) {
  const auto frame_start = Clock::now();
  const int w = color.width, h = color.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<std::size_t> shadowed;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    if (scene.lights[l].enabled && scene.lights[l].shadow.method != ShadowMethod::none) shadowed.push_back(l);
  }
  auto float_view = [&](std::vector<float>& buffer) {
    buffer.resize(4 * pixels);
    return ImageView{buffer.data(), w, h, static_cast<std::size_t>(w) * 4 * sizeof(float), PixelFormat::rgba32f, false};
  };
  const std::function<bool(double)>* user_progress = progress;
  progress = nullptr;
  auto finish = [&] {
    sub_frame = SubFrame::none;
    part_lighting = nullptr;
    part_without_emission = false;
    progress = user_progress;
  };
  auto stopped = [&] { return !frame_status.ok() || cancelled.load(std::memory_order_relaxed); };
  FrameStats shadow_stats;
  RenderOptions sub = options;
  sub.srgb = false;
  sub.hdr = options.hdr && color.format == PixelFormat::rgba32f;  // as the lighting would clamp into `color`
  double seconds_shadows = 0;
  // 1. Visibility, three lights a sub-frame.
  composite_visibility.resize(shadowed.size() * pixels);
  sub_frame = SubFrame::visibility;
  RenderOptions vis = sub;
  vis.shading = ShadingMode::phong;
  vis.clear_color = {1.0f, 1.0f, 1.0f, 1.0f};
  vis.hdr = false;
  for (std::size_t g = 0; g < shadowed.size(); g += 3) {
    for (std::size_t c = 0; c < 3; ++c) visibility_lights[c] = g + c < shadowed.size() ? shadowed[g + c] : SIZE_MAX;
    render(scene, vis, float_view(composite_part), nullptr);
    seconds_shadows += stats.seconds_total;
    if (g == 0) shadow_stats = stats;  // the casters, maps and their texels (every sub-frame draws the same)
    if (stopped()) return finish();
    for (std::size_t c = 0; c < 3 && g + c < shadowed.size(); ++c) {
      float* out = composite_visibility.data() + (g + c) * pixels;
      for (std::size_t i = 0; i < pixels; ++i) out[i] = composite_part[4 * i + c];
    }
  }
  // 2. The base.
  sub_frame = SubFrame::part;
  composite_lights.lights = scene.lights;
  composite_lights.global_ambient = scene.global_ambient;
  composite_lights.viewer = scene.viewer;
  composite_lights.two_sided = scene.two_sided;
  composite_lights.fog = scene.fog;
  for (const std::size_t l : shadowed) {
    composite_lights.lights[l].diffuse = Color3(0.0f, 0.0f, 0.0f);
    composite_lights.lights[l].specular = Color3(0.0f, 0.0f, 0.0f);
  }
  part_lighting = &composite_lights;
  render(scene, sub, float_view(composite_base), depth);
  const FrameStats base = stats;
  if (stopped()) return finish();
  // 3. The parts, each added times its visibility.
  RenderOptions part = sub;
  part.clear_color = {0.0f, 0.0f, 0.0f, 0.0f};
  composite_lights.global_ambient = Color3(0.0f, 0.0f, 0.0f);
  composite_lights.fog.color = Color3(0.0f, 0.0f, 0.0f);
  part_without_emission = true;
  for (std::size_t k = 0; k < shadowed.size(); ++k) {
    composite_lights.lights = scene.lights;
    for (std::size_t l = 0; l < scene.lights.size(); ++l) composite_lights.lights[l].enabled = l == shadowed[k];
    composite_lights.lights[shadowed[k]].ambient = Color3(0.0f, 0.0f, 0.0f);
    if (k + 1 == shadowed.size()) progress = user_progress;
    render(scene, part, float_view(composite_part), nullptr);
    seconds_shadows += stats.seconds_total;
    if (stopped()) return finish();
    const float* v = composite_visibility.data() + k * pixels;
    for (std::size_t i = 0; i < pixels; ++i) {
      for (int c = 0; c < 3; ++c) composite_base[4 * i + static_cast<std::size_t>(c)] += v[i] * composite_part[4 * i + static_cast<std::size_t>(c)];
    }
  }
  finish();
  // 4. Store.
  const bool clamp = !(options.hdr && color.format == PixelFormat::rgba32f);
  const float* srgb_threshold = options.srgb && color.format != PixelFormat::rgba32f ? srgb.threshold : nullptr;
  const std::size_t bytes = color.format == PixelFormat::rgba32f ? 16 : 4;
  for (int y = 0; y < h; ++y) {
    const int row = color.y_up ? h - 1 - y : y;
    auto* dst = static_cast<std::uint8_t*>(color.data) + static_cast<std::size_t>(row) * color.stride_bytes;
    for (int x = 0; x < w; ++x) {
      float* rgba = composite_base.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x));
      if (clamp) {
        for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] > 0.0f ? (rgba[c] < 1.0f ? rgba[c] : 1.0f) : 0.0f;
      }
      raster::store_pixel(rgba, color.format, srgb_threshold, dst + static_cast<std::size_t>(x) * bytes);
    }
  }
  stats = base;
  stats.seconds_shadows = seconds_shadows;  // the visibility sub-frames and the parts
  stats.shadow_casters = shadow_stats.shadow_casters;
  stats.shadow_map_texels = shadow_stats.shadow_map_texels;
  stats.shadow_map_pixels = shadow_stats.shadow_map_pixels;
  stats.seconds_total = seconds_since(frame_start);
}

void Renderer::Impl::run_pass(const Scene& scene, const RenderOptions& options, const raster::RenderPass& p,
                              std::span<const DrawUnit> pass_draws) {
  pass = &p;
  const ShadingMode shading = p.shading;
  const int tiles_x = p.tiles_x, tile_size = p.tile_size;
  range_count = 0;  // counted below, per draw
  bins.resize(static_cast<std::size_t>(p.tile_count()));
  for (auto& bin : bins) bin.clear();
  units = pass_draws;
  shaders.resize(units.size());
  plan_draws(scene, options, p);
  const bool two_sided = std::find(draw_two_sided.begin(), draw_two_sided.end(), 1) != draw_two_sided.end();

  const Eigen::Matrix4d& view = p.view;
  const Eigen::Matrix4d& proj = p.projection;
  LightingOptions lighting;
  lighting.path = options.path;
  lighting.isa = options.isa;
  lighting.pow_tier = options.pow_tier;
  lighting.clamp = !(options.hdr && p.color && p.color->format == PixelFormat::rgba32f);
  lighting.cull_lights = options.cull_lights;
  light_every_vertex = options.light_every_vertex;

  // Set-up ranges, numbered in draw order.
  const std::size_t object_count = units.size();
  first_range.resize(object_count);
  for (std::size_t o = 0; o < object_count; ++o) {
    first_range[o] = range_count;
    range_count += units[o].ranges();
  }
  if (range_triangles.size() < range_count) {  // grows only with the scene
    range_triangles.resize(range_count);
    range_binning.resize(range_count);
    range_pending.resize(range_count);
  }
  object_counts.assign(object_count, {});
  object_scratch.resize(workers.size());
  // Runs of two or more small objects are set up side by side, one task per object (the built-in scene's six
  // objects took 1.6 ms of a 5.8 ms frame one after another on 2 threads). Larger objects are set
  // up one at a time with their chunks and ranges spread over the threads.
  auto small = [&](std::size_t o) {
    const Mesh& mesh = scene.meshes[scene.objects[units[o].object].mesh].mesh;
    const std::size_t lit = shading == ShadingMode::flat ? mesh.triangle_count() : mesh.vertex_count();
    return lit <= kSmallObjectVertices && mesh.triangle_count() <= kSmallObjectTriangles;
  };
  // Which slot sets up which small object depends on the schedule, so every slot's scratch is
  // sized here, on the calling thread, for the largest object it could get: slot 0 for every
  // object (large ones always run on it), the others for every small one. A frame that has run
  // once then allocates nothing, whatever the schedule (tests/alloc).
  std::size_t small_v = 0, small_t = 0, all_v = 0, all_t = 0;
  for (std::size_t o = 0; o < object_count; ++o) {
    const Mesh& mesh = scene.meshes[scene.objects[units[o].object].mesh].mesh;
    all_v = std::max(all_v, mesh.vertex_count());
    all_t = std::max(all_t, mesh.triangle_count());
    if (small(o)) {
      small_v = std::max(small_v, mesh.vertex_count());
      small_t = std::max(small_t, mesh.triangle_count());
    }
  }
  for (std::size_t slot = 0; slot < object_scratch.size(); ++slot) {
    object_scratch[slot].reserve(slot == 0 ? all_v : small_v, slot == 0 ? all_t : small_t, shading, two_sided,
                                 !scene.textures.empty());
  }
  for (std::size_t o = 0; o < object_count;) {
    if (!small(o)) {
      set_up_object(scene, static_cast<std::uint32_t>(o), view, proj, lighting, object_scratch[0], -1);
      ++o;
      continue;
    }
    std::size_t end = o + 1;
    while (end < object_count && small(end)) ++end;
    if (end == o + 1) {  // alone: its own chunks and ranges are the only parallelism
      set_up_object(scene, static_cast<std::uint32_t>(o), view, proj, lighting, object_scratch[0], -1);
      ++o;
      continue;
    }
    arena->parallel_for(tbb::blocked_range<std::size_t>(o, end, 1), [&](const tbb::blocked_range<std::size_t>& r, int slot) {
      for (std::size_t k = r.begin(); k != r.end(); ++k) {
        set_up_object(scene, static_cast<std::uint32_t>(k), view, proj, lighting,
                      object_scratch[static_cast<std::size_t>(slot)], slot);
      }
    });
    o = end;
  }
  for (const ObjectCounts& c : object_counts) {  // in draw order
    if (p.depth_only) break;  // a shadow map's set-up counts as the shadows' time
    stats.vertices_lit += c.vertices_lit;
    stats.vertices_skipped += c.vertices_skipped;
    stats.vertex_lights_evaluated += c.pairs_evaluated;
    stats.vertex_lights_skipped += c.pairs_skipped;
    stats.seconds_lighting += c.seconds_lighting;
    stats.seconds_geometry += c.seconds_geometry;
  }

  if (cancelled.load(std::memory_order_relaxed)) return;  // before any pixel is written

  // The tile loop: each tile is rasterized and resolved by exactly one task, from its bin (in
  // submission order) into its own pixels, so the image does not depend on the schedule.
  // Counters are kept per tile and added up in tile order afterwards.
  const auto merge_start = Clock::now();
  raster::merge_ranges(range_binning, range_count, bins, stats);
  if (!p.depth_only) stats.seconds_geometry += seconds_since(merge_start);
  range_data.resize(range_count);
  for (std::size_t r = 0; r < range_count; ++r) range_data[r] = range_triangles[r].data();
  const raster::RasterJob job{shading,
                              range_data.data(),
                              shaders,
                              p.clear_color,
                              simd_kernels,
                              draws.data(),
                              &fog,
                              options.srgb && p.color && p.color->format != PixelFormat::rgba32f ? srgb.threshold : nullptr,
                              p.assembly.viewport.depth};
  const int tile_count = p.tile_count();
  tile_counters.assign(static_cast<std::size_t>(tile_count), {});
  const auto raster_start = Clock::now();
  arena->parallel_for(tbb::blocked_range<int>(0, tile_count), [&](const tbb::blocked_range<int>& range, int slot) {
    WorkerScratch& w = worker(slot);
    for (int index = range.begin(); index != range.end(); ++index) {
      if (cancelled.load(std::memory_order_relaxed)) return;
      const int tx = index % tiles_x, ty = index / tiles_x;
      const raster::TileRect rect{tx * tile_size, ty * tile_size, std::min(p.width(), (tx + 1) * tile_size),
                                  std::min(p.height(), (ty + 1) * tile_size)};
      raster::RasterCounters& c = tile_counters[static_cast<std::size_t>(index)];
      const auto& bin = bins[static_cast<std::size_t>(index)];
      if (p.depth_only) {  // a shadow map's face: depth alone
        std::uint8_t& dirty = p.depth_dirty[index];
        if (bin.empty()) {
          if (dirty) raster::resolve_clear_depth(rect, *p.depth);  // else still far depth from an earlier frame
          dirty = 0;
        } else {
          raster::rasterize_tile(job, bin, rect, w.tile, w.soa, c);
          raster::resolve_depth_tile(job, w.tile, rect, *p.depth);
          dirty = 1;
        }
        unit_done();
        continue;
      }
      if (bin.empty()) {  // nothing to rasterize: the clear colour goes straight to the image
        const auto resolve_start = Clock::now();
        raster::resolve_clear_tile(p.clear_color, job.srgb, rect, *p.color, p.depth, job.depth.output(job.depth.far()));
        c.seconds_resolve = seconds_since(resolve_start);
        continue;
      }
      raster::rasterize_tile(job, bin, rect, w.tile, w.soa, c);
      const auto resolve_start = Clock::now();
      raster::resolve_tile(job, w.tile, rect, *p.color, p.depth);
      c.seconds_resolve = seconds_since(resolve_start);
      unit_done();
    }
  });
  stats.seconds_raster = seconds_since(raster_start);
  raster::RasterCounters counters;
  for (const raster::RasterCounters& c : tile_counters) counters += c;  // in tile order
  if (p.depth_only) {
    if (p.casters_only) stats.shadow_map_pixels += counters.filled;
    return;
  }
  stats.seconds_resolve = counters.seconds_resolve;
  stats.pixels_tested = counters.tested;
  stats.pixels_filled = counters.filled;
  stats.vertices_lit += counters.shaded;
  stats.vertex_lights_evaluated += counters.light_pairs;
  stats.vertex_lights_skipped += counters.skipped_pairs;
}

}  // namespace facet

namespace facet::raster {

RenderPass depth_pass(const Eigen::Matrix4d& view, const Eigen::Matrix4d& projection, const DepthView& depth,
                      int tile_size) {
  RenderPass p;
  p.view = view;
  p.projection = projection;
  p.shading = ShadingMode::flat;
  p.depth_only = true;
  p.casters_only = true;
  p.tile_size = tile_size;
  p.tiles_x = (depth.width + tile_size - 1) / tile_size;
  p.tiles_y = (depth.height + tile_size - 1) / tile_size;
  p.assembly.viewport = {depth.width, depth.height};
  p.assembly.planes = geometry::guard_band_planes(p.assembly.viewport);
  p.assembly.cull = CullMode::none;
  p.assembly.two_sided = true;
  p.assembly.grid = {p.tile_size, p.tiles_x, p.tiles_y};
  p.depth = &depth;
  return p;
}

RenderPass camera_pass(const Scene& scene, const RenderOptions& options, const ImageView& color, const DepthView* depth) {
  RenderPass p;
  const int width = color.width, height = color.height;
  const float aspect = scene.camera.aspect > 0.0f ? scene.camera.aspect : float(width) / float(height);
  p.view = look_at_d(scene.camera);
  p.projection = projection_matrix(scene.camera, aspect).cast<double>();
  p.shading = options.shading;
  p.clear_color = options.clear_color;
  p.tile_size = options.tile_size;
  p.tiles_x = (width + p.tile_size - 1) / p.tile_size;
  p.tiles_y = (height + p.tile_size - 1) / p.tile_size;
  p.assembly.viewport = {width, height, {depth_mode_for(scene.camera, options.depth) == DepthMode::reversed, scene.camera.near}};
  p.assembly.planes = geometry::guard_band_planes(p.assembly.viewport);
  p.assembly.cull = options.cull;
  p.assembly.two_sided = scene.two_sided;
  p.assembly.grid = {p.tile_size, p.tiles_x, p.tiles_y};
  p.color = &color;
  p.depth = depth;
  return p;
}

}  // namespace facet::raster

namespace facet {

void Renderer::Impl::ObjectScratch::reserve(std::size_t vertices, std::size_t triangles, ShadingMode mode,
                                            bool both_faces, bool surfaces) {
  clip.reserve(vertices);
  screen.reserve(vertices);
  if (mode == ShadingMode::gouraud) {
    drawn.reserve(vertices);
    lit_index.reserve(vertices);
    front.reserve(vertices);
    if (both_faces) back.reserve(vertices);
    if (surfaces) {  // a textured object's specular, kept apart
      front_spec.reserve(vertices);
      if (both_faces) back_spec.reserve(vertices);
    }
    return;
  }
  if (mode == ShadingMode::flat) {
    flat_albedo.reserve(triangles);
    if (surfaces) {
      front_spec.reserve(triangles);
      if (both_faces) back_spec.reserve(triangles);
    }
  }
  eye_p.reserve(vertices);
  eye_n.reserve(vertices);
  if (mode == ShadingMode::flat) {
    centroid.reserve(triangles);
    face_normal.reserve(triangles);
    front.reserve(triangles);
    if (both_faces) back.reserve(triangles);
  }
}

// The frame plan per object: what its lighting takes and gives, its varyings and its pixel
// program. An untextured opaque material without alpha test or fog (and, lit per pixel, without
// vertex colours) runs the plain kernels: exactly what ran before surfaces existed.
void Renderer::Impl::plan_draws(const Scene& scene, const RenderOptions& options, const raster::RenderPass& p) {
  samplers.resize(scene.textures.size());
  for (std::size_t i = 0; i < scene.textures.size(); ++i) samplers[i] = texture::make_sampler(scene.textures[i]);
  const Fog& f = sub_frame == SubFrame::visibility ? Fog{} : part_lighting ? part_lighting->fog : scene.fog;
  fog = raster::simd::Fog{};
  fog.mode = static_cast<int>(f.mode);
  for (int c = 0; c < 3; ++c) fog.color[c] = f.color[c];
  fog.start = f.start, fog.end = f.end, fog.density = f.density;
  fog.scale = f.end > f.start ? static_cast<float>(1.0 / (double(f.end) - double(f.start))) : 0.0f;
  const bool clamp = !(options.hdr && p.color && p.color->format == PixelFormat::rgba32f);
  const raster::LitAt lit = p.shading == ShadingMode::flat      ? raster::LitAt::triangle
                            : p.shading == ShadingMode::gouraud ? raster::LitAt::vertex
                                                                : raster::LitAt::pixel;
  draws.resize(units.size());
  features.resize(units.size());
  draw_two_sided.resize(units.size());
  for (std::size_t o = 0; o < units.size(); ++o) {
    const Instance& inst = scene.objects[units[o].object];
    const Material& m = scene.materials[units[o].material];
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    const bool plain = sub_frame == SubFrame::visibility;  // visibility: no texture, colour or blend
    const bool textured = !plain && m.diffuse_texture != kNoTexture;
    const bool colours = !plain && !mesh.colors.empty();
    // Emission after the texture environment (adds_emission_after_texture); none in the
    // visibility and part sub-frames.
    const bool emission_stage = !plain && !part_without_emission && adds_emission_after_texture(m);
    const bool emission_texture = emission_stage && m.emissive_texture != kNoTexture;
    draw_two_sided[o] = p.two_sided() || inst.double_sided;
    lighting::LightingFeatures& lf = features[o];
    lf.color_material = colours;
    lf.separate_specular = textured;
    raster::SurfaceNeeds needs;
    needs.secondary = textured && lit == raster::LitAt::vertex;
    needs.albedo = colours && lit == raster::LitAt::pixel;
    needs.uv = textured || emission_texture;
    raster::simd::Draw& d = draws[o];
    d = raster::simd::Draw{};
    if (p.depth_only) continue;  // no varying, no program: depth alone (every caster is opaque)
    d.layout = raster::plan_varyings(lit, draw_two_sided[o] != 0, needs);
    d.texture = textured ? &samplers[static_cast<std::size_t>(m.diffuse_texture)] : nullptr;
    d.texture_env = static_cast<int>(m.texture_mode);
    if (emission_stage) {
      d.emission = 1;
      for (int c = 0; c < 3; ++c) d.emission_rgb[c] = m.emissive[c];
      if (emission_texture) d.emission_texture = &samplers[static_cast<std::size_t>(m.emissive_texture)];
    }
    d.uv_scale[0] = m.uv_scale.x(), d.uv_scale[1] = m.uv_scale.y();
    d.alpha_cutoff = m.alpha_cutoff;
    d.blend = plain ? static_cast<int>(BlendMode::opaque) : static_cast<int>(m.blend);
    d.depth_write = writes_depth(m);
    d.clamp = clamp ? 1 : 0;
    d.program = textured || d.emission || d.blend != static_cast<int>(BlendMode::opaque) || m.alpha_cutoff > 0.0f || !d.depth_write ||
                f.mode != FogMode::none || needs.albedo;
  }
}

template <class Body>
void Renderer::Impl::for_chunks(std::size_t begin, std::size_t end, std::size_t grain, int slot, const Body& body) {
  auto unit = [&](const tbb::blocked_range<std::size_t>& r, int s) {
    if (cancelled.load(std::memory_order_relaxed)) return;
    body(r, s);
    unit_done();
  };
  if (slot < 0) {
    if (begin < end) arena->parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain), unit);
  } else {
    for (std::size_t b = begin; b < end; b += grain) unit(tbb::blocked_range<std::size_t>(b, std::min(end, b + grain), grain), slot);
  }
}

// One object: lighting, then assembly into its set-up ranges. slot < 0: spread over the threads.
void Renderer::Impl::set_up_object(const Scene& scene, std::uint32_t object, const Eigen::Matrix4d& view,
                                   const Eigen::Matrix4d& proj, const LightingOptions& lighting, ObjectScratch& os,
                                   int slot) {
  const DrawUnit& u = units[object];
  const Instance& inst = scene.objects[u.object];
  prepare_object(scene, inst, view, proj, lighting, object, os, slot);
  const auto geometry_start = Clock::now();
  assemble_object(scene.meshes[inst.mesh].mesh, object, scene.materials[u.material].alpha, os, slot);
  object_counts[object].seconds_geometry += seconds_since(geometry_start);
}

void Renderer::Impl::prepare_object(const Scene& scene, const Instance& inst, const Eigen::Matrix4d& view,
                                    const Eigen::Matrix4d& proj, const LightingOptions& lighting,
                                    std::uint32_t object, ObjectScratch& os, int slot) {
  const ShadingMode shading = pass->shading;
  const bool two_sided = draw_two_sided[object] != 0;
  const Mesh& mesh = scene.meshes[inst.mesh].mesh;
  const DrawUnit& unit = units[object];
  // Arrays are indexed by the mesh's vertex and triangle numbers; a draw fills its own part.
  const std::size_t n = mesh.vertex_count(), v0 = unit.first_vertex, v1 = unit.end_vertex;
  const auto lighting_start = Clock::now();
  std::vector<std::array<float, 4>>& clip = os.clip;
  std::vector<ScreenVertex>& screen = os.screen;
  os.mirrored = inst.model.cast<double>().topLeftCorner<3, 3>().determinant() < 0.0;
  // Clip-space positions.
  const geometry::Mat4Rows mvp = geometry::to_rows(proj * view * inst.model.cast<double>());
  clip.resize(n);
  screen.resize(n);
  // The simd path transforms with its ISA's kernel (bit-identical to the scalar function).
  static_assert(sizeof(Vec3) == 3 * sizeof(float), "the kernels read positions as xyz triples");
  const raster::simd::TransformFunction transform = simd_kernels ? simd_kernels->transform : nullptr;
  for_chunks(v0, v1, kVertexChunk, slot, [&](const tbb::blocked_range<std::size_t>& r, int) {
    if (transform) {
      transform(mvp, mesh.positions.data()->data(), r.begin(), r.end(), pass->assembly.planes, pass->assembly.viewport,
                clip.data(), screen.data());
    } else {
      geometry::transform_vertices(mvp, mesh.positions.data(), r.begin(), r.end(), pass->assembly.planes,
                                   pass->assembly.viewport, clip.data(), screen.data());
    }
  });

  if (pass->depth_only) return;  // a shadow map: positions are all it needs

  lighting::PointShader& shader = shaders[object];
  const lighting::EyeSphere bounds = lighting::eye_bounding_sphere(mesh, view, inst.model);
  // Options were checked in render(), so preparing cannot fail here.
  const lighting::LightingFeatures& lf = features[object];
  Material material = scene.materials[unit.material];
  // Emission left out of the lighting: in the parts of a composite frame, or added by the pixel program.
  if (part_without_emission || draws[object].emission) material.emissive = Color3(0.0f, 0.0f, 0.0f);
  (void)shader.prepare(part_lighting ? *part_lighting : scene, view, material, lighting, &bounds, lf,
                       inst.receive_shadows && has_shadows ? &frame_shadows : nullptr);
  if (sub_frame == SubFrame::visibility) shader.output_visibility(visibility_lights);
  ObjectCounts& counts = object_counts[object];
  auto count_pairs = [&](std::size_t evaluations) {
    counts.vertices_lit += evaluations;
    counts.pairs_evaluated += evaluations * shader.light_count();
    counts.pairs_skipped += evaluations * shader.culled_lights();
  };
  std::vector<Color3>&front = os.front, &back = os.back;
  std::vector<Vec3>&eye_p = os.eye_p, &eye_n = os.eye_n, &centroid = os.centroid, &face_normal = os.face_normal;

  const bool split = lf.separate_specular;
  if (shading == ShadingMode::gouraud) {
    front.resize(n);
    if (two_sided) back.resize(n);
    if (split) {
      os.front_spec.resize(n);
      if (two_sided) os.back_spec.resize(n);
    }
    // Only the vertices of triangles that may be drawn are lit (the others' colours are never
    // read): the first phase of assembly places the triangles without their varyings and marks
    // their vertices (raster::place_range, ranges in parallel), then they are listed per vertex
    // chunk. A vertex's colour does not depend on its batch or its neighbours, so the image is
    // the same as with every vertex lit; assemble_object() finishes the placed triangles.
    const std::uint32_t* index = nullptr;
    std::atomic<std::size_t> listed{0};  // vertices lit
    if (!light_every_vertex) {
      std::vector<std::uint8_t>& drawn = os.drawn;
      drawn.resize(n);
      os.lit_index.resize(n);
      std::fill(drawn.begin() + static_cast<std::ptrdiff_t>(v0), drawn.begin() + static_cast<std::ptrdiff_t>(v1), 0);
      place_object(mesh, object, os, drawn.data(), slot);
      index = os.lit_index.data();
    }
    for_chunks(v0, v1, kVertexChunk, slot, [&](const tbb::blocked_range<std::size_t>& r, int chunk_slot) {
      lighting::SoaScratch& soa = worker(chunk_slot).soa;
      std::size_t begin = r.begin(), end = r.end();
      if (index) {  // this chunk's drawn vertices, listed from its own offset
        std::uint32_t* list = os.lit_index.data() + begin;
        std::size_t count = 0;
        for (std::size_t v = begin; v != end; ++v) {
          list[count] = static_cast<std::uint32_t>(v);
          count += os.drawn[v];
        }
        end = begin + count;
      }
      listed.fetch_add(end - begin, std::memory_order_relaxed);
      shader.light_mesh(mesh, view, inst.model, false, begin, end, front.data(), soa,
                        split ? os.front_spec.data() : nullptr, index);
      if (two_sided) {
        shader.light_mesh(mesh, view, inst.model, true, begin, end, back.data(), soa,
                          split ? os.back_spec.data() : nullptr, index);
      }
    });
    const std::size_t lit_vertices = listed.load(std::memory_order_relaxed);
    counts.vertices_skipped += (v1 - v0 - lit_vertices) * (two_sided ? 2 : 1);
    count_pairs(lit_vertices * (two_sided ? 2 : 1));
    counts.seconds_lighting += seconds_since(lighting_start);
    return;
  }

  // Flat and Phong need eye-space positions and normals.
  const auto xf = lighting::make_eye_transform<float>(view, inst.model);
  eye_p.resize(n);
  eye_n.resize(n);
  for (std::size_t i = v0; i < v1; ++i) {
    const Vec3& p = mesh.positions[i];
    const Vec3& nn = mesh.normals[i];
    const float* m = xf.position;
    const float* q = xf.normal;
    eye_p[i] = Vec3(m[0] * p.x() + m[1] * p.y() + m[2] * p.z() + m[3], m[4] * p.x() + m[5] * p.y() + m[6] * p.z() + m[7],
                    m[8] * p.x() + m[9] * p.y() + m[10] * p.z() + m[11]);
    eye_n[i] = Vec3(q[0] * nn.x() + q[1] * nn.y() + q[2] * nn.z(), q[3] * nn.x() + q[4] * nn.y() + q[5] * nn.z(),
                    q[6] * nn.x() + q[7] * nn.y() + q[8] * nn.z());
  }
  if (shading == ShadingMode::flat) {
    // One evaluation per triangle: the face normal (from the eye-space corners) at the centroid.
    const std::size_t t_count = mesh.triangle_count(), t0 = unit.first_triangle, t1 = unit.end_triangle;
    centroid.resize(t_count);
    face_normal.resize(t_count);
    for (std::size_t t = t0; t < t1; ++t) {
      const auto& tri = mesh.triangles[t];
      const Vec3 &a = eye_p[tri[0]], &b = eye_p[tri[1]], &c = eye_p[tri[2]];
      centroid[t] = (a + b + c) / 3.0f;
      face_normal[t] = os.mirrored ? (c - a).cross(b - a) : (b - a).cross(c - a);
    }
    if (lf.color_material) {  // the albedo at the centroid: the mean of the corners' colours
      os.flat_albedo.resize(t_count);
      for (std::size_t t = t0; t < t1; ++t) {
        const auto& tri = mesh.triangles[t];
        os.flat_albedo[t] = (mesh.colors[tri[0]] + mesh.colors[tri[1]] + mesh.colors[tri[2]]) / 3.0f;
      }
    }
    front.resize(t_count);
    if (two_sided) back.resize(t_count);
    if (split) {
      os.front_spec.resize(t_count);
      if (two_sided) os.back_spec.resize(t_count);
    }
    // Only triangles that may be drawn are lit (unless light_every_vertex): the first phase of
    // assembly lists them per range (raster::place_range); per range their centroids, normals
    // and albedos are moved to the front of the range's part of the arrays, lit there, and each
    // colour moved back to its triangle, last first (triangle t_k >= slot k, so no colour is
    // overwritten before it is moved). A point's colour does not depend on its place in a batch,
    // so the colours are those of lighting every triangle.
    if (!light_every_vertex) place_object(mesh, object, os, nullptr, slot);
    std::atomic<std::size_t> listed{0};
    const std::size_t first = first_range[object];
    // Triangles [begin, end): lit whole, or (a set-up range) only those the first phase listed.
    auto light = [&](std::size_t begin, std::size_t end, const raster::PendingTriangles* pending, int chunk_slot) {
      std::size_t count = end - begin;
      const std::uint32_t* list = nullptr;
      if (pending) {
        list = pending->triangle.data();
        count = pending->triangle.size();
        for (std::size_t k = 0; k < count; ++k) {
          const std::size_t t = list[k];
          centroid[begin + k] = centroid[t], face_normal[begin + k] = face_normal[t];
          if (lf.color_material) os.flat_albedo[begin + k] = os.flat_albedo[t];
        }
      }
      listed.fetch_add(count, std::memory_order_relaxed);
      auto shade = [&](std::vector<Color3>& out, std::vector<Color3>& spec) {
        shader.shade_points(count, centroid.data() + begin, face_normal.data() + begin, out.data() + begin,
                            worker(chunk_slot).soa, lf.color_material ? os.flat_albedo.data() + begin : nullptr,
                            split ? spec.data() + begin : nullptr);
        if (!list) return;
        for (std::size_t k = count; k-- > 0;) {
          out[list[k]] = out[begin + k];
          if (split) spec[list[k]] = spec[begin + k];
        }
      };
      shade(front, os.front_spec);
      if (two_sided) {
        for (std::size_t k = begin; k != begin + count; ++k) face_normal[k] = -face_normal[k];
        shade(back, os.back_spec);
      }
    };
    if (light_every_vertex) {
      for_chunks(t0, t1, kVertexChunk, slot, [&](const tbb::blocked_range<std::size_t>& r, int chunk_slot) {
        light(r.begin(), r.end(), nullptr, chunk_slot);
      });
    } else {
      for_chunks(0, unit.ranges(), 1, slot, [&](const tbb::blocked_range<std::size_t>& rs, int chunk_slot) {
        for (std::size_t r = rs.begin(); r != rs.end(); ++r) {
          const std::size_t begin = t0 + r * kTriangleRange;
          light(begin, std::min(t1, begin + kTriangleRange), &range_pending[first + r], chunk_slot);
        }
      });
    }
    const std::size_t lit_triangles = listed.load(std::memory_order_relaxed);
    counts.vertices_skipped += (t1 - t0 - lit_triangles) * (two_sided ? 2 : 1);
    count_pairs(lit_triangles * (two_sided ? 2 : 1));
  }
  counts.seconds_lighting += seconds_since(lighting_start);
}

void Renderer::Impl::place_object(const Mesh& mesh, std::uint32_t object, const ObjectScratch& os, std::uint8_t* drawn,
                                  int slot) {
  raster::ObjectVertices placing;  // what the first phase reads: positions and winding
  placing.clip = os.clip;
  placing.screen = os.screen;
  placing.mirrored = os.mirrored;
  placing.two_sided = draw_two_sided[object] != 0;
  placing.object = object;
  const std::size_t first = first_range[object];
  const DrawUnit& unit = units[object];
  for_chunks(0, unit.ranges(), 1, slot, [&](const tbb::blocked_range<std::size_t>& rs, int) {
    for (std::size_t r = rs.begin(); r != rs.end(); ++r) {
      const std::size_t begin = unit.first_triangle + r * kTriangleRange;
      raster::place_range(pass->assembly, mesh, placing, begin, std::min(unit.end_triangle, begin + kTriangleRange),
                          range_triangles[first + r], range_binning[first + r], range_pending[first + r], drawn);
    }
  });
}

void Renderer::Impl::assemble_object(const Mesh& mesh, std::uint32_t object, float alpha, const ObjectScratch& os,
                                     int slot) {
  const bool two_sided = draw_two_sided[object] != 0;
  const std::size_t first = first_range[object];
  const bool flat = pass->shading == ShadingMode::flat;
  raster::ObjectVertices vertices;
  const raster::simd::Draw& draw = draws[object];
  const lighting::LightingFeatures& lf = features[object];
  vertices.layout = draw.layout;
  vertices.clip = os.clip;
  vertices.screen = os.screen;
  using raster::Varying;
  // Vec3 and Color3 are three packed floats (types.hpp); an empty array (a mesh without vertices) is null.
  auto source = [&](Varying v, const auto& values) {
    vertices.varying[static_cast<int>(v)] = draw.layout.has(v) ? reinterpret_cast<const float*>(values.data()) : nullptr;
  };
  source(Varying::front_color, os.front);
  source(Varying::back_color, os.back);
  source(Varying::front_secondary, os.front_spec);
  source(Varying::back_secondary, os.back_spec);
  source(Varying::eye_position, os.eye_p);
  source(Varying::normal, os.eye_n);
  source(Varying::albedo, mesh.colors);
  source(Varying::uv, mesh.uvs);
  vertices.flat_front = flat ? os.front.data() : nullptr;
  vertices.flat_back = flat && two_sided ? os.back.data() : nullptr;
  vertices.flat_secondary_front = flat && lf.separate_specular ? os.front_spec.data() : nullptr;
  vertices.flat_secondary_back = flat && two_sided && lf.separate_specular ? os.back_spec.data() : nullptr;
  vertices.mirrored = os.mirrored;
  vertices.two_sided = two_sided;
  vertices.object = object;
  vertices.alpha = alpha;
  // Gouraud and flat lit only where drawn: the second phase of the assembly prepare_object() began.
  const bool placed = !pass->depth_only && pass->shading != ShadingMode::phong && !light_every_vertex;
  const DrawUnit& unit = units[object];
  for_chunks(0, unit.ranges(), 1, slot, [&](const tbb::blocked_range<std::size_t>& rs, int) {
    for (std::size_t r = rs.begin(); r != rs.end(); ++r) {
      if (placed) {
        raster::finish_range(pass->assembly, mesh, vertices, range_triangles[first + r], range_binning[first + r],
                             range_pending[first + r]);
        continue;
      }
      const std::size_t begin = unit.first_triangle + r * kTriangleRange;
      raster::assemble_range(pass->assembly, mesh, vertices, begin, std::min(unit.end_triangle, begin + kTriangleRange),
                             range_triangles[first + r], range_binning[first + r], range_pending[first + r]);
    }
  });
}

}  // namespace facet
