// Shared helpers of the facet command-line program.
#pragma once

#include <chrono>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "facet/facet.hpp"

namespace facet::cli {

// `s` as the inside of a JSON string: quotes, backslashes and control characters escaped.
std::string json_escape(const std::string& s);
// The context of a measurement, a JSON object: facet's version, the commit (when built from a git
// checkout), build type, compiler, CPU model, hardware threads, the CPU's best ISA and, when
// given, the ISA and pow method used and the threads asked for (0: all cores). Values not known
// are left out.
std::string json_context(const std::string& isa = "", const std::string& pow = "", int threads = -1);
// {"median", "min", "max", "count"} of repeated measurements (null for none).
std::string json_spread(std::vector<double> values);

// Prints "facet: message" to stderr and returns the usage-error exit status (2).
int fail(const std::string& message);

// CLI11 validators whose messages name what was expected and what was found (CLI11 prefixes the
// option: "--width: expected an integer in [1, 16384], found '20000'").
CLI::Validator int_in(long lo, long hi);
CLI::Validator number_in(double lo, double hi);
// `what` names the kind of value in the message: "unknown shading 'x' (flat, gouraud or phong)".
CLI::Validator one_of(std::vector<std::string> names, const std::string& what);

// A subcommand: its CLI11 app (options bound to the command's own state) and what runs it.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};
Command add_render(CLI::App& facet);
Command add_compare(CLI::App& facet);
Command add_compare_runs(CLI::App& facet);
Command add_light(CLI::App& facet);
Command add_check(CLI::App& facet);
Command add_accuracy(CLI::App& facet);
Command add_bake(CLI::App& facet);

std::optional<LightingPath> parse_path(const std::string& name);
std::optional<Isa> parse_isa(const std::string& name);  // "auto" -> Isa::best
std::optional<PowTier> parse_pow_tier(const std::string& name);
std::optional<ShadingMode> parse_shading(const std::string& name);  // flat, gouraud, phong
// --shadows: none, map, raycast (volume is refused by the scene's validation).
std::optional<ShadowMethod> parse_shadow_method(const std::string& name);
// Every light of `scene` casts shadows by `method` (none: no light does).
void override_shadows(Scene& scene, ShadowMethod method);
// --transparent-order: submission, back_to_front ("" when not given: the scene's own).
std::optional<TransparentOrder> parse_transparent_order(const std::string& name);
inline constexpr const char* kTransparentOrderHelp =
    "submission | back_to_front: the order blended objects are drawn in (default: the scene's; scene files "
    "submission, models back_to_front)";
// --exposure EV|auto and --tone-mapping none|neutral|aces over the scene's own display ("" when
// not given). Prints the error and returns false for an exposure that is neither.
bool apply_display_options(const std::string& exposure, const std::string& tone_mapping, Display& display);
// --environment-image studio|none|FILE, --environment-intensity K, --environment-rotation DEG:
// what PBR materials see around them, over the scene's own (Scene::environment_light).
struct EnvironmentState {
  std::string image;
  double intensity = -1.0, rotation_deg = 1e9;  // not given
  std::string background;                       // "", "colour" or "environment"
};
void add_environment_options(CLI::App* app, EnvironmentState& st, const char* group = nullptr);
// Reads the picture (a file the user named: not confined to the scene's folder) within the
// memory budget; prints the error and returns false when it cannot.
bool apply_environment_options(const EnvironmentState& st, std::uint64_t memory_budget_bytes, Scene& scene);
// One line: "studio", "none" or "image 2048x1024", with the intensity and rotation.
std::string describe_environment(const Scene& scene);

// "reference", "scalar", or "simd avx512 (pow auto)" with `best` resolved.
std::string describe_path(LightingPath path, Isa isa, PowTier tier);

// A path's extension in lower case (".png"), or "".
std::string lower_extension(const std::string& path);

// True for the files `facet render` reads as models rather than scene files: .gltf, .glb, .obj.
bool is_model_path(const std::string& path);

inline constexpr const char* kAllowPathHelp =
    "a folder whose files a scene or model may name, besides its own folder (repeatable; by default files outside "
    "the folder of the file given are not read)";

struct InputOptions {
  std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes;
  bool allow_missing = true;  // false with --strict (--allow-missing, the default, says so)
  bool gl_materials = false;  // --gl-materials: ModelOptions::gl_materials, LoadOptions::gl_materials
  std::vector<std::string> allowed_paths;  // --allow-path: AssetAccess::allowed_roots
  float aspect = 16.0f / 9.0f; // of the image, for framing a model without a camera
  ViewOptions view;            // --view, --up, --fov
  bool reframe = false;        // --view, --fov, --projection or --ignore-camera: frame even a file that has a camera
  std::string camera;          // --camera: ModelOptions::camera
  // A scene file's load asks it whether to go on (LoadOptions::progress): --time-limit; the
  // message printed when it said no.
  std::function<bool(double done)> progress;
  std::string cancelled_message;
  // Told of every file the load read, and its bytes (AssetAccess::on_read).
  std::function<void(const std::string& name, const std::string& bytes)> on_read;
  // --animation INDEX|NAME and --time SECONDS (NaN: not given): a glTF model's pose.
  std::string animation;
  double time = std::numeric_limits<double>::quiet_NaN();
};

// The options that say where a framing camera looks from (render, check, light).
struct ViewState {
  std::string view, up = "y";
  double fov_deg = 0.0;  // 0: not given
  bool ignore_camera = false;
  std::string projection;  // --projection: "" (not given), perspective, orthographic
  std::string camera;      // --camera INDEX|NAME: a glTF file's camera
};
void add_view_options(CLI::App* app, ViewState& st, const char* group = nullptr);
// Sets input.view and input.reframe from the parsed options; prints and returns false if --view
// is malformed.
bool apply_view_options(const ViewState& st, InputOptions& input);

struct Input {
  Scene scene;
  bool framed = false;       // the camera is facet's framing, not the file's
  std::size_t rig_first = 0;  // facet's default rig is lights [rig_first, end); none when == lights.size()
  std::vector<std::string> cameras;  // a glTF file's cameras (Model::cameras), for --camera
  // A glTF model that moves: what posing it again needs (pose_input), and what --animation chose.
  std::shared_ptr<const Rig> rig;
  MotionInfo motion;
  bool file_camera = false;  // the scene's camera is the file's (it follows its node)
  int animation = -1;
  double seconds = 0.0;
  Bounds moving;  // the box over the animation (animation_bounds), when one is chosen
};
// The input's model posed at `seconds` into its animation (Input::animation); nothing for a
// model that does not move.
Status pose_input(Input& input, double seconds);
// "  animations: 0 \"Walk\" 0 to 1.25 s (24 channels); skins: ...", for check and render's notes.
std::vector<std::string> describe_motion(const MotionInfo& motion);
// What a --json record says of its input ("input": {"name", "hash", "files"}): the file's name and
// a hash of the bytes of every file the load read (FNV-1a 64 over each file's size and bytes, in
// the order read), so that facet compare-runs can tell records of different inputs apart, and
// of the same input moved or renamed alike.
struct InputIdentity {
  std::string name;  // the file's name without its folder; "built-in scene"
  std::uint64_t hash = 0xcbf29ce484222325ull;
  int files = 0;
  void add(const std::string& bytes);
  // "\"input\": {...}, "
  std::string json_field() const;
};

// --shading as given, or its default for the input: phong for a model (.gltf, .glb, .obj: lit per
// pixel, as a viewer lights it; a spot's pool on a two-triangle floor does not show per vertex),
// gouraud for a scene file and the built-in scene (GL's fixed function, as the llvmpipe comparisons
// draw them).
std::string default_shading(const std::string& given, const std::string& input_path);

// "eye (..), target (..), fov 45 deg" or "..., orthographic, half height 2".
std::string describe_camera(const Camera& c);

// The background pixel as a frame of `scene` drawn with `options` into `format` stores it (the clear
// colour through the scene's display and the output encoding), found by drawing an empty 1 x 1
// frame the same way: once per run, for nothing_visible.
std::vector<std::uint8_t> background_pixel(const Scene& scene, const RenderOptions& options, PixelFormat format);
// The verdict `render` and `check` share (exit status 1 when it is not empty): why the frame in
// `image` shows nothing. No pixel filled: explain_empty_frame's reason. Every pixel still
// `background` (background_pixel): fully transparent materials, or a model the colour of the
// background. Empty when something shows.
std::string nothing_visible(const FrameStats& stats, const ImageView& image, const std::vector<std::uint8_t>& background);
// A scene file, a model (framed by a camera and lit by the default rig when the file has none;
// `notes` says so, with the model's warnings) or, for an empty path, the built-in scene. Prints
// the error and returns nothing on failure.
std::optional<Input> load_input(const std::string& path, const InputOptions& options, std::vector<std::string>& notes);

// --time-limit S: a deadline that progress callbacks check. `expired()` is false while there is
// time left (always, with no limit); the message names the limit.
class Deadline {
 public:
  explicit Deadline(double seconds = 0);
  bool expired() const;
  std::string message(const std::string& what) const;

 private:
  double seconds_;
  std::chrono::steady_clock::time_point end_;
};
inline constexpr const char* kTimeLimitHelp =
    "stop with an error (exit 2) if the job is not done after S seconds, loading included (default: no limit)";

// The output image (and a depth image) that `facet render` allocates, against the memory budget
// (0 = no limit): `facet check` makes the same check.
Status check_output_image(int width, int height, PixelFormat format, bool depth, std::uint64_t budget);

// Lights every object of `scene` into out[i] (light_instance for each), through `lighter` (kept by
// a caller that lights again and again) or a Lighter of its own.
Status light_scene(Lighter& lighter, const Scene& scene, const LightingOptions& options, std::vector<VertexColors>& out);
Status light_scene(const Scene& scene, const LightingOptions& options, std::vector<VertexColors>& out);


}  // namespace facet::cli
