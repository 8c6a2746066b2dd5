// Internal: the renderer's state, kept from frame to frame (capacity is kept, so a steady frame
// allocates nothing), and the steps of a frame. The steps live in this folder in the order they
// run: frame_plan.cpp (the passes), plan.cpp (checks, draws, pixel programs), renderer.cpp (the
// frame: plan, then each pass), object_setup.cpp (per draw: transform, light, assemble into set-up ranges), pass.cpp
// (bins, tiles, resolve), composite.cpp (flat and Gouraud frames with shadows, as sub-frames).
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "common/parallel.hpp"
#include "facet/render.hpp"
#include "frame/frame_plan.hpp"
#include "frame/pass.hpp"
#include "frame/plan.hpp"
#include "geometry/project.hpp"
#include "io/srgb.hpp"
#include "lighting/image_light.hpp"
#include "lighting/point_shader.hpp"
#include "raster/assemble.hpp"
#include "raster/bins.hpp"
#include "tile/tile_raster.hpp"
#include "shadow/frame.hpp"
#include "shadow/map.hpp"
#include "shadow/raycast.hpp"
#include "shadow/volume.hpp"

namespace facet {

using frame::DrawUnit;
using frame::FrameKind;
using frame::PassDraws;
using frame::RenderPass;
using frame::kSmallObjectTriangles;
using frame::kSmallObjectVertices;
using frame::kTriangleRange;
using frame::kVertexChunk;

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// What each worker thread needs for itself, kept from frame to frame.
struct WorkerScratch {
  tile::TileBuffers tile;
  lighting::SoaScratch soa;
};

struct Renderer::Impl {
  // Threads: this renderer's own arena, rebuilt only when the thread count changes.
  std::unique_ptr<parallel::Arena> arena;
  int arena_threads = 0;
  // Ray-cast shadows: the frame's casters (built in the arena when a light casts ray-cast shadows).
  shadow::RayCaster caster;
  const shadow::RayCaster* frame_caster = nullptr;  // this frame's, or null
  bool has_shadows = false;  // some light is shadowed this frame (frame_shadows applies)
  // The frame plan (frame_plan.hpp) and the targets its passes draw into.
  frame::FrameTargets targets;
  frame::FramePlan plan;
  shadow::FrameShadows frame_shadows;
  // PBR materials' DFG table and prepared surroundings: made when a scene first has a PBR
  // material, rebuilt only when Scene::environment_light's picture changes.
  std::unique_ptr<lighting::ImageLight> image_light;
  const lighting::ImageLight* frame_image_light = nullptr;  // this frame's, or null (no PBR material)
  // Scene::background == environment: the camera pass's clear value per pixel (tile/backdrop.hpp).
  std::optional<tile::Backdrop> frame_backdrop;
  Status prepare_image_light(const Scene& scene);
  Status frame_status;  // a failure inside the arena (the casters' build)
  // One per arena slot (tbb::this_task_arena::current_thread_index()), sized on the calling
  // thread before any parallel loop, so that no task ever allocates.
  std::vector<WorkerScratch> workers;
  WorkerScratch& worker(int slot) { return workers[static_cast<std::size_t>(slot)]; }
  std::vector<tile::RasterCounters> tile_counters;
  // Frame-wide state, reused from frame to frame (capacity is kept).
  std::vector<std::vector<raster::ScreenTriangle>> range_triangles;
  std::vector<raster::RangeBinning> range_binning;
  std::vector<raster::PendingTriangles> range_pending;  // per range: between the assembly phases
  std::vector<const raster::ScreenTriangle*> range_data;
  std::size_t range_count = 0;
  std::vector<std::vector<std::uint32_t>> bins;
  std::vector<std::uint32_t> merge_offsets;  // merge_bins: each range's first slot in each bin
  // Each pass's draws (objects, or their material groups), planned once per pass (plan_units),
  // kept with their capacity; `units` is the running pass's.
  std::vector<std::vector<DrawUnit>> pass_units;
  std::span<const DrawUnit> units;
  std::vector<lighting::PointShader> shaders;  // one per draw
  PassDraws draws;  // the running pass's: per draw its pixel program, lighting features and faces (plan.hpp)
  frame::SceneSamplers samplers;  // the scene's textures as the pixel programs read them (plan.hpp)
  pixel::Fog fog;
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
    std::vector<Vec3> eye_t;          // Phong with a normal map: the tangents in eye space
    std::vector<float> tangent_sign;  // and their w, negated by a mirroring model matrix
    std::vector<Vec3> relief_normals; // Gouraud with RenderOptions::vertex_relief: the perturbed normals
    std::array<std::vector<float>, raster::kGeneratedVaryings.size()> generated;  // raster::kGeneratedVaryings at each vertex
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
    void reserve_generated(std::size_t vertices);
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

  // The running pass.
  const RenderPass* pass = nullptr;
  bool simd_raster = true;  // the simd path rasterizes with the SIMD kernels
  const tile::simd::Kernels* simd_kernels = nullptr;  // its ISA's, when simd_raster
  bool light_every_vertex = false;  // RenderOptions::light_every_vertex
  bool vertex_relief = false;       // RenderOptions::vertex_relief
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

  // One frame of `kind` (a whole frame, or a sub-frame of render_composite): plan, then run the passes.
  void render(const Scene& scene, const RenderOptions& options, const ImageView& color, const DepthView* depth,
              const FrameKind& kind = {});
  FrameKind kind;  // the running frame's (set by render, read by its passes)
  // Flat and Gouraud shading with shadows: a frame of sub-frames summed per pixel (see below).
  void render_composite(const Scene& scene, const RenderOptions& options, const ImageView& color,
                        const DepthView* depth);
  std::vector<float> composite_base, composite_part, composite_visibility;
  // A frame with a display transform (Scene::display not GL's): rendered into display_color (and
  // display_depth without the caller's), then metered, exposed, tone-mapped and stored (display.cpp).
  void render_display(const Scene& scene, const RenderOptions& options, const ImageView& color, const DepthView* depth,
                      bool composite);
  std::vector<float> display_color, display_depth;
  std::vector<float> display_peaks;  // metering: each lit pixel's brightest channel (the highlight guard)
  std::vector<std::pair<double, double>> display_rows;  // metering: per row, the sum of ln(1e-4 + L) and the pixels
  Scene composite_lights;  // lights, ambient and fog of a part (no meshes)
  // One pass: its draws' geometry and lighting, set-up and bins (object_setup.cpp), then its tiles
  // and their resolve (pass.cpp).
  void run_pass(const Scene& scene, const RenderOptions& options, const RenderPass& p, std::span<const DrawUnit> pass_draws);
  void merge_bins();
  void set_up_objects(const Scene& scene, const RenderOptions& options);
  void draw_tiles(const RenderOptions& options);
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

}  // namespace facet
