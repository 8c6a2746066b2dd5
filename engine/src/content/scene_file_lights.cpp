// The scene file's lights and their shadows (docs/scene-format.md, "lights[i]"): read by the
// scene reader (scene_file.cpp) through the same JsonFields, so that messages name the line.
#include "content/scene_file_lights.hpp"

#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "common/try.hpp"

namespace facet::scene_json {

Status read_light(const JsonFields& f, const json& j, const std::string& p, const Scene& scene, Light& l) {
  // The light's own fields by the field table (facet/fields.hpp); its nested objects (attenuation,
  // spot, shadow, projector) by the rules between their fields, below.
  std::vector<std::string_view> keys = {"name", "attenuation", "spot", "shadow", "projector"};
  for (const LightField& field : light_fields())
    if (!std::strchr(field.name, '.')) keys.push_back(field.name);
  FACET_TRY(f.expect_object(j, p, keys));
  FACET_TRY(f.opt_string(j, p, "name", l.name));
  if (!j.contains("type")) return f.invalid(child(p, "type"), "missing: \"directional\", \"point\" or \"spot\"");
  for (const LightField& field : light_fields()) {
    if (std::strchr(field.name, '.')) continue;
    FACET_TRY(f.opt_field(j, p, field.name, field, scene.textures, l));
    if (std::string_view(field.name) == "type") {  // (first: the rules below need it)
      if (l.type == LightType::point && j.contains("direction")) return f.invalid(child(p, "direction"), "a point light has no direction");
      if (l.type == LightType::directional && j.contains("position")) {
        return f.invalid(child(p, "position"), "a directional light has no position (give its \"direction\")");
      }
    }
  }
  if (j.contains("attenuation")) {
    if (l.type == LightType::directional) return f.invalid(child(p, "attenuation"), "a directional light has no attenuation");
    const json& a = j["attenuation"];
    const std::string ap = child(p, "attenuation");
    FACET_TRY(f.expect_object(a, ap, {"model", "constant", "linear", "quadratic", "min", "max"}));
    std::string model = "gl";
    if (a.contains("model")) FACET_TRY(f.read_enum(a["model"], child(ap, "model"), {"gl", "linear_range"}, model));
    if (model == "linear_range") {
      l.attenuation_model = AttenuationModel::linear_range;
      for (const char* k : {"constant", "linear", "quadratic"}) {
        if (a.contains(k)) return f.invalid(child(ap, k), "the linear_range model takes \"min\" and \"max\", not GL's coefficients");
      }
      if (!a.contains("max")) return f.invalid(child(ap, "max"), "missing: the linear_range model needs \"max\" (> 0)");
      FACET_TRY(f.opt_number(a, ap, "min", l.range_min));
      FACET_TRY(f.opt_number(a, ap, "max", l.range_max));
    } else {
      for (const char* k : {"min", "max"}) {
        if (a.contains(k)) return f.invalid(child(ap, k), "only the linear_range model has \"min\" and \"max\"");
      }
      FACET_TRY(f.opt_number(a, ap, "constant", l.constant_attenuation));
      FACET_TRY(f.opt_number(a, ap, "linear", l.linear_attenuation));
      FACET_TRY(f.opt_number(a, ap, "quadratic", l.quadratic_attenuation));
    }
  }
  if (j.contains("spot")) {
    const std::string sp = child(p, "spot");
    if (l.type != LightType::spot) return f.invalid(sp, "only spot lights have a \"spot\" cone");
    const json& s = j["spot"];
    FACET_TRY(f.expect_object(s, sp, {"shape", "cutoff_deg", "exponent", "inner_deg", "outer_deg", "falloff"}));
    const bool gl = s.contains("cutoff_deg") || s.contains("exponent");
    const bool smooth = s.contains("inner_deg") || s.contains("outer_deg") || s.contains("falloff");
    if (gl && smooth) {
      return f.invalid(sp, "use either cutoff_deg/exponent (GL cone) or inner_deg/outer_deg/falloff (smooth cone), not both");
    }
    // The shape named, or the one whose keys are given (GL's cone when none are).
    l.spot_shape = smooth ? SpotShape::smooth_cone : SpotShape::cutoff_exponent;
    if (s.contains("shape")) {
      const LightField& shape = *find_light_field("spot.shape");
      FACET_TRY(f.opt_field(s, sp, "shape", shape, scene.textures, l));
      if (l.spot_shape == SpotShape::cutoff_exponent ? smooth : gl) {
        return f.invalid(child(sp, "shape"), std::string("a ") + (smooth ? "smooth cone's keys (inner_deg, outer_deg, falloff)" : "GL cone's keys (cutoff_deg, exponent)") +
                                                  " with \"shape\": \"" + shape.choices[static_cast<std::size_t>(l.spot_shape)] + "\"");
      }
    }
    FACET_TRY(f.opt_number(s, sp, "cutoff_deg", l.spot_cutoff_deg));
    FACET_TRY(f.opt_number(s, sp, "exponent", l.spot_exponent));
    FACET_TRY(f.opt_number(s, sp, "inner_deg", l.spot_inner_deg));
    FACET_TRY(f.opt_number(s, sp, "outer_deg", l.spot_outer_deg));
    FACET_TRY(f.opt_number(s, sp, "falloff", l.spot_falloff));
  }
  if (j.contains("shadow")) FACET_TRY(read_shadow(f, j["shadow"], child(p, "shadow"), l.shadow));
  if (j.contains("projector")) {
    const std::string pp = child(p, "projector");
    if (l.type != LightType::spot) return f.invalid(pp, "only spot lights project a picture");
    const json& pj = j["projector"];
    FACET_TRY(f.expect_object(pj, pp, {"texture", "mode"}));
    if (!pj.contains("texture")) return f.invalid(child(pp, "texture"), "missing: the picture's texture name");
    FACET_TRY(f.opt_texture(pj, pp, "texture", scene.textures, l.projector.texture));
    if (pj.contains("mode")) {
      std::string mode;
      FACET_TRY(f.read_enum(pj["mode"], child(pp, "mode"), {"modulate", "gobo"}, mode));
      l.projector.mode = mode == "gobo" ? ProjectorMode::gobo : ProjectorMode::modulate;
    }
  }
  return {};
}

Status read_shadow(const JsonFields& f, const json& s, const std::string& p, Shadow& shadow) {
  FACET_TRY(f.expect_object(s, p, {"method", "resolution", "filter", "bias"}));
  if (!s.contains("method")) return f.invalid(child(p, "method"), "missing: \"raycast\", \"map\", \"volume\" or \"none\"");
  std::string method;
  FACET_TRY(f.read_enum(s["method"], child(p, "method"), {"none", "map", "volume", "raycast"}, method));
  shadow.method = method == "none"     ? ShadowMethod::none
                  : method == "map"    ? ShadowMethod::map
                  : method == "volume" ? ShadowMethod::volume
                                       : ShadowMethod::raycast;
  FACET_TRY(f.opt_int(s, p, "resolution", 16, 16384, shadow.resolution));
  if (s.contains("filter")) {
    std::string filter;
    FACET_TRY(f.read_enum(s["filter"], child(p, "filter"), {"none", "pcf2x2", "pcf3x3", "pcf5x5"}, filter));
    shadow.filter = filter == "none"     ? ShadowFilter::none
                    : filter == "pcf2x2" ? ShadowFilter::pcf2x2
                    : filter == "pcf3x3" ? ShadowFilter::pcf3x3
                                         : ShadowFilter::pcf5x5;
  }
  if (s.contains("bias")) {
    const json& b = s["bias"];
    const std::string bp = child(p, "bias");
    FACET_TRY(f.expect_object(b, bp, {"constant", "slope", "normal"}));
    FACET_TRY(f.opt_number(b, bp, "constant", shadow.bias.constant));
    FACET_TRY(f.opt_number(b, bp, "slope", shadow.bias.slope));
    FACET_TRY(f.opt_number(b, bp, "normal", shadow.bias.normal));
  }
  return {};
}

}  // namespace facet::scene_json
