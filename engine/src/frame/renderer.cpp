// The frame, on the renderer's own task arena: plan its passes (frame_plan.cpp: shadow-map
// faces, the camera's depth for shadow volumes, environment faces, the camera's pass), then run
// each, and its after-step: per draw, transform and light the
// vertices and assemble triangles in parallel fixed ranges (object_setup.cpp); merge the ranges'
// bins in order; rasterize and resolve every tile, one task per tile (pass.cpp). Flat and Gouraud
// frames with shadows are sums of such frames (composite.cpp).
#include <algorithm>
#include <cmath>
#include <new>

#include <tbb/info.h>

#include "frame/frame.hpp"
#include "lighting/setup.hpp"

namespace facet {

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
      if (!scene.display.identity() || scene.background == Background::environment) {
        impl_->render_display(scene, options, color, depth, composite);
      } else if (composite) {
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

Status Renderer::Impl::prepare_image_light(const Scene& scene) {
  if (!image_light) image_light = std::make_unique<lighting::ImageLight>();
  return image_light->prepare(
      scene.environment_light,
      [&](std::size_t count, const std::function<void(std::size_t)>& fn) {
        arena->parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r, int) {
          for (std::size_t i = r.begin(); i < r.end(); ++i) fn(i);
        });
      },
      [&] { return cancelled.load(std::memory_order_relaxed); });
}

void Renderer::Impl::render(const Scene& scene, const RenderOptions& options, const ImageView& color,
                            const DepthView* depth, const FrameKind& frame_kind) {
  const auto frame_start = Clock::now();
  kind = frame_kind;
  stats = FrameStats{};
  stats.threads = arena_threads;
  for (WorkerScratch& w : workers) {  // grows only when the tile size or the chunk size grows
    w.tile.resize(options.tile_size, options.samples);
    // The most points one lighting call takes: a vertex chunk, or a set-up range's triangles (flat).
    w.soa.reserve_padded(std::max(kVertexChunk, kTriangleRange));
  }
  // A part of a flat or Gouraud frame with shadows is drawn without them (render_composite).
  const bool shadows = kind.shadows();
  const bool raycast = shadows && frame::casts_shadows(scene, ShadowMethod::raycast);
  const bool map_shadows = shadows && frame::casts_shadows(scene, ShadowMethod::map);
  // The shadowed lights' visibility of a lighting call's points, and its padded copies.
  if (raycast || map_shadows || (shadows && frame::casts_shadows(scene, ShadowMethod::volume))) {
    const std::size_t points = lighting::simd::padded(std::max(kVertexChunk, kTriangleRange));
    for (WorkerScratch& w : workers) {
      if (w.soa.visibility.size() < 2 * kMaxShadowedLights * points) w.soa.visibility.resize(2 * kMaxShadowedLights * points);
    }
  }
  light_every_vertex = options.light_every_vertex;
  vertex_relief = options.vertex_relief;
  frame::make_samplers(scene, samplers);
  frame_image_light = nullptr;
  const bool pbr = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.model == MaterialModel::pbr; });
  // The backdrop: in whole frames and a shadowed frame's base, not in its visibility or light parts.
  const bool backdrop = scene.background == Background::environment &&
                        (kind.kind == FrameKind::Kind::whole || (kind.kind == FrameKind::Kind::part && !kind.without_emission));
  if (pbr || backdrop) {
    const auto start = Clock::now();
    frame_status = prepare_image_light(scene);
    stats.seconds_environment += seconds_since(start);
    if (!frame_status.ok()) return;
    if (pbr) frame_image_light = image_light.get();
  }
  simd_raster = options.path == LightingPath::simd;
  simd_kernels = simd_raster ? tile::simd_raster_kernels(options.isa) : nullptr;
  frame::plan_frame(scene, options, kind, color, depth, simd_kernels, targets, plan);
  stats.shadow_map_texels = plan.shadow_map_texels;
  stats.shadow_casters = plan.map_casters + plan.volume_casters;
  stats.seconds_shadows += plan.seconds_maps;
  // Ray-cast shadows: the casters as Embree sees them, built here, in this renderer's arena.
  const RenderPass& camera = plan.camera().pass;
  frame_backdrop.reset();
  if (backdrop) {
    frame_backdrop = tile::make_backdrop(*image_light, scene.environment_light, camera.view, camera.projection, color.width, color.height);
  }
  frame_caster = nullptr;
  if (plan.raycast) {
    const auto start = Clock::now();
    frame_status = caster.build(scene, camera.view);
    stats.seconds_shadows += seconds_since(start);
    stats.shadow_casters = caster.triangle_count();
    if (!frame_status.ok()) return;
    frame_caster = &caster;
  }
  frame_shadows = {frame_caster, plan.maps, plan.volumes ? &targets.volumes : nullptr};
  has_shadows = frame_caster || plan.any_map() || plan.volumes;
  work_total = 0;
  if (pass_units.size() < plan.passes.size()) pass_units.resize(plan.passes.size());
  for (std::size_t k = 0; k < plan.passes.size(); ++k) {
    frame::plan_units(scene, plan.passes[k].pass, pass_units[k], order_keys, kind.plain());
    work_total += frame::pass_work(scene, plan.passes[k].pass, pass_units[k], light_every_vertex);
  }
  work_total = std::max<std::uint64_t>(work_total, 1);
  for (std::size_t k = 0; k < plan.passes.size(); ++k) {
    const frame::PlannedPass& p = plan.passes[k];
    const auto start = Clock::now();
    run_pass(scene, options, p.pass, pass_units[k]);
    if (cancelled.load(std::memory_order_relaxed)) break;
    switch (p.after) {
      case frame::AfterPass::nothing: break;
      case frame::AfterPass::finish_environment_face: frame::finish_environment_face(targets, p); break;
      case frame::AfterPass::build_shadow_volumes: targets.volumes.build(scene, camera.view, camera.projection, *arena); break;
    }
    if (p.pass.depth_only) stats.seconds_shadows += seconds_since(start);
  }
  pass = nullptr;
  units = {};
  stats.seconds_total = seconds_since(frame_start);
}

}  // namespace facet
