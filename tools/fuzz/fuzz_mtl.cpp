// Fuzzes the MTL reader: any text either fails with a message naming a line, or gives materials
// that pass validate_material.
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  facet::ModelOptions options;
  options.memory_budget_bytes = 64u << 20;
  options.allow_missing = true;  // texture files resolve under a folder that does not exist
  facet::Scene scene;
  std::vector<std::string> warnings;
  const facet::Status s = facet::parse_mtl(text, "fuzz.mtl", "/nonexistent-facet-fuzz", options, scene, warnings);
  if (!s.ok()) {
    if (s.message().find("fuzz.mtl") == std::string::npos) facet::fuzz::broken("an error that does not name the file");
    return 0;
  }
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (!facet::validate_material(scene.materials[i], i).ok()) facet::fuzz::broken("parse_mtl returned an invalid material");
    for (const auto t : {scene.materials[i].diffuse_texture, scene.materials[i].emissive_texture}) {
      if (t != facet::kNoTexture && (t < 0 || static_cast<std::size_t>(t) >= scene.textures.size())) {
        facet::fuzz::broken("a material names a texture that does not exist");
      }
    }
  }
  return 0;
}
