// The JSON scene format (documented in README.md, "Scene files"). Every field is optional with a
// documented default; unknown fields are errors. Errors name the file, the line, the field's path
// (`lights[2].position`), what was expected and what was found.
#pragma once

#include <string>

#include "facet/scene.hpp"
#include "facet/status.hpp"

namespace facet {

Result<Scene> load_scene_file(const std::string& path);

// The same from text. `source_name` is used in messages; OBJ paths are resolved against
// `base_dir` (empty = the current directory).
Result<Scene> parse_scene_json(const std::string& text, const std::string& source_name,
                               const std::string& base_dir);

}  // namespace facet
