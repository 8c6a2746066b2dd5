// Internal: the scene file's lights (scene_file_lights.cpp), read through the scene reader's
// JsonFields.
#pragma once

#include <string>

#include "facet/light.hpp"
#include "facet/scene.hpp"
#include "content/json_fields.hpp"

namespace facet::scene_json {

// lights[i] at path `p` into `l`; a projector's texture is looked up by name in scene.textures.
Status read_light(const JsonFields& f, const json& j, const std::string& p, const Scene& scene, Light& l);
// A light's "shadow" object.
Status read_shadow(const JsonFields& f, const json& s, const std::string& p, Shadow& shadow);

}  // namespace facet::scene_json
