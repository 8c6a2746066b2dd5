// Models made elsewhere: glTF 2.0 (.gltf, .glb) and Wavefront OBJ with its MTL materials, read
// into a facet Scene (docs/content.md lists what is read, how it maps onto facet's lighting model
// and what is ignored; everything ignored is named in Model::warnings, nothing is dropped in
// silence). Also what a viewer needs around a model: a camera that frames it, a default rig of
// lights, and the reason a frame drew nothing.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

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
  // OBJ: a missing .mtl file or texture is a warning (the material is untextured, or facet's
  // default) instead of an error. glTF: a missing image file likewise.
  bool allow_missing = false;
  // OBJ: the crease angle used when the file has no normals (glTF: flat normals, as its
  // specification requires).
  float crease_angle_deg = kDefaultCreaseAngleDeg;
  // Which files the model may name (its buffers, images, `mtllib`s and textures): by default only
  // files in the model's own folder (facet/assets.hpp).
  AssetAccess assets;
};

struct Model {
  // Meshes, materials, textures and objects; the file's lights and camera when it has them (else
  // none, and the default camera). Objects are placed in the file's world coordinates. Blended
  // objects are drawn back to front (Scene::transparent_order), as glTF asks of renderers.
  Scene scene;
  bool has_camera = false;  // the scene's camera is the file's
  bool has_lights = false;  // the scene's lights are the file's
  // What was read approximately or not at all, one line each ("materials[2]: normalTexture is
  // not supported; ignored").
  std::vector<std::string> warnings;
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

// A camera looking at the centre of the bounding sphere of `bounds` from the front and a little
// above (+z, +y), far enough that the whole sphere fits the vertical field of view and the
// horizontal one at `aspect` (width / height); near and far planes around the sphere.
Camera frame_bounds(const Bounds& bounds, float aspect, float vertical_fov_deg = 45.0f);

// facet's default rig, for models that bring no lights: a white headlight along the camera's view
// (diffuse 0.5, no specular) and a key light from above, left and in front of the camera (diffuse
// 0.7, specular 0.5), both directional, and a global ambient of 0.15.
void add_default_lights(Scene& scene);

// Why a frame drew nothing ("no objects", "every triangle is outside the view", "every triangle
// is back-facing and culled", ...), or an empty string when it filled pixels.
std::string explain_empty_frame(const FrameStats& stats);

}  // namespace facet
