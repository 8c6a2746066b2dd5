// The C API's field access (facet.h, "Fields by name"): every material and light field of the
// field table (facet/fields.hpp) by its name, so a field added to the table reaches C without a
// change to facet_material or facet_light.
#include <cmath>
#include <span>
#include <string>

#include "c_api/handles.hpp"
#include "common/format.hpp"
#include "facet/fields.hpp"

using namespace facet::c_api;

namespace {

template <class T>
void fill_info(const facet::FieldSpec<T>& f, facet_field_info* info) {
  info->name = f.name;
  info->type = facet::to_string(f.type);
  info->components = f.components;
  info->lo = f.lo, info->hi = f.hi, info->also = f.also;
  info->choices = f.choices.data();
  info->choice_count = f.choices.size();
  info->doc = f.doc;
}

template <class T>
facet_status field_info(std::span<const facet::FieldSpec<T>> fields, size_t index, facet_field_info* info) {
  if (!info || index >= fields.size()) return FACET_INVALID_ARGUMENT;
  fill_info(fields[index], info);
  return FACET_OK;
}

// The entry named `name`, or a message naming it (printable: a caller's bytes never reach a message raw).
template <class T, class Find>
const facet::FieldSpec<T>* lookup(std::string& error, const char* name, Find find) {
  const facet::FieldSpec<T>* f = name ? find(name) : nullptr;
  if (!f) fail(error, "name", name ? "no field named " + facet::quote(name, 48) : std::string("null"));
  return f;
}

template <class T>
facet_status read_values(std::string& error, const facet::FieldSpec<T>& f, const T& object, double* values, size_t count) {
  if (!values || count != size_t(f.components)) {
    return fail(error, "count", std::string(f.name) + " holds " + std::to_string(f.components) + " value" +
                                           (f.components == 1 ? "" : "s") + ", asked for " + std::to_string(count));
  }
  for (int c = 0; c < f.components; ++c) values[c] = f.get(object, c);
  return report(error, {});
}

}  // namespace

extern "C" {

size_t facet_material_field_count(void) { return facet::material_fields().size(); }
size_t facet_light_field_count(void) { return facet::light_fields().size(); }
facet_status facet_material_field_info(size_t index, facet_field_info* info) {
  return field_info(facet::material_fields(), index, info);
}
facet_status facet_light_field_info(size_t index, facet_field_info* info) { return field_info(facet::light_fields(), index, info); }

facet_status facet_scene_set_material_field(facet_scene* scene, uint32_t material_id, const char* name, const double* values,
                                            size_t count) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const facet::MaterialField* f = lookup<facet::Material>(scene->error, name, facet::find_material_field);
    if (!f) return FACET_INVALID_ARGUMENT;
    facet::Scene& s = scene->scene;
    if (material_id >= s.materials.size() || scene->material_removed[material_id]) {
      return fail(scene->error, "material_id", "no such material");
    }
    if (!values) return fail(scene->error, "values", "null");
    const std::string path = "materials[" + std::to_string(material_id) + "]." + f->name;
    facet::Material m = s.materials[material_id];
    if (facet::Status st = facet::set_field(*f, m, std::span<const double>(values, count), path); !st.ok()) {
      return report(scene->error, st);
    }
    // The material alone, then the scene with it (its textures exist, its meshes have uvs): a
    // failure changes nothing.
    return report(scene->error, facet::replace_material(s, material_id, m));
  });
}

facet_status facet_scene_get_material_field(const facet_scene* scene, uint32_t material_id, const char* name, double* values,
                                            size_t count) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  const facet_scene* s = scene;  // (only its error message, a mutable member, changes)
  return guarded(&s->error, [&] {
    const facet::MaterialField* f = lookup<facet::Material>(scene->error, name, facet::find_material_field);
    if (!f) return FACET_INVALID_ARGUMENT;
    if (material_id >= s->scene.materials.size() || s->material_removed[material_id]) {
      return fail(s->error, "material_id", "no such material");
    }
    return read_values(s->error, *f, s->scene.materials[material_id], values, count);
  });
}

facet_status facet_scene_set_light_field(facet_scene* scene, uint32_t light_id, const char* name, const double* values,
                                         size_t count) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    const facet::LightField* f = lookup<facet::Light>(scene->error, name, facet::find_light_field);
    if (!f) return FACET_INVALID_ARGUMENT;
    const std::size_t index = facet_scene::index_of(scene->light_ids, light_id);
    if (index == SIZE_MAX) return fail(scene->error, "light_id", "no light " + std::to_string(light_id));
    if (!values) return fail(scene->error, "values", "null");
    facet::Scene& s = scene->scene;
    const std::string path = "lights[" + std::to_string(index) + "]." + f->name;
    facet::Light l = s.lights[index];
    if (facet::Status st = facet::set_field(*f, l, std::span<const double>(values, count), path); !st.ok()) {
      return report(scene->error, st);
    }
    return report(scene->error, facet::replace_light(s, index, l));  // (the scene's limits: shadowed lights, projectors)
  });
}

facet_status facet_scene_get_light_field(const facet_scene* scene, uint32_t light_id, const char* name, double* values,
                                         size_t count) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  const facet_scene* s = scene;
  return guarded(&s->error, [&] {
    const facet::LightField* f = lookup<facet::Light>(scene->error, name, facet::find_light_field);
    if (!f) return FACET_INVALID_ARGUMENT;
    const std::size_t index = facet_scene::index_of(s->light_ids, light_id);
    if (index == SIZE_MAX) return fail(s->error, "light_id", "no light " + std::to_string(light_id));
    return read_values(s->error, *f, s->scene.lights[index], values, count);
  });
}

}  // extern "C"
