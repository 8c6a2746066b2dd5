// JSON scene files: nlohmann-json for the document, JsonLines for where each value is, and one
// reader per object kind. The reader checks types and the JSON-only fields; validate_scene() checks
// the rest, and its field path is mapped back to a line of the file.
#include "facet/scene_file.hpp"
#include "facet/lightmap.hpp"
#include "facet/model.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/format.hpp"
#include "common/try.hpp"
#include "io/assets.hpp"
#include "io/file_access.hpp"
#include "texture/texture_file.hpp"
#include "content/json_fields.hpp"
#include "content/json_lines.hpp"
#include "content/scene_file_lights.hpp"

namespace facet {
namespace {

using json = nlohmann::json;
using scene_json::child;
using scene_json::describe;
using scene_json::join;

class SceneReader : public scene_json::JsonFields {
 public:
  SceneReader(std::string source, const JsonLines& lines, std::string base_dir, const LoadOptions& options)
      : JsonFields(std::move(source), lines), base_dir_(std::move(base_dir)), options_(options),
        folder_(options.assets, base_dir_) {}

  Status read(const json& root, Scene& scene) {
    FACET_TRY(expect_object(root, "", {"camera", "global_ambient", "viewer", "two_sided", "transparent_order",
                                       "exposure", "tone_mapping", "environment_image", "background", "textures", "materials", "meshes", "objects", "lights", "fog", "imports"}));
    if (root.contains("camera")) FACET_TRY(read_camera(root["camera"], scene.camera));
    FACET_TRY(opt_color(root, "", "global_ambient", scene.global_ambient));
    if (root.contains("viewer")) {
      std::string mode;
      FACET_TRY(read_enum(root["viewer"], "viewer", {"local", "infinite"}, mode));
      scene.viewer = mode == "local" ? ViewerMode::local : ViewerMode::infinite;
    }
    FACET_TRY(opt_bool(root, "", "two_sided", scene.two_sided));
    if (root.contains("transparent_order")) {
      std::string order;
      FACET_TRY(read_enum(root["transparent_order"], "transparent_order", {"submission", "back_to_front"}, order));
      scene.transparent_order = order == "submission" ? TransparentOrder::submission : TransparentOrder::back_to_front;
    }
    if (root.contains("exposure")) {  // stops, or "auto" (facet/display.hpp)
      const json& e = root["exposure"];
      if (e.is_string()) {
        std::string mode;
        FACET_TRY(read_enum(e, "exposure", {"auto"}, mode));
        scene.display.automatic = true;
      } else {
        FACET_TRY(opt_number(root, "", "exposure", scene.display.ev));
        if (!(scene.display.ev >= -30.0f && scene.display.ev <= 30.0f)) return mismatch("exposure", "stops in [-30, 30] or \"auto\"", e);
      }
    }
    if (root.contains("tone_mapping")) {
      std::string op;
      FACET_TRY(read_enum(root["tone_mapping"], "tone_mapping", {"none", "neutral", "aces"}, op));
      scene.display.tone_mapping = op == "neutral" ? ToneMapping::neutral : op == "aces" ? ToneMapping::aces : ToneMapping::none;
    }
    if (root.contains("environment_image")) FACET_TRY(read_environment_image(root["environment_image"], scene.environment_light));
    if (root.contains("background")) {  // what is drawn behind the model (facet/environment_light.hpp)
      std::string b;
      FACET_TRY(read_enum(root["background"], "background", {"colour", "color", "environment"}, b));
      scene.background = b == "environment" ? Background::environment : Background::colour;
    }
    auto add_texture = [&](const json& j, const std::string& p) {
      Texture t;
      FACET_TRY(read_texture(j, p, t));
      scene.textures.push_back(std::move(t));
      return Status{};
    };
    auto add_material = [&](const json& j, const std::string& p) {
      Material m;
      FACET_TRY(read_material(j, p, scene, m));
      scene.materials.push_back(std::move(m));
      return Status{};
    };
    const std::size_t mesh_total = root.contains("meshes") && root["meshes"].is_array() ? root["meshes"].size() : 0;
    auto add_mesh = [&](const json& j, const std::string& p) {
      NamedMesh m;
      FACET_TRY(read_mesh(j, p, m));
      scene.meshes.push_back(std::move(m));
      reported_ = static_cast<double>(scene.meshes.size()) / static_cast<double>(std::max<std::size_t>(mesh_total, 1));
      if (options_.progress && !options_.progress(reported_)) {
        return Status{ErrorCode::cancelled, p, source_ + ": " + p + ": the load was cancelled"};
      }
      return Status{};
    };
    auto add_object = [&](const json& j, const std::string& p) {
      Instance inst;
      FACET_TRY(read_object(j, p, scene, inst));
      scene.objects.push_back(inst);
      return Status{};
    };
    auto add_light = [&](const json& j, const std::string& p) {
      Light l;
      FACET_TRY(scene_json::read_light(*this, j, p, scene, l));
      scene.lights.push_back(std::move(l));
      return Status{};
    };
    FACET_TRY(read_list(root, "textures", add_texture));
    FACET_TRY(read_list(root, "materials", add_material));
    if (root.contains("fog")) FACET_TRY(read_fog(root["fog"], scene.fog));
    FACET_TRY(read_list(root, "meshes", add_mesh));
    auto add_import = [&](const json& j, const std::string& p) { return read_import(j, p, root.contains("camera"), scene); };
    FACET_TRY(read_list(root, "imports", add_import));
    FACET_TRY(read_list(root, "objects", add_object));
    FACET_TRY(read_list(root, "lights", add_light));
    FACET_TRY(frame_imports(root, scene));
    if (Status s = generate_missing_tangents(scene); !s.ok()) return located(s.field(), s.code(), s.message());
    if (Status s = validate_scene(scene); !s.ok()) return located(s.field(), s.code(), s.message());
    return {};
  }


  Status read_camera(const json& j, Camera& c) const {
    const std::string p = "camera";
    FACET_TRY(expect_object(j, p, {"eye", "target", "up", "projection", "fov_deg", "half_height", "aspect", "near", "far"}));
    FACET_TRY(opt_vec3(j, p, "eye", c.eye));
    FACET_TRY(opt_vec3(j, p, "target", c.target));
    FACET_TRY(opt_vec3(j, p, "up", c.up));
    if (j.contains("projection")) {
      std::string projection;
      FACET_TRY(read_enum(j["projection"], child(p, "projection"), {"perspective", "orthographic"}, projection));
      c.projection = projection == "orthographic" ? Projection::orthographic : Projection::perspective;
    }
    // Each projection's own size; the other's would be read and ignored in silence.
    const bool ortho = c.projection == Projection::orthographic;
    if (j.contains(ortho ? "fov_deg" : "half_height")) {
      return invalid(child(p, ortho ? "fov_deg" : "half_height"),
                     ortho ? "an orthographic camera has no field of view: give \"half_height\""
                           : "only an orthographic camera has a half height (\"projection\": \"orthographic\")");
    }
    FACET_TRY(opt_number(j, p, "fov_deg", c.vertical_fov_deg));
    FACET_TRY(opt_number(j, p, "half_height", c.half_height));
    FACET_TRY(opt_number(j, p, "aspect", c.aspect));
    FACET_TRY(opt_number(j, p, "near", c.near));
    if (j.contains("far") && j["far"].is_string()) {  // JSON has no infinity: "far": "infinite"
      std::string infinite;
      FACET_TRY(read_enum(j["far"], child(p, "far"), {"infinite"}, infinite));
      c.far = std::numeric_limits<float>::infinity();
      return {};
    }
    return opt_number(j, p, "far", c.far);
  }

  // "environment_image": {"file": F} or {"source": "studio" | "none"}, with "intensity": k and
  // "rotation_deg": a (what PBR materials see around them; facet/environment_light.hpp). The file
  // is read as textures are: in the scene's folder, counted against the memory budget.
  Status read_environment_image(const json& j, EnvironmentLight& e) {
    const std::string p = "environment_image";
    FACET_TRY(expect_object(j, p, {"file", "source", "intensity", "rotation_deg"}));
    if (j.contains("file") == j.contains("source")) {
      return invalid(p, "give either \"file\" (a picture) or \"source\" (\"studio\" or \"none\")");
    }
    if (j.contains("file")) {
      std::string file;
      FACET_TRY(opt_string(j, p, "file", file));
      const std::string fp = child(p, "file");
      const std::uint64_t limit = left() == 0 ? io::kNoSizeLimit : left();
      Result<std::string> bytes = folder_.read(file, fp, "environment picture", limit);
      if (!bytes) return located(fp, bytes.status().code(), bytes.status().message() + (bytes.status().code() == ErrorCode::out_of_memory ? spent() : ""));
      Result<EnvironmentLight> picture = decode_environment_image(
          std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size()), fp + " " + quote(file, 80),
          left());
      if (!picture) return located(fp, picture.status().code(), picture.status().message() + (picture.status().code() == ErrorCode::out_of_memory ? spent() : ""));
      FACET_TRY(reserve(p, picture->rgb.size() * sizeof(float), "the environment picture (" + std::to_string(picture->width) + "x" +
                                                                     std::to_string(picture->height) + ")"));
      e = std::move(*picture);
    } else {
      std::string source;
      FACET_TRY(read_enum(j["source"], child(p, "source"), {"studio", "none"}, source));
      e.source = source == "studio" ? EnvironmentSource::studio : EnvironmentSource::none;
    }
    FACET_TRY(opt_number(j, p, "intensity", e.intensity));
    if (!(e.intensity >= 0.0f && e.intensity <= 1e6f)) return mismatch(child(p, "intensity"), "a number in [0, 1e6]", j["intensity"]);
    FACET_TRY(opt_number(j, p, "rotation_deg", e.rotation_deg));
    if (!(e.rotation_deg >= -3600.0f && e.rotation_deg <= 3600.0f)) {
      return mismatch(child(p, "rotation_deg"), "a number in [-3600, 3600]", j["rotation_deg"]);
    }
    return {};
  }

  // A material: each field of the field table (facet/fields.hpp) by its name, the environment by
  // read_environment's rules.
  Status read_material(const json& j, const std::string& p, Scene& scene, Material& m) {
    std::vector<std::string_view> keys = {"name", "environment"};
    for (const MaterialField& f : material_fields())
      if (!std::strchr(f.name, '.')) keys.push_back(f.name);
    FACET_TRY(expect_object(j, p, keys));
    FACET_TRY(opt_string(j, p, "name", m.name));
    for (const MaterialField& f : material_fields())
      if (!std::strchr(f.name, '.')) FACET_TRY(opt_field(j, p, f.name, f, scene.textures, m));
    if (j.contains("environment")) FACET_TRY(read_environment(j["environment"], child(p, "environment"), scene, m.environment));
    return {};
  }

  // "environment": {"mode": "sphere" | "normal", "texture": NAME} or {"mode": "cube", "faces":
  // [+X, -X, +Y, -Y, +Z, -Z names]} or {"mode": "cube", "texture": an equirectangular picture,
  // "face_size": N}, with "strength" and "blend".
  Status read_environment(const json& j, const std::string& p, Scene& scene, Environment& e) {
    FACET_TRY(expect_object(j, p, {"mode", "texture", "faces", "face_size", "strength", "blend", "dynamic", "resolution"}));
    if (!j.contains("mode")) return invalid(child(p, "mode"), "missing (\"sphere\", \"cube\" or \"normal\")");
    std::string mode;
    FACET_TRY(read_enum(j["mode"], child(p, "mode"), {"sphere", "cube", "normal"}, mode));
    e.mode = mode == "sphere" ? EnvironmentMode::sphere : mode == "cube" ? EnvironmentMode::cube : EnvironmentMode::normal;
    FACET_TRY(opt_bool(j, p, "dynamic", e.dynamic));
    if (j.contains("resolution")) {
      if (!e.dynamic) return invalid(child(p, "resolution"), "only a dynamic environment (\"dynamic\": true) has a resolution");
      FACET_TRY(opt_int(j, p, "resolution", 1, 4096, e.resolution));
    }
    const bool cube_picture = e.mode == EnvironmentMode::cube && !e.dynamic && j.contains("texture");
    if (j.contains("face_size") && !cube_picture) {
      return invalid(child(p, "face_size"), "only a cube environment read from an equirectangular \"texture\" has a face size");
    }
    if (e.dynamic) {
      if (e.mode != EnvironmentMode::cube) return invalid(child(p, "dynamic"), "only a cube environment is rendered from the scene");
      if (j.contains("faces") || j.contains("texture")) {
        return invalid(child(p, j.contains("faces") ? "faces" : "texture"), "a dynamic environment is rendered, not read");
      }
    } else if (cube_picture) {
      if (j.contains("faces")) {
        return invalid(child(p, "faces"), "a cube environment takes \"faces\" or one equirectangular \"texture\", not both");
      }
      std::uint32_t index = 0;
      FACET_TRY(find_name(j["texture"], child(p, "texture"), scene.textures, "texture", index));
      FACET_TRY(cube_from_equirect(j, p, scene, index, e));
    } else if (e.mode == EnvironmentMode::cube) {
      if (!j.contains("faces")) {
        return invalid(child(p, "faces"), "missing: six texture names, +X, -X, +Y, -Y, +Z, -Z (or one equirectangular \"texture\")");
      }
      const json& faces = j["faces"];
      const std::string fp = child(p, "faces");
      if (!faces.is_array() || faces.size() != 6) return mismatch(fp, "an array of six texture names", faces);
      for (std::size_t k = 0; k < 6; ++k) {
        std::uint32_t index = 0;
        FACET_TRY(find_name(faces[k], fp + "[" + std::to_string(k) + "]", scene.textures, "texture", index));
        e.maps[k] = static_cast<std::int32_t>(index);
      }
    } else {
      if (j.contains("faces")) return invalid(child(p, "faces"), "only a cube environment has faces; this one takes \"texture\"");
      if (!j.contains("texture")) return invalid(child(p, "texture"), "missing: the name of the map");
      std::uint32_t index = 0;
      FACET_TRY(find_name(j["texture"], child(p, "texture"), scene.textures, "texture", index));
      e.maps[0] = static_cast<std::int32_t>(index);
    }
    FACET_TRY(opt_number(j, p, "strength", e.strength));
    if (j.contains("blend")) {
      FACET_TRY(read_enum(j["blend"], child(p, "blend"), {"add", "modulate", "mix"}, mode));
      e.blend = mode == "add" ? EnvironmentBlend::add : mode == "modulate" ? EnvironmentBlend::modulate : EnvironmentBlend::mix;
    }
    return {};
  }

  // The six faces converted from equirectangular texture `picture` (cube_faces_from_equirect),
  // face_size texels a side (default: a quarter of the picture's width), appended to the scene's
  // textures once per picture and size, counted against the memory budget.
  Status cube_from_equirect(const json& j, const std::string& p, Scene& scene, std::uint32_t picture, Environment& e) {
    const Texture& source = scene.textures[picture];
    int size = std::max(1, std::min(kEquirectMaxFace, source.width() / 4));
    FACET_TRY(opt_int(j, p, "face_size", 1, kEquirectMaxFace, size));
    const std::uint64_t key = std::uint64_t{picture} << 32 | static_cast<std::uint32_t>(size);
    auto [at, added] = converted_.try_emplace(key, static_cast<std::int32_t>(scene.textures.size()));
    if (added) {
      TextureOptions options;
      options.filter = TextureFilter::bilinear;  // read at level 0 only (texgen has no derivatives)
      options.wrap = TextureWrap::clamp;
      options.memory_budget_bytes = left();
      // Long for large faces: the load's progress is asked (with the share it last reported) as
      // the faces are made, so that a host can stop it.
      std::function<bool(double)> asked;
      if (options_.progress) asked = [this](double) { return options_.progress(reported_); };
      Result<std::vector<Texture>> faces = cube_faces_from_equirect(source, size, source.name, options, asked);
      if (!faces) {
        converted_.erase(at);
        return located(child(p, "texture"), faces.status().code(),
                       child(p, "texture") + ": " + faces.status().message() +
                           (faces.status().code() == ErrorCode::out_of_memory ? spent() : ""));
      }
      const std::uint64_t bytes = 6 * std::uint64_t{4} * static_cast<std::uint64_t>(size) * static_cast<std::uint64_t>(size);
      FACET_TRY(reserve(child(p, "texture"), bytes, "its six cube faces (" + std::to_string(size) + "x" + std::to_string(size) + ")"));
      for (Texture& f : *faces) scene.textures.push_back(std::move(f));
    }
    for (int k = 0; k < 6; ++k) e.maps[k] = at->second + k;
    return {};
  }

  // A texture file, resolved against the scene file's folder, decoded with its filter and wrap.
  Status read_texture(const json& j, const std::string& p, Texture& out) {
    FACET_TRY(expect_object(j, p, {"name", "file", "filter", "wrap", "encoding"}));
    std::string name, file, mode;
    FACET_TRY(opt_string(j, p, "name", name));
    if (!j.contains("file")) return invalid(child(p, "file"), "missing: every texture names its image file");
    FACET_TRY(opt_string(j, p, "file", file));
    TextureOptions options;
    options.memory_budget_bytes = left();
    if (j.contains("filter")) {
      FACET_TRY(read_enum(j["filter"], child(p, "filter"), {"nearest", "bilinear", "trilinear"}, mode));
      options.filter = mode == "nearest" ? TextureFilter::nearest : mode == "bilinear" ? TextureFilter::bilinear : TextureFilter::trilinear;
    }
    if (j.contains("wrap")) {
      FACET_TRY(read_enum(j["wrap"], child(p, "wrap"), {"repeat", "clamp", "mirror"}, mode));
      options.wrap = mode == "repeat" ? TextureWrap::repeat : mode == "clamp" ? TextureWrap::clamp : TextureWrap::mirror;
    }
    if (j.contains("encoding")) {  // "auto" (the default): the file's tag, else linear
      FACET_TRY(read_enum(j["encoding"], child(p, "encoding"), {"auto", "srgb", "linear"}, mode));
      if (mode != "auto") options.encoding = mode == "srgb" ? TextureEncoding::srgb : TextureEncoding::linear;
    }
    const std::string fp = child(p, "file");
    Result<Texture> t = facet::read_texture(folder_, file, fp, name, options);
    if (!t) {
      return located(fp, t.status().code(), t.status().message() + (t.status().code() == ErrorCode::out_of_memory ? spent() : ""));
    }
    FACET_TRY(reserve(p, t->texels.size() * sizeof(std::uint32_t), "this texture (" + std::to_string(t->width()) + "x" + std::to_string(t->height()) + ")"));
    out = std::move(*t);
    return {};
  }

  // What is left of the memory budget for the next mesh or texture (never 0, which would mean
  // no limit); 0 when there is no budget.
  std::uint64_t left() const {
    const std::uint64_t budget = options_.memory_budget_bytes;
    return budget == 0 ? 0 : std::max<std::uint64_t>(1, budget - std::min(used_, budget));
  }
  // Appended to a refusal made with what was left(): what the rest of the budget went to.
  std::string spent() const {
    if (options_.memory_budget_bytes == 0 || used_ == 0) return "";
    return " (the scene's meshes and textures before it use " + format_bytes(used_) + " of the memory budget of " +
           format_bytes(options_.memory_budget_bytes) + ")";
  }

  Status read_fog(const json& j, Fog& fog) const {
    const std::string p = "fog";
    FACET_TRY(expect_object(j, p, {"mode", "color", "start", "end", "density"}));
    if (j.contains("mode")) {
      std::string mode;
      FACET_TRY(read_enum(j["mode"], child(p, "mode"), {"none", "linear", "exp", "exp2"}, mode));
      fog.mode = mode == "none" ? FogMode::none : mode == "linear" ? FogMode::linear : mode == "exp" ? FogMode::exp : FogMode::exp2;
    } else {
      return invalid(child(p, "mode"), "missing: \"linear\", \"exp\", \"exp2\" or \"none\"");
    }
    FACET_TRY(opt_color(j, p, "color", fog.color));
    FACET_TRY(opt_number(j, p, "start", fog.start));
    FACET_TRY(opt_number(j, p, "end", fog.end));
    return opt_number(j, p, "density", fog.density);
  }

  // Counts `bytes` of a mesh or texture (`what`) against the memory budget.
  Status reserve(const std::string& p, std::uint64_t bytes, const std::string& what) {
    const std::uint64_t budget = options_.memory_budget_bytes;
    if (budget != 0 && (bytes > budget || used_ > budget - bytes)) {
      return located(p, ErrorCode::out_of_memory,
                     p + ": " + what + ", " + format_bytes(bytes) + ", takes the scene's meshes and textures to " +
                         format_bytes(used_ + bytes) + ", over the memory budget of " + format_bytes(budget) +
                         " (LoadOptions::memory_budget_bytes, facet --memory-budget-mb)");
    }
    used_ += bytes;
    return {};
  }
  // Counts a mesh of `vertices` and `triangles` against the memory budget before it is made.
  Status reserve_mesh(const json&, const std::string& p, std::uint64_t vertices, std::uint64_t triangles) {
    return reserve(p, vertices * (2 * sizeof(Vec3)) + triangles * 3 * sizeof(std::uint32_t),
                   "this mesh (" + std::to_string(vertices) + " vertices, " + std::to_string(triangles) + " triangles)");
  }

  Status read_mesh(const json& j, const std::string& p, NamedMesh& out) {
    if (!j.is_object()) return mismatch(p, "an object", j);
    FACET_TRY(opt_string(j, p, "name", out.name));
    if (j.contains("obj") == j.contains("shape")) {
      return invalid(p, "a mesh needs exactly one of \"obj\" (a file) or \"shape\" (a procedural shape)");
    }
    if (j.contains("obj")) {
      FACET_TRY(expect_object(j, p, {"name", "obj", "crease_angle_deg"}));
      std::string file;
      FACET_TRY(opt_string(j, p, "obj", file));
      ObjOptions options;
      options.memory_budget_bytes = left();
      FACET_TRY(opt_number(j, p, "crease_angle_deg", options.crease_angle_deg));
      if (!(options.crease_angle_deg >= 0.0f && options.crease_angle_deg <= 180.0f)) {
        return invalid(child(p, "crease_angle_deg"), "expected a number in [0, 180]");
      }
      const std::string op = child(p, "obj");
      Result<io::AssetFolder::Resolved> resolved = folder_.resolve(file, op);
      if (!resolved) return located(op, resolved.status().code(), resolved.status().message());
      Result<std::string> text = folder_.read(file, op, "OBJ file", options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes);
      if (!text) return located(op, text.status().code(), text.status().message());
      Result<Mesh> mesh = parse_obj(*text, resolved->name, options);
      if (!mesh) return located(op, mesh.status().code(), op + ": " + mesh.status().message());
      FACET_TRY(reserve_mesh(j, p, mesh->vertex_count(), mesh->triangle_count()));
      out.mesh = std::move(*mesh);
      return {};
    }
    std::string shape;
    FACET_TRY(read_enum(j["shape"], child(p, "shape"), {"sphere", "cube", "plane", "disc", "torus"}, shape));
    if (shape == "sphere") {
      FACET_TRY(expect_object(j, p, {"name", "shape", "radius", "segments", "rings"}));
      float radius = 1.0f;
      int segments = 48, rings = 24;
      FACET_TRY(opt_size(j, p, "radius", radius));
      FACET_TRY(opt_int(j, p, "segments", 3, 4096, segments));
      FACET_TRY(opt_int(j, p, "rings", 2, 4096, rings));
      FACET_TRY(reserve_mesh(j, p, std::uint64_t(segments + 1) * std::uint64_t(rings + 1), 2 * std::uint64_t(segments) * std::uint64_t(rings)));
      out.mesh = make_uv_sphere(radius, segments, rings);
    } else if (shape == "cube") {
      FACET_TRY(expect_object(j, p, {"name", "shape", "size", "subdivisions"}));
      float size = 1.0f;
      int subdivisions = 1;
      FACET_TRY(opt_size(j, p, "size", size));
      FACET_TRY(opt_int(j, p, "subdivisions", 1, 4096, subdivisions));
      const std::uint64_t s1 = std::uint64_t(subdivisions) + 1;
      FACET_TRY(reserve_mesh(j, p, 6 * s1 * s1, 12 * std::uint64_t(subdivisions) * std::uint64_t(subdivisions)));
      out.mesh = make_cube(size, subdivisions);
    } else if (shape == "plane") {
      FACET_TRY(expect_object(j, p, {"name", "shape", "size_x", "size_z", "subdivisions"}));
      float sx = 10.0f, sz = 10.0f;
      int subdivisions = 1;
      FACET_TRY(opt_size(j, p, "size_x", sx));
      FACET_TRY(opt_size(j, p, "size_z", sz));
      FACET_TRY(opt_int(j, p, "subdivisions", 1, 4096, subdivisions));
      const std::uint64_t s1 = std::uint64_t(subdivisions) + 1;
      FACET_TRY(reserve_mesh(j, p, s1 * s1, 2 * std::uint64_t(subdivisions) * std::uint64_t(subdivisions)));
      out.mesh = make_plane(sx, sz, subdivisions);
    } else if (shape == "disc") {
      FACET_TRY(expect_object(j, p, {"name", "shape", "radius", "segments"}));
      float radius = 1.0f;
      int segments = 64;
      FACET_TRY(opt_size(j, p, "radius", radius));
      FACET_TRY(opt_int(j, p, "segments", 3, 4096, segments));
      FACET_TRY(reserve_mesh(j, p, 2 * std::uint64_t(segments + 1), std::uint64_t(segments)));
      out.mesh = make_disc(radius, segments);
    } else {
      FACET_TRY(expect_object(j, p, {"name", "shape", "major_radius", "minor_radius", "segments", "sides"}));
      float major = 1.0f, minor = 0.25f;
      int segments = 48, sides = 24;
      FACET_TRY(opt_size(j, p, "major_radius", major));
      FACET_TRY(opt_size(j, p, "minor_radius", minor));
      FACET_TRY(opt_int(j, p, "segments", 3, 4096, segments));
      FACET_TRY(opt_int(j, p, "sides", 3, 4096, sides));
      FACET_TRY(reserve_mesh(j, p, std::uint64_t(segments + 1) * std::uint64_t(sides + 1), 2 * std::uint64_t(segments) * std::uint64_t(sides)));
      out.mesh = make_torus(major, minor, segments, sides);
    }
    return {};
  }

  // A strictly positive, finite length.
  Status opt_size(const json& obj, const std::string& path, const char* key, float& out) const {
    FACET_TRY(opt_number(obj, path, key, out));
    if (!(out > 0.0f)) return mismatch(child(path, key), "a number > 0", obj[key]);
    return {};
  }


  Status read_object(const json& j, const std::string& p, Scene& scene, Instance& inst) const {
    FACET_TRY(expect_object(j, p, {"mesh", "material", "mesh_materials", "translate", "rotate_deg", "scale", "matrix",
                                   "cast_shadows", "receive_shadows", "double_sided", "lightmap"}));
    FACET_TRY(find_by_name(j, p, "mesh", scene.meshes, "mesh", inst.mesh));
    FACET_TRY(opt_bool(j, p, "double_sided", inst.double_sided));
    FACET_TRY(opt_bool(j, p, "mesh_materials", inst.mesh_materials));
    FACET_TRY(opt_bool(j, p, "cast_shadows", inst.cast_shadows));
    FACET_TRY(opt_bool(j, p, "receive_shadows", inst.receive_shadows));
    if (inst.mesh_materials && j.contains("material")) {
      return invalid(child(p, "material"), "an object with \"mesh_materials\" takes its materials from its mesh's groups");
    }
    if (inst.mesh_materials) {
      // The instance's own material is not drawn; any valid index will do.
      if (scene.materials.empty()) {
        Material m;
        m.name = "default";
        scene.materials.push_back(m);
      }
      inst.material = 0;
    } else if (j.contains("material")) {
      FACET_TRY(find_by_name(j, p, "material", scene.materials, "material", inst.material));
    } else {
      // Objects without a material share one with GL's default values.
      auto it = std::find_if(scene.materials.begin(), scene.materials.end(),
                             [](const Material& m) { return m.name == "default"; });
      if (it == scene.materials.end()) {
        Material m;
        m.name = "default";
        scene.materials.push_back(m);
        it = scene.materials.end() - 1;
      }
      inst.material = static_cast<std::uint32_t>(it - scene.materials.begin());
    }
    FACET_TRY(read_transform(j, p, inst.model));
    if (j.contains("lightmap")) FACET_TRY(read_lightmap(j["lightmap"], child(p, "lightmap"), scene, inst));
    return {};
  }

  // An object's baked light: {"texture", "scale", "mode", "uv"} and, for "uv": "generate", the
  // chart options a bake used. "generate" cuts the object's mesh into the charts bake_lightmaps
  // made (the same function of the same world-space mesh) and gives the object its own copy of
  // the mesh, split along the charts, with those lightmap coordinates; "mesh" uses the mesh's own
  // (Mesh::lightmap_uvs, glTF TEXCOORD_1).
  Status read_lightmap(const json& j, const std::string& p, Scene& scene, Instance& inst) const {
    FACET_TRY(expect_object(j, p, {"texture", "scale", "mode", "uv", "texels_per_unit", "padding", "chart_angle_deg", "max_size"}));
    if (!j.contains("texture")) return invalid(child(p, "texture"), "missing: the lightmap's texture");
    std::uint32_t texture = 0;
    FACET_TRY(find_by_name(j, p, "texture", scene.textures, "texture", texture));
    inst.lightmap = static_cast<std::int32_t>(texture);
    FACET_TRY(opt_number(j, p, "scale", inst.lightmap_scale));
    if (!(inst.lightmap_scale > 0.0f)) return mismatch(child(p, "scale"), "a number > 0", j["scale"]);
    std::string text = "diffuse";
    if (j.contains("mode")) FACET_TRY(read_enum(j["mode"], child(p, "mode"), {"diffuse", "replace"}, text));
    inst.lightmap_mode = text == "replace" ? LightmapMode::replace : LightmapMode::diffuse;
    text = "generate";
    if (j.contains("uv")) FACET_TRY(read_enum(j["uv"], child(p, "uv"), {"generate", "mesh"}, text));
    const bool generate = text == "generate";
    for (const char* key : {"texels_per_unit", "padding", "chart_angle_deg", "max_size"}) {
      if (!generate && j.contains(key)) return invalid(child(p, key), "only with \"uv\": \"generate\"");
    }
    if (!generate) return {};
    LightmapUvOptions o;
    if (!j.contains("texels_per_unit")) return invalid(child(p, "texels_per_unit"), "missing: the density the lightmap was baked at");
    FACET_TRY(opt_number(j, p, "texels_per_unit", o.texels_per_unit));
    FACET_TRY(opt_int(j, p, "padding", 1, 64, o.padding));
    FACET_TRY(opt_number(j, p, "chart_angle_deg", o.chart_angle_deg));
    FACET_TRY(opt_int(j, p, "max_size", 1, 65536, o.max_size));
    const NamedMesh& source = scene.meshes[inst.mesh];
    Result<LightmapUnwrap> u = unwrap_lightmap(world_space_mesh(source.mesh, inst.model), o);
    if (!u.ok()) {
      const std::string& field = u.status().field();
      const std::string& message = u.status().message();
      const bool prefixed = message.rfind(field + ": ", 0) == 0;  // "field: what"
      return invalid(child(p, field), prefixed ? message.substr(field.size() + 2) : message);
    }
    Result<Mesh> split = with_lightmap_uvs(source.mesh, *u);
    if (!split.ok()) return invalid(p, split.status().message());
    scene.meshes.push_back({source.name + "#lightmap" + std::to_string(scene.objects.size()), std::move(*split)});
    inst.mesh = static_cast<std::uint32_t>(scene.meshes.size() - 1);
    return {};
  }

  // "matrix" (row-major 4x4) or "translate", "rotate_deg" (x, then y, then z) and "scale".
  Status read_transform(const json& j, const std::string& p, Mat4& model) const {
    if (j.contains("matrix")) {
      if (j.contains("translate") || j.contains("rotate_deg") || j.contains("scale")) {
        return invalid(p, "\"matrix\" cannot be combined with \"translate\", \"rotate_deg\" or \"scale\"");
      }
      const json& m = j["matrix"];
      const std::string mp = child(p, "matrix");
      if (!m.is_array() || m.size() != 16) return mismatch(mp, "an array of 16 numbers (row-major 4x4)", m);
      for (int i = 0; i < 16; ++i) {
        FACET_TRY(read_number(m[static_cast<std::size_t>(i)], mp + "[" + std::to_string(i) + "]", model(i / 4, i % 4)));
      }
      return {};
    }
    Vec3 t = Vec3::Zero(), r = Vec3::Zero(), s = Vec3::Ones();
    FACET_TRY(opt_vec3(j, p, "translate", t));
    FACET_TRY(opt_vec3(j, p, "rotate_deg", r));
    if (j.contains("scale")) {
      if (j["scale"].is_number()) {
        float u = 1.0f;
        FACET_TRY(read_number(j["scale"], child(p, "scale"), u));
        s = Vec3(u, u, u);
      } else {
        FACET_TRY(read_vec3(j["scale"], child(p, "scale"), s));
      }
      if ((s.array() == 0.0f).any()) return invalid(child(p, "scale"), "every scale factor must be non-zero");
    }
    const float k = std::numbers::pi_v<float> / 180.0f;
    const Eigen::Matrix3f rot = (Eigen::AngleAxisf(k * r.z(), Vec3::UnitZ()) * Eigen::AngleAxisf(k * r.y(), Vec3::UnitY()) *
                                 Eigen::AngleAxisf(k * r.x(), Vec3::UnitX()))
                                    .toRotationMatrix();
    model = Mat4::Identity();
    model.topLeftCorner<3, 3>() = rot * s.asDiagonal();
    model.block<3, 1>(0, 3) = t;
    return {};
  }

  // A model file (model.hpp) placed in the scene: its meshes, materials and textures are added
  // with their names prefixed by the file name ("chair.obj:wood"), its objects transformed, its
  // lights added unless "lights" is false, its camera used when "camera" is true.
  Status read_import(const json& j, const std::string& p, bool scene_has_camera, Scene& scene) {
    FACET_TRY(expect_object(j, p, {"file", "translate", "rotate_deg", "scale", "matrix", "lights", "camera", "allow_missing", "lightmaps", "gl_materials",
                                  "animation", "time"}));
    if (!j.contains("file")) return invalid(child(p, "file"), "missing: the model file (.gltf, .glb or .obj)");
    std::string file;
    FACET_TRY(opt_string(j, p, "file", file));
    Mat4 place = Mat4::Identity();
    FACET_TRY(read_transform(j, p, place));
    if (!(std::abs(place.topLeftCorner<3, 3>().cast<double>().determinant()) > 0.0)) {
      return invalid(p, "the transform must be invertible");
    }
    bool lights = true, camera = false;
    ModelOptions mo;
    FACET_TRY(opt_bool(j, p, "lights", lights));
    FACET_TRY(opt_bool(j, p, "camera", camera));
    FACET_TRY(opt_bool(j, p, "allow_missing", mo.allow_missing));
    if (options_.strict) mo.allow_missing = false;
    mo.gl_materials = options_.gl_materials;
    FACET_TRY(opt_bool(j, p, "gl_materials", mo.gl_materials));
    if (camera && scene_has_camera) return invalid(child(p, "camera"), "the scene file has its own \"camera\"");
    mo.memory_budget_bytes = left();
    const std::string fp = child(p, "file");
    Result<io::AssetFolder::Resolved> resolved = folder_.resolve(file, fp);
    if (!resolved) return located(fp, resolved.status().code(), resolved.status().message());
    // The model's files may lie anywhere in the scene's folder, as the scene's own may.
    mo.assets = options_.assets;
    if (!options_.assets.resolver) mo.assets.allowed_roots.push_back(base_dir_.empty() ? std::string(".") : base_dir_);
    Result<Model> model = load_model(resolved->name, mo);
    if (!model) return located(child(p, "file"), model.status().code(), child(p, "file") + ": " + model.status().message());
    if (options_.warning) {
      for (const std::string& w : model->warnings) options_.warning(p + ": " + w);
    }
    // "animation" (an index or a name) and "time" (seconds): the model's pose (facet/animation.hpp).
    if (j.contains("animation") || j.contains("time")) {
      std::string name = "0";
      if (j.contains("animation") && j["animation"].is_number_unsigned()) name = std::to_string(j["animation"].get<std::uint64_t>());
      else FACET_TRY(opt_string(j, p, "animation", name));
      double seconds = std::numeric_limits<double>::quiet_NaN();
      FACET_TRY(opt_number(j, p, "time", seconds));
      Result<int> chosen = find_animation(*model, name);
      if (!chosen) return located(child(p, "animation"), chosen.status().code(), child(p, "animation") + ": " + chosen.status().message());
      PoseOptions po;
      po.animation = *chosen;
      if (std::isnan(seconds)) seconds = model->motion.animations[std::size_t(*chosen)].start_s;
      if (Status s = pose_model(*model, seconds, po); !s.ok()) return located(child(p, "time"), s.code(), child(p, "time") + ": " + s.message());
    }
    Scene& m = model->scene;
    std::uint64_t bytes = 0;
    for (const NamedMesh& nm : m.meshes) bytes += nm.mesh.vertex_count() * 2 * sizeof(Vec3) + nm.mesh.triangle_count() * 12;
    for (const Texture& t : m.textures) bytes += t.texels.size() * 4;
    used_ += bytes;
    const std::string prefix = file + ":";
    const auto mesh0 = static_cast<std::uint32_t>(scene.meshes.size());
    const auto material0 = static_cast<std::uint32_t>(scene.materials.size());
    const auto texture0 = static_cast<std::int32_t>(scene.textures.size());
    for (Texture& t : m.textures) {
      t.name = prefix + t.name;
      scene.textures.push_back(std::move(t));
    }
    for (Material& mat : m.materials) {
      mat.name = prefix + mat.name;
      if (mat.diffuse_texture != kNoTexture) mat.diffuse_texture += texture0;
      if (mat.emissive_texture != kNoTexture) mat.emissive_texture += texture0;
      scene.materials.push_back(std::move(mat));
    }
    for (NamedMesh& nm : m.meshes) {
      nm.name = prefix + nm.name;
      for (MaterialGroup& g : nm.mesh.groups) g.material = prefix + g.material;
      scene.meshes.push_back(std::move(nm));
    }
    const std::size_t object0 = scene.objects.size();
    for (Instance inst : m.objects) {
      inst.mesh += mesh0;
      inst.material += material0;
      inst.model = place * inst.model;
      scene.objects.push_back(inst);
    }
    // "lightmaps": one entry (an object's "lightmap", or null) per object the model adds, in the
    // model's order, as `facet bake` writes them.
    if (j.contains("lightmaps")) {
      const json& list = j["lightmaps"];
      const std::string lp = child(p, "lightmaps");
      if (!list.is_array()) return mismatch(lp, "an array", list);
      if (list.size() != m.objects.size()) {
        return invalid(lp, "expected one entry per object the model adds (" + std::to_string(m.objects.size()) + "), found " +
                               std::to_string(list.size()));
      }
      for (std::size_t i = 0; i < list.size(); ++i) {
        if (list[i].is_null()) continue;
        FACET_TRY(read_lightmap(list[i], lp + "[" + std::to_string(i) + "]", scene, scene.objects[object0 + i]));
      }
    }
    const Eigen::Matrix3f linear = place.topLeftCorner<3, 3>();
    if (lights && model->has_lights) {
      imported_lights_ = true;
      for (Light l : m.lights) {
        l.name = prefix + l.name;
        l.position = linear * l.position + place.block<3, 1>(0, 3);
        l.direction = (linear * l.direction).normalized();
        scene.lights.push_back(std::move(l));
      }
    }
    if (camera) {
      if (!model->has_camera) return invalid(child(p, "camera"), file + " has no camera");
      Camera c = m.camera;
      const Vec3 forward = c.target - c.eye;
      c.eye = linear * c.eye + place.block<3, 1>(0, 3);
      c.target = c.eye + linear * forward;
      c.up = linear * c.up;
      scene.camera = c;
      imported_camera_ = true;
    }
    return {};
  }

  // Imported models without a camera or lights of the scene's own are framed and lit as
  // `facet render MODEL` frames and lights a model (LoadOptions::view).
  Status frame_imports(const json& root, Scene& scene) {
    if (!root.contains("imports") || scene.objects.empty()) return {};
    auto note = [&](const std::string& what) {
      if (options_.warning) options_.warning(what);
    };
    if (!root.contains("camera") && !imported_camera_) {
      Result<Camera> framed = frame_scene(scene, options_.frame_aspect, options_.view);
      if (!framed) return located("imports", framed.status().code(), source_ + ": imports: " + framed.status().message());
      scene.camera = *framed;
      note("no \"camera\": framing the imported models from the front");
    }
    if (!root.contains("lights") && !imported_lights_) {
      note(std::string("no \"lights\": ") + add_default_lights(scene));
    }
    return {};
  }

  std::string base_dir_;
  const LoadOptions& options_;
  io::AssetFolder folder_;  // the files the scene names: in its folder (facet/assets.hpp)
  std::uint64_t used_ = 0;  // bytes of the meshes and textures read so far
  std::map<std::uint64_t, std::int32_t> converted_;  // (picture << 32 | face size) -> its first cube face
  bool imported_camera_ = false, imported_lights_ = false;
  double reported_ = 0;  // the share of the load last given to options_.progress  // an import brought the camera, lights
};

}  // namespace

Result<Scene> parse_scene_json(const std::string& text, const std::string& source_name, const std::string& base_dir,
                               const LoadOptions& options) {
  try {
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
      return Status{ErrorCode::parse_error, "", source_name + ":1: empty file: expected a JSON object"};
    }
    JsonLines lines;
    FACET_TRY(lines.scan(text, source_name));
    const json root = json::parse(text);
    Scene scene;
    SceneReader reader(source_name, lines, base_dir, options);
    FACET_TRY(reader.read(root, scene));
    return scene;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", source_name + ": out of memory while reading the scene"};
  } catch (const std::exception& e) {
    return Status{ErrorCode::parse_error, "", source_name + ": " + quote(e.what(), 200)};
  }
}

Result<Scene> load_scene_file(const std::string& path, const LoadOptions& options) {
  Result<std::string> text = io::read_named_by_host(options.assets, path, "scene file", options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes);
  if (!text) return text.status();
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_scene_json(*text, path, base, options);
}

}  // namespace facet
