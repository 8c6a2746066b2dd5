// The JSON scene format (documented in README.md, "Scene files"). Every field is optional with a
// documented default; unknown fields are errors. Errors name the file, the line, the field's path
// (`lights[2].position`), what was expected and what was found.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "facet/assets.hpp"
#include "facet/mesh.hpp"
#include "facet/model.hpp"
#include "facet/scene.hpp"
#include "facet/status.hpp"

namespace facet {

struct LoadOptions {
  // The most memory the loaded scene's meshes and the files read for it may take: each mesh's
  // size is computed before it is generated or read, and a scene over the budget is refused with
  // ErrorCode::out_of_memory, naming the mesh that crossed it. 0 = no limit. `facet
  // --memory-budget-mb` sets it.
  std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes;
  // Progress and cancellation: called on the calling thread after each mesh with the share of
  // meshes done, and again with the same share after each row of cube faces made from an
  // equirectangular picture (which takes seconds for large faces); return false to stop the load
  // with ErrorCode::cancelled.
  std::function<bool(double done)> progress;
  // Called on the calling thread with each warning of the models the scene imports ("imports":
  // what was read approximately or not at all, model.hpp). Null: warnings are dropped.
  std::function<void(const std::string& warning)> warning;
  // Which files the scene may name (meshes, textures, imported models; and what those models
  // name): by default only files in the naming file's own folder (facet/assets.hpp).
  AssetAccess assets;
  // A scene file that imports models but has no "camera" (and no import's "camera": true) gets
  // a camera framing every object (frame_scene, with this view at this aspect, width / height),
  // and one with neither "lights" nor an import's lights gets facet's default rig
  // (add_default_lights), as `facet render MODEL` frames and lights a model. `warning` says so.
  ViewOptions view;
  float frame_aspect = 16.0f / 9.0f;
  // Imported models load strictly (ModelOptions::allow_missing false: a missing or unreadable
  // material library or texture is an error), whatever an import's "allow_missing" says.
  bool strict = false;
  // Imported glTF models light their materials with GL's model (ModelOptions::gl_materials), as
  // an import's "gl_materials": true asks for one.
  bool gl_materials = false;
};

Result<Scene> load_scene_file(const std::string& path, const LoadOptions& options = {});

// The same from text. `source_name` is used in messages; OBJ paths are resolved against
// `base_dir` (empty = the current directory).
Result<Scene> parse_scene_json(const std::string& text, const std::string& source_name,
                               const std::string& base_dir, const LoadOptions& options = {});

}  // namespace facet
