// glTF 2.0 import: materials, textures, cameras and lights (gltf_reader.hpp says how the pieces fit).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/format.hpp"
#include "common/try.hpp"
#include "content/gltf_reader.hpp"
#include "content/import.hpp"

namespace facet::gltf {
namespace {

constexpr int kNearest = 9728, kLinear = 9729, kRepeat = 10497, kClamp = 33071, kMirror = 33648;

TextureFilter sampler_filter(int min, int mag) {
  switch (min) {
    case kNearest: return mag == kLinear ? TextureFilter::bilinear : TextureFilter::nearest;
    case kLinear: return TextureFilter::bilinear;
    default: return TextureFilter::trilinear;  // the mipmapped filters, or none given
  }
}

}  // namespace

std::uint32_t Reader::untextured_twin(std::uint32_t index) {
  if (auto it = untextured_.find(index); it != untextured_.end()) return it->second;
  Material copy = out_.scene.materials[index];
  copy.diffuse_texture = copy.emissive_texture = copy.normal_texture = copy.occlusion_texture = copy.bump_texture =
      copy.metallic_roughness_texture = kNoTexture;
  copy.name += " (untextured)";
  out_.scene.materials.push_back(copy);
  const auto twin = static_cast<std::uint32_t>(out_.scene.materials.size() - 1);
  untextured_[index] = twin;
  return twin;
}

// A textureInfo: the texture, and its KHR_texture_transform. A texture read from another set of
// texture coordinates is drawn without, with a warning.
Status Reader::texture_info(const Json& ti, const std::string& tp, std::int32_t& t, UvTransform& transform,
                            bool& has_transform, TextureEncoding encoding) {
  FACET_TRY(f_.object(ti, tp));
  int index = -1;
  std::uint64_t tex_coord = 0;
  FACET_TRY(f_.index(ti, tp, "index", doc_.count("textures"), index, true));
  FACET_TRY(f_.integer(ti, tp, "texCoord", tex_coord, 0, 1u << 20));
  const Json* ext = nullptr;
  FACET_TRY(f_.object(ti, tp, "extensions", ext));
  has_transform = false;
  if (const Json* tt = ext ? Fields::find(*ext, "KHR_texture_transform") : nullptr) {
    const std::string xp = tp + ".extensions.KHR_texture_transform";
    FACET_TRY(f_.object(*tt, xp));
    double offset[2] = {0, 0}, scale[2] = {1, 1}, rotation = 0;
    const double big = 1e30;
    FACET_TRY(f_.numbers(*tt, xp, "offset", 2, offset, -big, big));
    FACET_TRY(f_.numbers(*tt, xp, "scale", 2, scale, -big, big));
    FACET_TRY(f_.number(*tt, xp, "rotation", rotation, -big, big));
    FACET_TRY(f_.integer(*tt, xp, "texCoord", tex_coord, 0, 1u << 20));
    // T * R * S as the extension defines them: R = [cos sin; -sin cos].
    const double c = std::cos(rotation), s = std::sin(rotation);
    transform.m[0] = c * scale[0];
    transform.m[1] = s * scale[1];
    transform.m[2] = offset[0];
    transform.m[3] = -s * scale[0];
    transform.m[4] = c * scale[1];
    transform.m[5] = offset[1];
    has_transform = !transform.identity();
  }
  if (tex_coord != 0) {
    warn(tp + ": texCoord " + std::to_string(tex_coord) + " is not supported (facet reads TEXCOORD_0 only); drawn without it");
    has_transform = false;
    return {};
  }
  return texture(index, t, encoding);
}

Status Reader::material(int index, MaterialInfo& info) {
  if (auto it = materials_.find(index); it != materials_.end()) {
    info = it->second;
    return {};
  }
  Material mat;
  if (index < 0) {
    // No material: glTF's default (a white rough metal: base colour 1, metallic 1, roughness 1),
    // as three.js draws it; with GL materials facet's default (GL's grey), which the Blinn-Phong
    // mapping of the default metal would draw black (docs/content.md).
    mat = model_default_material();
    if (!options_.gl_materials) {
      mat.model = MaterialModel::pbr;
      mat.base_color = Color3::Ones();
      mat.metallic = mat.roughness = 1.0f;
    }
  } else {
    const Json& g = doc_.item("materials", static_cast<std::size_t>(index));
    const std::string p = Fields::at("materials", static_cast<std::size_t>(index));
    FACET_TRY(f_.string(g, p, "name", mat.name));
    if (mat.name.empty()) mat.name = p;
    const Json* pbr = nullptr;
    FACET_TRY(f_.object(g, p, "pbrMetallicRoughness", pbr));
    static const Json kEmpty = Json::object();
    if (!pbr) pbr = &kEmpty;
    const std::string pp = p + ".pbrMetallicRoughness";
    double bc[4] = {1, 1, 1, 1}, metallic = 1, roughness = 1;
    FACET_TRY(f_.numbers(*pbr, pp, "baseColorFactor", 4, bc, 0.0, 1.0));
    FACET_TRY(f_.number(*pbr, pp, "metallicFactor", metallic, 0.0, 1.0));
    FACET_TRY(f_.number(*pbr, pp, "roughnessFactor", roughness, 0.0, 1.0));
    const Color3 base{float(bc[0]), float(bc[1]), float(bc[2])};
    const PbrMapping map = map_metallic_roughness(base, float(metallic), float(roughness));
    mat.diffuse = map.diffuse;
    mat.ambient = map.diffuse;
    mat.specular = map.specular;
    mat.shininess = map.shininess;
    info.vertex_color_scale = map.diffuse;
    double ef[3] = {0, 0, 0};
    FACET_TRY(f_.numbers(g, p, "emissiveFactor", 3, ef, 0.0, 1.0));
    Color3 emissive{float(ef[0]), float(ef[1]), float(ef[2])};
    const Json* ext = nullptr;
    FACET_TRY(f_.object(g, p, "extensions", ext));
    if (const Json* es = ext ? Fields::find(*ext, "KHR_materials_emissive_strength") : nullptr) {
      const std::string ep = p + ".extensions.KHR_materials_emissive_strength";
      FACET_TRY(f_.object(*es, ep));
      double k = 1.0;
      FACET_TRY(f_.number(*es, ep, "emissiveStrength", k, 0.0, 1e30));
      emissive *= float(k);
    }
    mat.emissive = emissive;
    const bool unlit = ext && Fields::find(*ext, "KHR_materials_unlit");
    if (unlit) {
      // Unlit: the base colour as emission, nothing from lights.
      mat.emissive = base;
      mat.ambient = mat.diffuse = mat.specular = Color3::Zero();
      info.vertex_color_scale = Color3::Zero();
      warn(p + ": KHR_materials_unlit: drawn as emission of the base colour (vertex colours are not applied)");
    } else if (!options_.gl_materials) {
      // The glTF BRDF itself (docs/pbr.md); the GL colours above stay for a host that switches
      // the material to model gl. Vertex colours multiply the base colour in the BRDF.
      mat.model = MaterialModel::pbr;
      mat.base_color = base;
      mat.metallic = float(metallic);
      mat.roughness = float(roughness);
      info.vertex_color_scale = Color3::Ones();
      FACET_TRY(pbr_extensions(ext, p, mat));
    }
    mat.alpha = float(bc[3]);
    std::string alpha_mode = "OPAQUE";
    double cutoff = 0.5;
    FACET_TRY(f_.string(g, p, "alphaMode", alpha_mode));
    FACET_TRY(f_.number(g, p, "alphaCutoff", cutoff, 0.0, 1e30));
    if (alpha_mode == "MASK") {
      mat.alpha_cutoff = float(std::min(cutoff, 1.0));
    } else if (alpha_mode == "BLEND") {
      mat.blend = BlendMode::alpha;
    } else if (alpha_mode == "OPAQUE") {
      mat.alpha = 1.0f;
    } else {
      return f_.error(p + ".alphaMode", "expected \"OPAQUE\", \"MASK\" or \"BLEND\", found " + quote(alpha_mode, 32));
    }
    FACET_TRY(f_.boolean(g, p, "doubleSided", info.double_sided));
    info.uses_alpha = alpha_mode == "MASK" || alpha_mode == "BLEND";
    UvTransform base_transform, emissive_transform;
    bool base_has = false, emissive_has = false;
    if (const Json* bt = Fields::find(*pbr, "baseColorTexture")) {
      std::int32_t t = kNoTexture;
      FACET_TRY(texture_info(*bt, pp + ".baseColorTexture", t, base_transform, base_has, TextureEncoding::srgb));
      if (t != kNoTexture) {
        mat.diffuse_texture = t;
        mat.texture_mode = TextureMode::modulate;
        info.needs_uvs = true;
        info.uv_transform = base_transform;
      }
    }
    // BLEND with alpha 1 everywhere (the factor and every texel of the base colour texture) is
    // drawn opaque: blending with alpha 1 is replacing, and an opaque draw writes depth, so that
    // the object hides its own far side (drawn blended it shows it through, in sawtooth patches).
    if (mat.blend == BlendMode::alpha && mat.alpha == 1.0f) {
      bool opaque = true;
      if (mat.diffuse_texture != kNoTexture) {
        const Texture& t = out_.scene.textures[static_cast<std::size_t>(mat.diffuse_texture)];
        const std::size_t level0 = t.levels.empty() ? 0 : std::size_t(t.levels[0].width) * std::size_t(t.levels[0].height);
        for (std::size_t i = 0; i < level0 && opaque; ++i) opaque = (t.texels[i] >> 24) == 255;
      }
      if (opaque) {
        mat.blend = BlendMode::opaque;
        info.uses_alpha = false;
        warn(p + ".alphaMode: BLEND with alpha 1 everywhere; drawn opaque (the same picture, and depth-tested against itself)");
      }
    }
    const Json* et = Fields::find(g, "emissiveTexture");
    if (unlit) {
      if (et) warn(p + ".emissiveTexture: ignored by KHR_materials_unlit");
    } else {
      // glTF adds the emission after the base colour: not modulated by the base colour texture.
      mat.emission_after_texture = true;
      if (et) {
        std::int32_t t = kNoTexture;
        FACET_TRY(texture_info(*et, p + ".emissiveTexture", t, emissive_transform, emissive_has, TextureEncoding::srgb));
        if (t != kNoTexture) {
          mat.emissive_texture = t;
          if (!info.needs_uvs) info.uv_transform = emissive_transform;
          else if (!(emissive_transform == base_transform)) {
            warn(p + ".emissiveTexture: its KHR_texture_transform differs from the base colour texture's; facet samples "
                     "both at one set of coordinates and uses the base colour texture's transform");
          }
          info.needs_uvs = true;
        }
      }
    }
    // The normal map (tangent space; its `scale`) and the occlusion map (red channel; its
    // `strength` in [0, 1]): linear, read with the base colour's coordinates.
    auto linear_map = [&](const char* what, const char* factor_key, double lo, double hi, std::int32_t& texture,
                          float& factor) -> Status {
      const Json* node = Fields::find(g, what);
      if (!node) return {};
      const std::string np = p + "." + what;
      if (unlit) {
        warn(np + ": ignored by KHR_materials_unlit");
        return {};
      }
      std::int32_t t = kNoTexture;
      UvTransform transform;
      bool has = false;
      FACET_TRY(texture_info(*node, np, t, transform, has, TextureEncoding::linear));
      double value = 1.0;
      FACET_TRY(f_.number(*node, np, factor_key, value, lo, hi));
      if (t == kNoTexture) return {};
      texture = t;
      factor = static_cast<float>(value);
      if (!info.needs_uvs) info.uv_transform = transform;
      else if (!(transform == info.uv_transform)) {
        warn(np + ": its KHR_texture_transform differs from the base colour texture's; facet samples both at one set "
                  "of coordinates and uses the base colour texture's transform");
      }
      info.needs_uvs = true;
      return {};
    };
    FACET_TRY(linear_map("normalTexture", "scale", -1e6, 1e6, mat.normal_texture, mat.normal_scale));
    info.normal_map = mat.normal_texture != kNoTexture;
    FACET_TRY(linear_map("occlusionTexture", "strength", 0.0, 1.0, mat.occlusion_texture, mat.occlusion_strength));
    if (const Json* mr = Fields::find(*pbr, "metallicRoughnessTexture")) {
      const std::string mp = pp + ".metallicRoughnessTexture";
      if (mat.model != MaterialModel::pbr) {
        warn(mp + ": ignored with GL materials (the factors alone are mapped)");
      } else {
        std::int32_t t = kNoTexture;
        UvTransform transform;
        bool has = false;
        FACET_TRY(texture_info(*mr, mp, t, transform, has, TextureEncoding::linear));
        if (t != kNoTexture) {
          mat.metallic_roughness_texture = t;
          if (!info.needs_uvs) info.uv_transform = transform;
          else if (!(transform == info.uv_transform)) {
            warn(mp + ": its KHR_texture_transform differs from the base colour texture's; facet samples both at one set "
                      "of coordinates and uses the base colour texture's transform");
          }
          info.needs_uvs = true;
        }
      }
    }
  }
  out_.scene.materials.push_back(std::move(mat));
  info.index = static_cast<std::uint32_t>(out_.scene.materials.size() - 1);
  materials_[index] = info;
  return {};
}

// KHR_materials_ior (its schema's minimum is 1: a smaller value is warned of and glTF's 1.5 used)
// and KHR_materials_specular's factors; the latter's textures are warned and ignored.
Status Reader::pbr_extensions(const Json* ext, const std::string& p, Material& mat) {
  if (!ext) return {};
  if (const Json* ior = Fields::find(*ext, "KHR_materials_ior")) {
    const std::string ip = p + ".extensions.KHR_materials_ior";
    FACET_TRY(f_.object(*ior, ip));
    double value = 1.5;
    FACET_TRY(f_.number(*ior, ip, "ior", value, 0.0, 10.0));
    if (value < 1.0) {
      warn(ip + ".ior: " + format_number(value) + " is below the extension's minimum of 1; glTF's 1.5 is used");
      value = 1.5;
    }
    mat.ior = float(value);
  }
  if (const Json* sp = Fields::find(*ext, "KHR_materials_specular")) {
    const std::string xp = p + ".extensions.KHR_materials_specular";
    FACET_TRY(f_.object(*sp, xp));
    double weight = 1.0, colour[3] = {1, 1, 1};
    FACET_TRY(f_.number(*sp, xp, "specularFactor", weight, 0.0, 1.0));
    FACET_TRY(f_.numbers(*sp, xp, "specularColorFactor", 3, colour, 0.0, 1e6));
    mat.specular_weight = float(weight);
    mat.specular_color = Color3(float(colour[0]), float(colour[1]), float(colour[2]));
    for (const char* t : {"specularTexture", "specularColorTexture"}) {
      if (Fields::find(*sp, t)) warn(xp + "." + t + ": not supported; ignored (the factor alone applies)");
    }
  }
  return {};
}

Status Reader::texture(int index, std::int32_t& out, TextureEncoding encoding) {
  const Json& t = doc_.item("textures", static_cast<std::size_t>(index));
  const std::string p = Fields::at("textures", static_cast<std::size_t>(index));
  int source = -1, sampler = -1;
  FACET_TRY(f_.index(t, p, "source", doc_.count("images"), source));
  FACET_TRY(f_.index(t, p, "sampler", doc_.count("samplers"), sampler));
  if (source < 0) {
    warn(p + ": its image is not given by \"source\" (only by an extension facet does not read); drawn untextured");
    return {};
  }
  TextureOptions topt;
  topt.encoding = encoding;
  if (sampler >= 0) {
    const Json& s = doc_.item("samplers", static_cast<std::size_t>(sampler));
    const std::string sp = Fields::at("samplers", static_cast<std::size_t>(sampler));
    std::uint64_t min = 0, mag = 0, ws = kRepeat, wt = kRepeat;
    FACET_TRY(f_.integer(s, sp, "minFilter", min, 0, 1u << 20));
    FACET_TRY(f_.integer(s, sp, "magFilter", mag, 0, 1u << 20));
    if (min != 0 && min != kNearest && min != kLinear && (min < 9984 || min > 9987)) {
      return f_.error(sp + ".minFilter", "unknown filter " + std::to_string(min));
    }
    if (mag != 0 && mag != kNearest && mag != kLinear) return f_.error(sp + ".magFilter", "unknown filter " + std::to_string(mag));
    topt.filter = sampler_filter(int(min), int(mag));
    auto wrap = [&](const char* field, std::uint64_t& w, TextureWrap& out_wrap) -> Status {
      FACET_TRY(f_.integer(s, sp, field, w, 0, 1u << 20));
      switch (w) {
        case kRepeat: out_wrap = TextureWrap::repeat; return {};
        case kClamp: out_wrap = TextureWrap::clamp; return {};
        case kMirror: out_wrap = TextureWrap::mirror; return {};
        default: return f_.error(sp + "." + field, "unknown wrap mode " + std::to_string(w));
      }
    };
    TextureWrap s_wrap = TextureWrap::repeat, t_wrap = TextureWrap::repeat;
    FACET_TRY(wrap("wrapS", ws, s_wrap));
    FACET_TRY(wrap("wrapT", wt, t_wrap));
    if (s_wrap != t_wrap) warn(sp + ": wrapS and wrapT differ; facet has one wrap mode per texture and uses wrapS's");
    topt.wrap = s_wrap;
  }
  const auto key = std::make_tuple(source, topt.filter, topt.wrap, encoding);
  if (auto it = textures_.find(key); it != textures_.end()) {
    out = it->second;
    return {};
  }
  const std::string ip = Fields::at("images", static_cast<std::size_t>(source));
  const std::uint64_t budget = options_.memory_budget_bytes;
  const std::uint64_t left = budget == 0 ? io::kNoSizeLimit : budget - std::min(used_, budget);
  std::string bytes, name;
  if (Status s = doc_.image_bytes(static_cast<std::size_t>(source), folder_, left, bytes, name); !s.ok()) {
    // Missing, refused (outside the model's folder) or malformed: a warning unless strict.
    if (!skippable(s)) return s;
    if (!options_.allow_missing) return {s.code(), ip, s.message() + kStrictNote};
    warn(ip + ": the image could not be read: " + s.message() + "; drawn untextured");
    textures_[key] = kNoTexture;
    return {};
  }
  topt.memory_budget_bytes = budget == 0 ? 0 : std::max<std::uint64_t>(1, budget - std::min(used_ + bytes.size(), budget));
  Result<Texture> decoded =
      decode_texture(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                     f_.source() + ": " + ip, name, topt);
  if (!decoded) {
    if (!skippable(decoded.status()) || !options_.allow_missing) {
      return {decoded.status().code(), ip, decoded.status().message() + (skippable(decoded.status()) ? kStrictNote : "")};
    }
    warn(ip + ": the image could not be decoded: " + decoded.status().message() + "; drawn untextured");
    textures_[key] = kNoTexture;
    return {};
  }
  FACET_TRY(reserve(decoded->texels.size() * 4, ip));
  out_.scene.textures.push_back(std::move(*decoded));
  out = static_cast<std::int32_t>(out_.scene.textures.size() - 1);
  textures_[key] = out;
  return {};
}

Status Reader::add_camera(int camera, std::size_t node, const std::string& p, const Eigen::Matrix4d& world) {
  const Json& c = doc_.item("cameras", static_cast<std::size_t>(camera));
  const std::string cp = Fields::at("cameras", static_cast<std::size_t>(camera));
  std::string type, name, node_name;
  FACET_TRY(f_.string(c, cp, "type", type, true));
  if (type != "perspective" && type != "orthographic") {
    return f_.error(cp + ".type", "expected \"perspective\" or \"orthographic\", found " + quote(type, 32));
  }
  FACET_TRY(f_.string(c, cp, "name", name));
  FACET_TRY(f_.string(doc_.item("nodes", node), p, "name", node_name));
  // What `facet check` lists and --camera picks from: the index in `cameras`, or a name (the
  // camera's or its node's).
  out_.cameras.push_back(std::to_string(camera) + (name.empty() ? "" : " " + quote(name, 64)) +
                         (node_name.empty() || node_name == name ? "" : " (node " + quote(node_name, 64) + ")") + ", " + type);
  const std::string& wanted = options_.camera;
  if (!wanted.empty() && wanted != std::to_string(camera) && wanted != name && wanted != node_name) return {};
  if (out_.has_camera) {
    if (!cameras_noted_ && wanted.empty()) {
      warn("the file has more than one camera node; the first in the scene's order is used (facet --camera picks another)");
    }
    cameras_noted_ = true;
    return {};
  }
  Camera cam;
  const Eigen::Vector3d eye = world.topRightCorner<3, 1>();
  Eigen::Vector3d forward = -world.block<3, 1>(0, 2), up = world.block<3, 1>(0, 1);
  if (!(forward.norm() > 1e-12) || !(up.norm() > 1e-12)) return f_.error(p, "the camera node's matrix is singular");
  forward.normalize();
  up.normalize();
  cam.eye = eye.cast<float>();
  cam.target = (eye + forward).cast<float>();
  cam.up = up.cast<float>();
  cam.aspect = 0.0f;
  const Json* pc = nullptr;
  FACET_TRY(f_.object(c, cp, type, pc));
  const std::string pp = cp + "." + type;
  if (!pc) return f_.error(pp, "required, missing");
  if (type == "orthographic") {
    // glTF 2.0 §5.13: xmag, ymag, zfar > znear >= 0, all required. three.js draws the box as given
    // (stretched when the image's aspect differs); facet keeps ymag and takes the width from the
    // image, as it does with a perspective camera's aspectRatio, and the viewer at infinity (a
    // parallel projection's view direction is the same at every point, as three.js lights it).
    double xmag = 0, ymag = 0, znear = 0, zfar = 0;
    FACET_TRY(f_.number(*pc, pp, "xmag", xmag, -1e30, 1e30, true));
    FACET_TRY(f_.number(*pc, pp, "ymag", ymag, -1e30, 1e30, true));
    FACET_TRY(f_.number(*pc, pp, "znear", znear, 0.0, 1e30, true));
    FACET_TRY(f_.number(*pc, pp, "zfar", zfar, -1e30, 1e30, true));
    if (!(ymag != 0.0)) return f_.error(pp + ".ymag", "must not be zero");
    if (!(xmag != 0.0)) return f_.error(pp + ".xmag", "must not be zero");
    if (!(zfar > znear)) return f_.error(pp + ".zfar", "must be greater than znear (" + format_number(znear) + "), found " + format_number(zfar));
    if (xmag < 0.0 || ymag < 0.0) warn(pp + ": a negative xmag or ymag (a mirrored picture) is drawn unmirrored");
    cam.projection = Projection::orthographic;
    cam.half_height = float(std::abs(ymag));
    cam.near = float(znear);
    cam.far = float(zfar);
    out_.scene.viewer = ViewerMode::infinite;
    out_.scene.camera = cam;
    out_.has_camera = true;
    return {};
  }
  double yfov = 0, znear = 0, zfar = 0, aspect = 0;
  FACET_TRY(f_.number(*pc, pp, "yfov", yfov, 1e-6, std::numbers::pi - 1e-6, true));
  FACET_TRY(f_.number(*pc, pp, "znear", znear, 1e-30, 1e30, true));
  if (Fields::find(*pc, "aspectRatio")) {
    FACET_TRY(f_.number(*pc, pp, "aspectRatio", aspect, 1e-6, 1e6));
    warn(pp + ".aspectRatio " + format_number(aspect) +
         ": the image's own aspect is used, keeping the vertical field of view (never stretching the picture)");
  }
  cam.vertical_fov_deg = float(yfov * 180.0 / std::numbers::pi);
  cam.near = float(znear);
  if (Fields::find(*pc, "zfar")) {
    FACET_TRY(f_.number(*pc, pp, "zfar", zfar, -1e30, 1e30));
    if (!(zfar > znear)) return f_.error(pp + ".zfar", "must be greater than znear (" + format_number(znear) + "), found " + format_number(zfar));
    cam.far = float(zfar);
  } else {
    cam.far = std::numeric_limits<float>::infinity();  // an infinite projection, as glTF means
  }
  out_.scene.camera = cam;
  out_.has_camera = true;
  return {};
}

Status Reader::add_light(const Json& ext, const std::string& p, const Eigen::Matrix4d& world) {
  const std::string xp = p + ".extensions.KHR_lights_punctual";
  FACET_TRY(f_.object(ext, xp));
  const Json* root_ext = Fields::find(doc_.json(), "extensions");
  const Json* root_lights = root_ext ? Fields::find(*root_ext, "KHR_lights_punctual") : nullptr;
  const Json* lights = root_lights ? Fields::find(*root_lights, "lights") : nullptr;
  if (lights && !lights->is_array()) return f_.error("extensions.KHR_lights_punctual.lights", "expected an array");
  int index = -1;
  FACET_TRY(f_.index(ext, xp, "light", lights ? lights->size() : 0, index, true));
  const Json& g = (*lights)[static_cast<std::size_t>(index)];
  const std::string gp = "extensions.KHR_lights_punctual.lights[" + std::to_string(index) + "]";
  FACET_TRY(f_.object(g, gp));
  Light l;
  FACET_TRY(f_.string(g, gp, "name", l.name));
  if (l.name.empty()) l.name = gp;
  double color[3] = {1, 1, 1}, intensity = 1, range = 0;
  FACET_TRY(f_.numbers(g, gp, "color", 3, color, 0.0, 1e30));
  FACET_TRY(f_.number(g, gp, "intensity", intensity, 0.0, 1e30));
  std::string type;
  FACET_TRY(f_.string(g, gp, "type", type, true));
  // Units (docs/content.md, docs/color.md): directional lux and point/spot candela, falling off as
  // 1 / d^2 (quadratic attenuation 1). glTF's diffuse term is albedo / pi times the irradiance, GL's
  // is albedo times the light colour: the colour is intensity / pi, so that a white surface shows
  // the radiance glTF (and three.js) give it. Such light is far beyond GL's [0, 1]: the model gets
  // automatic exposure (Scene::display).
  l.diffuse = l.specular = Color3(float(color[0]), float(color[1]), float(color[2])) * float(intensity / std::numbers::pi);
  const Eigen::Vector3d pos = world.topRightCorner<3, 1>();
  Eigen::Vector3d dir = -world.block<3, 1>(0, 2);
  if (!(dir.norm() > 1e-12)) return f_.error(p, "the light node's matrix is singular");
  dir.normalize();
  if (type == "directional") {
    l.type = LightType::directional;
    l.direction = dir.cast<float>();
  } else if (type == "point" || type == "spot") {
    l.type = type == "point" ? LightType::point : LightType::spot;
    l.position = pos.cast<float>();
    l.constant_attenuation = 0.0f;
    l.quadratic_attenuation = 1.0f;
    if (Fields::find(g, "range")) {
      FACET_TRY(f_.number(g, gp, "range", range, 0.0, 1e30));
      if (!(range > 0.0)) return f_.error(gp + ".range", "expected a number > 0 (leave it out for an infinite range)");
      l.range = float(range);
    }
    if (l.type == LightType::spot) {
      const Json* spot = nullptr;
      FACET_TRY(f_.object(g, gp, "spot", spot));
      if (!spot) return f_.error(gp + ".spot", "required for a spot light, missing");
      double inner = 0.0, outer = std::numbers::pi / 4;
      FACET_TRY(f_.number(*spot, gp + ".spot", "innerConeAngle", inner, 0.0, std::numbers::pi / 2));
      FACET_TRY(f_.number(*spot, gp + ".spot", "outerConeAngle", outer, 0.0, std::numbers::pi / 2));
      l.direction = dir.cast<float>();
      if (!(inner < outer && outer > 0.0)) return f_.error(gp + ".spot", "expected 0 <= innerConeAngle < outerConeAngle <= pi/2");
      l.spot_shape = SpotShape::smooth_cone;
      l.spot_inner_deg = float(inner * 180.0 / std::numbers::pi);
      l.spot_outer_deg = float(outer * 180.0 / std::numbers::pi);
      l.spot_falloff = 2.0f;
    }
  } else {
    return f_.error(gp + ".type", "expected \"directional\", \"point\" or \"spot\", found " + quote(type, 32));
  }
  out_.scene.lights.push_back(l);
  out_.has_lights = true;
  return {};
}

}  // namespace facet::gltf
