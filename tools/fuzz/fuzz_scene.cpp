// Fuzzes the JSON scene parser; accepted scenes must validate and render into a small guarded
// image. (OBJ paths resolve in a directory that does not exist: they fail as missing files.)
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const facet::Result<facet::Scene> scene = facet::parse_scene_json(text, "fuzz.json", "/nonexistent-facet-fuzz");
  if (!scene.ok()) {
    if (scene.status().message().rfind("fuzz.json", 0) != 0) facet::fuzz::broken("an error that does not name the file");
    return 0;
  }
  if (!facet::validate_scene(*scene).ok()) facet::fuzz::broken("parse_scene_json returned an invalid scene");
  std::size_t vertices = 0;
  for (const auto& o : scene->objects) vertices += scene->meshes[o.mesh].mesh.vertex_count();
  if (vertices > 200000) return 0;  // valid, but too slow to render at fuzzing speed
  facet::fuzz::GuardedImage image(24, 16, facet::PixelFormat::rgba8, 3, false);
  facet::RenderOptions options;
  options.threads = 1;
  options.shading = static_cast<facet::ShadingMode>(size % 3);
  facet::Renderer renderer;
  if (!renderer.render(*scene, options, image.view()).ok()) facet::fuzz::broken("a valid scene failed to render");
  image.check();
  return 0;
}
