// Models made elsewhere: glTF 2.0 (.gltf, .glb) and Wavefront OBJ with its MTL materials, read
// into a facet Scene (docs/content.md lists what is read, how it maps onto facet's lighting model
// and what is ignored; everything ignored is named in Model::warnings, nothing is dropped in
// silence). Also what a viewer needs around a model: a camera that frames it, a default rig of
// lights, and the reason a frame drew nothing.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facet/animation.hpp"
#include "facet/assets.hpp"
#include "facet/mesh.hpp"
#include "facet/scene.hpp"
#include "facet/status.hpp"

namespace facet {

struct FrameStats;

struct ModelOptions {
  // The most memory the files, images and meshes of the model may take (ErrorCode::out_of_memory
  // beyond it, naming what crossed it). 0 = no limit.
  std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes;
  // A material library or texture that is missing or cannot be read (not found, outside the
  // model's folder, not an image facet reads) is a warning, as every viewer treats it: the
  // material is untextured, or facet's default. false (strict: `facet --strict`, C
  // FACET_LOAD_STRICT, Python strict=True) refuses the model instead, naming the file. Running out
  // of the memory budget is an error either way.
  bool allow_missing = true;
  // OBJ: the crease angle used when the file has no normals (glTF: flat normals, as its
  // specification requires).
  float crease_angle_deg = kDefaultCreaseAngleDeg;
  // Which files the model may name (its buffers, images, `mtllib`s and textures): by default only
  // files in the model's own folder (facet/assets.hpp).
  AssetAccess assets;
  // glTF: the camera to use, by its index in the file's `cameras` ("2") or by name (the camera's
  // or its node's); empty: the first camera node in the scene's order. A camera that is not in
  // the drawn scene is an error that lists the ones that are (`facet --camera`).
  std::string camera;
  // glTF: light its metallic-roughness materials with GL's lighting model (the Blinn-Phong mapping
  // of docs/content.md, as facet did before it had the glTF BRDF): what GL parity asks for
  // (`facet --gl-materials`, facet_vs_llvmpipe). false: Material::model pbr (docs/pbr.md).
  bool gl_materials = false;
};

struct Model {
  // Meshes, materials, textures and objects; the file's lights and camera when it has them (else
  // none, and the default camera). Objects are placed in the file's world coordinates. Blended
  // objects are drawn back to front (Scene::transparent_order), as glTF asks of renderers.
  Scene scene;
  bool has_camera = false;  // the scene's camera is the file's
  bool has_lights = false;  // the scene's lights are the file's
  // glTF: the camera nodes of the drawn scene in its order, one line each: the index in
  // `cameras`, the camera's name, its node's name when it differs, and its type
  // (`1 "Top" (node "Camera.001"), "orthographic"`).
  std::vector<std::string> cameras;
  // What was read approximately or not at all, one line each ("materials[2]: normalTexture is
  // not supported; ignored").
  std::vector<std::string> warnings;
  // glTF: what moves (facet/animation.hpp); pose_model() poses the scene. `rig` is what posing
  // reads (null for a static model), `pose` and `pose_seconds` the pose the scene shows (at load:
  // the rest pose, animation -1).
  MotionInfo motion;
  std::shared_ptr<const Rig> rig;
  PoseOptions pose{.animation = -1};
  double pose_seconds = 0.0;
};

// By extension: .gltf, .glb or .obj (case-insensitive). Errors name the file and the JSON path
// (`meshes[0].primitives[1].attributes.NORMAL`) or the line.
Result<Model> load_model(const std::string& path, const ModelOptions& options = {});

// glTF 2.0 through tinygltf: `.glb` when the bytes start with the binary header, else JSON.
// External buffers and images are read from `base_dir` (regular files only, within the budget).
Result<Model> load_gltf(const std::string& path, const ModelOptions& options = {});
Result<Model> parse_gltf(std::span<const std::uint8_t> bytes, const std::string& source_name,
                         const std::string& base_dir, const ModelOptions& options = {});

// OBJ with the materials of its `mtllib` files (resolved against the OBJ's folder): `usemtl` runs
// become per-face materials (Instance::mesh_materials).
Result<Model> load_obj_model(const std::string& path, const ModelOptions& options = {});
// The MTL reader alone, from text: the materials and their texture file names resolved against
// `base_dir`, textures loaded. `source_name` is used in messages.
Status parse_mtl(const std::string& text, const std::string& source_name, const std::string& base_dir,
                 const ModelOptions& options, Scene& scene, std::vector<std::string>& warnings);

// The world-space box around every object's vertices; empty (min > max) when there are none.
struct Bounds {
  Vec3 min{1.0f, 1.0f, 1.0f};
  Vec3 max{-1.0f, -1.0f, -1.0f};
  bool empty() const noexcept { return !(min.array() <= max.array()).all(); }
};
Bounds scene_bounds(const Scene& scene);

// Which way is up in a model's world, and so where its front is: glTF's convention (+Y up, the
// front faces +Z, the viewer) or the one of CAD and Blender (+Z up, the front faces -Y); right is
// +X in both. The other four axes, for models lying on their side or upside down: -y (the front
// faces +Z), x and -x (the front faces +Z), -z (the front faces -Y); in each, right = up x front.
enum class UpAxis { y, z, x, neg_x, neg_y, neg_z };
// "y", "z", "x", "-x", "-y", "-z"
const char* to_string(UpAxis up) noexcept;
// The axis named as to_string names it; false for anything else.
bool parse_up_axis(std::string_view name, UpAxis& out) noexcept;
Vec3 up_vector(UpAxis up) noexcept;
// Where the model's front faces: the direction the default view looks from.
Vec3 front_vector(UpAxis up) noexcept;

// Where a framing camera looks from, and how much of the image the model takes.
struct ViewOptions {
  float azimuth_deg = 0.0f;    // about the up axis: 0 from the front, 90 from +X (the right), 180 from behind
  float elevation_deg = 0.0f;  // above the horizon, in (-90, 90); negative looks from below
  UpAxis up = UpAxis::y;
  float vertical_fov_deg = 45.0f;  // (0, 180)
  // The part of the image's height or width (whichever the model reaches first) that the model's
  // projection spans, in (0, 1].
  float fill = 0.85f;
  // A perspective framing with the field of view above, or an orthographic one (glOrtho: parallel
  // rays, no foreshortening). Last, so that aggregate initialisers written before it still work.
  Projection projection = Projection::perspective;
};
Status validate_view(const ViewOptions& view);

// A camera that frames every vertex of the scene's objects at `aspect` (width / height): it looks
// from the direction `view` gives at the centre of their projection, from the distance at which
// the widest of them spans `view.fill` of the image's height or width (exactly, up to rounding);
// near and far planes just around them. The scene's camera is not changed. Errors: no vertex to
// frame, a view out of range, or coordinates too large to frame in float.
Result<Camera> frame_scene(const Scene& scene, float aspect, const ViewOptions& view = {});
// The same for the eight corners of a box (a model's box frames it loosely: its corners lie
// outside most models).
Result<Camera> frame_bounds(const Bounds& bounds, float aspect, const ViewOptions& view = {});

// A turntable's step: `camera` turned by `angle_deg` about the axis `up` through `centre`
// (counter-clockwise seen from above), its target moved to `centre`, its distance from `centre`
// kept. A light turned likewise (its position and direction) stays where it was relative to the
// camera: a rig that turns with the camera.
Camera orbit_camera(const Camera& camera, const Vec3& centre, UpAxis up, float angle_deg);
Light orbit_light(const Light& light, const Vec3& centre, UpAxis up, float angle_deg);

// facet's default lighting, for models that bring no lights. A scene whose materials are all
// pbr gets the neutral studio (Scene::environment_light, docs/pbr.md) and no ambient, as a glTF
// viewer lights a model; otherwise facet's rig: a white headlight along the camera's view
// (diffuse 0.5, no specular) and a key light from above, left and in front of the camera (diffuse
// 0.7, specular 0.5), both directional, and a global ambient of 0.15 (with the studio as well when
// some material is pbr). Returns what it added, in words (for a note).
const char* add_default_lights(Scene& scene);

// Why a frame drew nothing ("no objects", "every triangle is outside the view", "every triangle
// is back-facing and culled", ...), or an empty string when it filled pixels.
std::string explain_empty_frame(const FrameStats& stats);

}  // namespace facet
