// Surface material of the classic (OpenGL 2.1 fixed-function) lighting model. Defaults are GL's.
#pragma once

#include <cstdint>
#include <string>

#include "facet/types.hpp"

namespace facet {

// Largest accepted shininess and spot exponent. GL caps both at 128; facet allows more so that
// tight highlights can be studied (the pow tiers are specified up to this bound).
inline constexpr float kMaxShininess = 4096.0f;

// How a texel combines with the lit (primary) colour: GL 2.1's texture environment (table 3.22,
// RGBA texture; Cf, Af the fragment's colour and alpha, Ct, At the texel's):
enum class TextureMode : std::uint8_t {
  modulate,  // C = Cf Ct, A = Af At (GL's default: texture times light)
  replace,   // C = Ct, A = At
  decal,     // C = Cf (1 - At) + Ct At, A = Af
  add,       // C = min(Cf + Ct, 1), A = Af At
};

// How a fragment combines with the colour already in the image (GL's blend factors, the same for
// alpha as for colour; results saturate to [0, 1]). Cs, As: the fragment; Cd: the image.
enum class BlendMode : std::uint8_t {
  opaque,         // C = Cs
  alpha,          // C = Cs As + Cd (1 - As)       (SRC_ALPHA, ONE_MINUS_SRC_ALPHA)
  premultiplied,  // C = Cs + Cd (1 - As)          (ONE, ONE_MINUS_SRC_ALPHA)
  add,            // C = Cs + Cd                   (ONE, ONE)
  multiply,       // C = Cs Cd                     (DST_COLOR, ZERO)
  subtract,       // C = Cd - Cs                   (reverse subtract, ONE, ONE)
};

// The specular lobe: cos^shininess of the angle between
enum class SpecularModel : std::uint8_t {
  blinn,  // the normal and the half vector h = unit(L + V) (GL's, the default)
  phong,  // the reflected light direction R = 2 (n.L) n - L and the view direction V (Phong 1975);
          // R.V < 0 counts as 0, so shininess 0 still gives 1 on the lit side, as Blinn's does
};
const char* to_string(SpecularModel model) noexcept;

// Whether the material's fragments write depth: `automatic` writes for opaque materials and not
// for blended ones (they test depth but do not hide what is drawn after them).
enum class DepthWrite : std::uint8_t { automatic, on, off };

const char* to_string(TextureMode mode) noexcept;
const char* to_string(BlendMode mode) noexcept;
const char* to_string(DepthWrite mode) noexcept;

// No texture (Material::diffuse_texture).
inline constexpr std::int32_t kNoTexture = -1;

// Environment mapping: a picture of the surroundings looked up by the eye-space direction a
// surface reflects or faces (GL 2.1 §2.11.4 texture-coordinate generation), with u the unit vector
// from the eye to the point, n the unit eye-space normal and r = u - 2 n (n . u) the reflection:
enum class EnvironmentMode : std::uint8_t {
  none,
  sphere,  // GL_SPHERE_MAP: m = 2 sqrt(rx^2 + ry^2 + (rz + 1)^2), (s, t) = (rx / m + 1/2, ry / m + 1/2)
  cube,    // GL_REFLECTION_MAP into a cube map: the face of r's major axis (GL 2.1 §3.8.6), with r
           // turned into world space (GL: the texture matrix holds the view's inverse rotation),
           // so the room stays put as the camera moves
  normal,  // the eye-space normal's x and y: (s, t) = (nx / 2 + 1/2, ny / 2 + 1/2) (a precomputed
           // light texture looked up per normal, as the classic "environment-mapped" Gouraud does)
};
// How the environment's colour E combines with the textured colour C, strength k in [0, 1]:
enum class EnvironmentBlend : std::uint8_t {
  add,       // C + k E (a reflection or highlight on top; saturated)
  modulate,  // C (1 - k + k E)
  mix,       // C (1 - k) + k E (a mirror at k = 1)
};
struct Environment {
  EnvironmentMode mode = EnvironmentMode::none;
  // sphere, normal: maps[0] (a picture with up at its top); cube: the faces +X, -X, +Y, -Y, +Z,
  // -Z (square, the same size; each face's picture as the usual skybox images are drawn: GL's t
  // runs down the picture, as GL reads faces uploaded top row first), indices into Scene::textures.
  std::int32_t maps[6] = {kNoTexture, kNoTexture, kNoTexture, kNoTexture, kNoTexture, kNoTexture};
  float strength = 1.0f;  // [0, 1]
  EnvironmentBlend blend = EnvironmentBlend::add;
  // cube only: render the six faces from the scene every frame instead of reading `maps` (which
  // stay -1): square views of `resolution` pixels from the centre of the box of each object drawn
  // with this material, the object itself left out (a chrome ball reflects the room it stands in).
  // Inside those views, other dynamic reflectors are drawn without their reflection, and nothing
  // is shadowed.
  bool dynamic = false;
  int resolution = 128;  // [1, 4096]
  // Lit per pixel (Phong): looked up per pixel from the interpolated position and normal. Flat and
  // Gouraud: the coordinates are generated at the vertices and interpolated (as GL's texgen), and
  // the map looked up per pixel.
};
const char* to_string(EnvironmentMode mode) noexcept;
const char* to_string(EnvironmentBlend mode) noexcept;

// The lighting model of a material: GL 2.1's fixed function (emissive, ambient, diffuse, specular,
// shininess), or glTF 2.0's metallic-roughness BRDF (base_color, metallic, roughness, ior,
// specular; docs/pbr.md), which is also lit by the scene's surroundings (Scene::environment_light).
enum class MaterialModel : std::uint8_t { gl, pbr };
const char* to_string(MaterialModel model) noexcept;

struct Material {
  std::string name;
  MaterialModel model = MaterialModel::gl;
  Color3 emissive{0.0f, 0.0f, 0.0f};
  Color3 ambient{0.2f, 0.2f, 0.2f};
  Color3 diffuse{0.8f, 0.8f, 0.8f};
  Color3 specular{0.0f, 0.0f, 0.0f};
  float shininess = 0.0f;  // specular exponent in [0, kMaxShininess]; 0^0 = 1 as in GL
  SpecularModel specular_model = SpecularModel::blinn;
  float alpha = 1.0f;      // [0, 1]: the fragment's alpha (blending, alpha test, the output's alpha)

  // pbr: the metallic-roughness material (glTF's pbrMetallicRoughness, KHR_materials_ior and
  // KHR_materials_specular). Its base colour texture is diffuse_texture (sRGB), its alpha `alpha`,
  // its emission `emissive` (with emissive_texture), and normal_texture and occlusion_texture
  // apply as they do to GL materials (occlusion darkening the surroundings' light). Vertex colours
  // multiply the base colour. The GL colours, shininess and specular_model are not read.
  Color3 base_color{1.0f, 1.0f, 1.0f};  // linear, [0, 1]
  float metallic = 0.0f;                // [0, 1]
  float roughness = 1.0f;               // perceptual roughness, [0, 1] (held at >= 0.045 when lit)
  float ior = 1.5f;                     // [1, 10]: dielectric reflectance ((ior - 1) / (ior + 1))^2
  float specular_weight = 1.0f;         // [0, 1]: KHR_materials_specular's specularFactor
  Color3 specular_color{1.0f, 1.0f, 1.0f};  // [0, 1e6]: its specularColorFactor (reflectance capped at 1)
  // glTF's metallicRoughnessTexture (linear): its blue channel times `metallic` and its green
  // channel times `roughness` are the pixel's, at the diffuse texture's uvs. Lit per pixel only
  // (Phong), as the normal and occlusion maps: flat and Gouraud shading use the factors.
  std::int32_t metallic_roughness_texture = kNoTexture;  // index into Scene::textures

  // Surface (see docs/surfaces.md). A texture needs the mesh's uvs.
  std::int32_t diffuse_texture = kNoTexture;  // index into Scene::textures
  TextureMode texture_mode = TextureMode::modulate;
  Vec2 uv_scale{1.0f, 1.0f};  // texture coordinates are multiplied by it; finite and non-zero
  float alpha_cutoff = 0.0f;  // alpha test: fragments with alpha < cutoff are discarded; [0, 1], 0 = off
  // Alpha to coverage (GL_SAMPLE_ALPHA_TO_COVERAGE), multisampled frames only (RenderOptions::samples
  // > 1; at one sample it does nothing, as in GL): of a pixel's N samples, sample s keeps its
  // coverage when the fragment's alpha > s / N (llvmpipe's rule), so alpha a covers about a N of
  // them; the alpha itself is unchanged. Before the alpha test, which still applies.
  bool alpha_to_coverage = false;
  BlendMode blend = BlendMode::opaque;
  DepthWrite depth_write = DepthWrite::automatic;

  // Emission after texturing (glTF's rule). GL adds the emission into the lit colour, so a
  // diffuse texture modulates it; with `emission_after_texture` the emission is left out of the
  // lighting and added after the texture environment instead (saturated, before the separate
  // specular). An `emissive_texture` implies it: the emission is `emissive` times the texel's RGB
  // (its alpha is not read), sampled at the same uvs as the diffuse texture (uv_scale included).
  // Without either texture both rules give the same colour, and the emission stays in the lighting.
  std::int32_t emissive_texture = kNoTexture;  // index into Scene::textures
  bool emission_after_texture = false;

  // Relief (docs/relief.md). A tangent-space normal map (glTF normalTexture, linear): the texel's
  // RGB as n = (2 rgb - 1) with x and y times normal_scale, in the frame of the mesh's tangents
  // (Mesh::tangents: t, b = w cross(normal, t), the normal), perturbs the normal each pixel is lit
  // with. Lit per pixel only (Phong): flat and Gouraud shading light the vertex normals, as GL does.
  // Needs the mesh's uvs and tangents (generate_tangents); sampled at the diffuse texture's uvs.
  std::int32_t normal_texture = kNoTexture;  // index into Scene::textures
  float normal_scale = 1.0f;                 // finite, |scale| <= 1e6
  // An ambient-occlusion map (glTF occlusionTexture, linear): its red channel r darkens every
  // ambient term (the scene's and each light's) by 1 + occlusion_strength (r - 1); direct light is
  // untouched. Lit per pixel only (Phong), like the normal map; sampled at the same uvs.
  std::int32_t occlusion_texture = kNoTexture;
  float occlusion_strength = 1.0f;  // [0, 1]
  // A height map (Blinn's bump mapping; linear, red channel h): its differences over one texel,
  // dh/du and dh/dv, tilt the normal as the tangent-space normal (-bump_scale dh/du, -bump_scale
  // dh/dv, 1) would (lit per pixel, with the normal map's tangents; both maps add). Flat and
  // Gouraud: with a sphere or normal environment map, the differences move the environment's
  // coordinates by bump_scale (dh/du, dh/dv) instead (environment-mapped bump mapping).
  std::int32_t bump_texture = kNoTexture;
  float bump_scale = 1.0f;  // finite, |scale| <= 1e6

  // Applied after the texture environment, before the emission added after texturing and the
  // separate specular (GL: a second texture unit). Sampled at level 0 (no mipmaps: texgen
  // coordinates have no derivatives per pixel).
  Environment environment;
};

// Whether the renderer adds the material's emission after the texture environment (and leaves it
// out of the lighting): where that differs from GL's rule, a texture, and only when there is emission.
inline bool adds_emission_after_texture(const Material& m) noexcept {
  const bool after = m.emission_after_texture || m.model == MaterialModel::pbr;  // PBR: glTF's rule always
  const bool differs = m.emissive_texture != kNoTexture || (after && m.diffuse_texture != kNoTexture);
  return differs && (m.emissive.array() != 0.0f).any();
}

// Whether the material perturbs normals in tangent space (a normal or a bump map: the mesh needs
// tangents, Mesh::tangents).
inline bool needs_tangents(const Material& m) noexcept {
  return m.normal_texture != kNoTexture || m.bump_texture != kNoTexture;
}

// Whether the material samples a texture (and so needs the mesh's uvs).
inline bool uses_textures(const Material& m) noexcept {
  return m.diffuse_texture != kNoTexture || m.emissive_texture != kNoTexture || m.normal_texture != kNoTexture ||
         m.occlusion_texture != kNoTexture || m.bump_texture != kNoTexture || m.metallic_roughness_texture != kNoTexture;
}

}  // namespace facet
