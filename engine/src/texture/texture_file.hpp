// Internal: a texture file named by a scene or a material, read through its AssetFolder (within
// the folder rules and the budget) and decoded. A file that cannot be read is ErrorCode::io_error;
// decoding never gives that code, so callers can tell a missing file from a bad one.
#pragma once

#include <string>
#include <string_view>

#include "facet/texture.hpp"
#include "io/assets.hpp"

namespace facet {

// `where` starts every message ("m.mtl:4: texture"); the file's name follows it.
Result<Texture> read_texture(const io::AssetFolder& folder, std::string_view file, const std::string& where,
                             std::string name, const TextureOptions& options);

}  // namespace facet
