// Animated models: glTF 2.0's animations (keyframes of nodes' translation, rotation, scale and
// morph weights), skins (vertices bent by a skeleton's joints) and morph targets (vertex offsets
// blended by weights), posed at any time (docs/animation.md).
//
// A Model read from a glTF file keeps what posing needs (Model::rig, shared and immutable); its
// scene is drawn as the file places it (the rest pose, skins at their joints' rest transforms)
// until pose_model() moves its objects, deforms its skinned and morphed meshes and moves the
// file's camera and lights to where they are at that time.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "facet/status.hpp"

namespace facet {

struct Model;
struct Bounds;
struct Rig;  // internal: the node tree, animations, skins and morph targets a pose is made from

// One of the file's animations.
struct AnimationInfo {
  std::string name;  // the file's name, or "animations[i]"
  double start_s = 0.0, end_s = 0.0;  // its first and last keyframe over every channel, in seconds
  std::size_t channels = 0;
};

// One of the file's skins that the drawn scene uses.
struct SkinInfo {
  std::string name;  // the file's name, or "skins[i]"
  std::size_t joints = 0;
  std::size_t vertices = 0;  // skinned vertices, over every mesh that uses the skin
  int influences = 4;        // joints per vertex: 4 (JOINTS_0) or 8 (JOINTS_0 and JOINTS_1)
};

// What moves in a model, for `facet check` and hosts; empty for a static model.
struct MotionInfo {
  std::vector<AnimationInfo> animations;
  std::vector<SkinInfo> skins;
  std::size_t morphed_meshes = 0;  // drawn meshes with morph targets
  std::size_t morph_targets = 0;   // over those meshes
  bool any() const noexcept { return !animations.empty() || !skins.empty() || morphed_meshes > 0; }
};

// How the normals (and tangents) of a skinned vertex are transformed by its blended joint matrix
// M (docs/animation.md measures the two):
//  - cofactor: by M's cofactor matrix (the inverse transpose times det M, its sign kept), exact
//    for any blended matrix, non-uniform scale included (the default);
//  - linear: by M's upper 3x3 itself, as many engines (three.js among them) do: exact only while
//    the joints neither shear nor scale unevenly.
enum class NormalTransform : unsigned char { cofactor, linear };

// Where a pose is computed (every path draws the same picture; simd within the bound that
// docs/animation.md states, byte-identical for any thread count).
enum class PosePath : unsigned char { simd, scalar, reference };

struct PoseOptions {
  // The animation to play, by index into MotionInfo::animations; -1: none (the rest pose, morph
  // weights as the file gives them).
  int animation = 0;
  NormalTransform normals = NormalTransform::cofactor;
  PosePath path = PosePath::simd;
};

// The model's scene at `seconds` into the animation (clamped to its keys: before the first the
// first, after the last the last). Objects of animated nodes move, skinned and morphed meshes are
// rewritten, the file's camera and lights follow their nodes. Errors: an animation index out of
// range, a time that is not finite. A model with nothing that moves is left as it is.
Status pose_model(Model& model, double seconds, const PoseOptions& options = {});

// pose_model for a host that keeps a model's scene apart from its Model (the C and Python
// bindings, facet's CLI): the scene `rig` was read with (null: nothing moves), whose camera is the
// file's when `file_camera`.
struct Scene;
Status pose_scene(Scene& scene, const Rig* rig, bool file_camera, double seconds, const PoseOptions& options = {});

// An animation by index ("0") or by name; the index, or an error listing the model's animations.
Result<int> find_animation(const Model& model, std::string_view index_or_name);
Result<int> find_animation(const MotionInfo& motion, std::string_view index_or_name);

// The times at which framing samples an animation: `count` (at least 2) times spread evenly from
// its first to its last key, both included.
std::vector<double> animation_sample_times(const AnimationInfo& animation, int count);

// The box around the model's vertices over its animation: the union of the poses' boxes at
// animation_sample_times(count); the model is posed again as it was (Model::pose). For a static
// model or animation -1, the box of that pose.
Result<Bounds> animation_bounds(Model& model, const PoseOptions& options, int count = 32);

// frame_scene (facet/model.hpp) over the whole animation: a camera that frames every vertex of
// the poses at animation_sample_times(count), so that the model does not leave the picture; the
// model is posed again as it was. Animation -1: frame_scene of the rest pose.
struct Camera;
struct ViewOptions;
Result<Camera> frame_animation(Model& model, float aspect, const ViewOptions& view, const PoseOptions& options,
                               int count = 16);

}  // namespace facet
