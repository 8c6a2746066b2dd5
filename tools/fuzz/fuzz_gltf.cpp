// Fuzzes the glTF importer (the container, the JSON reader, the meshopt and Draco decoders): any bytes, as .gltf JSON or .glb, either
// fail with a message or give a valid scene, which then renders within its image.
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  facet::ModelOptions options;
  options.memory_budget_bytes = 64u << 20;
  options.allow_missing = true;
  // External files resolve under a folder that does not exist: the input alone decides.
  const facet::Result<facet::Model> model =
      facet::parse_gltf(std::span<const std::uint8_t>(data, size), "fuzz.gltf", "/nonexistent-facet-fuzz", options);
  if (!model.ok()) {
    if (model.status().message().empty()) facet::fuzz::broken("an error without a message");
    return 0;
  }
  if (!facet::validate_scene(model->scene).ok()) facet::fuzz::broken("parse_gltf returned an invalid scene");
  for (const std::string& w : model->warnings)
    if (w.empty()) facet::fuzz::broken("an empty warning");
  std::size_t triangles = 0;
  for (const auto& m : model->scene.meshes) triangles += m.mesh.triangle_count();
  if (triangles > 20000) return 0;
  // Posing: every animation (up to 4) at its ends, its middle and beyond; a pose either fails
  // with a message or leaves a valid scene.
  facet::Model posed = *model;
  const int animations = static_cast<int>(std::min<std::size_t>(posed.motion.animations.size(), 4));
  for (int a = -1; a < animations; ++a) {
    const facet::AnimationInfo span = a >= 0 ? posed.motion.animations[std::size_t(a)] : facet::AnimationInfo{};
    for (const double t : {span.start_s, 0.5 * (span.start_s + span.end_s), span.end_s, span.end_s + 1e6}) {
      facet::PoseOptions po;
      po.animation = a;
      const facet::Status s = facet::pose_model(posed, t, po);
      if (!s.ok() && s.message().empty()) facet::fuzz::broken("a pose error without a message");
      if (s.ok() && !facet::validate_scene(posed.scene).ok()) facet::fuzz::broken("pose_model left an invalid scene");
    }
  }
  facet::Scene scene = model->scene;
  if (!model->has_camera) {
    facet::Result<facet::Camera> framed = facet::frame_scene(scene, 1.0f);
    if (!framed) {
      if (framed.status().message().empty()) facet::fuzz::broken("a framing error without a message");
      return 0;
    }
    scene.camera = *framed;
  }
  if (!model->has_lights) facet::add_default_lights(scene);
  facet::fuzz::GuardedImage image(17, 13, facet::PixelFormat::rgba8, 3, false);
  facet::RenderOptions o;
  o.threads = 1;
  o.vertex_relief = size % 2 != 0;  // normal maps read per vertex (Gouraud)
  facet::Renderer renderer(o);
  const facet::Status s = renderer.render(scene, image.view());
  if (!s.ok() && s.message().empty()) facet::fuzz::broken("a render error without a message");
  image.check();
  return 0;
}
