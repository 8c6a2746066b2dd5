// facet light / facet check.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <vector>

#include "cli.hpp"

namespace facet::cli {
namespace {

constexpr const char* kLightUsage =
    "usage: facet light [SCENE.json] [options]\n"
    "\n"
    "Lights all vertices of every object in eye space, repeatedly, for each path, and reports the rate.\n"
    "\n"
    "options:\n"
    "  --path P       reference | scalar | all (default: all)\n"
    "  --seconds S    minimum measuring time per path, in seconds (default: 0.5)\n"
    "  --json         print the results as one JSON object\n"
    "  -h, --help     this text\n";

constexpr const char* kCheckUsage = "usage: facet check SCENE.json\n";

struct PathResult {
  LightingPath path;
  double seconds = 0;
  std::size_t vertices = 0;       // vertex evaluations (front and, if two-sided, back)
  std::size_t vertex_lights = 0;  // vertex evaluations x enabled lights
  std::size_t passes = 0;
};

std::size_t enabled_lights(const Scene& scene) {
  return static_cast<std::size_t>(
      std::count_if(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.enabled; }));
}

std::size_t scene_vertices(const Scene& scene) {
  std::size_t n = 0;
  for (const auto& obj : scene.objects) n += scene.meshes[obj.mesh].mesh.vertex_count();
  return n;
}

Status light_scene(const Scene& scene, LightingPath path, std::vector<VertexColors>& out) {
  out.resize(scene.objects.size());
  LightingOptions options;
  options.path = path;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (Status s = light_instance(scene, i, options, out[i]); !s.ok()) return s;
  }
  return {};
}

}  // namespace

int run_light(int argc, char** argv) {
  std::string scene_path, path_name = "all";
  double min_seconds = 0.5;
  bool json = false;
  Args args(argc, argv);
  std::string arg;
  while (args.next(arg)) {
    if (arg == "-h" || arg == "--help") {
      std::fputs(kLightUsage, stdout);
      return 0;
    } else if (arg == "--path") {
      const auto v = args.value(arg);
      if (!v) return 2;
      path_name = *v;
      if (path_name == "simd") return fail("--path simd: this build has no SIMD lighting path yet (it has: reference, scalar, all)");
      if (path_name != "reference" && path_name != "scalar" && path_name != "all") {
        return fail("--path: unknown path '" + path_name + "' (this build has: reference, scalar, all)");
      }
    } else if (arg == "--seconds") {
      const auto v = args.number_value(arg, 1e-3, 3600);
      if (!v) return 2;
      min_seconds = *v;
    } else if (arg == "--json") {
      json = true;
    } else if (!arg.empty() && arg[0] == '-') {
      return fail("light: unknown option '" + arg + "' (see 'facet light --help')");
    } else if (scene_path.empty()) {
      scene_path = arg;
    } else {
      return fail("light: more than one scene given ('" + scene_path + "' and '" + arg + "')");
    }
  }
  std::optional<Scene> loaded = load_scene_or_default(scene_path);
  if (!loaded) return 2;
  const Scene& scene = *loaded;
  const std::string scene_name = scene_path.empty() ? "built-in default scene" : scene_path;

  std::vector<LightingPath> paths;
  if (path_name == "all" || path_name == "reference") paths.push_back(LightingPath::reference);
  if (path_name == "all" || path_name == "scalar") paths.push_back(LightingPath::scalar);

  const std::size_t vertices_per_pass = scene_vertices(scene) * (scene.two_sided ? 2 : 1);
  const std::size_t lights = enabled_lights(scene);
  std::vector<PathResult> results;
  std::vector<std::vector<VertexColors>> colours(paths.size());
  for (std::size_t k = 0; k < paths.size(); ++k) {
    if (Status s = light_scene(scene, paths[k], colours[k]); !s.ok()) return fail(s.message());  // warm-up
    PathResult r{paths[k]};
    const auto start = std::chrono::steady_clock::now();
    do {
      if (Status s = light_scene(scene, paths[k], colours[k]); !s.ok()) return fail(s.message());
      ++r.passes;
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } while (r.seconds < min_seconds);
    r.vertices = r.passes * vertices_per_pass;
    r.vertex_lights = r.vertices * lights;
    results.push_back(r);
  }

  double max_diff = -1.0;  // scalar vs reference, as a sanity line
  if (paths.size() == 2) {
    max_diff = 0.0;
    for (std::size_t o = 0; o < colours[0].size(); ++o) {
      const auto& a = colours[0][o].front;
      const auto& b = colours[1][o].front;
      for (std::size_t v = 0; v < a.size(); ++v) max_diff = std::max<double>(max_diff, (a[v] - b[v]).cwiseAbs().maxCoeff());
    }
  }

  if (json) {
    std::printf("{\"scene\": \"%s\", \"objects\": %zu, \"vertices\": %zu, \"lights\": %zu, \"results\": [",
                scene_name.c_str(), scene.objects.size(), vertices_per_pass, lights);
    for (std::size_t k = 0; k < results.size(); ++k) {
      const auto& r = results[k];
      std::printf("%s{\"path\": \"%s\", \"seconds\": %.6f, \"passes\": %zu, \"vertices_lit_per_s\": %.6g, "
                  "\"vertex_lights_per_s\": %.6g}",
                  k ? ", " : "", to_string(r.path), r.seconds, r.passes, double(r.vertices) / r.seconds,
                  double(r.vertex_lights) / r.seconds);
    }
    std::printf("]");
    if (max_diff >= 0.0) std::printf(", \"max_abs_difference_scalar_vs_reference\": %.3g", max_diff);
    std::printf("}\n");
    return 0;
  }
  std::printf("facet light: %s\n", scene_name.c_str());
  std::printf("  %zu objects, %zu vertices per pass%s, %zu enabled lights\n\n", scene.objects.size(),
              vertices_per_pass, scene.two_sided ? " (front and back)" : "", lights);
  std::printf("  %-10s %16s %18s %11s %8s\n", "path", "vertices lit/s", "vertex-lights/s", "ns/vertex", "passes");
  for (const auto& r : results) {
    const double vps = double(r.vertices) / r.seconds;
    std::printf("  %-10s %14.2f M %16.2f M %11.2f %8zu\n", to_string(r.path), vps / 1e6,
                double(r.vertex_lights) / r.seconds / 1e6, 1e9 / vps, r.passes);
  }
  if (max_diff >= 0.0) {
    std::printf("\n  scalar vs reference: largest colour difference %.3g (%.3g of an 8-bit step)\n", max_diff,
                max_diff * 255.0);
  }
  std::printf("  (one thread; measured for at least %.2g s per path)\n", min_seconds);
  return 0;
}

int run_check(int argc, char** argv) {
  if (argc >= 1 && (std::strcmp(argv[0], "-h") == 0 || std::strcmp(argv[0], "--help") == 0)) {
    std::fputs(kCheckUsage, stdout);
    return 0;
  }
  if (argc != 1) return fail(std::string("check needs exactly one scene file\n") + kCheckUsage);
  Result<Scene> scene = load_scene_file(argv[0]);
  if (!scene) return fail(scene.status().message());
  std::size_t triangles = 0;
  for (const auto& obj : scene->objects) triangles += scene->meshes[obj.mesh].mesh.triangle_count();
  std::printf("%s: ok — %zu meshes, %zu materials, %zu objects (%zu vertices, %zu triangles), %zu lights\n", argv[0],
              scene->meshes.size(), scene->materials.size(), scene->objects.size(), scene_vertices(*scene), triangles,
              scene->lights.size());
  return 0;
}

}  // namespace facet::cli
