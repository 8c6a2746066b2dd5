// facet bake: lightmaps of a scene (direct light and radiosity) into a folder.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "common/format.hpp"
#include "baked_scene.hpp"
#include "output_folder.hpp"

namespace facet::cli {
namespace {

#define FACET_CLI_TRY(expr)          \
  do {                               \
    if (Status s_ = (expr); !s_.ok()) return s_; \
  } while (0)

struct BakeState {
  std::string input, out;
  double texels_per_unit = 0;  // 0: 128 texels along the scene's bounding-box diagonal
  int padding = 2, subdivisions = 2, burial_rays = 16, rays = 256, threads = 0;
  long memory_mb = -1;  // -1: the default budget
  std::size_t max_shots = 100000;
  double residual = 1e-3, seconds = 0, scale = 0, small_texel = 0.25;  // scale 0: the 99.9th percentile of the light
  std::string lights = "all", mode = "diffuse";
  bool no_radiosity = false, json = false, generate_uvs = false, overwrite = false;
  std::vector<std::string> allow_paths;
};

int bake(const BakeState& st);

}  // namespace

Command add_bake(CLI::App& facet) {
  auto st = std::make_shared<BakeState>();
  CLI::App* app = facet.add_subcommand("bake", "bake lightmaps (direct light and radiosity) of a scene into a folder");
  app->footer(
      "Writes DIR/lightmap_K.png (8-bit: the light arriving at each texel divided by --scale), DIR/lightmap_K.exr and\n"
      "DIR/lightmap_K.pfm (float, linear, unscaled) for each object K, and DIR/bake.json (the atlases, the options and the bake's\n"
      "statistics: patches, shots, rays, power entered, absorbed, escaped and left unshot). For a scene file, also\n"
      "DIR/scene.json: the same scene drawn with its lightmaps (the files it names copied beside it), so that\n"
      "'facet render DIR/scene.json' draws the baked light. A surface's colour is its emission plus its albedo\n"
      "times the lightmap. docs/baking.md.");
  app->add_option("scene", st->input, "SCENE.json | MODEL.gltf | MODEL.glb | MODEL.obj (default: the built-in scene)");
  app->add_option("-o,--output", st->out, "the folder to write into: new or empty (created if missing)")->required();
  app->add_flag("--overwrite", st->overwrite,
                "write into a folder that is not empty, replacing the files of an earlier bake (never a file the bake "
                "reads, never through a symbolic link)");
  app->add_option("--texels-per-unit", st->texels_per_unit,
                  "lightmap density in texels per unit of world length (default: 128 along the scene's bounding-box "
                  "diagonal)")
      ->check(number_in(0, 1e9));
  app->add_option("--padding", st->padding, "empty texels between charts (default 2)")->check(int_in(1, 64));
  app->add_option("--subdivisions", st->subdivisions, "footprint pieces per texel side (default 2)")->check(int_in(1, 8));
  app->add_flag("--generate-uvs", st->generate_uvs,
               "generate lightmap charts for every object, even one whose model brings lightmap coordinates (a glTF's "
               "TEXCOORD_1, used by default)");
  app->add_option("--small-texel", st->small_texel,
                  "a texel covering less than this share of a full texel joins its fullest neighbour's patch (default 0.25; "
                  "0: none)")
      ->check(number_in(0, 1));
  app->add_option("--burial-rays", st->burial_rays,
                  "probe rays per footprint piece: a piece more than half of whose rays meet back faces is inside geometry "
                  "and dropped (default 16; 0: keep every piece)")
      ->check(int_in(0, 1024));
  app->add_option("--rays", st->rays, "rays per radiosity shot (default 256)")->check(int_in(1, 1 << 20));
  app->add_option("--max-shots", st->max_shots, "stop after this many shots (default 100000)")->check(int_in(0, 1000000000));
  app->add_option("--residual", st->residual, "stop when the unshot power is below this share of the power that entered (default 0.001)")
      ->check(number_in(0, 1));
  app->add_option("--seconds", st->seconds,
                  "the whole bake's time limit: radiosity stops at it with the light shot so far, an earlier phase fails "
                  "(default: no limit; a time limit makes the result machine-dependent)")
      ->check(number_in(0, 1e9));
  app->add_option("--lights", st->lights,
                  "all | none: whether the scene's lights are baked as direct light (none: only emissive surfaces light the scene)")
      ->check(one_of({"all", "none"}, "light choice"));
  app->add_flag("--no-radiosity", st->no_radiosity, "direct light only");
  app->add_option("--scale", st->scale,
                  "the PNGs hold light / scale (default: the 99.9th percentile of the baked light, so that few texels clip)")
      ->check(number_in(1e-6, 1e6));
  app->add_option("--mode", st->mode,
                  "diffuse | replace: in DIR/scene.json, whether the lights still add their specular term to lightmapped "
                  "objects (diffuse, the default) or nothing (replace)")
      ->check(one_of({"diffuse", "replace"}, "lightmap mode"));
  app->add_option("--memory-budget-mb", st->memory_mb,
                  "the most memory the loaded scene and the bake's own data (texels, footprint pieces) may take, in MiB "
                  "(default 4096; 0: no limit)")
      ->check(int_in(0, 1L << 30));
  app->add_option("--threads", st->threads, "threads (default: all)")->check(int_in(0, 1024));
  app->add_flag("--json", st->json, "print the statistics as one JSON object");
  app->add_option("--allow-path", st->allow_paths, kAllowPathHelp);
  return {app, [st] { return bake(*st); }};
}

namespace {

int bake(const BakeState& st) {
  InputOptions in;
  in.allowed_paths = st.allow_paths;
  in.gl_materials = true;  // lightmaps are GL's: glTF materials bake and draw with GL's model
  if (st.memory_mb >= 0) in.memory_budget_bytes = static_cast<std::uint64_t>(st.memory_mb) << 20;
  Files read;
  in.on_read = [&read](const std::string& name, const std::string& bytes) { read.emplace(loader_name(name), bytes); };
  std::vector<std::string> notes;
  std::optional<Input> input = load_input(st.input, in, notes);
  if (!input) return 2;
  const Scene& scene = input->scene;
  BakeOptions o;
  o.charts.padding = st.padding;
  o.subdivisions = st.subdivisions;
  o.burial_rays = st.burial_rays;
  o.small_texel = st.small_texel;
  o.use_mesh_uvs = !st.generate_uvs;
  o.rays_per_shot = st.rays;
  o.max_shots = st.max_shots;
  o.residual = st.residual;
  o.max_seconds = st.seconds;
  if (st.memory_mb >= 0) o.memory_budget_bytes = static_cast<std::uint64_t>(st.memory_mb) << 20;
  o.threads = st.threads;
  o.direct = st.lights == "all";
  o.radiosity = !st.no_radiosity;
  o.charts.texels_per_unit = st.texels_per_unit;
  if (o.charts.texels_per_unit == 0) {
    Eigen::AlignedBox3d box;
    for (const Instance& inst : scene.objects)
      for (const Vec3& p : scene.meshes[inst.mesh].mesh.positions) {
        const Eigen::Vector3d w = (inst.model.cast<double>() * p.cast<double>().homogeneous()).head<3>();
        if (w.allFinite()) box.extend(w);
      }
    const double diagonal = box.isEmpty() ? 1.0 : box.diagonal().norm();
    o.charts.texels_per_unit = 128.0 / (diagonal > 0 ? diagonal : 1.0);
  }
  Result<OutputFolder> folder = OutputFolder::open(st.out, st.overwrite);
  if (!folder) return fail(folder.status().message());
  if (!st.input.empty()) folder->protect(st.input);
  for (const auto& file : read) folder->protect(file.first);
  // The files the bake will write, checked before it runs (a link, the input, a FIFO: refused now).
  std::vector<std::string> outputs = {"scene.json", "bake.json"};
  for (std::size_t k = 0; k < scene.objects.size(); ++k)
    for (const char* ext : {".png", ".pfm", ".exr"}) outputs.push_back("lightmap_" + std::to_string(k) + ext);
  for (const std::string& name : outputs) {
    if (Result<std::string> p = folder->path(name); !p) return fail(p.status().message());
  }
  const Result<BakeResult> r = bake_lightmaps(scene, o);
  if (!r) return fail(r.status().message());
  const double scale = st.scale > 0 ? st.scale : lightmap_scale(*r);
  std::string objects;
  for (const BakedLightmap& lm : r->lightmaps) {
    const int w = lm.unwrap.width, h = lm.unwrap.height;
    std::vector<float> rgba(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
    for (std::size_t i = 0; i < lm.light.size(); ++i) {
      for (int c = 0; c < 3; ++c) rgba[4 * i + static_cast<std::size_t>(c)] = lm.light[i][c];
      rgba[4 * i + 3] = 1.0f;
    }
    const std::string base = "lightmap_" + std::to_string(lm.object);
    Result<std::string> pfm = folder->path(base + ".pfm"), exr = folder->path(base + ".exr"), png_path = folder->path(base + ".png");
    for (const auto* p : {&pfm, &exr, &png_path})
      if (!*p) return fail(p->status().message());
    const ImageView raw{rgba.data(), w, h, static_cast<std::size_t>(w) * 4 * sizeof(float), PixelFormat::rgba32f, true};
    if (Status s = write_pfm(*pfm, raw); !s.ok()) return fail(s.message());
    if (Status s = write_exr(*exr, raw); !s.ok()) return fail(s.message());
    std::vector<float> scaled = rgba;
    for (std::size_t i = 0; i < scaled.size(); ++i)
      if (i % 4 != 3) scaled[i] = static_cast<float>(scaled[i] / scale);
    const ImageView png{scaled.data(), w, h, static_cast<std::size_t>(w) * 4 * sizeof(float), PixelFormat::rgba32f, true};
    if (Status s = write_png(*png_path, png); !s.ok()) return fail(s.message());
    const Instance& inst = scene.objects[lm.object];
    objects += std::string(objects.empty() ? "" : ", ") + "{\"object\": " + std::to_string(lm.object) + ", \"mesh\": \"" +
               json_escape(scene.meshes[inst.mesh].name) + "\", \"width\": " + std::to_string(w) + ", \"height\": " +
               std::to_string(h) + ", \"charts\": " + std::to_string(lm.unwrap.charts.size()) + ", \"png\": \"lightmap_" +
               std::to_string(lm.object) + ".png\", \"pfm\": \"lightmap_" + std::to_string(lm.object) + ".pfm\", \"exr\": \"lightmap_" +
               std::to_string(lm.object) + ".exr\"}";
  }
  const BakeStats& s = r->stats;
  char stats[1024];
  std::snprintf(stats, sizeof stats,
                "\"texels_per_unit\": %.9g, \"scale\": %.9g, \"texels\": %zu, \"patches\": %zu, \"pieces\": %zu, \"buried\": %zu, \"merged\": %zu, \"shots\": %zu, "
                "\"rays\": %zu, \"seconds\": %.6g, \"rays_per_second\": %.6g, \"shots_per_second\": %.6g, \"stopped_by\": \"%s\", "
                "\"entered\": %.9g, \"absorbed\": %.9g, \"escaped\": %.9g, \"back_faces\": %.9g, \"unshot\": %.9g",
                o.charts.texels_per_unit, scale, s.texels, s.patches, s.pieces, s.buried, s.merged, s.shots, s.rays, s.seconds,
                s.seconds > 0 ? double(s.rays) / s.seconds : 0.0, s.seconds > 0 ? double(s.shots) / s.seconds : 0.0,
                s.stopped_by.c_str(), s.entered, s.absorbed, s.escaped, s.back_faces, s.unshot);
  std::string scene_note;
  if (Status w = write_baked_scene({st.input, st.mode, st.allow_paths}, *folder, read, o, scale, *r, scene_note); !w.ok()) {
    return fail(w.message());
  }
  const std::string json = std::string("{") + stats + ", \"lightmaps\": [" + objects + "]" +
                           (scene_note.empty() ? ", \"scene\": \"scene.json\"" : "") + "}";
  if (Status w = folder->write("bake.json", json + "\n"); !w.ok()) return fail(w.message());
  if (st.json) {
    std::printf("%s\n", json.c_str());
  } else {
    for (const std::string& n : notes) std::printf("%s\n", n.c_str());
    if (!scene_note.empty()) std::printf("%s\n", scene_note.c_str());
    std::printf("baked %zu lightmaps (%zu texels, %zu patches) at %.4g texels per unit: %zu shots, %zu rays in %.3f s "
                "(%.3g rays/s), stopped by %s with %.3g%% of the power unshot; written to %s\n",
                r->lightmaps.size(), s.texels, s.patches, o.charts.texels_per_unit, s.shots, s.rays, s.seconds,
                s.seconds > 0 ? double(s.rays) / s.seconds : 0.0, s.stopped_by.c_str(),
                s.entered > 0 ? 100.0 * s.unshot / s.entered : 0.0, st.out.c_str());
  }
  return 0;
}

}  // namespace
}  // namespace facet::cli
