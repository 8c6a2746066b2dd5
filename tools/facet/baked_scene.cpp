#include "baked_scene.hpp"

#include <cctype>
#include <set>

#include <nlohmann/json.hpp>

#include "common/format.hpp"

namespace facet::cli {

#define FACET_CLI_TRY(expr)                      \
  do {                                           \
    if (Status s_ = (expr); !s_.ok()) return s_; \
  } while (0)

namespace {

// `name` relative to folder `base` (both loader names), or "" when it lies outside it.
std::string relative_to(const std::string& name, const std::string& base) {
  if (base.empty()) return name.empty() || name[0] == '/' ? std::string() : name;
  if (name.size() > base.size() + 1 && name.compare(0, base.size(), base) == 0 && name[base.size()] == '/') {
    return name.substr(base.size() + 1);
  }
  return {};
}

// The deepest folder holding both folders (loader names; "" for none, "/" for the root).
std::string common_folder(const std::string& a, const std::string& b) {
  std::size_t n = 0, last = 0;
  while (n < a.size() && n < b.size() && a[n] == b[n]) {
    if (a[n] == '/') last = n;
    ++n;
  }
  if ((n == a.size() || a[n] == '/') && (n == b.size() || b[n] == '/')) last = n;  // one holds the other
  if (last == 0) return !a.empty() && a[0] == '/' && !b.empty() && b[0] == '/' ? "/" : "";
  return a.substr(0, last);
}

}  // namespace

// A path as the loader names the files it reads: normal, relative while it does not climb out of
// the current directory, else absolute.
std::string loader_name(const std::filesystem::path& p) {
  std::filesystem::path n = p.lexically_normal();
  if (!n.empty() && *n.begin() == "..") n = std::filesystem::absolute(p).lexically_normal();
  std::string s = n.generic_string();
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return s == "." ? std::string() : s;
}

// DIR/scene.json: the input (a scene file, or a model, which becomes a scene that imports it)
// with every object given its lightmap, the lightmaps as textures, and the files the loader read
// for it copied into DIR, byte for byte as it read them (the scene's own under scene_files/; an
// imported model's under import_N/, at their places relative to each other). Nothing is read
// again from the input's folder: a file the loader did not read is not copied. An object
// drawn over generated charts gets the charts' options, so that loading the scene cuts the same
// charts; one baked over its mesh's own coordinates gets "uv": "mesh". `note` says why no scene
// was written, when none was.
Status write_baked_scene(const BakedSceneRequest& st, const OutputFolder& folder, const Files& read, const BakeOptions& o,
                         double scale, const BakeResult& r, std::string& note) {
  namespace fs = std::filesystem;
  std::string ext = std::filesystem::path(st.input).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  nlohmann::json root;
  fs::path from;
  if (ext == ".json") {
    const auto text = read.find(loader_name(st.input));
    if (text == read.end()) return {ErrorCode::io_error, "", st.input + ": the scene file was not read"};
    root = nlohmann::json::parse(text->second, nullptr, false);
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
  // The copy of a file the loader read, at DIR/placed; a note (and no scene) for one it did not
  // read (allow_missing).
  auto carry = [&](const Files& files, const std::string& name, const std::string& placed) -> Status {
    const auto f = files.find(name);
    if (f == files.end()) {
      note = "no scene.json: " + quote(name, 200) + " was not read by the loader (allow_missing?), so it cannot be carried";
      return {};
    }
    return folder.write(placed, f->second);
  };
  // The scene's own meshes and textures name nothing themselves: each under scene_files/, by its
  // order and file name.
  int own = 0;
  for (const char* list : {"meshes", "textures"}) {
    if (!root.contains(list) || !root[list].is_array()) continue;
    for (auto& item : root[list]) {
      if (!item.is_object()) continue;
      for (const char* key : {"obj", "file"}) {
        if (!item.contains(key) || !item[key].is_string()) continue;
        const std::string name = loader_name(from / item[key].get<std::string>());
        const std::string placed = "scene_files/" + std::to_string(own++) + "_" + fs::path(name).filename().string();
        FACET_CLI_TRY(carry(read, name, placed));
        if (!note.empty()) return {};
        item[key] = placed;
      }
    }
  }
  // The lightmaps' texture names: none the scene's own textures use.
  std::set<std::string> taken;
  if (root.contains("textures") && root["textures"].is_array()) {
    for (const auto& t : root["textures"])
      if (t.is_object() && t.contains("name") && t["name"].is_string()) taken.insert(t["name"].get<std::string>());
  }
  std::vector<std::string> names(r.lightmaps.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    names[k] = "lightmap_" + std::to_string(k);
    for (int n = 1; taken.count(names[k]); ++n) names[k] = "lightmap_" + std::to_string(k) + "_" + std::to_string(n);
    taken.insert(names[k]);
  }
  auto entry = [&](std::size_t k) {
    nlohmann::json e = {{"texture", names[k]}, {"scale", scale}, {"mode", st.mode}};
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
      // Read again as the scene's loader read it: how many objects it adds, and which files.
      Files files;
      ModelOptions mo;
      mo.allow_missing = import.value("allow_missing", ModelOptions{}.allow_missing);
      mo.gl_materials = true;  // as the bake read it (a lightmap draws with GL's model)
      mo.assets.allowed_roots.push_back(from.empty() ? std::string(".") : from.string());
      for (const std::string& a : st.allow_paths) mo.assets.allowed_roots.push_back(a);
      mo.assets.on_read = [&files](const std::string& name, const std::string& bytes) { files.emplace(loader_name(name), bytes); };
      Result<Model> m = load_model(loader_name(model), mo);
      if (!m) return {m.status().code(), "", model.string() + ": " + m.status().message()};
      // The model and the files it read keep their places relative to each other: each at its
      // place under the deepest folder holding them all.
      std::string base;
      bool first = true;
      for (const auto& file : files) {
        const std::string folder_of = fs::path(file.first).parent_path().generic_string();
        base = first ? folder_of : common_folder(base, folder_of);
        first = false;
      }
      const std::string prefix = "import_" + std::to_string(i);
      std::string placed;
      for (const auto& file : files) {
        std::string rel = base.empty() || base == "/" ? file.first : relative_to(file.first, base);
        while (!rel.empty() && rel[0] == '/') rel.erase(0, 1);
        if (rel.empty()) return {ErrorCode::io_error, "", quote(file.first, 200) + ": cannot place it in the baked folder"};
        FACET_CLI_TRY(folder.write(prefix + "/" + rel, file.second));
        if (file.first == loader_name(model)) placed = prefix + "/" + rel;
      }
      if (placed.empty()) return {ErrorCode::io_error, "", model.string() + ": the model file was not read"};
      import["file"] = placed;
      nlohmann::json lightmaps = nlohmann::json::array();
      for (std::size_t k = 0; k < m->scene.objects.size(); ++k) {
        if (next >= r.lightmaps.size()) break;
        lightmaps.push_back(entry(next++));
      }
      import["lightmaps"] = lightmaps;
      import["gl_materials"] = true;
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
    textures.push_back({{"name", names[k]}, {"file", "lightmap_" + std::to_string(k) + ".png"}, {"filter", "bilinear"},
                        {"wrap", "clamp"}, {"encoding", "linear"}});
  }
  std::string text;
  try {
    text = root.dump(2) + "\n";
  } catch (const nlohmann::json::exception&) {
    return {ErrorCode::invalid_argument, "", "cannot write scene.json: a file name is not valid UTF-8"};
  }
  return folder.write("scene.json", text);
}

}  // namespace facet::cli
