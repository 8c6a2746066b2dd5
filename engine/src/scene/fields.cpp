// The material and light field tables (facet/fields.hpp) and the rules every interface applies
// through them. A field's default is its struct's default member value, not restated here.
#include "facet/fields.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <type_traits>

#include "common/format.hpp"
#include "common/try.hpp"
#include "scene/validate.hpp"

namespace facet {
// (a named namespace, not an anonymous one: unity builds put this file beside others)
namespace field_table {

constexpr double kFloatMax = std::numeric_limits<float>::max();
constexpr double kBig = 3.0e38;  // the largest coefficient a light takes (sums of three stay finite)
constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();
constexpr double kMaxIndex = std::numeric_limits<std::int32_t>::max();  // the largest texture index an int32 holds

// Reading and writing one component of a member, whatever its C++ type.
template <class V>
double read_value(const V& v, int c) {
  if constexpr (std::is_enum_v<V>) {
    return static_cast<double>(static_cast<int>(v));
  } else if constexpr (std::is_same_v<V, bool>) {
    return v ? 1.0 : 0.0;
  } else if constexpr (std::is_arithmetic_v<V>) {
    return static_cast<double>(v);
  } else {  // an Eigen vector or a plain array
    return static_cast<double>(v[c]);
  }
}

template <class V>
void write_value(V& v, int c, double x) {
  if constexpr (std::is_enum_v<V>) {
    v = static_cast<V>(static_cast<int>(x));
  } else if constexpr (std::is_same_v<V, bool>) {
    v = x != 0.0;
  } else if constexpr (std::is_arithmetic_v<V>) {
    v = static_cast<V>(x);
  } else {
    using E = std::remove_cvref_t<decltype(v[c])>;
    v[c] = static_cast<E>(x);
  }
}

// The member at `Path` (one pointer to member, or a chain into nested structs).
template <class T, auto... Path>
double get_at(const T& object, int c) {
  return read_value((object .* ... .* Path), c);
}
template <class T, auto... Path>
void set_at(T& object, int c, double x) {
  write_value((object .* ... .* Path), c, x);
}

template <class T, auto... Path>
constexpr FieldSpec<T> field(const char* name, FieldType type, int components, double lo, double hi,
                             std::span<const char* const> choices, const char* doc, double also = kNoValue) {
  return {name, type, components, lo, hi, also, choices, doc, &get_at<T, Path...>, &set_at<T, Path...>};
}

template <auto... Path>
constexpr MaterialField m(const char* name, FieldType type, int n, double lo, double hi, std::span<const char* const> choices,
                          const char* doc) {
  return field<Material, Path...>(name, type, n, lo, hi, choices, doc);
}
template <auto... Path>
constexpr LightField l(const char* name, FieldType type, int n, double lo, double hi, std::span<const char* const> choices,
                       const char* doc, double also = kNoValue) {
  return field<Light, Path...>(name, type, n, lo, hi, choices, doc, also);
}

using FT = FieldType;
constexpr std::span<const char* const> kNone{};
// Choices, in each enum's order (facet/material.hpp, facet/light.hpp).
constexpr const char* kSpecularModels[] = {"blinn", "phong"};
constexpr const char* kMaterialModels[] = {"gl", "pbr"};
constexpr const char* kTextureModes[] = {"modulate", "replace", "decal", "add"};
constexpr const char* kBlendModes[] = {"opaque", "alpha", "premultiplied", "add", "multiply", "subtract"};
constexpr const char* kDepthWrites[] = {"auto", "on", "off"};
constexpr const char* kEnvironmentModes[] = {"none", "sphere", "cube", "normal"};
constexpr const char* kEnvironmentBlends[] = {"add", "modulate", "mix"};
constexpr const char* kLightTypes[] = {"directional", "point", "spot"};
constexpr const char* kAttenuationModels[] = {"gl", "linear_range"};
constexpr const char* kSpotShapes[] = {"cutoff_exponent", "smooth_cone"};
constexpr const char* kShadowMethods[] = {"none", "map", "volume", "raycast"};
constexpr const char* kShadowFilters[] = {"none", "pcf2x2", "pcf3x3", "pcf5x5"};
constexpr const char* kProjectorModes[] = {"modulate", "gobo"};

using M = Material;
using E = Environment;
constexpr MaterialField kMaterialFields[] = {
    m<&M::model>("model", FT::choice, 1, 0, 0, kMaterialModels,
                 "the lighting model: GL's fixed function (gl) or glTF's metallic-roughness BRDF (pbr; docs/pbr.md)"),
    m<&M::emissive>("emissive", FT::colour, 3, 0, kFloatMax, kNone, "light the surface gives off (GL's emission)"),
    m<&M::ambient>("ambient", FT::colour, 3, 0, kFloatMax, kNone, "reflectance of ambient light"),
    m<&M::diffuse>("diffuse", FT::colour, 3, 0, kFloatMax, kNone, "reflectance of diffuse light (the albedo)"),
    m<&M::specular>("specular", FT::colour, 3, 0, kFloatMax, kNone, "reflectance of the specular highlight"),
    m<&M::shininess>("shininess", FT::number, 1, 0, kMaxShininess, kNone, "the specular exponent (0^0 = 1, as GL)"),
    m<&M::specular_model>("specular_model", FT::choice, 1, 0, 0, kSpecularModels,
                          "the specular lobe: around the half vector (blinn) or the reflected light (phong)"),
    m<&M::base_color>("base_color", FT::colour, 3, 0, 1, kNone, "pbr: the base colour, linear (diffuse_texture is its texture)"),
    m<&M::metallic>("metallic", FT::number, 1, 0, 1, kNone, "pbr: 0 a dielectric, 1 a metal (between: a mix)"),
    m<&M::roughness>("roughness", FT::number, 1, 0, 1, kNone, "pbr: perceptual roughness, 0 a mirror (held at >= 0.045), 1 matte"),
    m<&M::ior>("ior", FT::number, 1, 1, 10, kNone, "pbr: the dielectric's index of refraction (its reflectance, 0.04 at 1.5)"),
    m<&M::specular_weight>("specular_weight", FT::number, 1, 0, 1, kNone,
                           "pbr: strength of the dielectric's specular layer (KHR_materials_specular)"),
    m<&M::specular_color>("specular_color", FT::colour, 3, 0, 1e6, kNone,
                          "pbr: tints the dielectric's reflectance at normal incidence (capped at 1)"),
    m<&M::metallic_roughness_texture>("metallic_roughness_texture", FT::texture, 1, -1, kMaxIndex, kNone,
                                      "pbr: blue times metallic, green times roughness, per pixel (Phong; needs uvs)"),
    m<&M::alpha>("alpha", FT::number, 1, 0, 1, kNone, "the fragment's alpha (blending, the alpha test, the output's alpha)"),
    m<&M::diffuse_texture>("diffuse_texture", FT::texture, 1, -1, kMaxIndex, kNone,
                           "the texture combined with the lit colour by texture_mode (needs uvs)"),
    m<&M::texture_mode>("texture_mode", FT::choice, 1, 0, 0, kTextureModes,
                        "how the diffuse texture combines with the lit colour (GL's texture environment)"),
    m<&M::uv_scale>("uv_scale", FT::vector, 2, -kFloatMax, kFloatMax, kNone,
                    "texture coordinates are multiplied by it (non-zero; a scene file may give one number)"),
    m<&M::alpha_cutoff>("alpha_cutoff", FT::number, 1, 0, 1, kNone, "the alpha test: fragments with alpha below it are discarded (0: off)"),
    m<&M::alpha_to_coverage>("alpha_to_coverage", FT::boolean, 1, 0, 1, kNone,
                             "with multisampling, alpha decides how many of a pixel's samples the fragment covers"),
    m<&M::blend>("blend", FT::choice, 1, 0, 0, kBlendModes, "how the fragment combines with the image (GL's blend factors)"),
    m<&M::depth_write>("depth_write", FT::choice, 1, 0, 0, kDepthWrites,
                       "whether fragments write depth (auto: opaque materials do; a scene file may say true or false)"),
    m<&M::emissive_texture>("emissive_texture", FT::texture, 1, -1, kMaxIndex, kNone,
                            "the emission is emissive times this texture's RGB, added after texturing"),
    m<&M::emission_after_texture>("emission_after_texture", FT::boolean, 1, 0, 1, kNone,
                                  "add the emission after the texture environment (glTF's rule) instead of lighting it"),
    m<&M::normal_texture>("normal_texture", FT::texture, 1, -1, kMaxIndex, kNone,
                          "a tangent-space normal map (lit per pixel; needs uvs and tangents)"),
    m<&M::normal_scale>("normal_scale", FT::number, 1, -1e6, 1e6, kNone, "the normal map's x and y are multiplied by it"),
    m<&M::occlusion_texture>("occlusion_texture", FT::texture, 1, -1, kMaxIndex, kNone,
                             "an ambient-occlusion map: its red channel darkens every ambient term (lit per pixel)"),
    m<&M::occlusion_strength>("occlusion_strength", FT::number, 1, 0, 1, kNone, "how much the occlusion map darkens (0: not at all)"),
    m<&M::bump_texture>("bump_texture", FT::texture, 1, -1, kMaxIndex, kNone,
                        "a height map whose differences tilt the normal (Blinn's bump mapping)"),
    m<&M::bump_scale>("bump_scale", FT::number, 1, -1e6, 1e6, kNone, "the height map's differences are multiplied by it"),
    m<&M::environment, &E::mode>("environment.mode", FT::choice, 1, 0, 0, kEnvironmentModes,
                                 "environment mapping: a picture of the surroundings looked up per reflected direction or normal"),
    m<&M::environment, &E::maps>("environment.maps", FT::texture, 6, -1, kMaxIndex, kNone,
                                 "sphere and normal: the map first; cube: the faces +X, -X, +Y, -Y, +Z, -Z (a scene file names them)"),
    m<&M::environment, &E::strength>("environment.strength", FT::number, 1, 0, 1, kNone, "how strongly the environment combines"),
    m<&M::environment, &E::blend>("environment.blend", FT::choice, 1, 0, 0, kEnvironmentBlends,
                                  "how the environment combines with the textured colour"),
    m<&M::environment, &E::dynamic>("environment.dynamic", FT::boolean, 1, 0, 1, kNone,
                                    "cube only: render the six faces from the scene every frame"),
    m<&M::environment, &E::resolution>("environment.resolution", FT::integer, 1, 1, 4096, kNone,
                                       "a dynamic cube's face size in pixels"),
};

using L = Light;
using S = Shadow;
using B = ShadowBias;
using P = Projector;
constexpr LightField kLightFields[] = {
    l<&L::type>("type", FT::choice, 1, 0, 0, kLightTypes, "directional (from far away), point or spot"),
    l<&L::enabled>("enabled", FT::boolean, 1, 0, 1, kNone, "a disabled light is skipped"),
    l<&L::position>("position", FT::vector, 3, -kFloatMax, kFloatMax, kNone, "point and spot lights: where the light is (world space)"),
    l<&L::direction>("direction", FT::vector, 3, -kFloatMax, kFloatMax, kNone,
                     "directional and spot lights: the way the light travels (non-zero)"),
    l<&L::ambient>("ambient", FT::colour, 3, 0, kFloatMax, kNone, "the light's ambient term (never shadowed)"),
    l<&L::diffuse>("diffuse", FT::colour, 3, 0, kFloatMax, kNone, "the light's diffuse colour and intensity"),
    l<&L::specular>("specular", FT::colour, 3, 0, kFloatMax, kNone, "the light's specular colour and intensity"),
    l<&L::attenuation_model>("attenuation.model", FT::choice, 1, 0, 0, kAttenuationModels,
                             "point and spot: GL's 1 / (constant + linear d + quadratic d^2), or a linear ramp from min to max + min"),
    l<&L::constant_attenuation>("attenuation.constant", FT::number, 1, 0, kBig, kNone, "gl model: the constant coefficient"),
    l<&L::linear_attenuation>("attenuation.linear", FT::number, 1, 0, kBig, kNone, "gl model: the coefficient of d"),
    l<&L::quadratic_attenuation>("attenuation.quadratic", FT::number, 1, 0, kBig, kNone, "gl model: the coefficient of d^2"),
    l<&L::range_min>("attenuation.min", FT::number, 1, 0, 1e30, kNone, "linear_range model: full light up to this distance (<= max)"),
    l<&L::range_max>("attenuation.max", FT::number, 1, 0, 1e30, kNone, "linear_range model: the ramp's length (> 0)"),
    l<&L::range>("range", FT::number, 1, 0, kBig, kNone, "point and spot: nothing beyond this distance (a smooth window; 0: unbounded)"),
    l<&L::spot_shape>("spot.shape", FT::choice, 1, 0, 0, kSpotShapes,
                      "GL's cone (cutoff_deg, exponent) or a smooth one (inner_deg, outer_deg, falloff); a scene file may leave it to the keys it gives"),
    l<&L::spot_cutoff_deg>("spot.cutoff_deg", FT::number, 1, 0, 90, kNone, "GL cone: the half-angle, or 180 for no cone", 180),
    l<&L::spot_exponent>("spot.exponent", FT::number, 1, 0, kMaxShininess, kNone, "GL cone: cos(angle) to this power"),
    l<&L::spot_inner_deg>("spot.inner_deg", FT::number, 1, 0, 90, kNone, "smooth cone: full light within this half-angle (<= outer_deg)"),
    l<&L::spot_outer_deg>("spot.outer_deg", FT::number, 1, 0, 90, kNone, "smooth cone: no light beyond this half-angle"),
    l<&L::spot_falloff>("spot.falloff", FT::number, 1, 0, kMaxShininess, kNone, "smooth cone: the exponent of the ramp between them"),
    l<&L::shadow, &S::method>("shadow.method", FT::choice, 1, 0, 0, kShadowMethods, "what decides where the light is blocked"),
    l<&L::shadow, &S::resolution>("shadow.resolution", FT::integer, 1, 16, 16384, kNone, "map: texels a side of each face"),
    l<&L::shadow, &S::filter>("shadow.filter", FT::choice, 1, 0, 0, kShadowFilters, "map: the nearest texel or N x N filtered comparisons"),
    l<&L::shadow, &S::bias, &B::constant>("shadow.bias.constant", FT::number, 1, 0, 1e4, kNone,
                                          "map: moves the point towards the light, in filter radii"),
    l<&L::shadow, &S::bias, &B::slope>("shadow.bias.slope", FT::number, 1, 0, 1e4, kNone,
                                       "map: as constant, times the tangent of the light's angle to the normal"),
    l<&L::shadow, &S::bias, &B::normal>("shadow.bias.normal", FT::number, 1, 0, 1e4, kNone,
                                        "map and raycast: moves the point along its normal"),
    l<&L::projector, &P::texture>("projector.texture", FT::texture, 1, -1, kMaxIndex, kNone, "spot lights: a picture the light projects"),
    l<&L::projector, &P::mode>("projector.mode", FT::choice, 1, 0, 0, kProjectorModes,
                               "the picture multiplies the light per channel (modulate) or by its luminance (gobo)"),
};

template <class T>
std::string colour_bound(const FieldSpec<T>& f) {
  return f.hi < kFloatMax ? "in [0, " + format_number(f.hi) + "]" : ">= 0";
}

template <class T>
std::string range_words(const FieldSpec<T>& f) {
  switch (f.type) {
    case FieldType::boolean: return "false or true";
    case FieldType::choice: {
      std::string s;
      for (std::size_t i = 0; i < f.choices.size(); ++i) s += (i ? " | " : "") + std::string(f.choices[i]);
      return s;
    }
    case FieldType::texture: return f.components > 1 ? std::to_string(f.components) + " textures or -1 (none)" : "a texture or -1 (none)";
    case FieldType::colour: return "[r, g, b], each " + colour_bound(f);
    case FieldType::vector:
      if (f.lo == -kFloatMax && f.hi == kFloatMax) return std::to_string(f.components) + " finite numbers";
      [[fallthrough]];
    case FieldType::number:
    case FieldType::integer:
      return "[" + format_number(f.lo) + ", " + format_number(f.hi) + "]" + (f.also == f.also ? " or " + format_number(f.also) : "");
  }
  return "";
}

template <class T>
Status check_value(const FieldSpec<T>& f, double v, const std::string& path) {
  auto bad = [&](const std::string& what) {
    return Status{ErrorCode::invalid_argument, path, path + ": " + what};
  };
  switch (f.type) {
    case FieldType::boolean:
      if (v != 0.0 && v != 1.0) return bad("expected false or true (0 or 1), found " + format_number(v));
      return {};
    case FieldType::choice:
      if (!(v >= 0.0 && v < double(f.choices.size()) && v == std::floor(v))) {
        return bad("expected " + range_words(f) + " (0.." + std::to_string(f.choices.size() - 1) + "), found " + format_number(v));
      }
      return {};
    case FieldType::texture:
      if (!(v >= -1.0 && v <= f.hi && v == std::floor(v))) return bad("expected a texture index or -1 (none), found " + format_number(v));
      return {};
    case FieldType::colour:
      if (!(v >= 0.0 && v <= f.hi)) return bad("expected finite colour components " + colour_bound(f) + ", found " + format_number(v));
      return {};
    case FieldType::integer:
      if (!(v >= f.lo && v <= f.hi && v == std::floor(v))) return bad("expected an integer in " + range_words(f) + ", found " + format_number(v));
      return {};
    case FieldType::number:
    case FieldType::vector:
      if (!(v >= f.lo && v <= f.hi) && !(v == f.also)) {
        return bad(f.type == FieldType::vector && f.lo == -kFloatMax ? "expected finite numbers, found " + format_number(v)
                                                                      : "expected a number in " + range_words(f) + ", found " + format_number(v));
      }
      return {};
  }
  return bad("unknown field type");
}

template <class T>
Status set_values(const FieldSpec<T>& f, T& object, std::span<const double> values, const std::string& path) {
  if (values.size() != std::size_t(f.components)) {
    return {ErrorCode::invalid_argument, path,
            path + ": expected " + std::to_string(f.components) + " value" + (f.components == 1 ? "" : "s") + ", found " +
                std::to_string(values.size())};
  }
  for (int c = 0; c < f.components; ++c) {
    FACET_TRY(check_value(f, values[std::size_t(c)], f.components > 1 && f.type == FieldType::texture ? path + "[" + std::to_string(c) + "]" : path));
  }
  for (int c = 0; c < f.components; ++c) f.set(object, c, values[std::size_t(c)]);
  return {};
}

template <class T>
bool equals_default(const FieldSpec<T>& f, const T& object) {
  const T fresh{};
  for (int c = 0; c < f.components; ++c)
    if (!(f.get(object, c) == f.get(fresh, c))) return false;
  return true;
}

// A float member's value as the shortest decimal that reads back as the same float ("0.2", not
// "0.200000003").
std::string shortest(double v) {
  char buf[32];
  const bool plain = std::abs(v) < 1e15 && (v == 0.0 || std::abs(v) >= 1e-4);  // "30", not "3e+01"
  for (int digits = 1; digits <= 9; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (plain && std::strchr(buf, 'e')) continue;
    if (static_cast<float>(std::strtod(buf, nullptr)) == static_cast<float>(v)) return buf;
  }
  return format_number(v);
}

template <class T>
std::string format_value(const FieldSpec<T>& f, const T& object) {
  auto one = [&](int c) -> std::string {
    const double v = f.get(object, c);
    switch (f.type) {
      case FieldType::boolean: return v != 0.0 ? "true" : "false";
      case FieldType::choice: {
        const int i = static_cast<int>(v);
        return i >= 0 && std::size_t(i) < f.choices.size() ? std::string("\"") + f.choices[std::size_t(i)] + "\"" : format_number(v);
      }
      case FieldType::number:
      case FieldType::colour:
      case FieldType::vector: return shortest(v);
      default: return format_number(v);
    }
  };
  if (f.components == 1) return one(0);
  std::string s = "[";
  for (int c = 0; c < f.components; ++c) s += (c ? ", " : "") + one(c);
  return s + "]";
}

template <class T>
Status check_all(std::span<const FieldSpec<T>> fields, const T& object, const FieldPath& path) {
  for (const FieldSpec<T>& f : fields) {
    for (int c = 0; c < f.components; ++c) {
      const double v = f.get(object, c);
      if (check_value(f, v, std::string()).ok()) continue;  // (no message made for a good value)
      if (f.type == FieldType::colour) {
        const std::string p = path(f.name);
        return {ErrorCode::invalid_argument, p, p + ": expected finite colour components " + colour_bound(f) + ", found " + format_value(f, object)};
      }
      return check_value(f, v, f.components > 1 && f.type == FieldType::texture ? path(f.name) + "[" + std::to_string(c) + "]" : path(f.name));
    }
  }
  return {};
}

// Swaps `object` into `list[index]` if it passes `alone` and the scene passes with it; swaps it
// back otherwise.
template <class T, class Check>
Status replace(Scene& scene, std::vector<T>& list, std::size_t index, T& object, const Check& alone) {
  if (index >= list.size()) return {ErrorCode::invalid_argument, "index", "index: " + std::to_string(index) + " is out of range"};
  FACET_TRY(alone(object, index));
  std::swap(list[index], object);
  Status st = validate_scene(scene);
  if (!st.ok()) std::swap(list[index], object);
  return st;
}

}  // namespace field_table


const char* to_string(FieldType type) noexcept {
  switch (type) {
    case FieldType::number: return "number";
    case FieldType::integer: return "integer";
    case FieldType::boolean: return "boolean";
    case FieldType::choice: return "choice";
    case FieldType::colour: return "colour";
    case FieldType::vector: return "vector";
    case FieldType::texture: return "texture";
  }
  return "unknown";
}

std::span<const MaterialField> material_fields() noexcept { return field_table::kMaterialFields; }
std::span<const LightField> light_fields() noexcept { return field_table::kLightFields; }

const MaterialField* find_material_field(std::string_view name) noexcept {
  for (const MaterialField& f : field_table::kMaterialFields)
    if (name == f.name) return &f;
  return nullptr;
}
const LightField* find_light_field(std::string_view name) noexcept {
  for (const LightField& f : field_table::kLightFields)
    if (name == f.name) return &f;
  return nullptr;
}

Status replace_material(Scene& scene, std::size_t index, Material& material) {
  return field_table::replace(scene, scene.materials, index, material, validate_material);
}
Status replace_light(Scene& scene, std::size_t index, Light& light) {
  return field_table::replace(scene, scene.lights, index, light, validate_light);
}

Status check_field_value(const MaterialField& f, double v, const std::string& path) { return field_table::check_value(f, v, path); }
Status check_field_value(const LightField& f, double v, const std::string& path) { return field_table::check_value(f, v, path); }
Status set_field(const MaterialField& f, Material& m, std::span<const double> v, const std::string& path) { return field_table::set_values(f, m, v, path); }
Status set_field(const LightField& f, Light& l, std::span<const double> v, const std::string& path) { return field_table::set_values(f, l, v, path); }
bool is_default(const MaterialField& f, const Material& m) noexcept { return field_table::equals_default(f, m); }
bool is_default(const LightField& f, const Light& l) noexcept { return field_table::equals_default(f, l); }
std::string format_field(const MaterialField& f, const Material& m) { return field_table::format_value(f, m); }
std::string format_field(const LightField& f, const Light& l) { return field_table::format_value(f, l); }
std::string describe_range(const MaterialField& f) { return field_table::range_words(f); }
std::string describe_range(const LightField& f) { return field_table::range_words(f); }

Status check_material_fields(const Material& material, const FieldPath& path) {
  return field_table::check_all(material_fields(), material, path);
}
Status check_light_fields(const Light& light, const FieldPath& path) { return field_table::check_all(light_fields(), light, path); }

}  // namespace facet
