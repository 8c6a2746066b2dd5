// facet bake: lightmaps of a scene (direct light and radiosity) into a folder.
#include <algorithm>
#include <cctype>
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
  double residual = 1e-3, seconds = 0, scale = 0, small_texel = 0.25;  // scale 0: the 99.9th percentile of the light
  std::string lights = "all", mode = "diffuse";
  bool no_radiosity = false, json = false, generate_uvs = false;
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

// A file name from a glTF URI: %XX escapes decoded.
std::string decode_uri(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// The files a model names beside itself, relative to its folder: a glTF's buffers and images
// (not data: URIs), an OBJ's material libraries and the maps they name. Paths that leave the
// model's folder are not listed (the loader would refuse them without --allow-path).
std::vector<std::string> model_dependencies(const std::filesystem::path& model) {
  std::vector<std::string> out;
  auto keep = [&](const std::string& relative) {
    const std::filesystem::path p = std::filesystem::path(relative).lexically_normal();
    if (relative.empty() || p.is_absolute() || p.empty() || *p.begin() == "..") return;
    if (std::find(out.begin(), out.end(), p.generic_string()) == out.end()) out.push_back(p.generic_string());
  };
  const std::string ext = lower_extension(model.string());
  if (ext == ".gltf") {
    std::ifstream file(model);
    const nlohmann::json doc = nlohmann::json::parse(file, nullptr, false);
    if (!doc.is_object()) return out;
    for (const char* list : {"buffers", "images"}) {
      if (!doc.contains(list) || !doc[list].is_array()) continue;
      for (const auto& item : doc[list]) {
        if (item.is_object() && item.contains("uri") && item["uri"].is_string()) {
          const std::string uri = item["uri"].get<std::string>();
          if (uri.rfind("data:", 0) != 0) keep(decode_uri(uri));
        }
      }
    }
  } else if (ext == ".obj") {
    std::ifstream obj(model);
    std::string line;
    std::vector<std::string> libraries;
    while (std::getline(obj, line)) {
      if (line.rfind("mtllib", 0) == 0 && line.size() > 7) libraries.push_back(line.substr(7));
    }
    for (std::string lib : libraries) {
      while (!lib.empty() && std::isspace(static_cast<unsigned char>(lib.back()))) lib.pop_back();
      keep(lib);
      std::ifstream mtl(model.parent_path() / lib);
      while (std::getline(mtl, line)) {
        std::size_t at = line.find_first_not_of(" \t");
        if (at == std::string::npos) continue;
        const std::string key = line.substr(at, line.find_first_of(" \t", at) - at);
        if (key.rfind("map_", 0) != 0 && key != "bump" && key != "disp" && key != "decal" && key != "refl") continue;
        std::string name = line.substr(line.find_last_of(" \t") + 1);
        while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
        keep(name);
      }
    }
  }
  return out;
}

// DIR/scene.json: the input (a scene file, or a model, which becomes a scene that imports it)
// with every object given its lightmap, the lightmaps as textures, and the files it names copied
// into DIR (paths rewritten; an imported model with the files it names, in a folder of its own).
// An object drawn over generated charts gets the charts' options, so that loading the scene cuts
// the same charts; one baked over its mesh's own coordinates gets "uv": "mesh". `note` says why
// no scene was written, when none was.
Status write_baked_scene(const BakeState& st, const BakeOptions& o, double scale, const BakeResult& r, std::string& note) {
  namespace fs = std::filesystem;
  const std::string ext = lower_extension(st.input);
  nlohmann::json root;
  fs::path from;
  if (ext == ".json") {
    std::ifstream file(st.input);
    root = nlohmann::json::parse(file, nullptr, false);
    if (root.is_discarded() || !root.is_object()) return {ErrorCode::parse_error, "", st.input + ": not a JSON object"};
    from = fs::path(st.input).parent_path();
    bool baked = false;
    if (root.contains("objects") && root["objects"].is_array()) {
      for (const auto& object : root["objects"]) baked = baked || (object.is_object() && object.contains("lightmap"));
    }
    if (root.contains("imports") && root["imports"].is_array()) {
      for (const auto& import : root["imports"]) baked = baked || (import.is_object() && import.contains("lightmaps"));
    }
    if (baked) {
      note = "no scene.json: the scene has lightmaps already; bake the scene it was baked from (the lightmaps are written)";
      return {};
    }
  } else if (!st.input.empty()) {
    from = fs::path(st.input).parent_path();
    root = {{"imports", nlohmann::json::array({{{"file", fs::path(st.input).filename().string()}}})}};
  } else {
    note = "no scene.json: the built-in scene is not a file (the lightmaps are written)";
    return {};
  }
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
  auto entry = [&](std::size_t k) {
    const std::string name = "lightmap_" + std::to_string(k);
    nlohmann::json e = {{"texture", name}, {"scale", scale}, {"mode", st.mode}};
    if (r.lightmaps[k].mesh_uvs) {
      e["uv"] = "mesh";
    } else {
      e["uv"] = "generate";
      e["texels_per_unit"] = o.charts.texels_per_unit;
      e["padding"] = o.charts.padding;
      e["chart_angle_deg"] = o.charts.chart_angle_deg;
      e["max_size"] = o.charts.max_size;
    }
    return e;
  };
  // Objects: the imports' first (in import order, each model's in its order), then the file's own.
  std::size_t next = 0;
  if (root.contains("imports") && root["imports"].is_array()) {
    for (std::size_t i = 0; i < root["imports"].size(); ++i) {
      nlohmann::json& import = root["imports"][i];
      if (!import.is_object() || !import.contains("file") || !import["file"].is_string()) continue;
      const fs::path model = from / import["file"].get<std::string>();
      // How many objects the model adds: read again as the bake read it.
      ModelOptions mo;
      mo.allow_missing = import.value("allow_missing", false);
      mo.assets.allowed_roots.push_back(from.empty() ? std::string(".") : from.string());
      for (const std::string& a : st.allow_paths) mo.assets.allowed_roots.push_back(a);
      Result<Model> m = load_model(model.string(), mo);
      if (!m) return {m.status().code(), "", model.string() + ": " + m.status().message()};
      const std::string folder = "import_" + std::to_string(i);
      fs::create_directories(fs::path(st.out) / folder, ec);
      if (ec) return {ErrorCode::io_error, "", "cannot create '" + st.out + "/" + folder + "': " + ec.message()};
      std::vector<std::string> files = model_dependencies(model);
      files.insert(files.begin(), model.filename().string());
      for (const std::string& f : files) {
        const fs::path target = fs::path(st.out) / folder / f;
        fs::create_directories(target.parent_path(), ec);
        fs::copy_file(model.parent_path() / f, target, fs::copy_options::overwrite_existing, ec);
        if (ec) return {ErrorCode::io_error, "", "cannot copy '" + (model.parent_path() / f).string() + "' into '" + target.string() + "': " + ec.message()};
      }
      import["file"] = folder + "/" + model.filename().string();
      nlohmann::json lightmaps = nlohmann::json::array();
      for (std::size_t k = 0; k < m->scene.objects.size(); ++k) {
        if (next >= r.lightmaps.size()) break;
        lightmaps.push_back(entry(next++));
      }
      import["lightmaps"] = lightmaps;
    }
  }
  nlohmann::json& list = root["objects"];
  if (list.is_null()) list = nlohmann::json::array();
  if (!list.is_array() || next + list.size() != r.lightmaps.size()) {
    note = "no scene.json: the scene's objects do not match the baked ones";
    return {};
  }
  for (auto& object : list) object["lightmap"] = entry(next++);
  if (list.empty()) root.erase("objects");
  nlohmann::json& textures = root["textures"];
  if (!textures.is_array()) textures = nlohmann::json::array();
  for (std::size_t k = 0; k < r.lightmaps.size(); ++k) {
    const std::string name = "lightmap_" + std::to_string(k);
    textures.push_back({{"name", name}, {"file", name + ".png"}, {"filter", "bilinear"}, {"wrap", "clamp"}, {"encoding", "linear"}});
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
  o.small_texel = st.small_texel;
  o.use_mesh_uvs = !st.generate_uvs;
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
                "\"texels_per_unit\": %.9g, \"scale\": %.9g, \"texels\": %zu, \"patches\": %zu, \"pieces\": %zu, \"buried\": %zu, \"merged\": %zu, \"shots\": %zu, "
                "\"rays\": %zu, \"seconds\": %.6g, \"rays_per_second\": %.6g, \"shots_per_second\": %.6g, \"stopped_by\": \"%s\", "
                "\"entered\": %.9g, \"absorbed\": %.9g, \"escaped\": %.9g, \"back_faces\": %.9g, \"unshot\": %.9g",
                o.charts.texels_per_unit, scale, s.texels, s.patches, s.pieces, s.buried, s.merged, s.shots, s.rays, s.seconds,
                s.seconds > 0 ? double(s.rays) / s.seconds : 0.0, s.seconds > 0 ? double(s.shots) / s.seconds : 0.0,
                s.stopped_by.c_str(), s.entered, s.absorbed, s.escaped, s.back_faces, s.unshot);
  std::string scene_note;
  if (Status w = write_baked_scene(st, o, scale, *r, scene_note); !w.ok()) return fail(w.message());
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
