// A scene: meshes, materials, instances of (mesh, material, transform), lights, a camera and the
// global switches of the lighting model. Plain data, owned by the caller; validate_scene() checks
// it and names the offending field in the scene-file path form ("lights[2].position").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "facet/camera.hpp"
#include "facet/display.hpp"
#include "facet/environment_light.hpp"
#include "facet/light.hpp"
#include "facet/material.hpp"
#include "facet/mesh.hpp"
#include "facet/status.hpp"
#include "facet/texture.hpp"
#include "facet/types.hpp"

namespace facet {

enum class ViewerMode {
  local,     // specular half-vector uses the true direction to the eye (GL_LIGHT_MODEL_LOCAL_VIEWER)
  infinite,  // uses (0, 0, 1) in eye space: cheaper, GL's default
};

// Fog (GL 2.1 §3.10) on the eye-space depth z of each pixel (its distance along the view axis),
// factor f in [0, 1] (1: no fog), colour = f colour + (1 - f) fog colour, after texturing and
// before blending; alpha is unchanged.
enum class FogMode : std::uint8_t {
  none,
  linear,  // f = (end - z) / (end - start); start == end: 1 before it, 0 beyond
  exp,     // f = e^(-density z)
  exp2,    // f = e^(-(density z)^2)
};
const char* to_string(FogMode mode) noexcept;

struct Fog {  // GL's defaults
  FogMode mode = FogMode::none;
  Color3 color{0.0f, 0.0f, 0.0f};
  float start = 0.0f, end = 1.0f;  // linear: finite, start <= end
  float density = 1.0f;            // exp, exp2: finite, >= 0
};

struct NamedMesh {
  std::string name;
  Mesh mesh;
};

enum class LightmapMode : std::uint8_t { diffuse, replace };
const char* to_string(LightmapMode mode) noexcept;

struct Instance {
  std::uint32_t mesh = 0;      // index into Scene::meshes
  std::uint32_t material = 0;  // index into Scene::materials
  Mat4 model = Mat4::Identity();  // model -> world; must be invertible
  // Per-face materials: draw each of the mesh's material groups (Mesh::groups, OBJ `usemtl`) with
  // the scene material of the group's name, instead of `material` for the whole mesh.
  bool mesh_materials = false;
  // Shadows (Light::shadow): whether this object blocks shadowed lights, and whether its pixels
  // can be in shadow.
  bool cast_shadows = true;
  bool receive_shadows = true;
  // Both faces of each triangle are drawn and lit (back faces with the negated normal), as if
  // Scene::two_sided were set and culling were off for this object alone (glTF `doubleSided`).
  bool double_sided = false;
  // Baked light (docs/baking.md): a texture of Scene::textures read at the mesh's lightmap
  // coordinates (Mesh::lightmap_uvs), whose RGB times lightmap_scale is the light arriving at the
  // surface; the colour is the emission plus the material's diffuse colour (times its texture)
  // times that light. With LightmapMode::diffuse the lights still add their specular term; with
  // replace, nothing else lights the object. kNoTexture: lit by the lights as usual. Not with
  // vertex colours, environment, normal or bump maps, or a texture environment other than modulate.
  std::int32_t lightmap = -1;
  float lightmap_scale = 1.0f;
  LightmapMode lightmap_mode = LightmapMode::diffuse;
};
// One layout whatever the host's compiler flags (types.hpp): a host built with -mavx2 or
// -march=native shares these structs with a library built for baseline x86-64.
static_assert(sizeof(Instance) == 88 && alignof(Instance) == 4, "facet::Instance must not depend on compiler flags");


// The order in which the camera's pass draws objects (shadow and depth passes need none).
//  - submission: scene order, as GL draws what it is given (the default);
//  - back_to_front: opaque objects first, in scene order; then every object with a blended
//    material (any blend but opaque, in any of its material groups), farthest first by the
//    eye-space depth of the centre of its mesh's box, ties in scene order. Within an object,
//    triangles keep their mesh order. The order is a function of the scene alone (draw_order),
//    so images stay byte-identical for any thread count.
enum class TransparentOrder { submission, back_to_front };
const char* to_string(TransparentOrder order) noexcept;  // its name in scene files and on the command line

struct Scene {
  std::vector<NamedMesh> meshes;
  std::vector<Material> materials;
  std::vector<Instance> objects;
  std::vector<Light> lights;
  std::vector<Texture> textures;  // Material::diffuse_texture indexes them
  Fog fog;
  Color3 global_ambient{0.2f, 0.2f, 0.2f};
  Camera camera;
  // Exposure and tone mapping (facet/display.hpp): GL's by default; models with lights in
  // physical units get automatic exposure and every model the neutral operator (docs/color.md).
  Display display;
  // What PBR materials see around them (facet/environment_light.hpp): none by default; glTF
  // models without lights of their own get the neutral studio.
  EnvironmentLight environment_light;
  // What is drawn behind the model: the clear colour (default), or the surroundings, which then
  // need a source (environment_light.source not none). Blended surfaces blend over it and
  // multisampled edges resolve against it, as against the clear colour.
  Background background = Background::colour;
  ViewerMode viewer = ViewerMode::local;
  bool two_sided = false;  // back faces are lit with the negated normal
  TransparentOrder transparent_order = TransparentOrder::submission;
};

// The objects (indices into scene.objects) in the order the camera's pass draws them
// (TransparentOrder). Every object appears once, drawable or not.
std::vector<std::size_t> draw_order(const Scene& scene);
// Whether an object is drawn with the transparent ones under back_to_front: its material, or one
// of its mesh's group materials, blends.
bool is_transparent(const Scene& scene, const Instance& object);

Status validate_scene(const Scene& scene);

// The index of the scene material called `name` (the first, if several are), or -1.
std::int64_t find_material(const Scene& scene, const std::string& name) noexcept;

// Tangents (generate_tangents) for every mesh an object draws with a normal-mapped material (its
// own, or a material group's) that has texture coordinates and no tangents. Scene files and
// models call it after loading; hosts that build scenes call it (or give Mesh::tangents) before
// rendering one with normal maps.
Status generate_missing_tangents(Scene& scene);

// Parts of validate_scene, for callers that build a scene piece by piece (the C API checks each
// piece as it is added): the same checks and messages, naming materials[index], lights[index],
// camera.* and global_ambient.
Status validate_material(const Material& material, std::size_t index);
Status validate_light(const Light& light, std::size_t index);
Status validate_camera(const Camera& camera);
Status validate_global_ambient(const Color3& ambient);
Status validate_fog(const Fog& fog);
Status validate_environment_light(const EnvironmentLight& environment);

// The built-in scene: procedural shapes only (spheres of shininess 8, 64 and 512, a cube, a torus
// and a ground plane with a procedural checkered texture; the shininess-512 sphere is alpha-blended
// glass, drawn last) lit by a directional light, a point light with attenuation, a GL spot light
// and a smooth-cone spot light. Needs no file.
Scene make_default_scene();

}  // namespace facet
