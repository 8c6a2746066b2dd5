// The frame, on the renderer's own task arena: plan its passes (shadow-map faces, the camera's
// depth for shadow volumes, the camera's pass), then run each: per draw, transform and light the
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

namespace {
// A dynamic environment's face f (+X, -X, +Y, -Y, +Z, -Z) as a camera sees it: GL's directions
// (table 3.21) at (s, t) with t counted from the top of the face's picture.
Eigen::Vector3d face_direction(int f, double s, double t) {
  const double sc = 2 * s - 1, tc = 2 * t - 1;
  switch (f) {
    case 0: return {1, -tc, -sc};
    case 1: return {-1, -tc, sc};
    case 2: return {sc, 1, tc};
    case 3: return {sc, -1, -tc};
    case 4: return {sc, -tc, 1};
    default: return {-sc, -tc, -1};
  }
}
}  // namespace

// One face pass per face of each object whose material's environment is dynamic, from the centre
// of the object's box, 90 degrees square: a camera looking along the face's axis with up towards
// the top of the face's picture. Faces are drawn into textures stored bottom row first (y_up
// views), as every texture is; where the face's s runs against the camera's right (GL's cube
// faces are mirror images of a camera's view), finish_environment_face mirrors the rows.
void Renderer::Impl::plan_environment_faces(const Scene& scene, const RenderOptions& options, const RenderPass& camera) {
  cubes.of_object.assign(scene.objects.size(), -1);
  std::size_t count = 0;
  if (kind.plain()) return;  // visibility sub-frames draw plain surfaces
  std::size_t reflectors = 0;  // sized first: the passes point into cube_faces
  for (const Instance& inst : scene.objects) reflectors += !inst.mesh_materials && scene.materials[inst.material].environment.dynamic;
  if (cube_faces.size() < reflectors) cube_faces.resize(reflectors);
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const Instance& inst = scene.objects[o];
    const Environment& e = scene.materials[inst.material].environment;
    Eigen::Vector3d lo, hi;
    if (inst.mesh_materials || !e.dynamic || !geometry::finite_box(scene.meshes[inst.mesh].mesh.positions, lo, hi)) continue;
    EnvironmentCube& cube = cube_faces[count];
    const int n = e.resolution;
    const Eigen::Vector3d centre = (inst.model.cast<double>() * (0.5 * (lo + hi)).homogeneous()).head<3>();
    for (int f = 0; f < 6; ++f) {
      Texture& t = cube.faces[static_cast<std::size_t>(f)];
      t.filter = TextureFilter::bilinear;
      t.wrap = TextureWrap::clamp;
      t.levels.assign(1, TextureLevel{n, n, 0});
      t.texels.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
      cube.views[static_cast<std::size_t>(f)] = {t.texels.data(), n, n, static_cast<std::size_t>(n) * 4, PixelFormat::rgba8, true};
      const Eigen::Vector3d forward = face_direction(f, 0.5, 0.5), up = face_direction(f, 0.5, 0.0) - forward;
      const Eigen::Vector3d right = face_direction(f, 1.0, 0.5) - forward;
      cube.mirrored[static_cast<std::size_t>(f)] = forward.cross(up).dot(right) < 0.0;
      Camera view = scene.camera;
      view.eye = centre.cast<float>();
      view.target = (centre + forward).cast<float>();
      view.up = up.cast<float>();
      view.vertical_fov_deg = 90.0f;
      view.aspect = 1.0f;
      RenderPass p = frame::view_pass(view, scene, options, cube.views[static_cast<std::size_t>(f)], nullptr);
      p.assembly.place = camera.assembly.place;
      p.exclude_object = static_cast<std::uint32_t>(o);
      p.environment_face = true;
      p.environment_cube = static_cast<int>(count);
      p.environment_face_index = f;
      passes.push_back(p);
    }
    cubes.of_object[o] = static_cast<std::int32_t>(count++);
  }
  cubes.samplers.resize(6 * count);
}

void Renderer::Impl::finish_environment_face(const RenderPass& p) {
  EnvironmentCube& cube = cube_faces[static_cast<std::size_t>(p.environment_cube)];
  const auto f = static_cast<std::size_t>(p.environment_face_index);
  Texture& t = cube.faces[f];
  const int n = t.levels[0].width;
  if (cube.mirrored[f]) {
    for (int y = 0; y < n; ++y) {
      std::uint32_t* row = t.texels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(n);
      std::reverse(row, row + n);
    }
  }
  cubes.samplers[6 * static_cast<std::size_t>(p.environment_cube) + f] = texture::make_sampler(t);
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
      if (!scene.display.identity()) {
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
  simd_raster = options.path == LightingPath::simd;
  simd_kernels = simd_raster ? tile::simd_raster_kernels(options.isa) : nullptr;
  passes.clear();
  RenderPass camera = frame::camera_pass(scene, options, color, depth);
  camera.assembly.place = simd_kernels ? simd_kernels->place : nullptr;
  // Shadow maps: fitted to the casters and the camera, then one depth-only pass per face, before
  // the camera's pass.
  frame_maps.assign(scene.lights.size(), nullptr);
  bool any_map = false;
  if (map_shadows) {
    const auto start = Clock::now();
    frame::bound_casters(scene, caster_bounds);
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
        passes.push_back(frame::depth_pass(map.face_view(f), map.face_projection(f), map_views.back(), options.tile_size));
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
    RenderPass d = camera;  // the same view, culling and triangles
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
  plan_environment_faces(scene, options, camera);
  // Multisampling: the camera's colour pass alone (its depth pass for shadow volumes, the
  // environment faces and the shadow maps are copied or built above with one sample).
  camera.samples = raster::sample_pattern(options.samples);
  camera.assembly.viewport.sample_lo = camera.samples.lo;
  camera.assembly.viewport.sample_hi = camera.samples.hi;
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
    frame::plan_units(scene, passes[k], pass_units[k], order_keys, kind.plain());
    work_total += frame::pass_work(scene, passes[k], pass_units[k], light_every_vertex);
  }
  work_total = std::max<std::uint64_t>(work_total, 1);
  for (std::size_t k = 0; k < passes.size(); ++k) {
    const RenderPass& p = passes[k];
    const auto start = Clock::now();
    run_pass(scene, options, p, pass_units[k]);
    if (p.environment_face) finish_environment_face(p);
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

}  // namespace facet
