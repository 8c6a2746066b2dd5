// The repository's scene files name meshes and textures in sibling folders of tests/data/scenes
// and models in ../shared/models beside the checkout: both are allowed on purpose, as a host would
// allow them (facet/assets.hpp).
#pragma once

#include <string>

#include "facet/scene_file.hpp"

inline facet::LoadOptions repo_scene_options() {
  facet::LoadOptions o;
  o.assets.allowed_roots = {std::string(FACET_SOURCE_DIR) + "/tests/data", std::string(FACET_SOURCE_DIR) + "/../shared/models"};
  return o;
}
