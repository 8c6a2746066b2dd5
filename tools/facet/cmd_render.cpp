// facet render: a scene into a PNG, PFM or EXR file, with statistics and throughput.
#include <chrono>
#include <array>
#include <memory>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <future>
#include <numbers>
#include <vector>

#include "cli.hpp"
#include "common/format.hpp"

namespace facet::cli {
namespace {



void print_stats_text(const FrameStats& s, int frames, double seconds) {
  std::printf("  triangles   %llu in: %llu drawn, %llu culled, %llu outside, %llu clipped, %llu degenerate, "
              "%llu between pixel centres, %llu non-finite; %llu bin entries\n",
              (unsigned long long)s.triangles_in, (unsigned long long)s.triangles_drawn,
              (unsigned long long)s.triangles_culled, (unsigned long long)s.triangles_outside,
              (unsigned long long)s.triangles_clipped, (unsigned long long)s.triangles_degenerate,
              (unsigned long long)s.triangles_small,
              (unsigned long long)s.triangles_nonfinite, (unsigned long long)s.bin_entries);
  std::printf("  lighting    %llu evaluations (vertices, centroids or pixels), %llu vertices not lit (no drawable "
              "triangle uses them); %llu vertex-light pairs evaluated, %llu skipped by the frame plan\n",
              (unsigned long long)s.vertices_lit, (unsigned long long)s.vertices_skipped,
              (unsigned long long)s.vertex_lights_evaluated,
              (unsigned long long)s.vertex_lights_skipped);
  std::printf("  pixels      %llu tested, %llu filled\n", (unsigned long long)s.pixels_tested,
              (unsigned long long)s.pixels_filled);
  if (s.shadow_casters > 0 || s.seconds_shadows > 0) {
    std::printf("  shadows     %llu caster triangles, %.3f ms (ray-cast hierarchy; maps, camera depth and volumes drawn)",
                (unsigned long long)s.shadow_casters, 1e3 * s.seconds_shadows);
    if (s.shadow_map_texels > 0) {
      std::printf("; maps: %.2f M texels, %.2f M written by casters", double(s.shadow_map_texels) / 1e6,
                  double(s.shadow_map_pixels) / 1e6);
    }
    std::printf("\n");
  }
  if (s.seconds_environment > 0) {
    std::printf("  environment %.3f ms (the PBR materials' DFG table, harmonics and prefiltered cube: once per renderer and picture)\n",
                1e3 * s.seconds_environment);
  }
  std::printf("  time (ms)   lighting %.3f, geometry %.3f, tiles %.3f (resolve %.3f of thread time), frame %.3f\n",
              1e3 * s.seconds_lighting, 1e3 * s.seconds_geometry, 1e3 * s.seconds_raster, 1e3 * s.seconds_resolve,
              1e3 * s.seconds_total);
  const double per_frame = seconds / frames;
  std::printf("  throughput  %.2f ms/frame (mean of %d), %.2f M vertices lit/s, %.1f M pixels filled/s\n",
              1e3 * per_frame, frames, double(s.vertices_lit) / per_frame / 1e6,
              double(s.pixels_filled) / per_frame / 1e6);
}

// `fields`: more "key": value pairs to open the object with ("\"frame\": 3, ").
// `frame_seconds`: each frame's time, reported as its median, min, max and count. `nothing`: why
// the frame shows nothing (nothing_visible), as "nothing_drawn"; the key is absent when it is empty.
void print_stats_json(const FrameStats& s, int frames, double seconds, const RenderOptions& o, int w, int h,
                      const std::string& fields, const std::vector<double>& frame_seconds, const std::string& display,
                      const std::string& nothing) {
  const double per_frame = seconds / frames;
  const Isa isa = o.isa == Isa::best ? best_isa() : o.isa;
  const std::string context = json_context(o.path == LightingPath::simd ? to_string(isa) : "none",
                                           o.path == LightingPath::simd ? to_string(o.pow_tier) : "std::pow", o.threads);
  std::printf("{%s\"context\": %s, \"width\": %d, \"height\": %d, \"shading\": \"%s\", \"path\": \"%s\", \"pixel_precision\": \"%s\", \"samples\": %d, %s\"threads\": %d, "
              "\"triangles_in\": %llu, \"triangles_drawn\": %llu, \"triangles_culled\": %llu, "
              "\"triangles_outside\": %llu, \"triangles_clipped\": %llu, \"triangles_degenerate\": %llu, "
              "\"triangles_small\": %llu, "
              "\"triangles_nonfinite\": %llu, \"bin_entries\": %llu, \"vertices_lit\": %llu, \"vertices_skipped\": %llu, "
              "\"vertex_lights_evaluated\": %llu, \"vertex_lights_skipped\": %llu, "
              "\"pixels_tested\": %llu, \"pixels_filled\": %llu, \"seconds_lighting\": %.6g, "
              "\"seconds_geometry\": %.6g, \"seconds_raster\": %.6g, \"seconds_resolve\": %.6g, "
              "\"shadow_casters\": %llu, \"seconds_shadows\": %.6g, \"seconds_environment\": %.6g, \"shadow_map_texels\": %llu, "
              "\"shadow_map_pixels\": %llu, "
              "\"seconds_frame\": %.6g, \"frames\": %d, \"mean_seconds_per_frame\": %.6g, "
              "\"vertices_lit_per_s\": %.6g, \"pixels_filled_per_s\": %.6g, \"frame_seconds\": %s%s}\n",
              fields.c_str(), context.c_str(), w, h, to_string(o.shading), describe_path(o.path, o.isa, o.pow_tier).c_str(),
              to_string(o.pixel_precision), o.samples, display.c_str(), s.threads,
              (unsigned long long)s.triangles_in,
              (unsigned long long)s.triangles_drawn, (unsigned long long)s.triangles_culled,
              (unsigned long long)s.triangles_outside, (unsigned long long)s.triangles_clipped,
              (unsigned long long)s.triangles_degenerate, (unsigned long long)s.triangles_small,
              (unsigned long long)s.triangles_nonfinite, (unsigned long long)s.bin_entries,
              (unsigned long long)s.vertices_lit, (unsigned long long)s.vertices_skipped,
              (unsigned long long)s.vertex_lights_evaluated,
              (unsigned long long)s.vertex_lights_skipped, (unsigned long long)s.pixels_tested, (unsigned long long)s.pixels_filled, s.seconds_lighting,
              s.seconds_geometry, s.seconds_raster, s.seconds_resolve, (unsigned long long)s.shadow_casters,
              s.seconds_shadows, s.seconds_environment, (unsigned long long)s.shadow_map_texels, (unsigned long long)s.shadow_map_pixels,
              s.seconds_total, frames, per_frame,
              double(s.vertices_lit) / per_frame, double(s.pixels_filled) / per_frame,
              json_spread(frame_seconds.empty() ? std::vector<double>{per_frame} : frame_seconds).c_str(),
              nothing.empty() ? "" : (", \"nothing_drawn\": \"" + json_escape(nothing) + "\"").c_str());
}

// What the picture did with the light: "exposure_ev": -11.2, "exposure": "auto", ... as JSON
// fields, or a line of text.
std::string display_fields(const Display& d, const RenderOptions& o, const FrameStats& s) {
  char buffer[200];
  std::snprintf(buffer, sizeof buffer, "\"output_encoding\": \"%s\", \"exposure\": \"%s\", \"exposure_ev\": %.4g, \"tone_mapping\": \"%s\", ",
                o.srgb ? "srgb" : "linear", d.automatic ? "auto" : "fixed", double(s.exposure_ev), to_string(d.tone_mapping));
  return buffer;
}
void print_display_text(const Display& d, const RenderOptions& o, const FrameStats& s) {
  std::printf("  display     exposure %+.2f EV (%s), tone mapping %s, 8-bit output %s\n", double(s.exposure_ev),
              d.automatic ? "metered" : "fixed", to_string(d.tone_mapping), o.srgb ? "sRGB" : "linear");
}

// OUT.png -> OUT_0007.png
std::string numbered(const std::string& output, int index) {
  const std::filesystem::path p(output);
  char digits[16];
  std::snprintf(digits, sizeof digits, "_%04d", index);
  return (p.parent_path() / (p.stem().string() + digits + p.extension().string())).string();
}

// A turntable's frame files, each written on its own thread while the next frame renders. The
// library renders into the caller's image, so each frame's bytes are copied first; at most one
// write is in flight, and a failed write is reported by the next wait().
class FrameWriter {
 public:
  void start(const std::string& name, const ImageView& image) {
    const std::size_t row = static_cast<std::size_t>(image.width) * bytes_per_pixel(image.format);
    std::vector<std::uint8_t> bytes(row * static_cast<std::size_t>(image.height));
    for (int y = 0; y < image.height; ++y) {
      std::memcpy(bytes.data() + static_cast<std::size_t>(y) * row,
                  static_cast<const std::uint8_t*>(image.data) + static_cast<std::size_t>(y) * image.stride_bytes, row);
    }
    const ImageView copy{nullptr, image.width, image.height, row, image.format, image.y_up};
    pending_ = std::async(std::launch::async, [name, copy, bytes = std::move(bytes)]() mutable {
      ImageView view = copy;
      view.data = bytes.data();
      const std::string ext = lower_extension(name);
      return ext == ".png" ? write_png(name, view) : ext == ".exr" ? write_exr(name, view) : write_pfm(name, view);
    });
  }
  Status wait() { return pending_.valid() ? pending_.get() : Status{}; }
  ~FrameWriter() {
    if (pending_.valid()) pending_.wait();
  }

 private:
  std::future<Status> pending_;
};

// Which lights turn with a turntable's camera: auto (facet's default rig, not the file's own
// lights), camera (all: the model seems to turn under fixed lights) or world (none).
enum class TurnLights { automatic, camera, world };

struct Turntable {
  int frames = 1;
  int first = 0, last = 1;  // the frames drawn, [first, last) (--frame-range; all by default)
  double orbit_deg = 360.0;
  TurnLights lights = TurnLights::automatic;
  bool json = false;
  std::string input;  // InputIdentity::json_field(), for the records
};

// --frames N: the camera orbits the centre of the objects' box about the up axis, `orbit_deg` in
// all, one image per frame. A framed camera keeps the distance at which every frame frames the
// model; a file's camera keeps its own distance from the centre.
int run_turntable(Renderer& renderer, Input& input, const InputOptions& in, const RenderOptions& options,
                  const ImageView& image, const std::string& output, const Turntable& t) {
  Scene& scene = input.scene;
  const bool animated = input.animation >= 0;
  const AnimationInfo* clip = animated ? &input.motion.animations[std::size_t(input.animation)] : nullptr;
  const Bounds bounds = animated ? input.moving : scene_bounds(scene);
  if (bounds.empty()) return fail("--frames: the scene has no vertices to turn around");
  const Vec3 centre = ((bounds.min.cast<double>() + bounds.max.cast<double>()) * 0.5).cast<float>();
  Camera start = scene.camera;
  // An animation with the camera still keeps the framing of its poses (load_input's).
  const bool still = animated && t.orbit_deg == 0.0;
  if (input.framed && !still) {
    // The farthest of every frame's framing distances, so that each frame holds the whole model.
    double distance = 0.0;
    for (int k = 0; k < t.frames; ++k) {
      ViewOptions view = in.view;
      view.azimuth_deg = static_cast<float>(double(view.azimuth_deg) + t.orbit_deg * k / t.frames);
      Result<Camera> c = animated ? frame_bounds(bounds, in.aspect, view) : frame_scene(scene, in.aspect, view);
      if (!c) return fail(c.status().message());
      distance = std::max(distance, (c->eye.cast<double>() - centre.cast<double>()).norm());
      if (k == 0) start = *c;
    }
    const Eigen::Vector3d dir = (start.eye.cast<double>() - start.target.cast<double>()).normalized();
    const double radius = 0.5 * (bounds.max.cast<double>() - bounds.min.cast<double>()).norm();
    start.eye = (centre.cast<double>() + distance * dir).cast<float>();
    start.target = centre;
    start.far = static_cast<float>(1.05 * (distance + radius));
    start.near = static_cast<float>(std::max(0.9 * (distance - radius), 1e-4 * double(start.far)));
  }
  const std::vector<Light> start_lights = scene.lights;
  const auto wall_start = std::chrono::steady_clock::now();
  FrameWriter writer;
  const std::vector<std::uint8_t> background = background_pixel(scene, options, image.format);  // the same every frame
  std::string first_nothing;  // why the first frame that shows nothing shows nothing
  double seconds = 0;
  std::vector<double> all_seconds;
  std::uint64_t pixels = 0;
  int empty_frames = 0;
  for (int k = t.first; k < t.last; ++k) {
    const double angle = t.orbit_deg * k / t.frames;
    // An animation's frame k is at k / N of its duration (a loop, as the turntable's angles).
    const double time = animated ? clip->start_s + (clip->end_s - clip->start_s) * k / t.frames : 0.0;
    if (animated) {
      if (Status s = pose_input(input, time); !s.ok()) return fail(s.message());
      if (input.file_camera) start = scene.camera;  // the file's camera where its node is now
    }
    scene.camera = still ? start : orbit_camera(start, centre, in.view.up, static_cast<float>(angle));
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
      const bool turn = t.lights == TurnLights::camera || (t.lights == TurnLights::automatic && i >= input.rig_first);
      if (turn) scene.lights[i] = orbit_light(start_lights[i], centre, in.view.up, static_cast<float>(angle));
      else if (!animated) scene.lights[i] = start_lights[i];  // posed lights stay where the pose put them
    }
    FrameStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    if (Status s = renderer.render(scene, options, image, nullptr, &stats); !s.ok()) return fail(s.message());
    const double frame_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    seconds += frame_seconds;
    all_seconds.push_back(frame_seconds);
    pixels += stats.pixels_filled;
    const std::string nothing = nothing_visible(stats, image, background);
    empty_frames += !nothing.empty();
    if (first_nothing.empty()) first_nothing = nothing;
    const std::string name = numbered(output, k);
    // The frame is encoded on another thread while the next one renders (PNG's deflate takes
    // longer than most frames); one frame in flight, its bytes copied.
    if (Status s = writer.wait(); !s.ok()) return fail(s.message());
    writer.start(name, image);
    if (t.json) {
      char fields[160];
      std::snprintf(fields, sizeof fields, "\"frame\": %d, \"angle_deg\": %.6g, %s", k, angle,
                    animated ? ("\"time_s\": " + format_number(time) + ", ").c_str() : "");
      print_stats_json(stats, 1, frame_seconds, options, image.width, image.height,
                       fields + std::string("\"file\": \"") + json_escape(name) + "\", " + t.input, {},
                       display_fields(scene.display, options, stats), nothing);
    } else {
      std::fprintf(stderr, "\rfacet: frame %d/%d -> %s", k - t.first + 1, t.last - t.first, name.c_str());
      std::fflush(stderr);
    }
  }
  if (Status s = writer.wait(); !s.ok()) return fail(s.message());
  const int count = t.last - t.first;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  // Exit status 1 when no frame shows anything (the verdict of a single frame, for the whole run).
  const int status = empty_frames == count ? 1 : 0;
  if (status) std::fprintf(stderr, "facet: no frame shows anything (exit status 1): %s\n", first_nothing.c_str());
  if (t.json) {
    std::printf("{\"summary\": true, %s\"context\": %s, \"frames\": %d, \"seconds_rendering\": %.6g, \"seconds_wall\": %.6g, "
                "\"mean_seconds_per_frame\": %.6g, \"frame_seconds\": %s, \"pixels_filled_per_s\": %.6g, \"empty_frames\": %d}\n",
                t.input.c_str(),
                json_context(options.path == LightingPath::simd ? to_string(options.isa == Isa::best ? best_isa() : options.isa) : "none",
                             options.path == LightingPath::simd ? to_string(options.pow_tier) : "std::pow", options.threads).c_str(),
                count, seconds, wall, seconds / count, json_spread(all_seconds).c_str(), double(pixels) / seconds, empty_frames);
    return status;
  }
  std::fprintf(stderr, "\n");
  std::printf("facet render: %d frames in %.3f s (%.3f s of rendering: %.2f ms/frame, %.1f M pixels filled/s; the rest "
              "writing the files)%s\n",
              count, wall, seconds, 1e3 * seconds / count, double(pixels) / seconds / 1e6,
              empty_frames ? (", " + std::to_string(empty_frames) + " frames show nothing").c_str() : "");
  return status;
}

}  // namespace

namespace {

struct RenderState {
  std::string scene_path, output, depth_path, frame_range, shading, shadows, path = "simd", isa = "auto", pow = "auto", pixel_precision = "auto",
                                                cull = "back", clear, transparent_order, lights = "auto", depth_mode = "auto",
                                                exposure, tone_mapping;
  int width = 1280, height = 720, threads = 0, tile = 64, memory_mb = -1, frame_count = 1, msaa = 1;
  double min_seconds = 0, orbit_deg = 360.0, time_limit = 0;
  double time = std::numeric_limits<double>::quiet_NaN();
  std::string animation;
  bool orbit_given = false;
  std::vector<std::string> allow_paths;
  ViewState view;
  bool gl_materials = false;
  EnvironmentState environment;
  bool stats = false, json = false, allow_missing = false, strict = false, hdr = false, srgb = false, linear = false, no_light_culling = false,
       light_every_vertex = false, vertex_relief = false;
};

int render(const RenderState& st);

}  // namespace

Command add_render(CLI::App& facet) {
  auto st = std::make_shared<RenderState>();
  CLI::App* app = facet.add_subcommand("render", "render a scene, a model or the built-in scene to PNG, PFM or EXR");
  app->footer(
      "Renders a scene file, a model (.gltf, .glb, .obj with .mtl) or, when none is given, the built-in\n"
      "scene. A model without a camera is framed by one; a model without lights gets a headlight and a\n"
      "key light (what was assumed is printed on stderr).");
  app->add_option("scene", st->scene_path, "SCENE.json | MODEL.gltf | MODEL.glb | MODEL.obj (default: the built-in scene)");
  const char* out = "Output";
  app->add_option("-o,--output", st->output, ".png (8-bit RGBA), .pfm or .exr (float RGB, linear)")->required()->group(out);
  app->add_option("--width", st->width, "image width (default 1280)")->check(int_in(1, kMaxImageDimension))->group(out);
  app->add_option("--height", st->height, "image height (default 720)")->check(int_in(1, kMaxImageDimension))->group(out);
  app->add_flag("--hdr", st->hdr, "keep unclamped lighting in .pfm or .exr output")->group(out);
  app->add_flag("--srgb", st->srgb, "encode 8-bit output with the sRGB transfer function, exactly (the default)")->group(out);
  app->add_flag("--linear", st->linear, "write 8-bit output's linear values as they are (GL 2.1's framebuffer; default sRGB)")
      ->excludes("--srgb")->group(out);
  app->add_option("--exposure", st->exposure,
                  "EV | auto: the light times 2^EV before tone mapping, or metered to middle grey per frame (default: the "
                  "scene's; a model with lights in physical units: auto; else 0)")
      ->group(out);
  app->add_option("--tone-mapping", st->tone_mapping,
                  "none | neutral | aces: from the exposed light to [0, 1] (default: the scene's; models neutral, scene "
                  "files none, GL's clamp)")
      ->check(one_of({"none", "neutral", "aces"}, "operator"))->group(out);
  add_environment_options(app, st->environment, out);
  app->add_option("--clear", st->clear, "the background colour R,G,B[,A], components in [0, 1] (default 0,0,0,1)")->group(out);
  app->add_option("--depth", st->depth_path, "also write window-space depth (0 near .. 1 far) to FILE.pfm")->group(out);
  const char* draw = "Drawing";
  app->add_option("--shading", st->shading, "flat | gouraud | phong (default: phong for a model, lit per pixel as a viewer lights it; gouraud for a scene file, GL's)")
      ->check(one_of({"flat", "gouraud", "phong"}, "shading"))->group(draw);
  app->add_option("--shadows", st->shadows, "none | map | volume | raycast: every light casts shadows so")
      ->check(one_of({"none", "map", "volume", "raycast"}, "method"))->group(draw);
  app->add_option("--cull", st->cull, "back | front | none (default back)")->check(one_of({"back", "front", "none"}, "cull mode"))->group(draw);
  app->add_option("--depth-mode", st->depth_mode,
                  "auto | gl | reversed: how depth is stored (default auto: reversed, which does not z-fight at far / near "
                  "ratios like 1e7, when the camera's far plane is infinite or over 1e5 x near; else GL's)")
      ->check(one_of({"auto", "gl", "reversed"}, "depth mode"))->group(draw);
  app->add_option("--transparent-order", st->transparent_order, kTransparentOrderHelp)
      ->check(one_of({"submission", "back_to_front"}, "order"))
      ->group(draw);
  app->add_option("--tile", st->tile, "tile size in pixels, a multiple of 8 in [8, 256] (default 64)")->check(int_in(8, 256))->group(draw);
  app->add_option("--msaa", st->msaa,
                  "1 | 4 | 8 | 16 samples per pixel (GL's multisampling: coverage and depth per sample, one colour per "
                  "pixel, averaged in linear colour; default 1)")
      ->check(CLI::IsMember({1, 4, 8, 16}))->group(draw);
  app->add_flag("--no-light-culling", st->no_light_culling, "light every object with every enabled light (frame plan off)")->group(draw);
  app->add_flag("--light-every-vertex", st->light_every_vertex,
                "also light vertices only culled or off-screen triangles use (same image; for measurements)")->group(draw);
  app->add_flag("--vertex-relief", st->vertex_relief,
                "Gouraud: light vertex normals perturbed by normal and bump maps (default: maps per pixel in Phong only)")
      ->group(draw);
  const char* how = "Lighting path";
  app->add_option("--path", st->path, "reference | scalar | simd (default simd)")
      ->check(one_of({"reference", "scalar", "simd"}, "path"))->group(how);
  app->add_option("--isa", st->isa, "auto | sse2 | avx2 | avx512: the simd path's instruction set (default auto: the widest this CPU has)")
      ->check(one_of({"auto", "sse2", "avx2", "avx512"}, "instruction set"))->group(how);
  app->add_option("--pow", st->pow, "auto | exact | fast | integer | schlick: the simd path's pow method (default auto)")
      ->check(one_of({"auto", "exact", "fast", "integer", "schlick"}, "tier"))->group(how);
  app->add_option("--pixel-precision", st->pixel_precision,
                  "auto | exact | fast: textured pixels in float (exact) or linear diffuse textures filtered in the 16-bit "
                  "tier's fixed point (default auto: exact until the fast tier is faster)")
      ->check(one_of({"auto", "exact", "fast"}, "pixel precision"))->group(how);
  app->add_option("--threads", st->threads, "worker threads, 0 = all cores (default 0); the image is the same for any N")
      ->check(int_in(0, 256))->group(how);
  const char* model = "Models";
  app->add_flag("--allow-missing", st->allow_missing, "a model's missing or unreadable .mtl, texture or image files are warnings (the default)")->group(model);
  app->add_flag("--strict", st->strict, "a model's missing or unreadable .mtl, texture or image files are errors")->excludes("--allow-missing")->group(model);
  app->add_flag("--gl-materials", st->gl_materials, "light a glTF model's materials with GL's lighting model (facet's Blinn-Phong mapping) instead of the glTF BRDF")->group(model);
  app->add_option("--allow-path", st->allow_paths, kAllowPathHelp)->group(model);
  add_view_options(app, st->view, model);
  app->add_option("--frames", st->frame_count,
                  "a turntable of N frames to OUT_0000.png, ...: the camera orbits the centre of the model's box about the up axis")
      ->check(int_in(1, 100000))->group(model);
  app->add_option("--frame-range", st->frame_range,
                  "A:B: of the --frames N turntable, draw frames A to B-1 only, named and framed as in the whole run (for job "
                  "arrays and render farms; default 0:N)")
      ->group(model);
  app->add_option("--lights", st->lights,
                  "auto | camera | world: which lights turn with a turntable's camera (default auto: facet's default rig "
                  "turns, a file's own lights stay; camera: all; world: none)")
      ->check(one_of({"auto", "camera", "world"}, "lights mode"))->group(model);
  app->add_option("--orbit", st->orbit_deg, "the turntable's whole sweep in degrees (default 360; 0 with --animation)")
      ->check(number_in(-36000, 36000))->group(model)->each([st](const std::string&) { st->orbit_given = true; });
  app->add_option("--animation", st->animation,
                  "INDEX | NAME: a glTF model's animation to pose (default: none, the file's rest pose); with --frames N, N "
                  "frames over its duration, the camera fixed unless --orbit is given")
      ->group(model);
  app->add_option("--time", st->time, "SECONDS into the animation (--animation, default 0: the first); clamped to its keys")
      ->check(number_in(-1e9, 1e9))->group(model);
  const char* measure = "Measurement";
  app->add_option("--time-limit", st->time_limit, kTimeLimitHelp)->check(number_in(0, 1e9))->group(measure);
  app->add_option("--seconds", st->min_seconds, "render repeatedly for at least S seconds; report the mean frame time")
      ->check(number_in(0, 3600))->group(measure);
  app->add_flag("--stats", st->stats, "print what the frame did and how long each stage took")->group(measure);
  app->add_flag("--json", st->json, "print the statistics as one JSON object (a turntable: one per frame, then a summary)")->group(measure);
  app->add_option("--memory-budget-mb", st->memory_mb,
                  "the most memory the scene, the frame and the image may take, in MiB; 0 = no limit (default 4096)")
      ->check(int_in(0, 1 << 30))->group(measure);
  return {app, [st] { return render(*st); }};
}

namespace {

int render(const RenderState& st) {
  const std::string& scene_path = st.scene_path;
  const std::string& output = st.output;
  const std::string& depth_path = st.depth_path;
  const int width = st.width, height = st.height, frame_count = st.frame_count;
  const double min_seconds = st.min_seconds, orbit_deg = st.orbit_deg;
  const bool stats = st.stats, as_json = st.json;
  std::optional<ShadowMethod> shadows;
  if (!st.shadows.empty()) shadows = parse_shadow_method(st.shadows);
  RenderOptions options;
  options.shading = *parse_shading(default_shading(st.shading, scene_path));
  options.path = *parse_path(st.path);
  options.isa = *parse_isa(st.isa);
  if (!isa_supported(options.isa)) {
    return fail("--isa " + st.isa + ": this CPU does not have it (best available: " + to_string(best_isa()) + ")");
  }
  options.pow_tier = *parse_pow_tier(st.pow);
  options.pixel_precision = st.pixel_precision == "exact"  ? PixelPrecision::exact
                            : st.pixel_precision == "fast" ? PixelPrecision::fast
                                                           : PixelPrecision::automatic;
  options.threads = st.threads;
  if (st.memory_mb >= 0) options.memory_budget_bytes = static_cast<std::uint64_t>(st.memory_mb) << 20;
  options.cull = st.cull == "back" ? CullMode::back : st.cull == "front" ? CullMode::front : CullMode::none;
  options.depth = st.depth_mode == "gl" ? DepthMode::gl : st.depth_mode == "reversed" ? DepthMode::reversed : DepthMode::automatic;
  options.tile_size = st.tile;
  options.samples = st.msaa;
  options.hdr = st.hdr;
  options.srgb = !st.linear;
  options.cull_lights = !st.no_light_culling;
  options.light_every_vertex = st.light_every_vertex;
  options.vertex_relief = st.vertex_relief;
  if (!st.clear.empty()) {
    const std::string* v = &st.clear;
    std::array<float, 4> c{0.0f, 0.0f, 0.0f, 1.0f};
    std::size_t n = 0, start = 0;
    bool ok = true;
    while (ok && start <= v->size()) {
      const std::size_t end = std::min(v->find(',', start), v->size());
      const std::string part = v->substr(start, end - start);
      char* stop = nullptr;
      const float x = std::strtof(part.c_str(), &stop);
      ok = n < 4 && !part.empty() && stop == part.c_str() + part.size() && x >= 0.0f && x <= 1.0f;
      if (ok) c[n++] = x;
      start = end + 1;
    }
    if (!ok || n < 3) return fail("--clear: expected R,G,B or R,G,B,A with components in [0, 1], found '" + *v + "'");
    options.clear_color = c;
  }
  if (!depth_path.empty() && lower_extension(depth_path) != ".pfm") return fail("--depth: the depth file must end in .pfm");
  if (output.empty()) return fail("render: no output file (-o OUT.png, OUT.pfm or OUT.exr)");
  const std::string ext = lower_extension(output);
  if (ext != ".png" && ext != ".pfm" && ext != ".exr") {
    return fail("-o: the output file must end in .png, .pfm or .exr, found '" + output + "'");
  }
  if (options.hdr && ext == ".png") return fail("--hdr needs a .pfm or .exr output (PNG is 8-bit)");

  // A turntable: more than one frame, or a range of frames (--frames 1 --frame-range 0:1, one job of
  // a sweep, writes OUT_0000.png as every other job does).
  const bool turntable = frame_count > 1 || !st.frame_range.empty();
  if (turntable && min_seconds > 0) return fail("--frames and --seconds cannot be combined");
  if (frame_count < 1) return fail("--frames: expected 1 or more");
  const Deadline deadline(st.time_limit);
  if (st.time_limit > 0) {
    options.progress = [&deadline](double) { return !deadline.expired(); };
  }
  InputOptions input;
  InputIdentity identity;
  identity.name = scene_path.empty() ? "built-in scene" : std::filesystem::path(scene_path).filename().string();
  input.on_read = [&identity](const std::string&, const std::string& bytes) { identity.add(bytes); };
  input.progress = options.progress;
  input.cancelled_message = deadline.message("loading " + (scene_path.empty() ? std::string("the scene") : scene_path));
  input.memory_budget_bytes = options.memory_budget_bytes;
  input.allow_missing = !st.strict;
  input.gl_materials = st.gl_materials;
  input.allowed_paths = st.allow_paths;
  input.aspect = float(width) / float(height);
  input.animation = st.animation;
  input.time = st.time;
  if (!apply_view_options(st.view, input)) return 2;
  std::vector<std::string> notes;
  std::optional<Input> loaded = load_input(scene_path, input, notes);
  if (!loaded) return 2;
  Scene* scene = &loaded->scene;
  for (const std::string& n : notes) std::fprintf(stderr, "facet: %s\n", n.c_str());
  if (shadows) override_shadows(*scene, *shadows);
  if (!st.transparent_order.empty()) scene->transparent_order = *parse_transparent_order(st.transparent_order);
  if (!apply_display_options(st.exposure, st.tone_mapping, scene->display)) return 2;
  if (!apply_environment_options(st.environment, options.memory_budget_bytes, *scene)) return 2;
  // Everything the renderer refuses is refused before the image is allocated: the image the
  // user asked for first (the plainer message), then the frame's scratch.
  const PixelFormat format = ext == ".png" ? PixelFormat::rgba8 : PixelFormat::rgba32f;
  const std::size_t stride = static_cast<std::size_t>(width) * bytes_per_pixel(format);
  if (Status s = check_output_image(width, height, format, !depth_path.empty(), options.memory_budget_bytes); !s.ok()) {
    return fail(s.message());
  }
  if (Status s = check_render(*scene, options, width, height); !s.ok()) return fail(s.message());
  std::vector<std::uint8_t> pixels;
  std::vector<float> depth_pixels;
  try {
    pixels.resize(stride * static_cast<std::size_t>(height));
  } catch (const std::bad_alloc&) {
    return fail("out of memory for a " + std::to_string(width) + " x " + std::to_string(height) + " image");
  }
  const ImageView image{pixels.data(), width, height, stride, format, false};
  DepthView depth;
  if (!depth_path.empty()) {
    depth_pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    depth = DepthView{depth_pixels.data(), width, height, static_cast<std::size_t>(width) * sizeof(float), false};
  }

  Renderer renderer;
  FrameStats frame;
  if (turntable) {
    Turntable t;
    t.frames = frame_count;
    t.last = frame_count;
    if (!st.frame_range.empty()) {
      int a = -1, b = -1;
      char rest = 0;
      if (std::sscanf(st.frame_range.c_str(), "%d:%d%c", &a, &b, &rest) != 2 || a < 0 || b <= a || b > frame_count) {
        return fail("--frame-range: expected A:B with 0 <= A < B <= --frames (" + std::to_string(frame_count) + "), found '" +
                    json_escape(st.frame_range) + "'");
      }
      t.first = a, t.last = b;
    }
    // An animation's frames keep the camera still unless --orbit asks for both.
    t.orbit_deg = loaded->animation >= 0 && !st.orbit_given ? 0.0 : orbit_deg;
    t.lights = st.lights == "camera" ? TurnLights::camera : st.lights == "world" ? TurnLights::world : TurnLights::automatic;
    t.json = as_json;
    t.input = identity.json_field();
    return run_turntable(renderer, *loaded, input, options, image, output, t);
  }
  int frames = 0;
  const auto start = std::chrono::steady_clock::now();
  double elapsed = 0;
  std::vector<double> frame_seconds;
  do {
    const auto t0 = std::chrono::steady_clock::now();
    if (Status s = renderer.render(*scene, options, image, depth_path.empty() ? nullptr : &depth, &frame); !s.ok()) {
      return fail(s.code() == ErrorCode::cancelled && deadline.expired() ? deadline.message("render") : s.message());
    }
    frame_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    ++frames;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } while (elapsed < min_seconds && !deadline.expired());

  const Status written = ext == ".png" ? write_png(output, image) : ext == ".exr" ? write_exr(output, image) : write_pfm(output, image);
  if (!written.ok()) return fail(written.message());
  if (!depth_path.empty()) {
    if (Status s = write_pfm(depth_path, depth); !s.ok()) return fail(s.message());
  }

  const std::string nothing = nothing_visible(frame, image, background_pixel(*scene, options, image.format));
  if (!nothing.empty()) std::fprintf(stderr, "facet: nothing to see (exit status 1; the image is written): %s\n", nothing.c_str());
  if (as_json) {
    print_stats_json(frame, frames, elapsed, options, width, height, identity.json_field(), frame_seconds,
                     display_fields(scene->display, options, frame), nothing);
  } else if (stats) {
    std::printf("facet render: %s -> %s (%d x %d, %s shading, %s, pixels %s, %d thread%s)\n",
                scene_path.empty() ? "built-in default scene" : scene_path.c_str(), output.c_str(), width, height,
                to_string(options.shading), describe_path(options.path, options.isa, options.pow_tier).c_str(),
                to_string(options.pixel_precision), frame.threads, frame.threads == 1 ? "" : "s");
    print_stats_text(frame, frames, elapsed);
    print_display_text(scene->display, options, frame);
  }
  return nothing.empty() ? 0 : 1;
}

}  // namespace
}  // namespace facet::cli
