// Fuzzes the JSON scene parser; accepted scenes must validate and, unless check_render refuses
// them (frame limits, memory budget) with the very message render() then gives, render into a
// small guarded image. Loads run under a 256 MiB budget, so no input can take more than that in
// meshes (the fuzzer's RSS limit is 3 GiB). (OBJ paths resolve in a directory that does not
// exist: they fail as missing files.)
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  facet::LoadOptions load;
  load.memory_budget_bytes = std::uint64_t{256} << 20;
  const facet::Result<facet::Scene> scene = facet::parse_scene_json(text, "fuzz.json", "/nonexistent-facet-fuzz", load);
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
  const facet::Status checked = facet::check_render(*scene, options, 24, 16);
  const facet::Status rendered = renderer.render(*scene, options, image.view());
  if (checked.message() != rendered.message()) facet::fuzz::broken("check_render and render disagree");
  if (!checked.ok()) return 0;  // a frame limit or the memory budget, the same for both
  image.check();
  return 0;
}
