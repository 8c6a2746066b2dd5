// Scene validation, camera matrices and the built-in default scene.
#include <cmath>
#include <new>
#include <numbers>
#include <string>

#include "facet/scene.hpp"
#include "facet/lightmap.hpp"
#include "common/format.hpp"
#include "common/look_at.hpp"
#include "common/try.hpp"
#include "scene/order.hpp"
#include "scene/validate.hpp"

namespace facet {

const char* to_string(ErrorCode code) noexcept {
  switch (code) {
    case ErrorCode::ok: return "ok";
    case ErrorCode::invalid_argument: return "invalid argument";
    case ErrorCode::parse_error: return "parse error";
    case ErrorCode::io_error: return "i/o error";
    case ErrorCode::unsupported: return "unsupported";
    case ErrorCode::out_of_memory: return "out of memory";
    case ErrorCode::cancelled: return "cancelled";
  }
  return "unknown error";
}

const char* to_string(TextureMode mode) noexcept {
  switch (mode) {
    case TextureMode::modulate: return "modulate";
    case TextureMode::replace: return "replace";
    case TextureMode::decal: return "decal";
    case TextureMode::add: return "add";
  }
  return "unknown";
}

const char* to_string(LightmapMode mode) noexcept {
  switch (mode) {
    case LightmapMode::diffuse: return "diffuse";
    case LightmapMode::replace: return "replace";
  }
  return "unknown";
}

const char* to_string(BlendMode mode) noexcept {
  switch (mode) {
    case BlendMode::opaque: return "opaque";
    case BlendMode::alpha: return "alpha";
    case BlendMode::premultiplied: return "premultiplied";
    case BlendMode::add: return "add";
    case BlendMode::multiply: return "multiply";
    case BlendMode::subtract: return "subtract";
  }
  return "unknown";
}

const char* to_string(EnvironmentMode mode) noexcept {
  switch (mode) {
    case EnvironmentMode::none: return "none";
    case EnvironmentMode::sphere: return "sphere";
    case EnvironmentMode::cube: return "cube";
    case EnvironmentMode::normal: return "normal";
  }
  return "unknown";
}

const char* to_string(EnvironmentBlend mode) noexcept {
  switch (mode) {
    case EnvironmentBlend::add: return "add";
    case EnvironmentBlend::modulate: return "modulate";
    case EnvironmentBlend::mix: return "mix";
  }
  return "unknown";
}

const char* to_string(SpecularModel model) noexcept {
  switch (model) {
    case SpecularModel::blinn: return "blinn";
    case SpecularModel::phong: return "phong";
  }
  return "unknown";
}

const char* to_string(DepthWrite mode) noexcept {
  switch (mode) {
    case DepthWrite::automatic: return "auto";
    case DepthWrite::on: return "on";
    case DepthWrite::off: return "off";
  }
  return "unknown";
}

const char* to_string(TransparentOrder order) noexcept {
  switch (order) {
    case TransparentOrder::submission: return "submission";
    case TransparentOrder::back_to_front: return "back_to_front";
  }
  return "unknown";
}

const char* to_string(ShadowMethod method) noexcept {
  switch (method) {
    case ShadowMethod::none: return "none";
    case ShadowMethod::map: return "map";
    case ShadowMethod::volume: return "volume";
    case ShadowMethod::raycast: return "raycast";
  }
  return "unknown";
}

const char* to_string(ShadowFilter filter) noexcept {
  switch (filter) {
    case ShadowFilter::none: return "none";
    case ShadowFilter::pcf2x2: return "pcf2x2";
    case ShadowFilter::pcf3x3: return "pcf3x3";
    case ShadowFilter::pcf5x5: return "pcf5x5";
  }
  return "unknown";
}

const char* to_string(MaterialModel model) noexcept {
  switch (model) {
    case MaterialModel::gl: return "gl";
    case MaterialModel::pbr: return "pbr";
  }
  return "?";
}

const char* to_string(FogMode mode) noexcept {
  switch (mode) {
    case FogMode::none: return "none";
    case FogMode::linear: return "linear";
    case FogMode::exp: return "exp";
    case FogMode::exp2: return "exp2";
  }
  return "unknown";
}

namespace {

constexpr float kDegToRad = std::numbers::pi_v<float> / 180.0f;

bool finite(const Vec3& v) { return v.allFinite(); }

std::string describe(const Vec3& v) {
  return "[" + format_number(v.x()) + ", " + format_number(v.y()) + ", " + format_number(v.z()) + "]";
}

using Field = FieldPath;

Status invalid(const std::string& field, const std::string& what) {
  return {ErrorCode::invalid_argument, field, field + ": " + what};
}

Status check_color(const Color3& c, const Field& f, const char* member) {
  if (!finite(c) || (c.array() < 0.0f).any()) {
    return invalid(f(member), "expected finite colour components >= 0, found " + describe(c));
  }
  return {};
}

Status check_range(float value, float lo, float hi, const Field& f, const char* member) {
  if (!(value >= lo && value <= hi)) {
    return invalid(f(member), "expected a number in [" + format_number(lo) + ", " + format_number(hi) +
                                  "], found " + format_number(value));
  }
  return {};
}

Status check_direction(const Vec3& d, const Field& f, const char* member) {
  if (!finite(d) || !(d.squaredNorm() > 1e-24f)) {
    return invalid(f(member), "expected a finite non-zero direction, found " + describe(d));
  }
  return {};
}

Status validate_material(const Material& m, const Field& f) {
  FACET_TRY(check_material_fields(m, f));  // each field's type and range (facet/fields.hpp)
  if (m.uv_scale.x() == 0.0f || m.uv_scale.y() == 0.0f) {
    return invalid(f("uv_scale"), "expected two finite non-zero numbers, found [" + format_number(m.uv_scale.x()) + ", " +
                                      format_number(m.uv_scale.y()) + "]");
  }
  const Environment& e = m.environment;
  if (m.model == MaterialModel::pbr && e.mode != EnvironmentMode::none) {
    return invalid(f("environment.mode"), "a pbr material is lit by the scene's environment_light, not by GL's environment mapping");
  }
  if (e.dynamic && e.mode != EnvironmentMode::cube) {
    return invalid(f("environment.dynamic"), "only a cube environment is rendered from the scene");
  }
  const int needed = e.mode == EnvironmentMode::none || e.dynamic ? 0 : e.mode == EnvironmentMode::cube ? 6 : 1;
  for (int k = 0; k < 6; ++k) {  // (messages made only on failure: validation runs every frame)
    auto member = [&] { return f(("environment.maps[" + std::to_string(k) + "]").c_str()); };
    if (k < needed && e.maps[k] < 0) {
      return invalid(member(), std::string("a ") + to_string(e.mode) + " environment needs " +
                                   (needed == 6 ? "six cube faces (+X, -X, +Y, -Y, +Z, -Z)" : "a map") + ", found " +
                                   std::to_string(e.maps[k]));
    }
    if (k >= needed && e.maps[k] != kNoTexture) {
      return invalid(member(), "expected -1 (unused by this mode), found " + std::to_string(e.maps[k]));
    }
  }
  return {};
}

Status validate_light(const Light& l, const Field& f) {
  FACET_TRY(check_light_fields(l, f));  // each field's type and range (facet/fields.hpp)
  if (l.type != LightType::point) FACET_TRY(check_direction(l.direction, f, "direction"));
  if (l.projector.texture != -1 && l.type != LightType::spot) return invalid(f("projector"), "only spot lights project a picture");
  if (l.type == LightType::directional) {
    if (l.range != 0.0f) return invalid(f("range"), "only point and spot lights have a range");
    return {};
  }
  if (l.attenuation_model == AttenuationModel::linear_range) {
    if (!(l.range_max > 0.0f)) return invalid(f("attenuation.max"), "expected a number in (0, 1e+30], found " + format_number(l.range_max));
    FACET_TRY(check_range(l.range_min, 0.0f, l.range_max, f, "attenuation.min"));
  } else if (!(l.constant_attenuation + l.linear_attenuation + l.quadratic_attenuation > 0.0f)) {
    return invalid(f("attenuation"), "at least one attenuation coefficient must be > 0");
  }
  if (l.type != LightType::spot) return {};
  if (l.spot_shape == SpotShape::smooth_cone) FACET_TRY(check_range(l.spot_inner_deg, 0.0f, l.spot_outer_deg, f, "spot.inner_deg"));
  return {};
}

Status check_camera(const Camera& c) {
  const Field f{"camera", 0, false};
  if (!finite(c.eye)) return invalid("camera.eye", "expected finite coordinates, found " + describe(c.eye));
  if (!finite(c.target)) return invalid("camera.target", "expected finite coordinates, found " + describe(c.target));
  FACET_TRY(check_direction(c.up, f, "up"));
  // In double: a camera far from the origin (coordinates of 1e30) has a view vector whose squared
  // length overflows a float.
  const Eigen::Vector3d forward = c.target.cast<double>() - c.eye.cast<double>();
  if (!(forward.squaredNorm() > 1e-24)) return invalid("camera.target", "must differ from camera.eye");
  if (!(forward.normalized().cross(c.up.cast<double>().normalized()).norm() > 1e-6)) {
    return invalid("camera.up", "must not be parallel to the viewing direction");
  }
  FACET_TRY(check_range(c.aspect, 0.0f, 1e6f, f, "aspect"));
  if (c.projection == Projection::orthographic) {
    if (!(c.half_height > 0.0f && c.half_height <= 1e30f)) {
      return invalid("camera.half_height", "expected a number in (0, 1e30], found " + format_number(c.half_height));
    }
    if (!(c.near >= 0.0f && std::isfinite(c.near))) {
      return invalid("camera.near", "expected a finite number >= 0, found " + format_number(c.near));
    }
    // In double: near and far of 1e38 are finite floats whose difference is not.
    if (!(c.far > c.near && std::isfinite(c.far) && std::isfinite(double(c.far) - double(c.near)))) {
      return invalid("camera.far", "expected a finite number > camera.near (an orthographic box has a far side), found " +
                                       format_number(c.far));
    }
    return {};
  }
  if (c.projection != Projection::perspective) return invalid("camera.projection", "unknown projection");
  if (!(c.vertical_fov_deg > 0.0f && c.vertical_fov_deg < 180.0f)) {
    return invalid("camera.fov_deg", "expected a number in (0, 180), found " + format_number(c.vertical_fov_deg));
  }
  if (!(c.near > 0.0f && std::isfinite(c.near))) {
    return invalid("camera.near", "expected a finite number > 0, found " + format_number(c.near));
  }
  if (!(c.far > c.near && (std::isfinite(c.far) || c.far > 0.0f))) {
    return invalid("camera.far", "expected a number > camera.near, or +infinity, found " + format_number(c.far));
  }
  return {};
}

}  // namespace

Status validate_material(const Material& material, std::size_t index) {
  return validate_material(material, Field{"materials", index, true});
}
Status validate_light(const Light& light, std::size_t index) { return validate_light(light, Field{"lights", index, true}); }
Status validate_camera(const Camera& camera) { return check_camera(camera); }
Status validate_global_ambient(const Color3& ambient) {
  return check_color(ambient, Field{"global_ambient", 0, false}, "");
}

Status validate_environment_light(const EnvironmentLight& e) {
  const char* p = "environment_light";  // (no string made unless it fails: validation runs every frame)
  if (e.source != EnvironmentSource::none && e.source != EnvironmentSource::studio && e.source != EnvironmentSource::image) {
    return invalid(std::string(p) + ".source", "unknown source");
  }
  if (!(e.intensity >= 0.0f && e.intensity <= 1e6f)) return invalid(std::string(p) + ".intensity", "expected a number in [0, 1e6], found " + format_number(e.intensity));
  if (!(e.rotation_deg >= -3600.0f && e.rotation_deg <= 3600.0f)) {
    return invalid(std::string(p) + ".rotation_deg", "expected a number in [-3600, 3600], found " + format_number(e.rotation_deg));
  }
  if (e.source != EnvironmentSource::image) return {};
  if (e.width < 2 || e.height < 1 || e.width > kMaxEnvironmentSide || e.height > kMaxEnvironmentSide || e.width != 2 * e.height) {
    return invalid(p, "an equirectangular picture is twice as wide as high, at most " + std::to_string(kMaxEnvironmentSide) +
                          " texels a side; found " + std::to_string(e.width) + "x" + std::to_string(e.height));
  }
  const std::size_t n = std::size_t(e.width) * std::size_t(e.height) * 3;
  if (e.rgb.size() != n) {
    return invalid(std::string(p) + ".rgb", "expected " + std::to_string(n) + " floats (3 a texel), found " + std::to_string(e.rgb.size()));
  }
  return {};  // (the texels' values are checked when the picture is prepared: validation runs every frame)
}

Status validate_fog(const Fog& fog) {
  const Field f{"fog", 0, false};
  if (static_cast<unsigned>(fog.mode) > static_cast<unsigned>(FogMode::exp2)) return invalid(f("mode"), "unknown fog mode");
  FACET_TRY(check_color(fog.color, f, "color"));
  const float big = 3.0e38f;
  FACET_TRY(check_range(fog.start, -big, big, f, "start"));
  FACET_TRY(check_range(fog.end, fog.start, big, f, "end"));
  FACET_TRY(check_range(fog.density, 0.0f, big, f, "density"));
  return {};
}

Status check_lightmap_object(const Scene& scene, std::size_t object) {
  if (object >= scene.objects.size()) return invalid("object", "out of range");
  const Instance& inst = scene.objects[object];
  if (inst.mesh >= scene.meshes.size()) return invalid(Field{"objects", object, true}("mesh"), "out of range");
  const Mesh& mesh = scene.meshes[inst.mesh].mesh;
  const std::string field = Field{"objects", object, true}("lightmap");
  if (!mesh.colors.empty()) {
    return invalid(field, "a lightmapped object cannot have vertex colours (meshes[" + std::to_string(inst.mesh) + "] has them)");
  }
  auto refuse = [&](const Material& m, const std::string& name) -> Status {
    if (m.model == MaterialModel::pbr) return invalid(field, "material " + name + " is a pbr material, which facet does not lightmap");
    if (m.environment.mode != EnvironmentMode::none || needs_tangents(m)) {
      return invalid(field, "material " + name + " has an environment, normal or bump map, which a lightmapped object cannot have");
    }
    if (m.diffuse_texture != kNoTexture && m.texture_mode != TextureMode::modulate) {
      return invalid(field, "material " + name + " uses the texture environment '" + std::string(to_string(m.texture_mode)) +
                                "'; a lightmapped object takes 'modulate' only");
    }
    return {};
  };
  if (inst.mesh_materials) {
    for (const MaterialGroup& g : mesh.groups) {
      const std::int64_t m = find_material(scene, g.material);
      if (m < 0) continue;  // validate_scene names it
      FACET_TRY(refuse(scene.materials[static_cast<std::size_t>(m)], quote(g.material, 40)));
    }
    return {};
  }
  if (inst.material >= scene.materials.size()) return {};  // validate_scene names it
  return refuse(scene.materials[inst.material], "materials[" + std::to_string(inst.material) + "]");
}

Status validate_lighting_inputs(const Scene& scene) {
  FACET_TRY(validate_global_ambient(scene.global_ambient));
  FACET_TRY(validate_fog(scene.fog));
  FACET_TRY(check_camera(scene.camera));
  FACET_TRY(validate_display(scene.display));
  FACET_TRY(validate_environment_light(scene.environment_light));
  if (scene.background == Background::environment && scene.environment_light.source == EnvironmentSource::none) {
    return {ErrorCode::invalid_argument, "background",
            "background: \"environment\" draws the surroundings, and environment_light.source is none (a picture or the studio)"};
  }
  if (scene.background != Background::colour && scene.background != Background::environment) {
    return {ErrorCode::invalid_argument, "background", "background: expected colour or environment"};
  }
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    const Field f{"materials", i, true};
    FACET_TRY(validate_material(m, f));
    for (const auto& [index, member] : {std::pair{m.diffuse_texture, "diffuse_texture"}, std::pair{m.emissive_texture, "emissive_texture"},
                                        std::pair{m.normal_texture, "normal_texture"}, std::pair{m.occlusion_texture, "occlusion_texture"},
                                        std::pair{m.bump_texture, "bump_texture"},
                                        std::pair{m.metallic_roughness_texture, "metallic_roughness_texture"}}) {
      if (index != kNoTexture && static_cast<std::size_t>(index) >= scene.textures.size()) {
        return invalid(f(member), "texture index " + std::to_string(index) + " is out of range (" +
                                      std::to_string(scene.textures.size()) + " textures)");
      }
    }
    for (int k = 0; k < 6; ++k) {
      const std::int32_t index = m.environment.maps[k];
      if (index == kNoTexture) continue;
      auto member = [&] { return f(("environment.maps[" + std::to_string(k) + "]").c_str()); };
      if (static_cast<std::size_t>(index) >= scene.textures.size()) {
        return invalid(member(), "texture index " + std::to_string(index) + " is out of range (" +
                                              std::to_string(scene.textures.size()) + " textures)");
      }
      if (m.environment.mode != EnvironmentMode::cube) continue;
      const Texture& face = scene.textures[static_cast<std::size_t>(index)];
      const Texture& first = scene.textures[static_cast<std::size_t>(m.environment.maps[0])];
      if (face.width() != face.height() || face.width() != first.width()) {
        return invalid(member(), "cube faces are square and the same size: face " + std::to_string(k) + " is " +
                                              std::to_string(face.width()) + "x" + std::to_string(face.height()) +
                                              ", face 0 " + std::to_string(first.width()) + "x" +
                                              std::to_string(first.height()));
      }
    }
  }
  int shadowed = 0, projectors = 0;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    FACET_TRY(validate_light(scene.lights[i], Field{"lights", i, true}));
    const Projector& pr = scene.lights[i].projector;
    if (pr.texture != -1 && static_cast<std::size_t>(pr.texture) >= scene.textures.size()) {
      return invalid(Field{"lights", i, true}("projector.texture"), "texture index " + std::to_string(pr.texture) +
                                                                        " is out of range (" + std::to_string(scene.textures.size()) + " textures)");
    }
    if (scene.lights[i].enabled && pr.texture != -1 && ++projectors > kMaxProjectors) {
      return invalid(Field{"lights", i, true}("projector"),
                     "at most " + std::to_string(kMaxProjectors) + " enabled lights can project a picture");
    }
    if (scene.lights[i].enabled && scene.lights[i].shadow.method != ShadowMethod::none && ++shadowed > kMaxShadowedLights) {
      return invalid(Field{"lights", i, true}("shadow"),
                     "at most " + std::to_string(kMaxShadowedLights) + " enabled lights can cast shadows");
    }
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Instance& inst = scene.objects[i];
    const Field f{"objects", i, true};
    if (inst.mesh >= scene.meshes.size()) {
      return invalid(f("mesh"), "mesh index " + std::to_string(inst.mesh) + " is out of range (" +
                                    std::to_string(scene.meshes.size()) + " meshes)");
    }
    if (inst.material >= scene.materials.size()) {
      return invalid(f("material"), "material index " + std::to_string(inst.material) + " is out of range (" +
                                        std::to_string(scene.materials.size()) + " materials)");
    }
    const Eigen::Matrix3f linear = inst.model.topLeftCorner<3, 3>();
    const float det = linear.determinant();
    if (!inst.model.allFinite() || !(std::abs(det) > 1e-30f) || !std::isfinite(1.0f / det)) {
      return invalid(f("transform"), "expected a finite invertible transform");
    }
    if (inst.model.row(3) != Eigen::RowVector4f(0, 0, 0, 1)) {
      return invalid(f("transform"), "expected an affine transform (last row 0 0 0 1)");
    }
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    if (inst.mesh_materials) {
      if (mesh.groups.empty()) {
        return invalid(f("mesh_materials"), "meshes[" + std::to_string(inst.mesh) + "] has no material groups");
      }
      for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
        const std::int64_t m = find_material(scene, mesh.groups[g].material);
        if (m < 0) {
          return invalid(f("mesh_materials"), "meshes[" + std::to_string(inst.mesh) + "].groups[" + std::to_string(g) +
                                                  "] names material " + quote(mesh.groups[g].material, 40) +
                                                  ", which the scene does not define");
        }
        if (uses_textures(scene.materials[static_cast<std::size_t>(m)]) && mesh.uvs.size() != mesh.positions.size()) {
          return invalid(f("mesh_materials"), "material " + quote(mesh.groups[g].material, 40) + " is textured but meshes[" +
                                                  std::to_string(inst.mesh) + "] has no texture coordinates (uvs)");
        }
        if (needs_tangents(scene.materials[static_cast<std::size_t>(m)]) && mesh.tangents.size() != mesh.positions.size()) {
          return invalid(f("mesh_materials"), "material " + quote(mesh.groups[g].material, 40) + " has a normal or bump map but meshes[" +
                                                  std::to_string(inst.mesh) + "] has no tangents (generate_tangents makes them)");
        }
      }
    }
    const Material& material = scene.materials[inst.material];
    if (uses_textures(material) && !inst.mesh_materials && mesh.uvs.size() != mesh.positions.size()) {
      return invalid(f("material"), "materials[" + std::to_string(inst.material) + "] is textured but meshes[" +
                                        std::to_string(inst.mesh) + "] has no texture coordinates (uvs)");
    }
    if (needs_tangents(material) && !inst.mesh_materials && mesh.tangents.size() != mesh.positions.size()) {
      return invalid(f("material"), "materials[" + std::to_string(inst.material) + "] has a normal or bump map but meshes[" +
                                        std::to_string(inst.mesh) + "] has no tangents (generate_tangents makes them)");
    }
    if (inst.lightmap != -1) {
      if (inst.lightmap < 0 || static_cast<std::size_t>(inst.lightmap) >= scene.textures.size()) {
        return invalid(f("lightmap"), "texture index " + std::to_string(inst.lightmap) + " is out of range (" +
                                          std::to_string(scene.textures.size()) + " textures)");
      }
      if (!(std::isfinite(inst.lightmap_scale) && inst.lightmap_scale > 0.0f)) {
        return invalid(f("lightmap_scale"), "expected a finite number > 0, found " + format_number(inst.lightmap_scale));
      }
      if (mesh.lightmap_uvs.size() != mesh.positions.size() || mesh.positions.empty()) {
        return invalid(f("lightmap"), "meshes[" + std::to_string(inst.mesh) +
                                          "] has no lightmap coordinates (lightmap_uvs; unwrap_lightmap makes them)");
      }
      FACET_TRY(check_lightmap_object(scene, i));
    }
    if (mesh.normals.size() != mesh.positions.size()) {
      return invalid(Field{"meshes", inst.mesh, true}("normals"),
                     "expected one normal per position (" + std::to_string(mesh.positions.size()) + "), found " +
                         std::to_string(mesh.normals.size()));
    }
  }
  return {};
}

Status generate_missing_tangents(Scene& scene) {
  std::vector<char> wanted(scene.meshes.size(), 0);
  auto normal_mapped = [&](std::int64_t m) {
    return m >= 0 && static_cast<std::size_t>(m) < scene.materials.size() &&
           needs_tangents(scene.materials[static_cast<std::size_t>(m)]);
  };
  for (const Instance& inst : scene.objects) {
    if (inst.mesh >= scene.meshes.size()) continue;  // validation reports it
    bool needs = !inst.mesh_materials && normal_mapped(inst.material);
    if (inst.mesh_materials) {
      for (const MaterialGroup& g : scene.meshes[inst.mesh].mesh.groups) needs = needs || normal_mapped(find_material(scene, g.material));
    }
    wanted[inst.mesh] = wanted[inst.mesh] || needs;
  }
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    Mesh& mesh = scene.meshes[i].mesh;
    if (!wanted[i] || !mesh.tangents.empty() || mesh.uvs.size() != mesh.positions.size()) continue;
    if (Status s = generate_tangents(mesh); !s.ok()) {
      return {s.code(), "meshes[" + std::to_string(i) + "].tangents", "meshes[" + std::to_string(i) + "]: " + s.message()};
    }
  }
  return {};
}

std::int64_t find_material(const Scene& scene, const std::string& name) noexcept {
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (scene.materials[i].name == name) return static_cast<std::int64_t>(i);
  }
  return -1;
}

bool is_transparent(const Scene& scene, const Instance& object) {
  auto blends = [&](std::int64_t m) {
    return m >= 0 && static_cast<std::size_t>(m) < scene.materials.size() &&
           scene.materials[static_cast<std::size_t>(m)].blend != BlendMode::opaque;
  };
  if (!object.mesh_materials || object.mesh >= scene.meshes.size()) return blends(object.material);
  for (const MaterialGroup& g : scene.meshes[object.mesh].mesh.groups) {
    if (blends(find_material(scene, g.material))) return true;
  }
  return false;
}

std::vector<std::size_t> draw_order(const Scene& scene) {
  std::vector<std::size_t> order(scene.objects.size());
  for (std::size_t o = 0; o < order.size(); ++o) order[o] = o;
  if (scene.transparent_order != TransparentOrder::back_to_front) return order;
  std::vector<scene_order::ObjectKey> keys;
  if (scene_order::order_objects(scene, look_at_d(scene.camera), keys)) {
    for (std::size_t o = 0; o < order.size(); ++o) order[o] = keys[o].object;
  }
  return order;
}

Status validate_scene(const Scene& scene) {
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    FACET_TRY(validate_texture(scene.textures[i], "textures[" + std::to_string(i) + "]"));
  }
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    const Mesh& mesh = scene.meshes[i].mesh;
    if (mesh_is_valid(mesh)) continue;  // the common case, checked without building a field name
    FACET_TRY(validate_mesh(mesh, Field{"meshes", i, true}("")));
  }
  return validate_lighting_inputs(scene);
}

Mat4 view_matrix(const Camera& camera) { return look_at_d(camera).cast<float>(); }

const char* to_string(Projection projection) noexcept {
  switch (projection) {
    case Projection::perspective: return "perspective";
    case Projection::orthographic: return "orthographic";
  }
  return "unknown";
}

Mat4 projection_matrix(const Camera& camera, float aspect) {
  if (camera.projection == Projection::orthographic) {
    // glOrtho(-w, w, -h, h, near, far): clip w stays 1, window depth is linear in eye depth.
    // In double: a box of 1e30 units has a width whose reciprocal is below float's normal range
    // only after the division.
    const double h = camera.half_height, w = h * double(aspect), n = camera.near, f = camera.far;
    Mat4 m = Mat4::Zero();
    m(0, 0) = static_cast<float>(1.0 / w);
    m(1, 1) = static_cast<float>(1.0 / h);
    m(2, 2) = static_cast<float>(-2.0 / (f - n));
    m(2, 3) = static_cast<float>(-(f + n) / (f - n));
    m(3, 3) = 1.0f;
    return m;
  }
  const float t = 1.0f / std::tan(0.5f * camera.vertical_fov_deg * kDegToRad);
  const float n = camera.near, f = camera.far;
  Mat4 m = Mat4::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  // In double: f n overflows a float once near and far pass about 1e19 (a model of 1e30 units).
  // An infinite far plane is the limit f -> infinity: clip z = -z_eye - 2n, never beyond w.
  const double nd = n, fd = f;
  m(2, 2) = std::isinf(fd) ? -1.0f : static_cast<float>((fd + nd) / (nd - fd));
  m(2, 3) = std::isinf(fd) ? static_cast<float>(-2.0 * nd) : static_cast<float>(2.0 * fd * nd / (nd - fd));
  m(3, 2) = -1.0f;
  return m;
}

namespace {

Mat4 translate_scale(const Vec3& t, float s) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() *= s;
  m.block<3, 1>(0, 3) = t;
  return m;
}

Material make_material(const char* name, Color3 diffuse, Color3 specular, float shininess) {
  Material m;
  m.name = name;
  m.ambient = diffuse;
  m.diffuse = diffuse;
  m.specular = specular;
  m.shininess = shininess;
  return m;
}

}  // namespace

Scene make_default_scene() {
  Scene scene;
  scene.meshes.push_back({"sphere", make_uv_sphere(1.0f, 64, 32)});
  scene.meshes.push_back({"cube", make_cube(1.0f, 8)});
  scene.meshes.push_back({"torus", make_torus(0.7f, 0.25f, 64, 24)});
  scene.meshes.push_back({"ground", make_plane(12.0f, 12.0f, 48)});

  scene.materials.push_back(make_material("matte_red", {0.75f, 0.18f, 0.15f}, {0.3f, 0.3f, 0.3f}, 8.0f));
  scene.materials.push_back(make_material("satin_green", {0.2f, 0.6f, 0.25f}, {0.6f, 0.6f, 0.6f}, 64.0f));
  scene.materials.push_back(make_material("glossy_blue", {0.15f, 0.3f, 0.8f}, {1.0f, 1.0f, 1.0f}, 512.0f));
  scene.materials.push_back(make_material("gold", {0.8f, 0.6f, 0.2f}, {0.9f, 0.8f, 0.5f}, 32.0f));
  scene.materials.push_back(make_material("ground", {0.55f, 0.55f, 0.5f}, {0.0f, 0.0f, 0.0f}, 0.0f));

  scene.objects.push_back({0, 0, translate_scale({-2.2f, 1.0f, 0.0f}, 1.0f)});
  scene.objects.push_back({0, 1, translate_scale({0.0f, 1.0f, -0.6f}, 1.0f)});
  scene.objects.push_back({0, 2, translate_scale({2.2f, 1.0f, 0.0f}, 1.0f)});
  Mat4 cube = translate_scale({-0.9f, 0.5f, 1.7f}, 1.0f);
  cube.topLeftCorner<3, 3>() = Eigen::AngleAxisf(0.6f, Vec3::UnitY()).toRotationMatrix();
  scene.objects.push_back({1, 3, cube});
  Mat4 torus = translate_scale({1.3f, 0.35f, 1.9f}, 1.0f);
  torus.topLeftCorner<3, 3>() = Eigen::AngleAxisf(-0.35f, Vec3::UnitX()).toRotationMatrix();
  scene.objects.push_back({2, 3, torus});
  scene.objects.push_back({3, 4, Mat4::Identity()});

  // Surfaces: a checkered stone texture on the ground (times its light, GL_MODULATE), and the
  // glossy blue sphere made of tinted glass (alpha blended, drawn after the opaque objects).
  {
    constexpr int kSide = 64, kCell = 8;
    std::vector<std::uint8_t> texels(4 * kSide * kSide);
    for (int j = 0; j < kSide; ++j) {
      for (int i = 0; i < kSide; ++i) {
        const bool light = ((i / kCell) + (j / kCell)) % 2 == 1;
        std::uint8_t* t = &texels[static_cast<std::size_t>(4 * (j * kSide + i))];
        t[0] = light ? 235 : 120, t[1] = light ? 225 : 110, t[2] = light ? 200 : 95, t[3] = 255;
      }
    }
    Result<Texture> stone = make_texture("stone", kSide, kSide, texels);
    if (!stone) throw std::bad_alloc();  // a valid 64 x 64 texture fails only for memory
    scene.textures.push_back(std::move(*stone));
    Material& ground = scene.materials[4];
    ground.diffuse_texture = 0;
    ground.uv_scale = Vec2(6.0f, 6.0f);
    Material& glass = scene.materials[2];
    glass.blend = BlendMode::alpha;
    glass.alpha = 0.55f;
    // Blended objects go last: facet draws in submission order and does not sort them.
    std::swap(scene.objects[2], scene.objects.back());
  }

  Light sun;
  sun.name = "sun";
  sun.type = LightType::directional;
  sun.direction = Vec3(-0.4f, -1.0f, -0.5f);
  sun.diffuse = {0.55f, 0.55f, 0.5f};
  sun.specular = {0.5f, 0.5f, 0.5f};
  scene.lights.push_back(sun);

  Light lamp;
  lamp.name = "lamp";
  lamp.type = LightType::point;
  lamp.position = {2.5f, 3.0f, 3.0f};
  lamp.diffuse = {1.0f, 0.85f, 0.6f};
  lamp.specular = {1.0f, 0.9f, 0.7f};
  lamp.ambient = {0.05f, 0.05f, 0.05f};
  lamp.linear_attenuation = 0.05f;
  lamp.quadratic_attenuation = 0.02f;
  lamp.range = 15.0f;
  scene.lights.push_back(lamp);

  Light spot;
  spot.name = "gl_spot";
  spot.type = LightType::spot;
  spot.position = {-3.0f, 5.0f, 2.0f};
  spot.direction = Vec3(-2.2f, 0.0f, 0.0f) - spot.position;
  spot.diffuse = {0.3f, 0.4f, 1.0f};
  spot.specular = {0.6f, 0.6f, 1.0f};
  spot.spot_cutoff_deg = 25.0f;
  spot.spot_exponent = 10.0f;
  scene.lights.push_back(spot);

  Light cone;
  cone.name = "stage_spot";
  cone.type = LightType::spot;
  cone.spot_shape = SpotShape::smooth_cone;
  cone.position = {1.0f, 6.0f, -3.0f};
  cone.direction = Vec3(0.5f, 0.0f, 0.5f) - cone.position;
  cone.diffuse = {1.0f, 0.5f, 0.8f};
  cone.specular = {1.0f, 0.6f, 0.9f};
  cone.spot_inner_deg = 12.0f;
  cone.spot_outer_deg = 24.0f;
  scene.lights.push_back(cone);

  scene.global_ambient = {0.12f, 0.12f, 0.14f};
  scene.camera.eye = {0.0f, 3.2f, 8.5f};
  scene.camera.target = {0.0f, 0.8f, 0.0f};
  scene.camera.vertical_fov_deg = 40.0f;
  return scene;
}

}  // namespace facet
