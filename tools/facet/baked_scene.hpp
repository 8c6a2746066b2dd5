// The scene facet bake writes beside its lightmaps (DIR/scene.json): the input drawn with its
// lightmaps, and the files the loader read for it copied into DIR byte for byte as it read them.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "facet/facet.hpp"
#include "output_folder.hpp"

namespace facet::cli {

using Files = std::map<std::string, std::string>;  // what a load read: name -> bytes (AssetAccess::on_read)

// A path as the loader names the files it reads: normal, relative while it does not climb out of
// the current directory, else absolute.
std::string loader_name(const std::filesystem::path& p);

struct BakedSceneRequest {
  std::string input;                     // the scene file or model baked ("": the built-in scene)
  std::string mode = "diffuse";          // the lightmaps' mode: diffuse | replace
  std::vector<std::string> allow_paths;  // --allow-path
};

// `read`: the files the input's load read (AssetAccess::on_read). `note` says why no scene was
// written, when none was (the built-in scene, a scene already baked, a file outside the scene's
// folder or not read).
Status write_baked_scene(const BakedSceneRequest& st, const OutputFolder& folder, const Files& read, const BakeOptions& o,
                         double scale, const BakeResult& r, std::string& note);

}  // namespace facet::cli
