#include "cli.hpp"

#include "common/format.hpp"
#include "common/try.hpp"

#include <cerrno>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <limits>

namespace facet::cli {

std::string json_escape(const std::string& s) {
  std::string o;
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char u[8];
      std::snprintf(u, sizeof u, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      o += u;
    } else {
      o += c;
    }
  }
  return o;
}

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

bool apply_display_options(const std::string& exposure, const std::string& tone_mapping, Display& display) {
  if (exposure == "auto") {
    display.automatic = true;
  } else if (!exposure.empty()) {
    char* stop = nullptr;
    const float ev = std::strtof(exposure.c_str(), &stop);
    if (stop != exposure.c_str() + exposure.size() || !(ev >= -30.0f && ev <= 30.0f)) {
      fail("--exposure: expected stops in [-30, 30] or auto, found '" + json_escape(exposure.substr(0, 40)) + "'");
      return false;
    }
    display.automatic = false;
    display.ev = ev;
  }
  for (ToneMapping t : {ToneMapping::none, ToneMapping::neutral, ToneMapping::aces}) {
    if (tone_mapping == to_string(t)) display.tone_mapping = t;
  }
  return true;
}

void override_shadows(Scene& scene, ShadowMethod method) {
  for (Light& l : scene.lights) l.shadow.method = method;
}

std::string describe_path(LightingPath path, Isa isa, PowTier tier) {
  if (path != LightingPath::simd) return to_string(path);
  return std::string("simd ") + to_string(isa == Isa::best ? best_isa() : isa) + " (pow " + to_string(tier) + ")";
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool is_model_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".gltf" || ext == ".glb" || ext == ".obj";
}

void add_environment_options(CLI::App* app, EnvironmentState& st, const char* group) {
  auto in_group = [&](CLI::Option* o) {
    if (group) o->group(group);
  };
  in_group(app->add_option("--environment-image", st.image,
                           "studio | none | FILE (.hdr, .exr, .png, .jpg; equirectangular): what PBR materials see around them "
                           "(default: the scene's; a glTF model without lights: studio, facet's neutral one)"));
  in_group(app->add_option("--environment-intensity", st.intensity, "the surroundings' radiance times K (default 1)")
               ->check(number_in(0, 1e6)));
  in_group(app->add_option("--environment-rotation", st.rotation_deg,
                           "turns the surroundings by DEG about the world's +Y axis (default 0)")
               ->check(number_in(-3600, 3600)));
  in_group(app->add_option("--background", st.background,
                           "colour | environment: what is drawn behind the model, the clear colour (default) or the "
                           "surroundings, exposed and tone-mapped with the model")
               ->check(CLI::IsMember({"colour", "color", "environment"})));
}

bool apply_environment_options(const EnvironmentState& st, std::uint64_t memory_budget_bytes, Scene& scene) {
  EnvironmentLight& e = scene.environment_light;
  if (st.image == "studio" || st.image == "none") {
    const float intensity = e.intensity, rotation = e.rotation_deg;
    e = EnvironmentLight{};
    e.source = st.image == "studio" ? EnvironmentSource::studio : EnvironmentSource::none;
    e.intensity = intensity, e.rotation_deg = rotation;
  } else if (!st.image.empty()) {
    Result<EnvironmentLight> picture = load_environment_image(st.image, {}, memory_budget_bytes);
    if (!picture) {
      fail("--environment-image: " + picture.status().message());
      return false;
    }
    const float intensity = e.intensity, rotation = e.rotation_deg;
    e = std::move(*picture);
    e.intensity = intensity, e.rotation_deg = rotation;
  }
  if (st.intensity >= 0.0) e.intensity = float(st.intensity);
  if (st.rotation_deg < 1e8) e.rotation_deg = float(st.rotation_deg);
  if (!st.background.empty()) scene.background = st.background == "environment" ? Background::environment : Background::colour;
  return true;
}

std::string describe_environment(const Scene& scene) {
  const EnvironmentLight& e = scene.environment_light;
  std::string s = to_string(e.source);
  if (e.source == EnvironmentSource::image) s += " " + std::to_string(e.width) + "x" + std::to_string(e.height);
  if (e.source != EnvironmentSource::none) {
    s += ", intensity " + format_number(e.intensity) + ", rotation " + format_number(e.rotation_deg) + " deg";
  }
  if (scene.background == Background::environment) s += ", drawn behind the model";
  return s;
}

void add_view_options(CLI::App* app, ViewState& st, const char* group) {
  auto in_group = [&](CLI::Option* o) {
    if (group) o->group(group);
  };
  in_group(app->add_option("--view", st.view,
                           "AZIMUTH,ELEVATION in degrees: where facet's framing camera looks from (default 0,0: the front; "
                           "90,0 from +X; 0,30 from the front and above); frames even a file that has a camera"));
  in_group(app->add_option("--up", st.up,
                           "y | z | x | -x | -y | -z: the model's up axis (default y, glTF's; z: CAD and Blender's, the front faces "
                           "-Y); write a negative axis as --up=-z")
               ->check(one_of({"y", "z", "x", "-x", "-y", "-z", "+x", "+y", "+z"}, "up axis")));
  in_group(app->add_option("--fov", st.fov_deg, "the framing camera's vertical field of view in degrees (default 45); frames even a file that has a camera")
               ->check(number_in(1, 170)));
  in_group(app->add_option("--projection", st.projection,
                           "perspective | orthographic: the framing camera's projection (orthographic: parallel rays, no "
                           "foreshortening); frames even a file that has a camera")
               ->check(one_of({"perspective", "orthographic"}, "projection")));
  in_group(app->add_option("--camera", st.camera,
                           "INDEX | NAME: which of a glTF file's cameras to look through, by its index in the file's cameras "
                           "or its (or its node's) name (default: the first in the scene; facet check lists them)"));
  in_group(app->add_flag("--ignore-camera", st.ignore_camera, "frame the model even when its file has a camera"));
}

bool apply_view_options(const ViewState& st, InputOptions& input) {
  if (!parse_up_axis(st.up, input.view.up)) {
    fail("--up: expected y, z, x, -x, -y or -z, found '" + json_escape(st.up.substr(0, 40)) + "'");
    return false;
  }
  if (st.fov_deg > 0.0) input.view.vertical_fov_deg = static_cast<float>(st.fov_deg);
  if (st.projection == "orthographic") input.view.projection = Projection::orthographic;
  if (!st.camera.empty() && (st.ignore_camera || !st.view.empty() || st.fov_deg > 0.0 || !st.projection.empty())) {
    fail("--camera looks through the file's camera: it cannot be combined with --view, --fov, --projection or --ignore-camera, "
         "which frame the model with facet's");
    return false;
  }
  input.camera = st.camera;
  if (!st.view.empty()) {
    const std::size_t comma = st.view.find(',');
    char* end = nullptr;
    bool ok = comma != std::string::npos;
    if (ok) {
      const std::string az = st.view.substr(0, comma), el = st.view.substr(comma + 1);
      input.view.azimuth_deg = std::strtof(az.c_str(), &end);
      ok = !az.empty() && end == az.c_str() + az.size();
      input.view.elevation_deg = std::strtof(el.c_str(), &end);
      ok = ok && !el.empty() && end == el.c_str() + el.size();
    }
    if (!ok || !validate_view(input.view).ok()) {
      fail("--view: expected AZIMUTH,ELEVATION in degrees, elevation in (-90, 90), found '" + json_escape(st.view.substr(0, 40)) + "'");
      return false;
    }
  }
  input.reframe = st.ignore_camera || !st.view.empty() || st.fov_deg > 0.0 || !st.projection.empty();
  return true;
}

std::string default_shading(const std::string& given, const std::string& input_path) {
  if (!given.empty()) return given;
  return is_model_path(input_path) ? "phong" : "gouraud";
}

std::string describe_camera(const Camera& c) {
  char buf[220];
  if (c.projection == Projection::orthographic) {
    std::snprintf(buf, sizeof buf, "eye (%.4g, %.4g, %.4g), target (%.4g, %.4g, %.4g), orthographic, half height %.4g", c.eye.x(),
                  c.eye.y(), c.eye.z(), c.target.x(), c.target.y(), c.target.z(), c.half_height);
  } else {
    std::snprintf(buf, sizeof buf, "eye (%.4g, %.4g, %.4g), target (%.4g, %.4g, %.4g), fov %.4g deg", c.eye.x(), c.eye.y(),
                  c.eye.z(), c.target.x(), c.target.y(), c.target.z(), c.vertical_fov_deg);
  }
  return buf;
}

void InputIdentity::add(const std::string& bytes) {
  const auto mix = [this](unsigned char c) { hash = (hash ^ c) * 0x100000001b3ull; };
  for (int k = 0; k < 8; ++k) mix(static_cast<unsigned char>(std::uint64_t(bytes.size()) >> (8 * k)));
  for (const char c : bytes) mix(static_cast<unsigned char>(c));
  ++files;
}

std::string InputIdentity::json_field() const {
  char hex[24];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return "\"input\": {\"name\": \"" + json_escape(name) + "\", \"hash\": \"" + (files ? std::string("fnv1a64:") + hex : std::string()) +
         "\", \"files\": " + std::to_string(files) + "}, ";
}

std::vector<std::uint8_t> background_pixel(const Scene& scene, const RenderOptions& options, PixelFormat format) {
  Scene empty;
  empty.display = scene.display;
  const std::size_t bpp = bytes_per_pixel(format);
  std::vector<std::uint8_t> pixel(bpp);
  RenderOptions one = options;
  one.threads = 1;
  if (!Renderer().render(empty, one, {pixel.data(), 1, 1, bpp, format, false}).ok()) return {};
  return pixel;
}

std::string nothing_visible(const FrameStats& stats, const ImageView& image, const std::vector<std::uint8_t>& background) {
  if (stats.pixels_filled == 0) return explain_empty_frame(stats);
  const std::size_t bpp = bytes_per_pixel(image.format);
  if (background.size() != bpp) return {};  // no background to compare with: something shows
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* row = static_cast<const std::uint8_t*>(image.data) + static_cast<std::size_t>(y) * image.stride_bytes;
    for (int x = 0; x < image.width; ++x) {
      if (std::memcmp(row + static_cast<std::size_t>(x) * bpp, background.data(), bpp) != 0) return {};
    }
  }
  return std::to_string(stats.pixels_filled) +
         " pixels were drawn, but every pixel is still the background colour: the materials are fully transparent "
         "(alpha 0), or the model has the background's colour (try --clear 0.5,0.5,0.5)";
}

namespace {

// Frames `scene` for `options`; prints and returns false when it cannot.
bool frame(Scene& scene, const std::string& path, const InputOptions& options, const std::string& why,
           std::vector<std::string>& notes) {
  Result<Camera> framed = frame_scene(scene, options.aspect, options.view);
  if (!framed) {
    for (const std::string& n : notes) std::fprintf(stderr, "facet: %s\n", n.c_str());  // why, often
    fail(path + ": " + framed.status().message());
    return false;
  }
  scene.camera = *framed;
  char view[120];
  std::snprintf(view, sizeof view, "azimuth %.4g, elevation %.4g, %s up", options.view.azimuth_deg,
                options.view.elevation_deg, to_string(options.view.up));
  notes.push_back(why + ": framing it (" + view + "): " + describe_camera(scene.camera));
  return true;
}

}  // namespace

std::optional<Input> load_input(const std::string& path, const InputOptions& options, std::vector<std::string>& notes) {
  Input input;
  input.rig_first = std::numeric_limits<std::size_t>::max();
  if (!options.camera.empty() && (!is_model_path(path) || lower_extension(path) == ".obj")) {
    fail("--camera picks one of a glTF file's cameras; " + (path.empty() ? std::string("the built-in scene") : json_escape(path)) +
         " is not a glTF file");
    return std::nullopt;
  }
  if (path.empty()) {
    input.scene = make_default_scene();
    if (options.reframe && !frame(input.scene, "built-in scene", options, "--view, --fov, --projection or --ignore-camera", notes)) return std::nullopt;
    input.framed = options.reframe;
    input.rig_first = input.scene.lights.size();
    return input;
  }
  {
    const std::string ext = lower_extension(path);
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
    lo.assets.on_read = options.on_read;
    lo.progress = options.progress;
    lo.view = options.view;
    lo.frame_aspect = options.aspect;
    lo.strict = !options.allow_missing;
    lo.gl_materials = options.gl_materials;
    lo.warning = [&](const std::string& w) { notes.push_back("warning: " + w); };
    Result<Scene> loaded = load_scene_file(path, lo);
    if (!loaded) {
      const bool stopped = loaded.status().code() == ErrorCode::cancelled && !options.cancelled_message.empty();
      fail(stopped ? options.cancelled_message : loaded.status().message());
      return std::nullopt;
    }
    input.scene = std::move(*loaded);
    if (options.reframe && !frame(input.scene, path, options, "--view, --fov, --projection or --ignore-camera", notes)) return std::nullopt;
    input.framed = options.reframe;
    // The rig a scene file that imports models gets when nothing else lights it (LoadOptions::view).
    const auto& lights = input.scene.lights;
    const bool rig = lights.size() == 2 && lights[0].name == "headlight" && lights[1].name == "key light";
    input.rig_first = rig ? 0 : lights.size();
    return input;
  }
  ModelOptions mo;
  mo.memory_budget_bytes = options.memory_budget_bytes;
  mo.allow_missing = options.allow_missing;
  mo.gl_materials = options.gl_materials;
  mo.assets.allowed_roots = options.allowed_paths;
  mo.assets.on_read = options.on_read;
  mo.camera = options.camera;
  Result<Model> model = load_model(path, mo);
  if (!model) {
    fail(model.status().message());
    return std::nullopt;
  }
  for (const std::string& w : model->warnings) notes.push_back("warning: " + w);
  input.cameras = model->cameras;
  input.rig = model->rig;
  input.motion = model->motion;
  input.file_camera = model->has_camera && !options.reframe;
  const bool posed = !options.animation.empty() || !std::isnan(options.time);
  if (posed && model->motion.animations.empty()) {
    if (!options.animation.empty()) {
      fail(path + ": --animation: the model has no animations");
      return std::nullopt;
    }
    notes.push_back("--time: the model has no animations; drawn as the file places it");
  } else if (posed) {
    Result<int> chosen = find_animation(*model, options.animation.empty() ? "0" : options.animation);
    if (!chosen) {
      fail(path + ": --animation: " + chosen.status().message());
      return std::nullopt;
    }
    input.animation = *chosen;
    const AnimationInfo& a = model->motion.animations[std::size_t(*chosen)];
    input.seconds = std::isnan(options.time) ? a.start_s : options.time;
    PoseOptions po;
    po.animation = input.animation;
    if (Status s = pose_model(*model, input.seconds, po); !s.ok()) {
      fail(path + ": " + s.message());
      return std::nullopt;
    }
  }
  // An animated model is framed over its animation (every vertex of its poses at 16 times): it
  // does not walk out of the picture; its box over 32 times is what a turntable turns about.
  std::optional<Camera> moving_camera;
  if (input.animation >= 0) {
    PoseOptions po;
    po.animation = input.animation;
    Result<Bounds> box = animation_bounds(*model, po);
    if (!box) {
      fail(path + ": " + box.status().message());
      return std::nullopt;
    }
    input.moving = *box;
    if (!model->has_camera || options.reframe) {
      Result<Camera> framed = frame_animation(*model, options.aspect, options.view, po);
      if (!framed) {
        fail(path + ": " + framed.status().message());
        return std::nullopt;
      }
      moving_camera = *framed;
    }
  }
  input.scene = std::move(model->scene);
  Scene& scene = input.scene;
  if (moving_camera) {
    scene.camera = *moving_camera;
    notes.push_back(std::string(model->has_camera ? "--view, --fov, --projection or --ignore-camera" : "no camera in the file") +
                    ": framing the whole animation: " + describe_camera(scene.camera));
    input.framed = true;
  } else if (!model->has_camera || options.reframe) {
    if (!frame(scene, path, options, model->has_camera ? "--view, --fov, --projection or --ignore-camera" : "no camera in the file", notes)) {
      return std::nullopt;
    }
    input.framed = true;
  }
  input.rig_first = scene.lights.size();
  if (!model->has_lights) {
    notes.push_back(std::string("no lights in the file: ") + add_default_lights(scene));
  }
  return input;
}

Status pose_input(Input& input, double seconds) {
  if (!input.rig) return {};
  PoseOptions po;
  po.animation = input.animation;
  FACET_TRY(pose_scene(input.scene, input.rig.get(), input.file_camera, seconds, po));
  input.seconds = seconds;
  return {};
}

std::vector<std::string> describe_motion(const MotionInfo& motion) {
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < motion.animations.size(); ++i) {
    const AnimationInfo& a = motion.animations[i];
    lines.push_back("animation " + std::to_string(i) + " " + json_escape(a.name) + ": " + format_number(a.start_s) + " to " +
                    format_number(a.end_s) + " s, " + std::to_string(a.channels) + " channels (--animation " + std::to_string(i) +
                    " --time SECONDS, or --frames N)");
  }
  for (const SkinInfo& s : motion.skins) {
    lines.push_back("skin " + json_escape(s.name) + ": " + std::to_string(s.joints) + " joints, " + std::to_string(s.vertices) +
                    " vertices, " + std::to_string(s.influences) + " influences per vertex");
  }
  if (motion.morphed_meshes > 0) {
    lines.push_back("morph targets: " + std::to_string(motion.morph_targets) + " over " + std::to_string(motion.morphed_meshes) + " meshes");
  }
  return lines;
}

Deadline::Deadline(double seconds)
    : seconds_(seconds),
      end_(std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                  std::chrono::duration<double>(seconds > 0 ? seconds : 0))) {}

bool Deadline::expired() const { return seconds_ > 0 && std::chrono::steady_clock::now() >= end_; }

std::string Deadline::message(const std::string& what) const {
  return what + ": stopped at the time limit of " + format_number(seconds_) + " s (--time-limit)";
}

Status check_output_image(int width, int height, PixelFormat format, bool depth, std::uint64_t budget) {
  const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
  const std::uint64_t bytes = pixels * bytes_per_pixel(format) + (depth ? 4 * pixels : 0);
  if (budget != 0 && bytes > budget) {
    return {ErrorCode::out_of_memory, "memory_budget_bytes",
            "--memory-budget-mb: a " + std::to_string(width) + " x " + std::to_string(height) + " image" +
                (depth ? " and its depth take " : " takes ") + format_bytes(bytes) + ", over the budget of " +
                format_bytes(budget)};
  }
  return {};
}

Status light_scene(Lighter& lighter, const Scene& scene, const LightingOptions& options, std::vector<VertexColors>& out) {
  out.resize(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (Status s = lighter.light_instance(scene, i, options, out[i]); !s.ok()) return s;
  }
  return {};
}

Status light_scene(const Scene& scene, const LightingOptions& options, std::vector<VertexColors>& out) {
  Lighter lighter;
  return light_scene(lighter, scene, options, out);
}

}  // namespace facet::cli
