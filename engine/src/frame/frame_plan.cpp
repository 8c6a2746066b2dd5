#include "frame/frame_plan.hpp"

#include <algorithm>
#include <chrono>

#include "geometry/bounds.hpp"
#include "texture/sampler.hpp"

namespace facet::frame {
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

// Shadow maps: fitted to the casters and the camera, then one depth-only pass per face.
void plan_shadow_maps(const Scene& scene, const RenderOptions& options, const RenderPass& camera,
                      const tile::simd::Kernels* kernels, FrameTargets& t, FramePlan& out) {
  const auto start = std::chrono::steady_clock::now();
  bound_casters(scene, t.caster_bounds);
  if (t.maps.size() < scene.lights.size()) t.maps.resize(scene.lights.size());
  t.map_views.clear();
  t.map_views.reserve(6 * kMaxShadowedLights);  // validated: the passes' pointers stay put
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const Light& light = scene.lights[l];
    if (!light.enabled || light.shadow.method != ShadowMethod::map || t.map_views.size() + 6 > t.map_views.capacity()) continue;
    shadow::ShadowMap& map = t.maps[l];
    map.plan(light, t.caster_bounds, camera.view, camera.projection);
    if (map.empty()) continue;  // nothing can shade a visible point: the light is not shadowed
    map.set_kernel(kernels ? kernels->shadow_map : nullptr);
    out.maps[l] = &map;
    for (int f = 0; f < map.face_count(); ++f) {
      t.map_views.push_back(map.depth_view(f));
      PlannedPass p;
      p.kind = PassKind::shadow_map_face;
      p.light = static_cast<std::uint32_t>(l);
      p.face = f;
      p.pass = depth_pass(map.face_view(f), map.face_projection(f), t.map_views.back(), options.tile_size);
      p.pass.depth_dirty = map.dirty_tiles(f, options.tile_size);
      p.pass.assembly.place = camera.assembly.place;
      out.passes.push_back(p);
      out.shadow_map_texels += static_cast<std::uint64_t>(map.resolution()) * static_cast<std::uint64_t>(map.resolution());
    }
  }
  for (const Instance& inst : scene.objects) {
    if (inst.cast_shadows) out.map_casters += scene.meshes[inst.mesh].mesh.triangle_count();
  }
  out.seconds_maps = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// One face pass per face of each object whose material's environment is dynamic, from the centre
// of the object's box, 90 degrees square: a camera looking along the face's axis with up towards
// the top of the face's picture. Faces are drawn into textures stored bottom row first (y_up
// views), as every texture is; where the face's s runs against the camera's right (GL's cube
// faces are mirror images of a camera's view), finish_environment_face mirrors the rows.
void plan_environment_faces(const Scene& scene, const RenderOptions& options, const FrameKind& kind,
                            const RenderPass& camera, FrameTargets& t, FramePlan& out) {
  t.cubes.of_object.assign(scene.objects.size(), -1);
  std::size_t count = 0;
  if (!kind.plain()) {  // visibility sub-frames draw plain surfaces
    std::size_t reflectors = 0;  // sized first: the passes point into cube_faces
    for (const Instance& inst : scene.objects) reflectors += !inst.mesh_materials && scene.materials[inst.material].environment.dynamic;
    if (t.cube_faces.size() < reflectors) t.cube_faces.resize(reflectors);
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      const Instance& inst = scene.objects[o];
      const Environment& e = scene.materials[inst.material].environment;
      Eigen::Vector3d lo, hi;
      if (inst.mesh_materials || !e.dynamic || !geometry::finite_box(scene.meshes[inst.mesh].mesh.positions, lo, hi)) continue;
      EnvironmentCube& cube = t.cube_faces[count];
      const int n = e.resolution;
      const Eigen::Vector3d centre = (inst.model.cast<double>() * (0.5 * (lo + hi)).homogeneous()).head<3>();
      for (int f = 0; f < 6; ++f) {
        Texture& tex = cube.faces[static_cast<std::size_t>(f)];
        tex.filter = TextureFilter::bilinear;
        tex.wrap = TextureWrap::clamp;
        tex.levels.assign(1, TextureLevel{n, n, 0});
        tex.texels.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
        cube.views[static_cast<std::size_t>(f)] = {tex.texels.data(), n, n, static_cast<std::size_t>(n) * 4, PixelFormat::rgba8, true};
        const Eigen::Vector3d forward = face_direction(f, 0.5, 0.5), up = face_direction(f, 0.5, 0.0) - forward;
        const Eigen::Vector3d right = face_direction(f, 1.0, 0.5) - forward;
        cube.mirrored[static_cast<std::size_t>(f)] = forward.cross(up).dot(right) < 0.0;
        Camera view = scene.camera;
        view.eye = centre.cast<float>();
        view.target = (centre + forward).cast<float>();
        view.up = up.cast<float>();
        view.vertical_fov_deg = 90.0f;
        view.aspect = 1.0f;
        PlannedPass p;
        p.kind = PassKind::environment_face;
        p.after = AfterPass::finish_environment_face;
        p.object = static_cast<std::uint32_t>(o);
        p.face = f;
        p.cube = static_cast<int>(count);
        p.pass = view_pass(view, scene, options, cube.views[static_cast<std::size_t>(f)], nullptr);
        p.pass.assembly.place = camera.assembly.place;
        p.pass.exclude_object = p.object;
        p.pass.environment_face = true;
        out.passes.push_back(p);
      }
      t.cubes.of_object[o] = static_cast<std::int32_t>(count++);
    }
  }
  t.cubes.samplers.resize(6 * count);
}

}  // namespace

const char* to_string(PassKind kind) noexcept {
  switch (kind) {
    case PassKind::shadow_map_face: return "shadow map face";
    case PassKind::volume_depth: return "volume depth";
    case PassKind::environment_face: return "environment face";
    case PassKind::camera: return "camera";
  }
  return "?";
}

const char* to_string(AfterPass after) noexcept {
  switch (after) {
    case AfterPass::nothing: return "nothing";
    case AfterPass::build_shadow_volumes: return "build shadow volumes";
    case AfterPass::finish_environment_face: return "finish environment face";
  }
  return "?";
}

std::string FramePlan::describe() const {
  std::string s;
  for (const PlannedPass& p : passes) {
    s += std::string(to_string(p.kind)) + ": " + std::to_string(p.pass.width()) + "x" + std::to_string(p.pass.height());
    if (p.pass.depth_only) {
      s += ", depth only";
    } else {
      s += std::string(", ") + to_string(p.pass.shading) + ", " + std::to_string(std::max(p.pass.samples.count, 1)) +
           " sample" + (p.pass.samples.count > 1 ? "s" : "");
    }
    if (p.light != UINT32_MAX) s += ", light " + std::to_string(p.light);
    if (p.object != UINT32_MAX) s += ", object " + std::to_string(p.object);
    if (p.face >= 0) s += ", face " + std::to_string(p.face);
    if (p.after != AfterPass::nothing) s += std::string(", then ") + to_string(p.after);
    s += "\n";
  }
  if (raycast) s += "before the passes: build the ray-cast casters\n";
  return s;
}

void plan_frame(const Scene& scene, const RenderOptions& options, const FrameKind& kind, const ImageView& color,
                const DepthView* depth, const tile::simd::Kernels* kernels, FrameTargets& t, FramePlan& out) {
  out.passes.clear();
  out.maps.assign(scene.lights.size(), nullptr);
  out.shadow_map_texels = out.map_casters = out.volume_casters = 0;
  out.seconds_maps = 0;
  // A part of a flat or Gouraud frame with shadows is drawn without them (render_composite).
  const bool shadows = kind.shadows();
  out.raycast = shadows && casts_shadows(scene, ShadowMethod::raycast);
  const bool map_shadows = shadows && casts_shadows(scene, ShadowMethod::map);
  RenderPass camera = camera_pass(scene, options, color, depth);
  camera.assembly.place = kernels ? kernels->place : nullptr;
  if (map_shadows) plan_shadow_maps(scene, options, camera, kernels, t, out);
  // Shadow volumes: the camera's depth alone (the same view, culling and triangles, one sample),
  // then, after that pass, the volumes' masks.
  if (shadows) {
    t.volumes.plan(scene, camera.width(), camera.height());
  } else {
    t.volumes.disable();
  }
  out.volumes = t.volumes.active();
  if (out.volumes) {
    t.volume_depth = t.volumes.depth_view();
    PlannedPass d;
    d.kind = PassKind::volume_depth;
    d.after = AfterPass::build_shadow_volumes;
    d.pass = camera;
    d.pass.shading = ShadingMode::flat;
    d.pass.depth_only = true;
    d.pass.casters_only = false;
    d.pass.color = nullptr;
    d.pass.depth = &t.volume_depth;
    d.pass.depth_dirty = t.volumes.dirty_tiles(options.tile_size);
    out.passes.push_back(d);
    for (const Instance& inst : scene.objects) {
      if (inst.cast_shadows && !map_shadows) out.volume_casters += scene.meshes[inst.mesh].mesh.triangle_count();
    }
  }
  plan_environment_faces(scene, options, kind, camera, t, out);
  // Multisampling: the camera's colour pass alone (the passes above draw one sample).
  PlannedPass c;
  c.kind = PassKind::camera;
  c.pass = camera;
  c.pass.samples = raster::sample_pattern(options.samples);
  c.pass.assembly.viewport.sample_lo = c.pass.samples.lo;
  c.pass.assembly.viewport.sample_hi = c.pass.samples.hi;
  out.passes.push_back(c);
}

void finish_environment_face(FrameTargets& t, const PlannedPass& p) {
  EnvironmentCube& cube = t.cube_faces[static_cast<std::size_t>(p.cube)];
  const auto f = static_cast<std::size_t>(p.face);
  Texture& tex = cube.faces[f];
  const int n = tex.levels[0].width;
  if (cube.mirrored[f]) {
    for (int y = 0; y < n; ++y) {
      std::uint32_t* row = tex.texels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(n);
      std::reverse(row, row + n);
    }
  }
  t.cubes.samplers[6 * static_cast<std::size_t>(p.cube) + f] = texture::make_sampler(tex);
}

}  // namespace facet::frame
