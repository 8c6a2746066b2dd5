// The C API's animated models (facet.h: facet_scene_animation_count, facet_scene_animation_info,
// facet_scene_pose; facet/animation.hpp).
#include <cmath>

#include "c_api/handles.hpp"

using namespace facet::c_api;  // NOLINT(google-build-using-namespace): the C API's shared helpers

extern "C" {

size_t facet_scene_animation_count(const facet_scene* scene) { return scene ? scene->motion.animations.size() : 0; }

facet_status facet_scene_animation_info(facet_scene* scene, size_t index, const char** name, double* start_s, double* end_s) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (index >= scene->motion.animations.size()) {
      return fail(scene->error, "index", std::to_string(index) + " is out of range (" + std::to_string(scene->motion.animations.size()) +
                                             " animations)");
    }
    const facet::AnimationInfo& a = scene->motion.animations[index];
    if (name) *name = a.name.c_str();
    if (start_s) *start_s = a.start_s;
    if (end_s) *end_s = a.end_s;
    return report(scene->error, {});
  });
}

facet_status facet_scene_pose(facet_scene* scene, int animation, double seconds) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!std::isfinite(seconds)) return fail(scene->error, "seconds", "not a finite number");
    if (!scene->rig) {
      if (animation == -1 && scene->motion.animations.empty() && scene->motion.skins.empty() && scene->motion.morphed_meshes == 0) {
        return report(scene->error, {});  // nothing moves: nothing to do
      }
      return fail(scene->error, "scene", "an object or light of the loaded model was removed; load it again to pose it");
    }
    facet::PoseOptions options;
    options.animation = animation;
    return report(scene->error, facet::pose_scene(scene->scene, scene->rig.get(), scene->file_camera, seconds, options));
  });
}

}  // extern "C"
