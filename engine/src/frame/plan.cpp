#include "frame/plan.hpp"

#include <algorithm>
#include <cmath>
#include <string>


#include "common/format.hpp"
#include "common/look_at.hpp"
#include "geometry/project.hpp"
#include "raster/triangle_setup.hpp"

namespace facet::frame {

bool writes_depth(const Material& m) {
  return m.depth_write == DepthWrite::on || (m.depth_write == DepthWrite::automatic && m.blend == BlendMode::opaque);
}
// Whether an object's draw of `material` shows both faces of a blended surface: what a sorted
// pass draws as two draws, back faces first (plan_units), and what takes twice its ranges.
static bool both_faces_blended(const Scene& scene, const Instance& inst, std::int64_t material) {
  return (inst.double_sided || scene.two_sided) && material >= 0 && static_cast<std::size_t>(material) < scene.materials.size() &&
         scene.materials[static_cast<std::size_t>(material)].blend != BlendMode::opaque;
}

void plan_units(const Scene& scene, const RenderPass& p, std::vector<DrawUnit>& units,
                std::vector<scene_order::ObjectKey>& keys, bool depth_writers_only) {
  units.clear();
  const bool casters_only = p.depth_only && p.casters_only;
  const bool depth_writers = (p.depth_only && !p.casters_only) || depth_writers_only;
  const bool sorted = !p.depth_only && scene.transparent_order == TransparentOrder::back_to_front &&
                      scene_order::order_objects(scene, p.view, keys);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const std::size_t o = sorted ? keys[k].object : k;
    const Instance& inst = scene.objects[o];
    if (o == p.exclude_object) continue;  // an environment face: the reflector itself
    if (casters_only && !inst.cast_shadows) continue;
    if (depth_writers && !inst.mesh_materials && !writes_depth(scene.materials[inst.material])) continue;
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    // Back faces first, then front faces, for a double-sided blended draw of a sorted pass.
    auto push = [&](const DrawUnit& u) {
      const bool split = sorted && p.assembly.cull == CullMode::back && both_faces_blended(scene, inst, u.material);
      if (!split) return units.push_back(u);
      DrawUnit back = u, front = u;
      back.only = 2, front.only = 1;
      units.push_back(back);
      units.push_back(front);
    };
    if (!inst.mesh_materials) {
      push({static_cast<std::uint32_t>(o), inst.material, 0, mesh.triangle_count(), 0, mesh.vertex_count()});
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
      push(u);
    }
  }
}

namespace {
std::string mib(std::uint64_t bytes) {
  return std::to_string((bytes + (std::uint64_t{1} << 20) - 1) >> 20) + " MiB";
}

// The set-up ranges an object takes: one per kTriangleRange triangles of each of its draws.
// A double-sided blended draw may take twice its ranges (plan_units draws its faces apart).
std::size_t object_ranges(const Scene& scene, const Instance& inst) {
  const Mesh& mesh = scene.meshes[inst.mesh].mesh;
  auto twice = [&](std::int64_t m) -> std::size_t { return both_faces_blended(scene, inst, m) ? 2 : 1; };
  if (!inst.mesh_materials) return twice(inst.material) * ranges_of(mesh.triangle_count());
  std::size_t n = 0;
  for (const MaterialGroup& g : mesh.groups) n += twice(find_material(scene, g.material)) * ranges_of(g.triangle_count);
  return n;
}
}  // namespace

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

bool casts_shadows(const Scene& scene, ShadowMethod method) {
  return std::any_of(scene.lights.begin(), scene.lights.end(),
                     [method](const Light& l) { return l.enabled && l.shadow.method == method; });
}

// World-space boxes of the objects that cast shadows (their finite vertices' model-space boxes,
// corners through the model matrix).
void bound_casters(const Scene& scene, shadow::CasterBounds& out) {
  out.lo.clear();
  out.hi.clear();
  for (const Instance& inst : scene.objects) {
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    Eigen::Vector3d lo, hi;
    if (!inst.cast_shadows || mesh.triangles.empty() || !geometry::finite_box(mesh.positions, lo, hi)) continue;
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

std::uint64_t pass_work(const Scene& scene, const RenderPass& p, std::span<const DrawUnit> pass_draws,
                        bool light_every_vertex) {
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
  return view_pass(scene.camera, scene, options, color, depth);
}

RenderPass view_pass(const Camera& camera, const Scene& scene, const RenderOptions& options, const ImageView& color,
                     const DepthView* depth) {
  RenderPass p;
  const int width = color.width, height = color.height;
  const float aspect = camera.aspect > 0.0f ? camera.aspect : float(width) / float(height);
  p.view = look_at_d(camera);
  p.projection = projection_matrix(camera, aspect).cast<double>();
  p.shading = options.shading;
  p.clear_color = options.clear_color;
  p.tile_size = options.tile_size;
  p.tiles_x = (width + p.tile_size - 1) / p.tile_size;
  p.tiles_y = (height + p.tile_size - 1) / p.tile_size;
  p.assembly.viewport = {width, height, {depth_mode_for(camera, options.depth) == DepthMode::reversed, camera.near}};
  p.assembly.planes = geometry::guard_band_planes(p.assembly.viewport);
  p.assembly.cull = options.cull;
  p.assembly.two_sided = scene.two_sided;
  p.assembly.grid = {p.tile_size, p.tiles_x, p.tiles_y};
  p.color = &color;
  p.depth = depth;
  return p;
}

bool PassDraws::any_two_sided() const { return std::find(two_sided.begin(), two_sided.end(), 1) != two_sided.end(); }

void make_samplers(const Scene& scene, SceneSamplers& out) {
  out.as_made.resize(scene.textures.size());
  out.clamped.resize(scene.textures.size());
  for (std::size_t i = 0; i < scene.textures.size(); ++i) out.as_made[i] = texture::make_sampler(scene.textures[i]);
  for (const Material& m : scene.materials) {
    if (m.environment.mode == EnvironmentMode::none || m.environment.dynamic) continue;
    for (const std::int32_t map : m.environment.maps) {
      if (map == kNoTexture) continue;
      texture::Sampler& s = out.clamped[static_cast<std::size_t>(map)];
      s = out.as_made[static_cast<std::size_t>(map)];
      s.wrap = static_cast<std::int32_t>(TextureWrap::clamp);
    }
  }
}

pixel::Fog plan_fog(const Fog& f) {
  pixel::Fog fog;
  fog.mode = f.mode;
  for (int c = 0; c < 3; ++c) fog.color[c] = f.color[c];
  fog.start = f.start, fog.end = f.end, fog.density = f.density;
  fog.scale = f.end > f.start ? static_cast<float>(1.0 / (double(f.end) - double(f.start))) : 0.0f;
  return fog;
}

// An untextured opaque material without alpha test or fog (and, lit per pixel, without vertex
// colours) runs its lighting's own program (flat colour, Gouraud colour, Phong): exactly what ran
// before surfaces existed.
void plan_draws(const Scene& scene, const RenderOptions& options, const RenderPass& p, std::span<const DrawUnit> units,
                const FrameKind& kind, const SceneSamplers& samplers, const DynamicCubes& cubes, PassDraws& out) {
  const Fog& f = kind.plain() ? Fog{} : kind.lights_of(scene).fog;
  const bool clamp = !(options.hdr && p.color && p.color->format == PixelFormat::rgba32f);
  const raster::LitAt lit = p.shading == ShadingMode::flat      ? raster::LitAt::triangle
                            : p.shading == ShadingMode::gouraud ? raster::LitAt::vertex
                                                                : raster::LitAt::pixel;
  out.programs.resize(units.size());
  out.features.resize(units.size());
  out.two_sided.resize(units.size());
  for (std::size_t o = 0; o < units.size(); ++o) {
    const Instance& inst = scene.objects[units[o].object];
    const Material& m = scene.materials[units[o].material];
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    const bool plain = kind.plain();
    const bool textured = !plain && m.diffuse_texture != kNoTexture;
    const bool colours = !plain && !mesh.colors.empty();
    // Emission after the texture environment (adds_emission_after_texture); none in the
    // visibility and part sub-frames.
    const bool emission_stage = !plain && !kind.without_emission && adds_emission_after_texture(m);
    const bool emission_texture = emission_stage && m.emissive_texture != kNoTexture;
    // Baked light: drawn in the part of a frame that holds the emission; the lights never add
    // their ambient and diffuse terms to a lightmapped object (scene validation keeps vertex
    // colours, environment, normal and bump maps off it).
    const bool lightmapped = !plain && inst.lightmap != kNoTexture;
    const bool lightmap_stage = lightmapped && !kind.without_emission;
    out.two_sided[o] = p.two_sided() || inst.double_sided;
    lighting::LightingFeatures& lf = out.features[o];
    lf.lightmapped = lightmapped;
    lf.lightmap_replaces = lightmapped && inst.lightmap_mode == LightmapMode::replace;
    lf.color_material = colours;
    lf.separate_specular = textured;
    raster::SurfaceNeeds needs;
    needs.secondary = textured && lit == raster::LitAt::vertex;
    needs.albedo = colours && lit == raster::LitAt::pixel;
    // A normal or bump map: lit per pixel, with the mesh's tangents; not with vertex colours, whose
    // albedo takes the varyings the tangent would need (docs/relief.md).
    const bool tangent_space = !plain && lit == raster::LitAt::pixel && !needs.albedo &&
                               mesh.tangents.size() == mesh.positions.size() && !mesh.positions.empty();
    const bool normal_map = tangent_space && m.normal_texture != kNoTexture;
    const Environment& env = m.environment;
    // Inside an environment face, dynamic reflectors are drawn without their reflection.
    const std::int32_t cube = env.dynamic && units[o].object < cubes.of_object.size() ? cubes.of_object[units[o].object] : -1;
    const bool environment = !plain && env.mode != EnvironmentMode::none && (!env.dynamic || (cube >= 0 && !p.environment_face));
    // A bump map: per pixel it tilts the normal; per vertex it moves a 2D environment's coordinates.
    const bool bump_map = !plain && m.bump_texture != kNoTexture &&
                          (tangent_space || (lit != raster::LitAt::pixel && environment && env.mode != EnvironmentMode::cube));
    needs.tangent = normal_map || (bump_map && lit == raster::LitAt::pixel);
    // An occlusion map: per pixel, into the lighting's ambient terms.
    const bool occlusion_map = !plain && lit == raster::LitAt::pixel && m.occlusion_texture != kNoTexture;
    lf.occlusion = occlusion_map;
    const bool metal_rough_map = !plain && lit == raster::LitAt::pixel && m.model == MaterialModel::pbr &&
                                 m.metallic_roughness_texture != kNoTexture;
    lf.metal_rough = metal_rough_map;
    lf.projectors = !plain && lit == raster::LitAt::pixel;  // spot lights' pictures, per pixel
    needs.uv = textured || emission_texture || normal_map || occlusion_map || bump_map || metal_rough_map;
    needs.environment = environment;
    needs.lightmap = lightmap_stage;
    pixel::Draw& d = out.programs[o];
    d = pixel::Draw{};
    if (p.depth_only) continue;  // no varying, no program: depth alone (every caster is opaque)
    d.layout = raster::plan_varyings(lit, out.two_sided[o] != 0, needs);
    d.texture = textured ? &samplers.as_made[static_cast<std::size_t>(m.diffuse_texture)] : nullptr;
    d.separate_specular = lf.separate_specular;
    d.texture_env = m.texture_mode;
    if (emission_stage) {
      d.emission = true;
      for (int c = 0; c < 3; ++c) d.emission_rgb[c] = m.emissive[c];
      if (emission_texture) d.emission_texture = &samplers.as_made[static_cast<std::size_t>(m.emissive_texture)];
    }
    if (lightmap_stage) {
      d.emission = true;  // the stage the baked light joins (emission_rgb stays 0 unless added after the texture)
      d.lightmap = &samplers.as_made[static_cast<std::size_t>(inst.lightmap)];
      for (int c = 0; c < 3; ++c) d.lightmap_albedo[c] = m.diffuse[c] * inst.lightmap_scale;
    }
    if (environment) {
      d.environment = env.mode;
      d.environment_blend = env.blend;
      d.environment_strength = env.strength;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) d.environment_to_world[3 * r + c] = static_cast<float>(p.view(c, r));
      }
      for (int k = 0; k < 6; ++k) {
        if (env.dynamic) {
          d.environment_map[k] = &cubes.samplers[6 * static_cast<std::size_t>(cube) + static_cast<std::size_t>(k)];
        } else if (env.maps[k] != kNoTexture) {
          d.environment_map[k] = &samplers.clamped[static_cast<std::size_t>(env.maps[k])];
        }
      }
    }
    if (normal_map) {
      d.normal_map = &samplers.as_made[static_cast<std::size_t>(m.normal_texture)];
      d.normal_scale = m.normal_scale;
    }
    if (metal_rough_map) d.metal_rough_map = &samplers.as_made[static_cast<std::size_t>(m.metallic_roughness_texture)];
    if (occlusion_map) {
      d.occlusion_map = &samplers.as_made[static_cast<std::size_t>(m.occlusion_texture)];
      d.occlusion_strength = m.occlusion_strength;
    }
    if (bump_map) {
      const Texture& h = scene.textures[static_cast<std::size_t>(m.bump_texture)];
      d.bump_map = &samplers.as_made[static_cast<std::size_t>(m.bump_texture)];
      d.bump_scale = m.bump_scale;
      d.bump_du = 1.0f / static_cast<float>(h.width());
      d.bump_dv = 1.0f / static_cast<float>(h.height());
    }
    d.uv_scale[0] = m.uv_scale.x(), d.uv_scale[1] = m.uv_scale.y();
    d.alpha_cutoff = m.alpha_cutoff;
    d.alpha_to_coverage = m.alpha_to_coverage && options.samples > 1;
    d.blend = plain ? BlendMode::opaque : m.blend;
    d.depth_write = writes_depth(m);
    d.clamp = clamp;
    const bool surface = textured || d.emission || d.blend != BlendMode::opaque || m.alpha_cutoff > 0.0f || d.alpha_to_coverage ||
                         !d.depth_write || f.mode != FogMode::none || needs.albedo || environment || normal_map ||
                         occlusion_map || bump_map || metal_rough_map;
    using pixel::PixelProgram;
    if (!surface) {
      d.program = lit == raster::LitAt::triangle ? PixelProgram::flat
                  : lit == raster::LitAt::vertex ? PixelProgram::gouraud
                                                 : PixelProgram::phong;
    } else if (!textured) {
      // The fused blended program's settings: Gouraud, a blend it has, clamped, no alpha test, no
      // emission, no secondary colour, no fog, nothing per pixel (environment, maps, albedo).
      const bool fused_blend = lit == raster::LitAt::vertex && !d.emission && d.clamp && d.alpha_cutoff <= 0.0f && !d.alpha_to_coverage &&
                               f.mode == FogMode::none && !needs.albedo && !environment && !normal_map &&
                               !occlusion_map && !bump_map && !metal_rough_map && !d.layout.has(raster::Varying::front_secondary) &&
                               (d.blend == BlendMode::alpha || d.blend == BlendMode::premultiplied || d.blend == BlendMode::add);
      d.program = !fused_blend                      ? PixelProgram::surface
                  : d.blend == BlendMode::alpha         ? PixelProgram::blend_alpha
                  : d.blend == BlendMode::premultiplied ? PixelProgram::blend_premultiplied
                                                        : PixelProgram::blend_add;
    } else {
      // The fused program's settings: Gouraud, modulate, the specular added after the texture, no
      // emission after it, opaque, clamped, no alpha test (the fragment's alpha is never NaN), no
      // environment.
      const bool modulate = lit == raster::LitAt::vertex && d.texture_env == TextureMode::modulate && !d.emission &&
                            d.blend == BlendMode::opaque && d.clamp && d.alpha_cutoff <= 0.0f && !d.alpha_to_coverage && !environment &&
                            d.layout.has(raster::Varying::front_secondary);
      // The 16-bit tier's fixed-point sampler, when asked for, where its contract holds (linear
      // textures), in the fused program or the general one. automatic picks the exact tier: the
      // fast one is not faster.
      const bool fixed = options.pixel_precision == PixelPrecision::fast &&
                         scene.textures[static_cast<std::size_t>(m.diffuse_texture)].encoding == TextureEncoding::linear;
      d.fixed_texels = fixed;
      d.program = !modulate                 ? PixelProgram::surface_textured
                  : f.mode == FogMode::none ? (fixed ? PixelProgram::modulate_fixed : PixelProgram::modulate)
                                            : (fixed ? PixelProgram::modulate_fog_fixed : PixelProgram::modulate_fog);
    }
  }
}

}  // namespace facet::frame
