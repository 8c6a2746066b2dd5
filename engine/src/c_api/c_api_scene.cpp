// The C API: building and editing scenes, loading scene and model files, framing, the camera,
// ambient light and fog.
#include <cmath>
#include <filesystem>

#include "c_api/handles.hpp"

using namespace facet::c_api;  // NOLINT(google-build-using-namespace): the C API's shared helpers

extern "C" {

facet_scene* facet_scene_create(void) {
  facet_scene* s = nullptr;
  (void)guarded(nullptr, [&] {
    s = new facet_scene{};
    return FACET_OK;
  });
  return s;
}

void facet_scene_destroy(facet_scene* scene) { delete scene; }

const char* facet_scene_last_error(const facet_scene* scene) {
  return scene ? scene->error.c_str() : "scene: null handle";
}

facet_status facet_scene_add_mesh(facet_scene* scene, const float* positions, size_t vertex_count,
                                  const float* normals, const uint32_t* indices, size_t triangle_count,
                                  uint32_t* mesh_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!positions && vertex_count > 0) return fail(scene->error, "positions", "null with a non-zero vertex count");
    if (!indices && triangle_count > 0) return fail(scene->error, "indices", "null with a non-zero triangle count");
    if (vertex_count > (SIZE_MAX / 12) || triangle_count > (SIZE_MAX / 12)) {
      return fail(scene->error, "vertex_count", "too large");
    }
    const std::span<const float> p(positions, 3 * vertex_count);
    const std::span<const float> n(normals, normals ? 3 * vertex_count : 0);
    const std::span<const std::uint32_t> i(indices, 3 * triangle_count);
    facet::Result<facet::Mesh> mesh = facet::mesh_from_arrays(p, n, i);
    if (!mesh) return report(scene->error, mesh.status());
    const auto id = static_cast<std::uint32_t>(scene->scene.meshes.size());
    scene->scene.meshes.push_back({"mesh" + std::to_string(id), std::move(*mesh)});
    if (mesh_id) *mesh_id = id;
    return report(scene->error, {});
  });
}

facet_status facet_scene_add_material(facet_scene* scene, const facet_material* material, uint32_t* material_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!material) return fail(scene->error, "material", "null");
    facet::Material m = to_material(*material);
    const auto id = static_cast<std::uint32_t>(scene->scene.materials.size());
    if (const char* field = nullptr; !textures_exist(m, scene->scene, field)) return fail(scene->error, field, "no such texture");
    // Checked now, so the error names this call's argument rather than the next render.
    if (facet::Status st = facet::validate_material(m, id); !st.ok()) return report(scene->error, st);
    m.name = "material" + std::to_string(id);
    scene->scene.materials.push_back(std::move(m));
    scene->material_removed.resize(scene->scene.materials.size(), 0);
    if (material_id) *material_id = id;
    return report(scene->error, {});
  });
}


facet_status facet_scene_add_object(facet_scene* scene, uint32_t mesh_id, uint32_t material_id, const float* model,
                                    uint32_t* object_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (mesh_id >= scene->scene.meshes.size()) return fail(scene->error, "mesh_id", "no such mesh");
    if (material_id >= scene->scene.materials.size() || scene->material_removed[material_id]) {
      return fail(scene->error, "material_id", "no such material");
    }
    facet::Instance inst;
    inst.mesh = mesh_id;
    inst.material = material_id;
    if (model) {
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) inst.model(r, c) = model[4 * c + r];
    }
    const std::uint32_t id = scene->next_object_id;
    scene->object_ids.reserve(scene->object_ids.size() + 1);
    scene->scene.objects.push_back(inst);
    scene->object_ids.push_back(id);
    ++scene->next_object_id;
    if (object_id) *object_id = id;
    return report(scene->error, {});
  });
}

facet_status facet_scene_add_object_with_mesh_materials(facet_scene* scene, uint32_t mesh_id, const float* model,
                                                        uint32_t* object_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (mesh_id >= scene->scene.meshes.size()) return fail(scene->error, "mesh_id", "no such mesh");
    if (scene->scene.meshes[mesh_id].mesh.groups.empty()) {
      return fail(scene->error, "mesh_id", "the mesh has no groups (facet_scene_set_mesh_groups)");
    }
    facet::Instance inst;
    inst.mesh = mesh_id;
    inst.material = 0;  // not drawn: the groups name theirs (which exist, so there is a material 0)
    inst.mesh_materials = true;
    if (model) {
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) inst.model(r, c) = model[4 * c + r];
    }
    const std::uint32_t id = scene->next_object_id;
    scene->object_ids.reserve(scene->object_ids.size() + 1);
    scene->scene.objects.push_back(inst);
    scene->object_ids.push_back(id);
    ++scene->next_object_id;
    if (object_id) *object_id = id;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_mesh_groups(facet_scene* scene, uint32_t mesh_id, const uint32_t* triangle_counts,
                                         const uint32_t* material_ids, size_t group_count) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (mesh_id >= scene->scene.meshes.size()) return fail(scene->error, "mesh_id", "no such mesh");
    if (group_count > 0 && (!triangle_counts || !material_ids)) return fail(scene->error, "triangle_counts", "null");
    facet::Mesh& mesh = scene->scene.meshes[mesh_id].mesh;
    facet::Mesh candidate;  // checked on a copy of the arrays' shape: a failure changes nothing
    candidate.positions = mesh.positions;
    candidate.normals = mesh.normals;
    candidate.triangles = mesh.triangles;
    std::uint64_t first = 0;
    for (std::size_t g = 0; g < group_count; ++g) {
      if (material_ids[g] >= scene->scene.materials.size() || scene->material_removed[material_ids[g]]) {
        return fail(scene->error, "material_ids", "entry " + std::to_string(g) + ": no such material");
      }
      if (first + triangle_counts[g] > mesh.triangle_count()) {
        return fail(scene->error, "triangle_counts", "the groups have more triangles than the mesh");
      }
      candidate.groups.push_back({scene->scene.materials[material_ids[g]].name, static_cast<std::uint32_t>(first),
                                  triangle_counts[g]});
      first += triangle_counts[g];
    }
    if (facet::Status st = facet::validate_mesh(candidate, "meshes[" + std::to_string(mesh_id) + "]"); !st.ok()) {
      return report(scene->error, st);
    }
    mesh.groups = std::move(candidate.groups);
    return report(scene->error, {});
  });
}

static_assert(static_cast<int>(facet::ShadowMethod::raycast) == FACET_SHADOW_RAYCAST &&
              static_cast<int>(facet::ShadowMethod::map) == FACET_SHADOW_MAP &&
              static_cast<int>(facet::ShadowMethod::volume) == FACET_SHADOW_VOLUME);
static_assert(static_cast<int>(facet::ShadowFilter::pcf5x5) == FACET_SHADOW_PCF5X5 &&
              static_cast<int>(facet::ShadowFilter::pcf2x2) == FACET_SHADOW_PCF2X2);

facet_status facet_scene_set_object_shadows(facet_scene* scene, uint32_t object_id, int cast, int receive) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const std::size_t index = facet_scene::index_of(scene->object_ids, object_id);
    if (index == SIZE_MAX) return fail(scene->error, "object_id", "no object " + std::to_string(object_id));
    facet::Instance& inst = scene->scene.objects[index];
    inst.cast_shadows = cast != 0;
    inst.receive_shadows = receive != 0;
    return report(scene->error, {});
  });
}

}  // extern "C"

namespace {
// A C light as a facet::Light, checked as validate_light checks lights[index].
facet_status to_light(facet_scene* scene, const facet_light* light, std::size_t index, facet::Light& l) {
  l = facet::Light{};
    if (!light) return fail(scene->error, "light", "null");
    const long type = raw(light->type);
    if (type < FACET_DIRECTIONAL || type > FACET_SPOT) return fail(scene->error, "light.type", "unknown type");
    const facet::LightType types[] = {facet::LightType::directional, facet::LightType::point, facet::LightType::spot};
    l.type = types[type];
    l.position = vec3(light->position);
    l.direction = vec3(light->direction);
    l.ambient = facet::Color3(vec3(light->ambient));
    l.diffuse = facet::Color3(vec3(light->diffuse));
    l.specular = facet::Color3(vec3(light->specular));
    l.constant_attenuation = light->constant_attenuation;
    l.linear_attenuation = light->linear_attenuation;
    l.quadratic_attenuation = light->quadratic_attenuation;
    l.spot_cutoff_deg = light->spot_cutoff_deg;
    l.spot_exponent = light->spot_exponent;
    const long method = raw(light->shadow_method), filter = raw(light->shadow_filter);
    if (method < FACET_SHADOW_NONE || method > FACET_SHADOW_RAYCAST) {
      return fail(scene->error, "light.shadow_method", "unknown shadow method");
    }
    if (filter < FACET_SHADOW_FILTER_NONE || filter > FACET_SHADOW_PCF5X5) {
      return fail(scene->error, "light.shadow_filter", "unknown shadow filter");
    }
    l.shadow.method = static_cast<facet::ShadowMethod>(method);
    l.shadow.filter = static_cast<facet::ShadowFilter>(filter);
    l.shadow.resolution = light->shadow_resolution;
    l.shadow.bias = {light->shadow_bias_constant, light->shadow_bias_slope, light->shadow_bias_normal};
    l.enabled = light->enabled != 0;
    l.range = light->range;
    l.spot_shape = light->spot_smooth ? facet::SpotShape::smooth_cone : facet::SpotShape::cutoff_exponent;
    l.spot_inner_deg = light->spot_inner_deg;
    l.spot_outer_deg = light->spot_outer_deg;
    l.spot_falloff = light->spot_falloff;
    const long model = raw(light->attenuation_model);
    l.attenuation_model = model == FACET_ATTENUATION_LINEAR_RANGE ? facet::AttenuationModel::linear_range
                          : model == FACET_ATTENUATION_GL        ? facet::AttenuationModel::gl
                                                                 : static_cast<facet::AttenuationModel>(255);
    l.range_min = light->range_min;
    l.range_max = light->range_max;
    l.projector.texture = light->projector_texture;
    const long pmode = raw(light->projector_mode);
    l.projector.mode = pmode == FACET_PROJECTOR_GOBO       ? facet::ProjectorMode::gobo
                       : pmode == FACET_PROJECTOR_MODULATE ? facet::ProjectorMode::modulate
                                                           : static_cast<facet::ProjectorMode>(255);
    if (facet::Status st = facet::validate_light(l, index); !st.ok()) return report(scene->error, st);
    if (l.projector.texture >= 0 && static_cast<std::size_t>(l.projector.texture) >= scene->scene.textures.size()) {
      return fail(scene->error, "light.projector_texture", "no such texture");
    }
    return FACET_OK;
}
// Whether `l`, added (replacing = SIZE_MAX) or put in place of light `replacing`, would make one
// enabled shadowed light more than facet::kMaxShadowedLights: refused when it is set, not at render.
bool casts_one_too_many(const facet::Scene& scene, const facet::Light& l, std::size_t replacing) {
  auto casts = [](const facet::Light& x) { return x.enabled && x.shadow.method != facet::ShadowMethod::none; };
  if (!casts(l)) return false;
  int others = 0;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) others += i != replacing && casts(scene.lights[i]);
  return others >= facet::kMaxShadowedLights;
}

facet_status too_many_shadowed(facet_scene* scene) {
  return fail(scene->error, "shadow_method",
              "at most " + std::to_string(facet::kMaxShadowedLights) + " enabled lights can cast shadows; the scene has " +
                  std::to_string(facet::kMaxShadowedLights) + " already");
}

}  // namespace

extern "C" {

facet_status facet_scene_add_light(facet_scene* scene, const facet_light* light, uint32_t* light_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    facet::Light l;
    if (const facet_status s = to_light(scene, light, scene->scene.lights.size(), l); s != FACET_OK) return s;
    if (casts_one_too_many(scene->scene, l, SIZE_MAX)) return too_many_shadowed(scene);
    const std::uint32_t id = scene->next_light_id;
    l.name = "light" + std::to_string(id);
    scene->light_ids.reserve(scene->light_ids.size() + 1);
    scene->scene.lights.push_back(std::move(l));
    scene->light_ids.push_back(id);
    ++scene->next_light_id;
    if (light_id) *light_id = id;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_light(facet_scene* scene, uint32_t light_id, const facet_light* light) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const std::size_t index = facet_scene::index_of(scene->light_ids, light_id);
    if (index == SIZE_MAX) return fail(scene->error, "light_id", "no light " + std::to_string(light_id));
    facet::Light l;
    if (const facet_status s = to_light(scene, light, index, l); s != FACET_OK) return s;
    if (casts_one_too_many(scene->scene, l, index)) return too_many_shadowed(scene);
    l.name = scene->scene.lights[index].name;
    scene->scene.lights[index] = std::move(l);
    return report(scene->error, {});
  });
}

facet_status facet_scene_remove_light(facet_scene* scene, uint32_t light_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const std::size_t index = facet_scene::index_of(scene->light_ids, light_id);
    if (index == SIZE_MAX) return fail(scene->error, "light_id", "no light " + std::to_string(light_id));
    scene->scene.lights.erase(scene->scene.lights.begin() + static_cast<std::ptrdiff_t>(index));
    scene->light_ids.erase(scene->light_ids.begin() + static_cast<std::ptrdiff_t>(index));
    scene->rig.reset();
    return report(scene->error, {});
  });
}

}  // extern "C"

namespace {
// The object of `object_id`, or null (and the error set).
facet::Instance* find_object(facet_scene* scene, std::uint32_t object_id) {
  const std::size_t index = facet_scene::index_of(scene->object_ids, object_id);
  if (index == SIZE_MAX) {
    fail(scene->error, "object_id", "no object " + std::to_string(object_id));
    return nullptr;
  }
  return &scene->scene.objects[index];
}
}  // namespace

extern "C" {

facet_status facet_scene_set_object_transform(facet_scene* scene, uint32_t object_id, const float* model) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    facet::Instance* inst = find_object(scene, object_id);
    if (!inst) return FACET_INVALID_ARGUMENT;
    facet::Mat4 m = facet::Mat4::Identity();
    if (model) {
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m(r, c) = model[4 * c + r];
    }
    if (!m.allFinite() || !(std::abs(m.topLeftCorner<3, 3>().cast<double>().determinant()) > 0.0)) {
      return fail(scene->error, "model", "the matrix must be finite and invertible");
    }
    inst->model = m;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_object_material(facet_scene* scene, uint32_t object_id, uint32_t material_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    facet::Instance* inst = find_object(scene, object_id);
    if (!inst) return FACET_INVALID_ARGUMENT;
    if (material_id >= scene->scene.materials.size() || scene->material_removed[material_id]) {
      return fail(scene->error, "material_id", "no such material");
    }
    const facet::Material& m = scene->scene.materials[material_id];
    if (facet::uses_textures(m) && scene->scene.meshes[inst->mesh].mesh.uvs.empty()) {
      return fail(scene->error, "material_id", "the material is textured but the object's mesh has no uvs");
    }
    inst->material = material_id;
    inst->mesh_materials = false;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_object_double_sided(facet_scene* scene, uint32_t object_id, int double_sided) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    facet::Instance* inst = find_object(scene, object_id);
    if (!inst) return FACET_INVALID_ARGUMENT;
    inst->double_sided = double_sided != 0;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_object_lightmap(facet_scene* scene, uint32_t object_id, int32_t texture_id, float scale,
                                            facet_lightmap_mode mode) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    facet::Instance* inst = find_object(scene, object_id);
    if (!inst) return FACET_INVALID_ARGUMENT;
    if (texture_id < -1 || (texture_id >= 0 && static_cast<std::size_t>(texture_id) >= scene->scene.textures.size())) {
      return fail(scene->error, "texture_id", "no such texture");
    }
    if (!(std::isfinite(scale) && scale > 0.0f)) return fail(scene->error, "scale", "expected a finite number > 0");
    const long m = raw(mode);
    if (m != FACET_LIGHTMAP_DIFFUSE && m != FACET_LIGHTMAP_REPLACE) return fail(scene->error, "mode", "unknown lightmap mode");
    if (texture_id >= 0 && scene->scene.meshes[inst->mesh].mesh.lightmap_uvs.empty()) {
      return fail(scene->error, "texture_id", "the object's mesh has no lightmap coordinates (facet_scene_set_mesh_lightmap_uvs)");
    }
    inst->lightmap = texture_id;
    inst->lightmap_scale = scale;
    inst->lightmap_mode = m == FACET_LIGHTMAP_REPLACE ? facet::LightmapMode::replace : facet::LightmapMode::diffuse;
    return report(scene->error, {});
  });
}

facet_bake_config facet_bake_config_default(void) {
  facet_bake_config c{};
  const facet::BakeOptions o;
  c.texels_per_unit = o.charts.texels_per_unit;
  c.padding = o.charts.padding;
  c.lights = 1;
  c.radiosity = 1;
  c.rays_per_shot = o.rays_per_shot;
  c.burial_rays = o.burial_rays;
  c.use_mesh_uvs = 1;
  c.small_texel = o.small_texel;
  c.max_shots = o.max_shots;
  c.residual = o.residual;
  c.threads = 0;
  c.scale = 0;
  c.mode = FACET_LIGHTMAP_DIFFUSE;
  c.progress = nullptr;
  c.progress_user = nullptr;
  c.max_seconds = 0;
  c.memory_budget_bytes = o.memory_budget_bytes;
  return c;
}

facet_status facet_scene_bake(facet_scene* scene, const facet_bake_config* config, facet_bake_stats* stats) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!config) return fail(scene->error, "config", "null");
    const long config_mode = raw(config->mode);
    if (config_mode != FACET_LIGHTMAP_DIFFUSE && config_mode != FACET_LIGHTMAP_REPLACE) {
      return fail(scene->error, "mode", "unknown lightmap mode");
    }
    if (!(config->scale >= 0 && std::isfinite(config->scale))) return fail(scene->error, "scale", "expected 0 or a finite number > 0");
    facet::BakeOptions o;
    o.charts.texels_per_unit = config->texels_per_unit;
    o.charts.padding = config->padding;
    o.direct = config->lights != 0;
    o.radiosity = config->radiosity != 0;
    o.rays_per_shot = config->rays_per_shot;
    o.burial_rays = config->burial_rays;
    o.use_mesh_uvs = config->use_mesh_uvs != 0;
    o.small_texel = config->small_texel;
    o.max_shots = static_cast<std::size_t>(config->max_shots);
    o.residual = config->residual;
    o.threads = config->threads;
    o.max_seconds = config->max_seconds;
    o.memory_budget_bytes = config->memory_budget_bytes;
    if (config->progress) {
      o.progress = [config](double done) { return config->progress(config->progress_user, done) != 0; };
    }
    facet::Result<facet::BakeResult> r = facet::bake_lightmaps(scene->scene, o);
    if (!r) return report(scene->error, r.status());
    const double scale = config->scale > 0 ? config->scale : facet::lightmap_scale(*r);
    const facet::LightmapMode mode = config_mode == FACET_LIGHTMAP_REPLACE ? facet::LightmapMode::replace : facet::LightmapMode::diffuse;
    if (facet::Status st = facet::apply_lightmaps(scene->scene, *r, scale, mode); !st.ok()) return report(scene->error, st);
    if (stats) {
      const facet::BakeStats& s = r->stats;
      *stats = facet_bake_stats{s.texels, s.patches, s.shots, s.rays, s.seconds, s.entered, s.absorbed, s.escaped, s.unshot, scale, s.buried, s.merged};
    }
    return report(scene->error, {});
  });
}

facet_status facet_scene_remove_object(facet_scene* scene, uint32_t object_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const std::size_t index = facet_scene::index_of(scene->object_ids, object_id);
    if (index == SIZE_MAX) return fail(scene->error, "object_id", "no object " + std::to_string(object_id));
    scene->scene.objects.erase(scene->scene.objects.begin() + static_cast<std::ptrdiff_t>(index));
    scene->object_ids.erase(scene->object_ids.begin() + static_cast<std::ptrdiff_t>(index));
    scene->rig.reset();
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_material(facet_scene* scene, uint32_t material_id, const facet_material* material) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!material) return fail(scene->error, "material", "null");
    if (material_id >= scene->scene.materials.size() || scene->material_removed[material_id]) {
      return fail(scene->error, "material_id", "no such material");
    }
    facet::Material m = to_material(*material);
    if (const char* field = nullptr; !textures_exist(m, scene->scene, field)) return fail(scene->error, field, "no such texture");
    if (facet::Status st = facet::validate_material(m, material_id); !st.ok()) return report(scene->error, st);
    m.name = scene->scene.materials[material_id].name;
    // A textured material needs uvs on every mesh drawn with it: checked on a copy, so a failure changes nothing.
    facet::Scene& s = scene->scene;
    const facet::Material previous = s.materials[material_id];
    s.materials[material_id] = m;
    const facet::Status st = facet::validate_scene(s);
    if (!st.ok()) {
      s.materials[material_id] = previous;
      return report(scene->error, st);
    }
    return report(scene->error, {});
  });
}

facet_status facet_scene_remove_material(facet_scene* scene, uint32_t material_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (material_id >= scene->scene.materials.size() || scene->material_removed[material_id]) {
      return fail(scene->error, "material_id", "no such material");
    }
    const std::string& name = scene->scene.materials[material_id].name;
    for (std::size_t i = 0; i < scene->scene.objects.size(); ++i) {
      const facet::Instance& inst = scene->scene.objects[i];
      if (!inst.mesh_materials && inst.material == material_id) {
        return fail(scene->error, "material_id", "object " + std::to_string(scene->object_ids[i]) + " uses it");
      }
    }
    for (std::size_t m = 0; m < scene->scene.meshes.size(); ++m) {
      for (const facet::MaterialGroup& g : scene->scene.meshes[m].mesh.groups) {
        if (g.material == name) return fail(scene->error, "material_id", "a group of mesh " + std::to_string(m) + " uses it");
      }
    }
    scene->material_removed[material_id] = 1;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_two_sided(facet_scene* scene, int two_sided) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  scene->scene.two_sided = two_sided != 0;
  scene->error.clear();
  return FACET_OK;
}

facet_status facet_scene_set_viewer(facet_scene* scene, facet_viewer viewer) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const long v = raw(viewer);
    if (v != FACET_VIEWER_LOCAL && v != FACET_VIEWER_INFINITE) return fail(scene->error, "viewer", "unknown viewer mode");
    scene->scene.viewer = v == FACET_VIEWER_LOCAL ? facet::ViewerMode::local : facet::ViewerMode::infinite;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_transparent_order(facet_scene* scene, facet_transparent_order order) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const long v = raw(order);
    if (v != FACET_TRANSPARENT_SUBMISSION && v != FACET_TRANSPARENT_BACK_TO_FRONT) {
      return fail(scene->error, "order", "unknown transparent order");
    }
    scene->scene.transparent_order = v == FACET_TRANSPARENT_SUBMISSION ? facet::TransparentOrder::submission
                                                                       : facet::TransparentOrder::back_to_front;
    return report(scene->error, {});
  });
}

facet_status facet_scene_load_file(facet_scene* scene, const char* path, unsigned flags, float aspect,
                                   uint64_t memory_budget_bytes) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!path) return fail(scene->error, "path", "null");
    if (flags & ~unsigned(FACET_LOAD_ALLOW_MISSING | FACET_LOAD_FRAME | FACET_LOAD_STRICT | FACET_LOAD_GL_MATERIALS)) {
      return fail(scene->error, "flags", "unknown flag");
    }
    if ((flags & FACET_LOAD_STRICT) && (flags & FACET_LOAD_ALLOW_MISSING)) {
      return fail(scene->error, "flags", "FACET_LOAD_STRICT and FACET_LOAD_ALLOW_MISSING contradict each other");
    }
    if ((flags & FACET_LOAD_FRAME) && !(aspect > 0.0f && aspect < 1e6f)) {
      return fail(scene->error, "aspect", "expected width / height > 0 with FACET_LOAD_FRAME");
    }
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    facet::Scene loaded;
    std::string warnings, cameras;
    std::shared_ptr<const facet::Rig> rig;
    facet::MotionInfo motion;
    bool file_camera = false;
    if (ext == ".gltf" || ext == ".glb" || ext == ".obj") {
      facet::ModelOptions o;
      o.memory_budget_bytes = memory_budget_bytes;
      o.allow_missing = (flags & FACET_LOAD_STRICT) == 0;
      o.assets = scene->assets;
      o.camera = scene->load_camera;
      o.gl_materials = (flags & FACET_LOAD_GL_MATERIALS) != 0;
      facet::Result<facet::Model> model = facet::load_model(path, o);
      if (!model) return report(scene->error, model.status());
      for (const std::string& w : model->warnings) warnings += w + "\n";
      for (const std::string& c : model->cameras) cameras += c + "\n";
      loaded = std::move(model->scene);
      rig = model->rig, motion = model->motion, file_camera = model->has_camera;
      if (flags & FACET_LOAD_FRAME) {
        if (!model->has_camera) {
          facet::Result<facet::Camera> framed = facet::frame_scene(loaded, aspect);
          if (!framed) return report(scene->error, framed.status());
          loaded.camera = *framed;
        }
        if (!model->has_lights) facet::add_default_lights(loaded);
      }
    } else {
      facet::LoadOptions o;
      o.memory_budget_bytes = memory_budget_bytes;
      o.warning = [&](const std::string& w) { warnings += w + "\n"; };
      o.assets = scene->assets;
      o.gl_materials = (flags & FACET_LOAD_GL_MATERIALS) != 0;
      facet::Result<facet::Scene> s = facet::load_scene_file(path, o);
      if (!s) return report(scene->error, s.status());
      loaded = std::move(*s);
    }
    scene->scene = std::move(loaded);
    scene->warnings = std::move(warnings);
    scene->cameras = std::move(cameras);
    scene->rig = std::move(rig), scene->motion = std::move(motion), scene->file_camera = file_camera;
    scene->reset_ids();
    return report(scene->error, {});
  });
}

const char* facet_scene_warnings(const facet_scene* scene) { return scene ? scene->warnings.c_str() : ""; }
const char* facet_scene_cameras(const facet_scene* scene) { return scene ? scene->cameras.c_str() : ""; }

facet_status facet_scene_set_load_camera(facet_scene* scene, const char* camera) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    scene->load_camera = camera ? camera : "";
    return report(scene->error, {});
  });
}

facet_status facet_scene_allow_path(facet_scene* scene, const char* folder) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!folder) {
      scene->assets.allowed_roots.clear();
    } else {
      if (!*folder) return fail(scene->error, "folder", "empty");
      scene->assets.allowed_roots.emplace_back(folder);
    }
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_resolver(facet_scene* scene, facet_resolve_fn resolve, void* user) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!resolve) {
      scene->assets.resolver = nullptr;
    } else {
      scene->assets.resolver = [resolve, user](const std::string& name) -> facet::Result<std::string> {
        const void* bytes = nullptr;
        std::size_t size = 0;
        if (resolve(user, name.c_str(), &bytes, &size) != 0) return facet::Status{facet::ErrorCode::io_error, "", "no such file"};
        if (!bytes && size > 0) return facet::Status{facet::ErrorCode::invalid_argument, "", "the resolver gave no bytes"};
        return size == 0 ? std::string() : std::string(static_cast<const char*>(bytes), size);
      };
    }
    return report(scene->error, {});
  });
}

facet_status facet_scene_frame(facet_scene* scene, float aspect) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!(aspect > 0.0f && aspect < 1e6f)) return fail(scene->error, "aspect", "expected width / height > 0");
    facet::ViewOptions view;
    view.projection = scene->scene.camera.projection;
    facet::Result<facet::Camera> framed = facet::frame_scene(scene->scene, aspect, view);
    if (!framed) return report(scene->error, framed.status());
    scene->scene.camera = *framed;
    return report(scene->error, {});
  });
}

facet_status facet_scene_frame_view(facet_scene* scene, float aspect, float azimuth_deg, float elevation_deg,
                                    facet_up up, float fov_deg, float fill) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    facet::ViewOptions view;
    if (!up_axis(up, view.up)) return fail(scene->error, "up", "expected FACET_UP_Y, FACET_UP_Z or another facet_up");
    view.azimuth_deg = azimuth_deg;
    view.elevation_deg = elevation_deg;
    view.projection = scene->scene.camera.projection;
    view.vertical_fov_deg = fov_deg;
    view.fill = fill;
    facet::Result<facet::Camera> framed = facet::frame_scene(scene->scene, aspect, view);
    if (!framed) return report(scene->error, framed.status());
    scene->scene.camera = *framed;
    return report(scene->error, {});
  });
}

facet_status facet_scene_orbit(facet_scene* scene, float angle_deg, facet_up up, int turn_lights) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    facet::UpAxis axis = facet::UpAxis::y;
    if (!up_axis(up, axis)) return fail(scene->error, "up", "expected FACET_UP_Y, FACET_UP_Z or another facet_up");
    if (!(std::abs(angle_deg) <= 36000.0f)) return fail(scene->error, "angle_deg", "expected a number in [-36000, 36000]");
    const facet::Bounds b = facet::scene_bounds(scene->scene);
    if (b.empty()) return fail(scene->error, "scene", "no vertices: nothing to orbit");
    const facet::Vec3 centre = ((b.min.cast<double>() + b.max.cast<double>()) * 0.5).cast<float>();
    scene->scene.camera = facet::orbit_camera(scene->scene.camera, centre, axis, angle_deg);
    if (turn_lights) {
      for (facet::Light& l : scene->scene.lights) l = facet::orbit_light(l, centre, axis, angle_deg);
    }
    return report(scene->error, {});
  });
}

facet_status facet_scene_add_default_lights(facet_scene* scene) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const std::size_t before = scene->scene.lights.size();
    facet::add_default_lights(scene->scene);
    for (std::size_t i = before; i < scene->scene.lights.size(); ++i) scene->light_ids.push_back(scene->next_light_id++);
    return report(scene->error, {});
  });
}


facet_status facet_scene_get_camera(const facet_scene* scene, facet_camera* camera) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  if (!camera) return fail(scene->error, "camera", "null");
  const facet::Camera& c = scene->scene.camera;
  for (int k = 0; k < 3; ++k) camera->eye[k] = c.eye[k], camera->target[k] = c.target[k], camera->up[k] = c.up[k];
  camera->vertical_fov_deg = c.vertical_fov_deg;
  camera->near_plane = c.near;
  camera->far_plane = c.far;
  return FACET_OK;
}

facet_status facet_scene_set_camera(facet_scene* scene, const facet_camera* camera) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!camera) return fail(scene->error, "camera", "null");
    facet::Camera c = scene->scene.camera;  // its projection and aspect kept
    c.eye = vec3(camera->eye);
    c.target = vec3(camera->target);
    c.up = vec3(camera->up);
    c.vertical_fov_deg = camera->vertical_fov_deg;
    c.near = camera->near_plane;
    c.far = camera->far_plane;
    if (facet::Status st = facet::validate_camera(c); !st.ok()) return report(scene->error, st);
    scene->scene.camera = c;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_projection(facet_scene* scene, facet_projection projection, float half_height) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const long p = raw(projection);  // any bits a C caller passes, read without loading an invalid enum
    if (p != FACET_PROJECTION_PERSPECTIVE && p != FACET_PROJECTION_ORTHOGRAPHIC) {
      return fail(scene->error, "projection", "expected FACET_PROJECTION_PERSPECTIVE or FACET_PROJECTION_ORTHOGRAPHIC");
    }
    facet::Camera c = scene->scene.camera;
    c.projection = p == FACET_PROJECTION_ORTHOGRAPHIC ? facet::Projection::orthographic : facet::Projection::perspective;
    if (c.projection == facet::Projection::orthographic) c.half_height = half_height;
    if (facet::Status st = facet::validate_camera(c); !st.ok()) return report(scene->error, st);
    scene->scene.camera = c;
    return report(scene->error, {});
  });
}

facet_status facet_scene_get_projection(const facet_scene* scene, facet_projection* projection, float* half_height) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  if (!projection || !half_height) return fail(scene->error, !projection ? "projection" : "half_height", "null");
  const facet::Camera& c = scene->scene.camera;
  *projection = c.projection == facet::Projection::orthographic ? FACET_PROJECTION_ORTHOGRAPHIC : FACET_PROJECTION_PERSPECTIVE;
  *half_height = c.half_height;
  return FACET_OK;
}

facet_status facet_scene_set_display(facet_scene* scene, const facet_display* display) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!display) return fail(scene->error, "display", "null");
    const long op = raw(display->tone_mapping);
    if (op < FACET_TONE_MAPPING_NONE || op > FACET_TONE_MAPPING_ACES) return fail(scene->error, "display.tone_mapping", "unknown operator");
    facet::Display d;
    d.ev = display->exposure_ev;
    d.automatic = display->auto_exposure != 0;
    d.tone_mapping = static_cast<facet::ToneMapping>(op);
    if (facet::Status st = facet::validate_display(d); !st.ok()) return report(scene->error, st);
    scene->scene.display = d;
    return report(scene->error, {});
  });
}

facet_status facet_scene_get_display(const facet_scene* scene, facet_display* display) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  if (!display) return fail(scene->error, "display", "null");
  display->exposure_ev = scene->scene.display.ev;
  display->auto_exposure = scene->scene.display.automatic ? 1 : 0;
  display->tone_mapping = static_cast<facet_tone_mapping>(scene->scene.display.tone_mapping);
  return FACET_OK;
}

facet_status facet_scene_set_global_ambient(facet_scene* scene, const float rgb[3]) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!rgb) return fail(scene->error, "global_ambient", "null");
    const facet::Color3 ambient(vec3(rgb));
    if (facet::Status st = facet::validate_global_ambient(ambient); !st.ok()) return report(scene->error, st);
    scene->scene.global_ambient = ambient;
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_fog(facet_scene* scene, const facet_fog* fog) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!fog) return fail(scene->error, "fog", "null");
    facet::Fog f;
    f.mode = static_cast<facet::FogMode>(fog->mode);
    f.color = facet::Color3(vec3(fog->color));
    f.start = fog->start, f.end = fog->end, f.density = fog->density;
    if (facet::Status st = facet::validate_fog(f); !st.ok()) return report(scene->error, st);
    scene->scene.fog = f;
    return report(scene->error, {});
  });
}

}  // extern "C"
