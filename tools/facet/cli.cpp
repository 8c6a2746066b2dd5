#include "cli.hpp"

#include <cerrno>
#include <cstdlib>
#include <filesystem>

namespace facet::cli {

int fail(const std::string& message) {
  std::fprintf(stderr, "facet: %s\n", message.c_str());
  return 2;
}

CLI::Validator int_in(long lo, long hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& v) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long n = std::strtol(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || errno != 0 || n < lo || n > hi) {
          return "expected an integer in " + range + ", found '" + v + "'";
        }
        return {};
      },
      "INT in " + range);
}

CLI::Validator number_in(double lo, double hi) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%g, %g]", lo, hi);
  const std::string range = buf;
  return CLI::Validator(
      [lo, hi, range](std::string& v) -> std::string {
        char* end = nullptr;
        const double n = std::strtod(v.c_str(), &end);
        if (v.empty() || *end != '\0' || !(n >= lo && n <= hi)) return "expected a number in " + range + ", found '" + v + "'";
        return {};
      },
      "NUMBER in " + range);
}

CLI::Validator one_of(std::vector<std::string> names, const std::string& what) {
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i) {
    list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  }
  std::string shown;
  for (std::size_t i = 0; i < names.size(); ++i) shown += (i ? "|" : "") + names[i];
  return CLI::Validator(
      [names, what, list](std::string& v) -> std::string {
        for (const std::string& n : names)
          if (v == n) return {};
        return "unknown " + what + " '" + v + "' (" + list + ")";
      },
      shown);
}

std::optional<LightingPath> parse_path(const std::string& name) {
  for (LightingPath p : {LightingPath::reference, LightingPath::scalar, LightingPath::simd})
    if (name == to_string(p)) return p;
  return std::nullopt;
}

std::optional<Isa> parse_isa(const std::string& name) {
  if (name == "auto") return Isa::best;
  for (Isa i : {Isa::sse2, Isa::avx2, Isa::avx512})
    if (name == to_string(i)) return i;
  return std::nullopt;
}

std::optional<PowTier> parse_pow_tier(const std::string& name) {
  for (PowTier t : {PowTier::automatic, PowTier::exact, PowTier::fast, PowTier::integer, PowTier::schlick})
    if (name == to_string(t)) return t;
  return std::nullopt;
}

std::optional<ShadingMode> parse_shading(const std::string& name) {
  if (name == "flat") return ShadingMode::flat;
  if (name == "gouraud") return ShadingMode::gouraud;
  if (name == "phong") return ShadingMode::phong;
  return std::nullopt;
}

std::optional<ShadowMethod> parse_shadow_method(const std::string& name) {
  for (ShadowMethod m : {ShadowMethod::none, ShadowMethod::map, ShadowMethod::volume, ShadowMethod::raycast})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

std::optional<TransparentOrder> parse_transparent_order(const std::string& name) {
  for (TransparentOrder o : {TransparentOrder::submission, TransparentOrder::back_to_front})
    if (name == to_string(o)) return o;
  return std::nullopt;
}

void override_shadows(Scene& scene, ShadowMethod method) {
  for (Light& l : scene.lights) l.shadow.method = method;
}

std::string describe_path(LightingPath path, Isa isa, PowTier tier) {
  if (path != LightingPath::simd) return to_string(path);
  return std::string("simd ") + to_string(isa == Isa::best ? best_isa() : isa) + " (pow " + to_string(tier) + ")";
}

std::optional<Scene> load_scene_or_default(const std::string& path, std::uint64_t memory_budget_bytes) {
  if (path.empty()) return make_default_scene();
  LoadOptions options;
  options.memory_budget_bytes = memory_budget_bytes;
  Result<Scene> loaded = load_scene_file(path, options);
  if (!loaded) {
    fail(loaded.status().message());
    return std::nullopt;
  }
  return std::move(*loaded);
}

bool is_model_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gltf" || ext == ".glb" || ext == ".obj";
}

std::optional<Scene> load_input(const std::string& path, const InputOptions& options, std::vector<std::string>& notes) {
  if (path.empty()) return make_default_scene();
  {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const char* other : {".fbx", ".dae", ".stl", ".ply", ".3ds", ".blend", ".usd", ".usda", ".usdz", ".abc", ".x3d"}) {
      if (ext == other) {
        fail(path + ": " + ext + " files are not supported: facet reads scene files (.json) and models (.gltf, .glb, "
             ".obj with .mtl); export or convert the model to glTF");
        return std::nullopt;
      }
    }
  }
  if (!is_model_path(path)) {
    LoadOptions lo;
    lo.memory_budget_bytes = options.memory_budget_bytes;
    lo.assets.allowed_roots = options.allowed_paths;
    lo.warning = [&](const std::string& w) { notes.push_back("warning: " + w); };
    Result<Scene> loaded = load_scene_file(path, lo);
    if (!loaded) {
      fail(loaded.status().message());
      return std::nullopt;
    }
    return std::move(*loaded);
  }
  ModelOptions mo;
  mo.memory_budget_bytes = options.memory_budget_bytes;
  mo.allow_missing = options.allow_missing;
  mo.assets.allowed_roots = options.allowed_paths;
  Result<Model> model = load_model(path, mo);
  if (!model) {
    fail(model.status().message());
    return std::nullopt;
  }
  for (const std::string& w : model->warnings) notes.push_back("warning: " + w);
  Scene& scene = model->scene;
  char buf[256];
  if (!model->has_camera) {
    const Bounds b = scene_bounds(scene);
    scene.camera = frame_bounds(b, options.aspect);
    const Camera& c = scene.camera;
    std::snprintf(buf, sizeof buf, "no camera in the file: framing its bounds, eye (%.4g, %.4g, %.4g), target (%.4g, %.4g, %.4g), fov %.4g deg",
                  c.eye.x(), c.eye.y(), c.eye.z(), c.target.x(), c.target.y(), c.target.z(), c.vertical_fov_deg);
    notes.push_back(buf);
  }
  if (!model->has_lights) {
    add_default_lights(scene);
    notes.push_back("no lights in the file: facet's default rig (a headlight and a key light, ambient 0.15)");
  }
  return std::move(scene);
}

Status light_scene(const Scene& scene, const LightingOptions& options, std::vector<VertexColors>& out) {
  out.resize(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (Status s = light_instance(scene, i, options, out[i]); !s.ok()) return s;
  }
  return {};
}

}  // namespace facet::cli
