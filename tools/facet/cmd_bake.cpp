// facet bake: lightmaps of a scene (direct light and radiosity) into a folder.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "cli.hpp"

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
  std::size_t max_shots = 100000;
  double residual = 1e-3, seconds = 0, scale = 0;  // scale 0: the 99.9th percentile of the light
  std::string lights = "all", mode = "diffuse";
  bool no_radiosity = false, json = false;
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
  app->add_option("-o,--output", st->out, "the folder to write into (created if missing)")->required();
  app->add_option("--texels-per-unit", st->texels_per_unit,
                  "lightmap density in texels per unit of world length (default: 128 along the scene's bounding-box "
                  "diagonal)")
      ->check(number_in(0, 1e9));
  app->add_option("--padding", st->padding, "empty texels between charts (default 2)")->check(int_in(1, 64));
  app->add_option("--subdivisions", st->subdivisions, "footprint pieces per texel side (default 2)")->check(int_in(1, 8));
  app->add_option("--burial-rays", st->burial_rays,
                  "probe rays per footprint piece: a piece more than half of whose rays meet back faces is inside geometry "
                  "and dropped (default 16; 0: keep every piece)")
      ->check(int_in(0, 1024));
  app->add_option("--rays", st->rays, "rays per radiosity shot (default 256)")->check(int_in(1, 1 << 20));
  app->add_option("--max-shots", st->max_shots, "stop after this many shots (default 100000)");
  app->add_option("--residual", st->residual, "stop when the unshot power is below this share of the power that entered (default 0.001)")
      ->check(number_in(0, 1));
  app->add_option("--seconds", st->seconds, "stop after this long (default: no limit; a time limit makes the result machine-dependent)")
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
  app->add_option("--threads", st->threads, "threads (default: all)")->check(int_in(0, 1024));
  app->add_flag("--json", st->json, "print the statistics as one JSON object");
  app->add_option("--allow-path", st->allow_paths, kAllowPathHelp);
  return {app, [st] { return bake(*st); }};
}

namespace {

// DIR/scene.json: the input scene file with every object given its lightmap (the charts' options,
// so that loading it cuts the same charts), the lightmaps as textures, and the files it names
// copied into DIR (paths rewritten). Scene files with imports are left out (their objects do not
// map one to one onto the file's); `note` then says why.
Status write_baked_scene(const BakeState& st, const BakeOptions& o, double scale, std::size_t objects, std::string& note) {
  namespace fs = std::filesystem;
  if (lower_extension(st.input) != ".json") {
    note = "no scene.json: only a scene file's bake is written as a scene (the lightmaps are written)";
    return {};
  }
  std::ifstream file(st.input);
  nlohmann::json root = nlohmann::json::parse(file, nullptr, false);
  if (root.is_discarded() || !root.is_object()) return {ErrorCode::parse_error, "", st.input + ": not a JSON object"};
  if (root.contains("imports")) {
    note = "no scene.json: the scene imports models, whose objects a baked scene cannot name yet (the lightmaps are written)";
    return {};
  }
  const fs::path from = fs::path(st.input).parent_path();
  std::error_code ec;
  int copied = 0;
  auto copy_file = [&](nlohmann::json& value) -> Status {
    if (!value.is_string()) return {};
    const fs::path source = from / value.get<std::string>();
    const std::string name = std::to_string(copied++) + "_" + source.filename().string();
    fs::copy_file(source, fs::path(st.out) / name, fs::copy_options::overwrite_existing, ec);
    if (ec) return {ErrorCode::io_error, "", "cannot copy '" + source.string() + "' into '" + st.out + "': " + ec.message()};
    value = name;
    return {};
  };
  for (const char* list : {"meshes", "textures"}) {
    if (!root.contains(list) || !root[list].is_array()) continue;
    for (auto& item : root[list]) {
      if (!item.is_object()) continue;
      for (const char* key : {"obj", "file"}) {
        if (item.contains(key)) FACET_CLI_TRY(copy_file(item[key]));
      }
    }
  }
  nlohmann::json& textures = root["textures"];
  if (!textures.is_array()) textures = nlohmann::json::array();
  nlohmann::json& list = root["objects"];
  if (!list.is_array() || list.size() != objects) {
    note = "no scene.json: the scene's objects do not match the baked ones";
    return {};
  }
  for (std::size_t k = 0; k < objects; ++k) {
    const std::string name = "lightmap_" + std::to_string(k);
    textures.push_back({{"name", name}, {"file", name + ".png"}, {"filter", "bilinear"}, {"wrap", "clamp"}, {"encoding", "linear"}});
    list[k]["lightmap"] = {{"texture", name},
                           {"scale", scale},
                           {"mode", st.mode},
                           {"uv", "generate"},
                           {"texels_per_unit", o.charts.texels_per_unit},
                           {"padding", o.charts.padding},
                           {"chart_angle_deg", o.charts.chart_angle_deg},
                           {"max_size", o.charts.max_size}};
  }
  std::ofstream out(st.out + "/scene.json");
  out << root.dump(2) << "\n";
  if (!out) return {ErrorCode::io_error, "", "cannot write '" + st.out + "/scene.json'"};
  return {};
}

int bake(const BakeState& st) {
  InputOptions in;
  in.allowed_paths = st.allow_paths;
  std::vector<std::string> notes;
  std::optional<Input> input = load_input(st.input, in, notes);
  if (!input) return 2;
  const Scene& scene = input->scene;
  BakeOptions o;
  o.charts.padding = st.padding;
  o.subdivisions = st.subdivisions;
  o.burial_rays = st.burial_rays;
  o.rays_per_shot = st.rays;
  o.max_shots = st.max_shots;
  o.residual = st.residual;
  o.max_seconds = st.seconds;
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
  const Result<BakeResult> r = bake_lightmaps(scene, o);
  if (!r) return fail(r.status().message());
  std::error_code ec;
  std::filesystem::create_directories(st.out, ec);
  if (ec) return fail("cannot create the folder '" + st.out + "': " + ec.message());
  const double scale = st.scale > 0 ? st.scale : lightmap_scale(*r);
  std::string objects;
  for (const BakedLightmap& lm : r->lightmaps) {
    const int w = lm.unwrap.width, h = lm.unwrap.height;
    std::vector<float> rgba(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
    for (std::size_t i = 0; i < lm.light.size(); ++i) {
      for (int c = 0; c < 3; ++c) rgba[4 * i + static_cast<std::size_t>(c)] = lm.light[i][c];
      rgba[4 * i + 3] = 1.0f;
    }
    const std::string base = st.out + "/lightmap_" + std::to_string(lm.object);
    const ImageView raw{rgba.data(), w, h, static_cast<std::size_t>(w) * 4 * sizeof(float), PixelFormat::rgba32f, true};
    if (Status s = write_pfm(base + ".pfm", raw); !s.ok()) return fail(s.message());
    if (Status s = write_exr(base + ".exr", raw); !s.ok()) return fail(s.message());
    std::vector<float> scaled = rgba;
    for (std::size_t i = 0; i < scaled.size(); ++i)
      if (i % 4 != 3) scaled[i] = static_cast<float>(scaled[i] / scale);
    const ImageView png{scaled.data(), w, h, static_cast<std::size_t>(w) * 4 * sizeof(float), PixelFormat::rgba32f, true};
    if (Status s = write_png(base + ".png", png); !s.ok()) return fail(s.message());
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
                "\"texels_per_unit\": %.9g, \"scale\": %.9g, \"texels\": %zu, \"patches\": %zu, \"pieces\": %zu, \"buried\": %zu, \"shots\": %zu, "
                "\"rays\": %zu, \"seconds\": %.6g, \"rays_per_second\": %.6g, \"shots_per_second\": %.6g, \"stopped_by\": \"%s\", "
                "\"entered\": %.9g, \"absorbed\": %.9g, \"escaped\": %.9g, \"back_faces\": %.9g, \"unshot\": %.9g",
                o.charts.texels_per_unit, scale, s.texels, s.patches, s.pieces, s.buried, s.shots, s.rays, s.seconds,
                s.seconds > 0 ? double(s.rays) / s.seconds : 0.0, s.seconds > 0 ? double(s.shots) / s.seconds : 0.0,
                s.stopped_by.c_str(), s.entered, s.absorbed, s.escaped, s.back_faces, s.unshot);
  std::string scene_note;
  if (Status w = write_baked_scene(st, o, scale, r->lightmaps.size(), scene_note); !w.ok()) return fail(w.message());
  const std::string json = std::string("{") + stats + ", \"lightmaps\": [" + objects + "]" +
                           (scene_note.empty() ? ", \"scene\": \"scene.json\"" : "") + "}";
  std::FILE* f = std::fopen((st.out + "/bake.json").c_str(), "w");
  if (!f || std::fputs((json + "\n").c_str(), f) < 0 || std::fclose(f) != 0) return fail("cannot write '" + st.out + "/bake.json'");
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
