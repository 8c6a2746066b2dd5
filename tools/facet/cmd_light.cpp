// facet light / facet check.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "cli.hpp"

#include <memory>
#include "common/format.hpp"
#include "shadow/volume.hpp"

namespace facet::cli {
namespace {

struct PathResult {
  LightingOptions options;
  double seconds = 0;
  std::size_t vertices = 0;       // vertex evaluations (front and, if two-sided, back)
  std::size_t vertex_lights = 0;  // vertex evaluations x enabled lights
  std::size_t passes = 0;
  std::vector<double> pass_rates;  // vertices lit per second in each pass
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

}  // namespace

struct LightState {
  std::string scene_path, path_name = "all", pow = "auto";
  double min_seconds = 0.5;
  int threads = 1, width = 1280, height = 720, memory_mb = -1;
  bool json = false, allow_missing = false, strict = false, gl_materials = false;
  EnvironmentState environment;
  std::vector<std::string> allow_paths;
  ViewState view;
};

int light(const LightState& st);

Command add_light(CLI::App& facet) {
  auto st = std::make_shared<LightState>();
  CLI::App* app = facet.add_subcommand("light", "light every vertex of a scene with each lighting path; print vertices lit per second");
  app->footer(
      "Lights all vertices of every object in eye space, repeatedly, for each path, and reports the rate.\n"
      "A model is framed and lit as 'facet render MODEL' frames and lights it.");
  app->add_option("scene", st->scene_path, "SCENE.json | MODEL.gltf | MODEL.glb | MODEL.obj (default: the built-in scene)");
  app->add_option("--path", st->path_name,
                  "reference | scalar | simd | all (default all: reference, scalar and simd on every instruction set this CPU has)")
      ->check(one_of({"reference", "scalar", "simd", "all"}, "path"));
  app->add_option("--pow", st->pow, "auto | exact | fast | integer | schlick: the simd path's pow method (default auto)")
      ->check(one_of({"auto", "exact", "fast", "integer", "schlick"}, "tier"));
  app->add_option("--seconds", st->min_seconds, "minimum measuring time per path, in seconds (default 0.5)")
      ->check(number_in(1e-3, 3600));
  app->add_option("--threads", st->threads, "threads per path (default 1; 0 = one per hardware thread)")->check(int_in(0, 1024));
  app->add_flag("--json", st->json, "print the results as one JSON object");
  const char* model = "Models";
  app->add_option("--width", st->width, "the image width a model is framed for (default 1280)")->check(int_in(1, kMaxImageDimension))->group(model);
  app->add_option("--height", st->height, "the image height a model is framed for (default 720)")->check(int_in(1, kMaxImageDimension))->group(model);
  app->add_flag("--allow-missing", st->allow_missing, "a model's missing or unreadable .mtl, texture or image files are warnings (the default)")->group(model);
  app->add_flag("--strict", st->strict, "a model's missing or unreadable .mtl, texture or image files are errors")->excludes("--allow-missing")->group(model);
  app->add_flag("--gl-materials", st->gl_materials, "light a glTF model's materials with GL's lighting model (facet's Blinn-Phong mapping) instead of the glTF BRDF")->group(model);
  app->add_option("--allow-path", st->allow_paths, kAllowPathHelp)->group(model);
  app->add_option("--memory-budget-mb", st->memory_mb, "the most memory the scene may take, in MiB; 0 = no limit (default 4096)")
      ->check(int_in(0, 1 << 30))->group(model);
  add_view_options(app, st->view, model);
  add_environment_options(app, st->environment, model);
  return {app, [st] { return light(*st); }};
}

int light(const LightState& st) {
  const std::string& scene_path = st.scene_path;
  const std::string& path_name = st.path_name;
  const PowTier tier = *parse_pow_tier(st.pow);
  const double min_seconds = st.min_seconds;
  const int threads = st.threads;
  const bool json = st.json;
  InputOptions input;
  InputIdentity identity;
  identity.name = scene_path.empty() ? "built-in scene" : std::filesystem::path(scene_path).filename().string();
  input.on_read = [&identity](const std::string&, const std::string& bytes) { identity.add(bytes); };
  input.allowed_paths = st.allow_paths;
  if (st.memory_mb >= 0) input.memory_budget_bytes = static_cast<std::uint64_t>(st.memory_mb) << 20;
  input.allow_missing = !st.strict;
  input.gl_materials = st.gl_materials;
  input.aspect = float(st.width) / float(st.height);
  if (!apply_view_options(st.view, input)) return 2;
  std::vector<std::string> notes;
  std::optional<Input> loaded = load_input(scene_path, input, notes);
  if (!loaded) return 2;
  if (!json) {
    for (const std::string& n : notes) std::fprintf(stderr, "facet: %s\n", n.c_str());
  }
  if (!apply_environment_options(st.environment, input.memory_budget_bytes, loaded->scene)) return 2;
  const Scene& scene = loaded->scene;
  const std::string scene_name = scene_path.empty() ? "built-in default scene" : scene_path;

  std::vector<LightingOptions> paths;
  auto add = [&](LightingPath p, Isa isa) {
    LightingOptions o;
    o.path = p;
    o.isa = isa;
    o.pow_tier = tier;
    o.threads = threads;
    paths.push_back(o);
  };
  if (path_name == "all" || path_name == "reference") add(LightingPath::reference, Isa::best);
  if (path_name == "all" || path_name == "scalar") add(LightingPath::scalar, Isa::best);
  if (path_name == "all" || path_name == "simd") {
    for (Isa isa : {Isa::sse2, Isa::avx2, Isa::avx512})
      if (isa_supported(isa)) add(LightingPath::simd, isa);
  }

  const std::size_t vertices_per_pass = scene_vertices(scene) * (scene.two_sided ? 2 : 1);
  const std::size_t lights = enabled_lights(scene);
  std::vector<PathResult> results;
  std::vector<std::vector<VertexColors>> colours(paths.size());
  for (std::size_t k = 0; k < paths.size(); ++k) {
    Lighter lighter;  // threads and working memory kept over the passes, as a caller would
    if (Status s = light_scene(lighter, scene, paths[k], colours[k]); !s.ok()) return fail(s.message());  // warm-up
    PathResult r;
    r.options = paths[k];
    const auto start = std::chrono::steady_clock::now();
    do {
      const auto t0 = std::chrono::steady_clock::now();
      if (Status s = light_scene(lighter, scene, paths[k], colours[k]); !s.ok()) return fail(s.message());
      r.pass_rates.push_back(double(vertices_per_pass) / std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      ++r.passes;
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } while (r.seconds < min_seconds);
    r.vertices = r.passes * vertices_per_pass;
    r.vertex_lights = r.vertices * lights;
    results.push_back(r);
  }

  // Largest difference of each path from the reference, when the reference ran.
  std::vector<double> max_diff(paths.size(), -1.0);
  if (!paths.empty() && paths[0].path == LightingPath::reference) {
    for (std::size_t k = 0; k < paths.size(); ++k) {
      max_diff[k] = 0.0;
      for (std::size_t o = 0; o < colours[0].size(); ++o) {
        const auto& a = colours[0][o].front;
        const auto& b = colours[k][o].front;
        for (std::size_t v = 0; v < a.size(); ++v) max_diff[k] = std::max<double>(max_diff[k], (a[v] - b[v]).cwiseAbs().maxCoeff());
      }
    }
  }
  double scalar_rate = 0;
  for (const auto& r : results)
    if (r.options.path == LightingPath::scalar) scalar_rate = double(r.vertices) / r.seconds;

  if (json) {
    // Each result: the mean rate over the run and the spread of the per-pass rates; the difference
    // from the reference only when the reference ran (absent otherwise).
    std::printf("{%s\"context\": %s, \"scene\": \"%s\", \"objects\": %zu, \"vertices\": %zu, \"lights\": %zu, \"results\": [",
                identity.json_field().c_str(), json_context("", "", threads).c_str(), json_escape(scene_name).c_str(), scene.objects.size(), vertices_per_pass, lights);
    for (std::size_t k = 0; k < results.size(); ++k) {
      const auto& r = results[k];
      const bool simd = r.options.path == LightingPath::simd;
      std::printf("%s{\"path\": \"%s\", \"lighting_path\": \"%s\", \"isa\": \"%s\", \"pow\": \"%s\", \"seconds\": %.6f, "
                  "\"passes\": %zu, \"vertices_lit_per_s\": %.6g, \"vertices_lit_per_s_per_pass\": %s, \"vertex_lights_per_s\": %.6g, ",
                  k ? ", " : "", describe_path(r.options.path, r.options.isa, r.options.pow_tier).c_str(), to_string(r.options.path),
                  simd ? to_string(r.options.isa) : "none", simd ? to_string(r.options.pow_tier) : "std::pow", r.seconds, r.passes,
                  double(r.vertices) / r.seconds, json_spread(r.pass_rates).c_str(), double(r.vertex_lights) / r.seconds);
      if (max_diff[k] >= 0) std::printf("\"max_abs_difference_vs_reference\": %.3g, ", max_diff[k]);
      std::printf("\"threads\": %d}", threads);
    }
    std::printf("]}\n");
    return 0;
  }
  std::printf("facet light: %s\n", scene_name.c_str());
  std::printf("  %zu objects, %zu vertices per pass%s, %zu enabled lights\n\n", scene.objects.size(),
              vertices_per_pass, scene.two_sided ? " (front and back)" : "", lights);
  std::printf("  %-26s %16s %18s %11s %9s %14s\n", "path", "vertices lit/s", "vertex-lights/s", "ns/vertex",
              "vs scalar", "max |d| vs ref");
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& r = results[k];
    const double vps = double(r.vertices) / r.seconds;
    // "-" where the comparison's other side did not run (--path without scalar or reference).
    char speedup[32] = "-", diff[32] = "-";
    if (scalar_rate > 0) std::snprintf(speedup, sizeof speedup, "%.2fx", vps / scalar_rate);
    if (max_diff[k] >= 0) std::snprintf(diff, sizeof diff, "%.3g", max_diff[k]);
    std::printf("  %-26s %14.2f M %16.2f M %11.2f %9s %14s\n",
                describe_path(r.options.path, r.options.isa, r.options.pow_tier).c_str(), vps / 1e6,
                double(r.vertex_lights) / r.seconds / 1e6, 1e9 / vps, speedup, diff);
  }
  if (threads == 1) {
    std::printf("  (one thread; measured for at least %.2g s per path)\n", min_seconds);
  } else {
    std::printf("  (%s thread%s per path; objects under 8192 vertices use one; measured for at least %.2g s per path)\n",
                threads == 0 ? "one per hardware" : std::to_string(threads).c_str(), threads == 1 ? "" : "s",
                min_seconds);
  }
  return 0;
}

struct CheckState {
  std::string scene_path, shading, shadows, transparent_order, output, depth, depth_mode = "auto";
  int width = 1280, height = 720, memory_mb = -1, msaa = 1;
  bool allow_missing = false, strict = false, vertex_relief = false, fields = false, gl_materials = false;
  EnvironmentState environment;
  std::vector<std::string> allow_paths;
  ViewState view;
  std::string animation;
  double time = std::numeric_limits<double>::quiet_NaN();
};

int check(const CheckState& st);

Command add_check(CLI::App& facet) {
  auto st = std::make_shared<CheckState>();
  CLI::App* app = facet.add_subcommand("check", "load and validate a scene or model; print a summary or the first error");
  app->footer(
      "Loads the scene or model and makes every check 'facet render' makes before it draws: the file,\n"
      "the frame's limits, its memory estimate and the image's memory, for an image of the given size\n"
      "(a PNG unless -o says otherwise). Then draws one frame and fails if a model, or a scene with\n"
      "meshes, draws nothing, saying why. For a model, lists what was not read (warnings) and what\n"
      "'facet render' would assume (camera, lights).");
  app->add_option("scene", st->scene_path, "SCENE.json | MODEL.gltf | MODEL.glb | MODEL.obj")->required();
  app->add_option("-o,--output", st->output, "the output 'facet render' would write (.png, .pfm or .exr; not written): its image memory is checked");
  app->add_option("--depth", st->depth, "the depth file 'facet render' would write (.pfm; not written)");
  app->add_option("--depth-mode", st->depth_mode, "auto | gl | reversed, as for 'facet render' (default auto)")
      ->check(one_of({"auto", "gl", "reversed"}, "depth mode"));
  app->add_option("--width", st->width, "the image width to check for (default 1280)")->check(int_in(1, kMaxImageDimension));
  app->add_option("--height", st->height, "the image height to check for (default 720)")->check(int_in(1, kMaxImageDimension));
  app->add_option("--shading", st->shading, "flat | gouraud | phong, as for 'facet render' (default: phong for a model, gouraud for a scene file)")
      ->check(one_of({"flat", "gouraud", "phong"}, "shading"));
  app->add_option("--shadows", st->shadows, "none | map | volume | raycast: every light casts shadows so")
      ->check(one_of({"none", "map", "volume", "raycast"}, "method"));
  app->add_option("--transparent-order", st->transparent_order, kTransparentOrderHelp)
      ->check(one_of({"submission", "back_to_front"}, "order"));
  app->add_option("--memory-budget-mb", st->memory_mb, "as for 'facet render' (default 4096; 0 = no limit)")->check(int_in(0, 1 << 30));
  app->add_flag("--vertex-relief", st->vertex_relief, "as for 'facet render': Gouraud reads normal and bump maps per vertex");
  app->add_flag("--fields", st->fields,
                "list every material's and light's fields that differ from their defaults (docs/scene-format.md's field tables)");
  app->add_option("--msaa", st->msaa, "1 | 4 | 8 | 16 samples per pixel, as for 'facet render' (the tiles' memory grows N-fold)")
      ->check(CLI::IsMember({1, 4, 8, 16}));
  app->add_flag("--allow-missing", st->allow_missing, "a model's missing or unreadable .mtl, texture or image files are warnings (the default)");
  app->add_flag("--strict", st->strict, "a model's missing or unreadable .mtl, texture or image files are errors")->excludes("--allow-missing");
  app->add_flag("--gl-materials", st->gl_materials, "light a glTF model's materials with GL's lighting model (facet's Blinn-Phong mapping) instead of the glTF BRDF");
  app->add_option("--animation", st->animation, "INDEX | NAME: check the pose of a glTF model's animation, as 'facet render'");
  app->add_option("--time", st->time, "SECONDS into the animation, as 'facet render'")->check(number_in(-1e9, 1e9));
  app->add_option("--allow-path", st->allow_paths, kAllowPathHelp);
  add_view_options(app, st->view);
  add_environment_options(app, st->environment);
  return {app, [st] { return check(*st); }};
}

namespace {


// One frame of `scene` at up to 640 pixels across (the whole size when that draws nothing, so that
// a small model is not missed between the pixel centres of the smaller image): what it drew.
// The frame's verdict (nothing_visible, as `render` gives it): empty when something shows.
Result<std::string> draw_once(const Scene& scene, const RenderOptions& options, int width, int height) {
  std::string nothing;
  const std::vector<std::uint8_t> background = background_pixel(scene, options, PixelFormat::rgba8);
  const double scale = std::min(1.0, 640.0 / std::max(width, height));
  for (const double s : {scale, 1.0}) {
    const int w = std::max(1, int(std::lround(width * s))), h = std::max(1, int(std::lround(height * s)));
    std::vector<std::uint8_t> pixels(std::size_t(w) * std::size_t(h) * 4);
    const ImageView image{pixels.data(), w, h, std::size_t(w) * 4, PixelFormat::rgba8, false};
    FrameStats stats;
    if (Status s2 = Renderer().render(scene, options, image, nullptr, &stats); !s2.ok()) return s2;
    nothing = nothing_visible(stats, image, background);
    if (nothing.empty() || s == 1.0) break;
  }
  return nothing;
}

// Each material's and light's fields that differ from their defaults, one object a line, in the
// field table's names and the scene file's notation (texture fields as indices).
template <class T>
void print_non_default(const char* list, std::size_t index, const std::string& name, std::span<const FieldSpec<T>> table,
                       const T& object) {
  std::string line;
  for (const FieldSpec<T>& f : table) {
    if (!is_default(f, object)) line += std::string(line.empty() ? "" : ", ") + f.name + " " + format_field(f, object);
  }
  std::printf("    %s[%zu] %s: %s\n", list, index, quote(name, 40).c_str(), line.empty() ? "the defaults" : line.c_str());
}

void print_fields(const Scene& scene) {
  std::printf("  fields that differ from their defaults (docs/scene-format.md, \"Material fields\" and \"Light fields\"):\n");
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    print_non_default("materials", i, scene.materials[i].name, material_fields(), scene.materials[i]);
  }
  for (std::size_t i = 0; i < scene.lights.size(); ++i) print_non_default("lights", i, scene.lights[i].name, light_fields(), scene.lights[i]);
}

}  // namespace

int check(const CheckState& st) {
  const std::string& scene_path = st.scene_path;
  const int width = st.width, height = st.height;
  RenderOptions options;
  options.shading = *parse_shading(default_shading(st.shading, scene_path));
  options.vertex_relief = st.vertex_relief;
  options.samples = st.msaa;
  if (st.memory_mb >= 0) options.memory_budget_bytes = static_cast<std::uint64_t>(st.memory_mb) << 20;
  options.depth = st.depth_mode == "gl" ? DepthMode::gl : st.depth_mode == "reversed" ? DepthMode::reversed : DepthMode::automatic;
  const std::string ext = st.output.empty() ? ".png" : lower_extension(st.output);
  if (ext != ".png" && ext != ".pfm" && ext != ".exr") {
    return fail("-o: the output file must end in .png, .pfm or .exr, found '" + st.output + "'");
  }
  if (!st.depth.empty() && lower_extension(st.depth) != ".pfm") return fail("--depth: the depth file must end in .pfm");
  InputOptions input;
  input.allowed_paths = st.allow_paths;
  input.memory_budget_bytes = options.memory_budget_bytes;
  input.allow_missing = !st.strict;
  input.gl_materials = st.gl_materials;
  input.animation = st.animation;
  input.time = st.time;
  input.aspect = float(width) / float(height);
  if (!apply_view_options(st.view, input)) return 2;
  std::vector<std::string> notes;
  std::optional<Input> loaded = load_input(scene_path, input, notes);
  if (!loaded) return 2;
  Scene* scene = &loaded->scene;
  if (!st.shadows.empty()) override_shadows(*scene, *parse_shadow_method(st.shadows));
  if (!st.transparent_order.empty()) scene->transparent_order = *parse_transparent_order(st.transparent_order);
  if (!apply_environment_options(st.environment, options.memory_budget_bytes, *scene)) return 2;
  // The image the user asked for first (the plainer message), then the frame's scratch.
  const PixelFormat format = ext == ".png" ? PixelFormat::rgba8 : PixelFormat::rgba32f;
  if (Status s = check_output_image(width, height, format, !st.depth.empty(), options.memory_budget_bytes); !s.ok()) {
    return fail(scene_path + ": " + s.message());
  }
  if (Status s = check_render(*scene, options, width, height); !s.ok()) return fail(scene_path + ": " + s.message());
  // Something to draw: a model always, a scene file when it has meshes.
  if (is_model_path(scene_path) || !scene->meshes.empty()) {
    Result<std::string> drawn = draw_once(*scene, options, width, height);
    if (!drawn) return fail(scene_path + ": " + drawn.status().message());
    if (!drawn->empty()) {  // the verdict `render` gives, with its exit status
      for (const std::string& n : notes) std::fprintf(stderr, "  %s\n", n.c_str());
      std::fprintf(stderr, "facet: %s: nothing to see: %s\n", json_escape(scene_path).c_str(), drawn->c_str());
      return 1;
    }
  }
  std::size_t triangles = 0, blended = 0, textured = 0, emissive = 0;
  for (const auto& obj : scene->objects) {
    triangles += scene->meshes[obj.mesh].mesh.triangle_count();
    blended += is_transparent(*scene, obj);
    textured += uses_textures(scene->materials[obj.material]);
    emissive += scene->materials[obj.material].emissive_texture != kNoTexture;
  }
  std::uint64_t texels = 0;
  std::size_t srgb_textures = 0;
  for (const auto& t : scene->textures) texels += t.texels.size(), srgb_textures += t.encoding == TextureEncoding::srgb;
  std::printf("%s: ok — %zu meshes, %zu materials, %zu objects (%zu vertices, %zu triangles), %zu lights; a %d x %d "
              "frame%s takes at most about %llu MiB of the renderer's scratch (a bound: every triangle counted as drawn; "
              "what --memory-budget-mb is checked against)\n",
              scene_path.c_str(), scene->meshes.size(), scene->materials.size(), scene->objects.size(),
              scene_vertices(*scene), triangles, scene->lights.size(), width, height,
              options.samples > 1 ? (" with " + std::to_string(options.samples) + " samples a pixel").c_str() : "",
              static_cast<unsigned long long>((estimate_frame_bytes(*scene, options, width, height) + (1u << 20) - 1) >> 20));
  for (const std::string& n : notes) std::printf("  %s\n", n.c_str());
  {
    const Display& d = scene->display;
    char ev[32];
    std::snprintf(ev, sizeof ev, "%+g EV", double(d.ev));
    std::printf("  display: exposure %s, tone mapping %s, 8-bit output sRGB (--linear for GL's)\n",
                d.automatic ? "auto (metered per frame)" : ev, to_string(d.tone_mapping));
  }
  {
    std::size_t pbr = 0;
    for (const Material& m : scene->materials) pbr += m.model == MaterialModel::pbr ? 1 : 0;
    std::printf("  materials: %zu pbr (glTF's BRDF), %zu gl (GL's fixed function); environment: %s%s\n", pbr,
                scene->materials.size() - pbr, describe_environment(*scene).c_str(),
                pbr == 0 && scene->environment_light.source != EnvironmentSource::none ? " (no pbr material sees it)" : "");
  }
  const Camera& cam = scene->camera;
  std::printf("  camera: %s (%s)\n", describe_camera(cam).c_str(), loaded->framed ? "facet's framing" : "the file's");
  if (!loaded->cameras.empty()) {
    std::printf("  the file's cameras (--camera INDEX or NAME):\n");
    for (const std::string& c : loaded->cameras) std::printf("    %s\n", c.c_str());
  }
  if (loaded->motion.any()) {
    std::printf("  what moves (docs/animation.md):\n");
    for (const std::string& line : describe_motion(loaded->motion)) std::printf("    %s\n", line.c_str());
  }
  if (depth_mode_for(cam, options.depth) == DepthMode::reversed) {
    std::printf("  depth: reversed-Z (near %g, far %s%s)\n", double(cam.near),
                std::isfinite(cam.far) ? std::to_string(cam.far).c_str() : "infinite",
                options.depth == DepthMode::automatic ? ": far / near is over 1e5 or infinite; --depth-mode gl for GL's" : "");
  }
  std::size_t shadowed = 0, casters = 0, receivers = 0;
  std::string methods;
  for (const auto& l : scene->lights) {
    if (!l.enabled || l.shadow.method == ShadowMethod::none) continue;
    ++shadowed;
    methods += std::string(methods.empty() ? "" : ", ") + (l.name.empty() ? "(unnamed)" : printable(l.name)) + " " +
               to_string(l.shadow.method);
    if (l.shadow.method == ShadowMethod::map) {
      methods += " " + std::to_string(l.shadow.resolution) + "^2 " + to_string(l.shadow.filter) +
                 (shadow_map_faces(l) == 6 ? " cube" : "");
    } else if (l.shadow.method == ShadowMethod::volume) {
      methods += " (stencil)";
    }
  }
  for (const auto& obj : scene->objects) casters += obj.cast_shadows, receivers += obj.receive_shadows;
  if (shadowed > 0) {
    std::printf("  shadows: %zu lights (%s), %zu casting and %zu receiving objects\n", shadowed,
                methods.c_str(), casters, receivers);
  }
  // Volumes: which caster meshes are closed (docs/shadows.md: open ones cast from both sides).
  const bool volumes = std::any_of(scene->lights.begin(), scene->lights.end(), [](const Light& l) {
    return l.enabled && l.shadow.method == ShadowMethod::volume;
  });
  if (volumes) {
    std::vector<char> casting(scene->meshes.size(), 0);
    for (const auto& obj : scene->objects) {
      if (obj.cast_shadows && !scene->meshes[obj.mesh].mesh.triangles.empty()) casting[obj.mesh] = 1;
    }
    std::string open;
    std::size_t closed = 0, open_count = 0;
    shadow::MeshEdges edges;
    for (std::size_t m = 0; m < scene->meshes.size(); ++m) {
      if (!casting[m]) continue;
      edges.build(scene->meshes[m].mesh);
      if (edges.closed) {
        ++closed;
      } else if (++open_count <= 5) {
        open += std::string(open.empty() ? "" : ", ") + printable(scene->meshes[m].name);
      }
    }
    std::printf("  volumes: exact, hard (resolution, filter and bias do not apply); %zu closed caster meshes, %zu open "
                "(%s%s): open meshes cast from both sides, with a cap for every triangle\n",
                closed, open_count, open_count ? open.c_str() : "none", open_count > 5 ? ", ..." : "");
  }
  if (!scene->textures.empty() || blended > 0 || scene->fog.mode != FogMode::none) {
    std::printf("  surfaces: %zu textures (%zu sRGB, decoded to linear before filtering; %llu KiB with their mipmaps), "
                "%zu textured (%zu with an emissive texture) and %zu blended objects (drawn %s), fog %s\n",
                scene->textures.size(), srgb_textures, static_cast<unsigned long long>((4 * texels + 1023) / 1024), textured, emissive,
                blended,
                scene->transparent_order == TransparentOrder::back_to_front ? "back to front, after the opaque ones"
                                                                             : "in scene order",
                to_string(scene->fog.mode));
  }
  {  // baked light: the lightmapped objects, their atlases and what they hold
    std::size_t lightmapped = 0, replace = 0, lightmap_bytes = 0, largest_side = 0;
    std::vector<char> counted(scene->textures.size(), 0);
    for (const auto& obj : scene->objects) {
      if (obj.lightmap < 0) continue;
      ++lightmapped;
      replace += obj.lightmap_mode == LightmapMode::replace;
      const Texture& t = scene->textures[static_cast<std::size_t>(obj.lightmap)];
      largest_side = std::max({largest_side, static_cast<std::size_t>(t.width()), static_cast<std::size_t>(t.height())});
      if (!counted[static_cast<std::size_t>(obj.lightmap)]++) lightmap_bytes += 4 * std::size_t(t.width()) * std::size_t(t.height());
    }
    if (lightmapped > 0) {
      std::printf("  lightmaps: %zu objects (%zu replacing their lighting, %zu keeping the lights' specular), atlases up to "
                  "%zu texels a side, %zu KiB at level 0; colour = emission + diffuse x texture x lightmap x scale\n",
                  lightmapped, replace, lightmapped - replace, largest_side, (lightmap_bytes + 1023) / 1024);
    }
  }
  const std::size_t coverage = static_cast<std::size_t>(
      std::count_if(scene->materials.begin(), scene->materials.end(), [](const Material& m) { return m.alpha_to_coverage; }));
  if (coverage > 0) {
    std::printf("  alpha to coverage: %zu materials; %s\n", coverage,
                options.samples > 1 ? ("sample s of " + std::to_string(options.samples) + " kept where alpha > s / " +
                                       std::to_string(options.samples)).c_str()
                                    : "NOT applied: it needs samples, use --msaa 4, 8 or 16");
  }
  std::size_t environment[4] = {}, mirrored = 0, dynamic = 0, dynamic_bytes = 0;
  for (const Material& m : scene->materials) ++environment[static_cast<int>(m.environment.mode)];
  for (const auto& obj : scene->objects) {
    const Environment& e = scene->materials[obj.material].environment;
    mirrored += !obj.mesh_materials && e.mode != EnvironmentMode::none;
    if (obj.mesh_materials || !e.dynamic) continue;
    ++dynamic;
    dynamic_bytes += 6 * std::size_t(e.resolution) * std::size_t(e.resolution) * 4;
  }
  if (environment[1] + environment[2] + environment[3] > 0) {
    std::printf("  environment: %zu sphere-mapped, %zu cube-mapped and %zu normal-mapped materials on %zu objects; "
                "generated per vertex in flat and Gouraud shading, per pixel in Phong\n",
                environment[1], environment[2], environment[3], mirrored);
  }
  if (dynamic > 0) {
    std::printf("  dynamic environments: %zu objects, 6 face passes each every frame (%zu KiB of faces)\n", dynamic,
                (dynamic_bytes + 1023) / 1024);
  }
  // Relief: normal-mapped objects, and where the map is not applied.
  std::size_t normal_mapped = 0, coloured = 0, occluded = 0, bumped = 0;
  for (const auto& obj : scene->objects) {
    if (obj.mesh_materials) {
      for (const MaterialGroup& g : scene->meshes[obj.mesh].mesh.groups) {
        const std::int64_t m = find_material(*scene, g.material);
        normal_mapped += m >= 0 && scene->materials[std::size_t(m)].normal_texture != kNoTexture;
        occluded += m >= 0 && scene->materials[std::size_t(m)].occlusion_texture != kNoTexture;
        bumped += m >= 0 && scene->materials[std::size_t(m)].bump_texture != kNoTexture;
      }
      continue;
    }
    occluded += scene->materials[obj.material].occlusion_texture != kNoTexture;
    bumped += scene->materials[obj.material].bump_texture != kNoTexture;
    if (scene->materials[obj.material].normal_texture != kNoTexture) {
      ++normal_mapped;
      coloured += !scene->meshes[obj.mesh].mesh.colors.empty();
    }
  }
  if (normal_mapped + occluded + bumped > 0) {
    std::printf("  relief: %zu normal-mapped, %zu occlusion-mapped and %zu bump-mapped objects (or material groups), "
                "tangent space (MikkTSpace where the file has no tangents); %s%s\n",
                normal_mapped, occluded, bumped,
                options.shading == ShadingMode::phong ? "lit per pixel"
                : options.shading == ShadingMode::gouraud && options.vertex_relief
                    ? "normal and bump maps perturb the vertex normals (--vertex-relief; occlusion maps are lit per pixel only)"
                    : "NOT applied: normal, occlusion and bump maps are lit per pixel, use --shading phong, or "
                      "--vertex-relief with Gouraud (bump maps move 2D environment maps per vertex)",
                coloured > 0 ? "; not applied to objects with vertex colours" : "");
  }
  std::size_t projectors = 0;
  for (const Light& l : scene->lights) projectors += l.enabled && l.type == LightType::spot && l.projector.texture >= 0;
  if (projectors > 0) {
    std::printf("  projectors: %zu spot lights project a picture; %s\n", projectors,
                options.shading == ShadingMode::phong ? "lit per pixel" : "NOT applied: projectors are lit per pixel, use --shading phong");
  }
  std::size_t phong_lobes = 0, linear_range = 0;
  for (const Material& m : scene->materials) phong_lobes += m.specular_model == SpecularModel::phong;
  for (const Light& l : scene->lights) linear_range += l.type != LightType::directional && l.attenuation_model == AttenuationModel::linear_range;
  if (phong_lobes + linear_range > 0) {
    std::printf("  lighting: %zu materials on Phong's R.V lobe (the rest Blinn's n.h), %zu lights with linear "
                "min/max range attenuation (each costs nothing beyond max + min)\n",
                phong_lobes, linear_range);
  }
  if (st.fields) print_fields(*scene);
  return 0;
}

}  // namespace facet::cli
