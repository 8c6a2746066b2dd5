// Every field of a Material and of a Light described once: its name, type, accepted range,
// choices and one line of documentation. Validation, the scene-file reader, the C API's field
// setters, Python, `facet check --fields` and the docs' field tables all read these tables, so a
// new field is one member, one entry here and the stage that uses it (docs/building.md).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "facet/light.hpp"
#include "facet/material.hpp"
#include "facet/scene.hpp"
#include "facet/status.hpp"

namespace facet {

enum class FieldType : std::uint8_t {
  number,   // a float in [lo, hi]
  integer,  // an integer in [lo, hi]
  boolean,  // false or true (0 or 1)
  choice,   // one of `choices`, the value its index (the enum's order)
  colour,   // three finite floats >= 0 (linear RGB)
  vector,   // `components` finite floats, each in [lo, hi]
  texture,  // `components` texture indices into Scene::textures, -1 for none (a scene file names them)
};
const char* to_string(FieldType type) noexcept;

template <class T>
struct FieldSpec {
  // The scene file's key, dotted below an object ("environment.strength", "shadow.bias.slope");
  // the C API's and Python's name for the field, and the path validation messages name.
  const char* name;
  FieldType type;
  int components;  // values the field holds (3 for a colour, 2 for uv_scale, 6 for cube faces)
  double lo, hi;   // number, integer, vector: each value's closed range (NaN is never in it)
  double also;     // number: one more accepted value outside [lo, hi] (NaN: none)
  std::span<const char* const> choices;  // choice: the names in the enum's order
  const char* doc;                        // one line: what the field does
  double (*get)(const T& object, int component);
  void (*set)(T& object, int component, double value);  // no check: see set_field
};
using MaterialField = FieldSpec<Material>;
using LightField = FieldSpec<Light>;

// The tables, in the order the docs list them.
std::span<const MaterialField> material_fields() noexcept;
std::span<const LightField> light_fields() noexcept;
// The entry named `name`, or nullptr.
const MaterialField* find_material_field(std::string_view name) noexcept;
const LightField* find_light_field(std::string_view name) noexcept;

// Whether `value` may be stored in component `component` of a field (its type's rule and range):
// an invalid_argument naming `path` (the field's full path, "materials[2].alpha") otherwise.
Status check_field_value(const MaterialField& field, double value, const std::string& path);
Status check_field_value(const LightField& field, double value, const std::string& path);
// Checks each of the field's values (exactly `components` of them) and stores them; on an error
// nothing is stored.
Status set_field(const MaterialField& field, Material& material, std::span<const double> values, const std::string& path);
Status set_field(const LightField& field, Light& light, std::span<const double> values, const std::string& path);
// Whether the field holds its default (a default-constructed Material or Light's) value.
bool is_default(const MaterialField& field, const Material& material) noexcept;
bool is_default(const LightField& field, const Light& light) noexcept;
// The value as the scene file writes it: 0.5, [1, 0, 0], "alpha", true (texture fields as their
// indices, -1 for none).
std::string format_field(const MaterialField& field, const Material& material);
std::string format_field(const LightField& field, const Light& light);
// Puts `material` in place of scene.materials[index] when it is valid alone and the scene is valid
// with it (its textures exist, the meshes it draws have uvs, the scene's limits); otherwise the
// scene is as it was and the first problem is returned. On success `material` holds the one it
// replaced. (What the C and Python field setters end in.) replace_light likewise.
Status replace_material(Scene& scene, std::size_t index, Material& material);
Status replace_light(Scene& scene, std::size_t index, Light& light);
// The accepted values in words ("[0, 1]", "blinn | phong", "a texture or -1 (none)").
std::string describe_range(const MaterialField& field);
std::string describe_range(const LightField& field);

}  // namespace facet
