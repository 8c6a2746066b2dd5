// Internal: what the SIMD lighting kernels read. Plain data with no Eigen and no standard-library
// containers, because the kernels are compiled once per ISA and must not instantiate inline code
// that the linker could merge across ISA files (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
#pragma once

#include <cstddef>

#include "facet/light_kinds.hpp"

namespace facet::lighting::simd {

// Widest batch (avx512: 16 floats). Streams are padded to a multiple of it: no tail loops.
inline constexpr std::size_t kMaxLanes = 16;

inline std::size_t padded(std::size_t n) { return (n + kMaxLanes - 1) / kMaxLanes * kMaxLanes; }

enum class PowMethod : int { one, exact, fast, integer, schlick };

}  // namespace facet::lighting::simd

namespace facet::lighting {

// The image light's DFG table (kDfgSize^2 cells, n.v by roughness) and prefiltered cube levels
// (level k holds roughness k / (kRadianceLevels - 1)); image_light.hpp.
inline constexpr int kDfgSize = 32;
inline constexpr int kRadianceLevels = 6;

}  // namespace facet::lighting

namespace facet::lighting::simd {

struct PowSpec {
  PowMethod method = PowMethod::one;
  float exponent = 0.0f;
  int integer_exponent = 0;
};

}  // namespace facet::lighting::simd

namespace facet::lighting {

template <class T>
struct V3 {
  T x, y, z;
};

// One light in eye space: the one representation the reference (T = double), scalar (float) and
// SIMD kernels (float lanes, or double lanes for the exact tier) all read, made once per draw by
// make_shade_params (setup.hpp). Its colours are already multiplied by the material's (GL's
// "light products": a_m a_i, d_m d_i, s_m s_i, as Mesa's fixed-function programs precompute them),
// because the material is the same at every point of a draw; where it is not (colour material:
// the vertex colours), the lights carry a_i and d_i alone and the albedo enters per point.
template <class T>
struct EyeLight {
  LightType type = LightType::directional;
  V3<T> position{};   // point, spot
  V3<T> to_light{};   // directional: unit vector towards the light
  V3<T> spot_axis{};  // spot: unit vector the light travels along
  T k0 = 1, k1 = 0, k2 = 0;
  // AttenuationModel::linear_range: clamp01((range_max - d + range_min) / range_max) replaces
  // 1 / (k0 + k1 d + k2 d^2); inv_range_max = 1 / range_max for the float kernels.
  bool linear_range = false;
  T range_min = 0, range_max = 1, inv_range_max = 1;
  T inv_range = 0;  // 0 = no range window
  SpotShape spot_shape = SpotShape::cutoff_exponent;
  bool has_cone = false;  // cutoff_exponent with cutoff < 180
  T cos_cutoff = -1, spot_exponent = 0;
  T cos_outer = -1, inv_cone_span = 0, spot_falloff = 0;  // smooth_cone; inv_cone_span 0 = hard edge
  simd::PowSpec spot_pow;  // the SIMD kernels' method for the spot exponent (or falloff) under the pow tier
  V3<T> ambient{}, diffuse{}, specular{};  // a_m a_i, d_m d_i, s_m s_i
  int scene_light = -1;  // index in Scene::lights
  // Shadowed: the slot of this light's visibility per point (0 in shadow, 1 lit, a filtered shadow
  // map's edge between), which multiplies its diffuse and specular terms (never its ambient
  // term); -1: never shadowed.
  int shadow = -1;
  // Projecting a picture (Light::projector): the slot of this point's RGB filter of the light
  // (three values), which multiplies its diffuse and specular terms per channel; -1: none.
  int projector = -1;
};

}  // namespace facet::lighting

namespace facet::lighting::simd {

// What the PBR kernel reads of an image light (lighting/image_light.hpp), as plain data.
struct ImageView {
  const float* dfg = nullptr;  // kDfgSize^2 cells of (scale, bias), n.v fastest
  int has_image = 0;           // 0: the DFG table alone
  float sh[3][9] = {};         // per channel, the harmonics' coefficients times their basis constants
  const float* radiance = nullptr;   // the prefiltered levels one after another
  int offset[kRadianceLevels] = {};  // level k's first float in `radiance`
  int size[kRadianceLevels] = {};    // level k's face size in texels
};

// A PBR material (pbr_shade.hpp's terms, rounded to float): Params::pbr.
struct PbrParams {
  int on = 0;
  int metal_rough = 0;  // Streams::pm and pr multiply the metallic and roughness factors
  float base_color[3] = {1.0f, 1.0f, 1.0f};
  float metallic = 0.0f, roughness = 1.0f, roughness_factor = 1.0f, alpha = 1.0f;
  float f0[3] = {}, f90 = 1.0f;
  float ambient[3] = {};  // uniform radiance around: the scene's ambient without a picture
  float intensity = 1.0f;
  float to_env[9] = {1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f};  // eye -> environment
  ImageView image;
};

struct Params {
  float base[3] = {};  // e_m + a_m a_scene; with color_material: e_m
  double base_d[3] = {};
  // Colour material (shade.hpp): Streams::ar/ag/ab multiply a_scene + the lights' ambient and diffuse.
  int color_material = 0;
  float scene_ambient[3] = {};
  double scene_ambient_d[3] = {};
  int separate_specular = 0;  // the specular sum goes to Streams::sr/sg/sb
  // Occlusion (shade.hpp): Streams::ao multiplies a_m a_scene (here `ambient`, base less the
  // emission `emission`), the scene ambient under colour material, and each light's ambient.
  int occlusion = 0;
  float emission[3] = {}, ambient[3] = {};
  double emission_d[3] = {}, ambient_d[3] = {};
  PowSpec specular_pow;
  int specular_on = 1;  // 0 when the material's specular colour is black
  int phong_lobe = 0;   // SpecularModel::phong: the lobe on R.V instead of n.h
  int local_viewer = 1;
  int clamp = 1;
  // 1: the exact tier's kernel, in double lanes, reading base_d, lights_d and the Transform's
  // double matrices; 0: the float kernel, reading base, lights and the float matrices.
  int exact_math = 0;
  const EyeLight<float>* lights = nullptr;
  const EyeLight<double>* lights_d = nullptr;
  int light_count = 0;
  // A PBR material: the PBR kernel (shade_pbr_simd.hpp) instead of the classic one; it reads
  // base (the emission), color_material, separate_specular, occlusion, local_viewer, clamp,
  // exact_math (IEEE sqrt and division instead of the estimates) and the float lights.
  PbrParams pbr;
};

// Model -> eye, row-major (3x4 for positions, 3x3 inverse-transpose for normals), in float for
// the float kernel and in double for the exact tier's.
struct Transform {
  float position[12];
  float normal[9];
  double position_d[12];
  double normal_d[9];
};

// Structure-of-arrays streams, `count` a multiple of kMaxLanes. Inputs are model space when a
// Transform is given, eye space otherwise.
struct Streams {
  const float *px, *py, *pz, *nx, *ny, *nz;
  float *r, *g, *b;
  std::size_t count;
  const float *ar = nullptr, *ag = nullptr, *ab = nullptr;  // albedo: read with Params::color_material
  float *sr = nullptr, *sg = nullptr, *sb = nullptr;        // secondary: written with Params::separate_specular
  // Shadowed lights (EyeLight::shadow >= 0): per shadow slot, each point's visibility of that light.
  const float* const* visibility = nullptr;
  const float* ao = nullptr;  // per point ambient occlusion: read with Params::occlusion
  // PBR: per point metallic and roughness texels, read with PbrParams::metal_rough.
  const float *pm = nullptr, *pr = nullptr;
  // Projectors (EyeLight::projector >= 0): stream 3 k + c is each point's channel c of slot k's filter.
  const float* const* projector = nullptr;
  // Triples instead of the streams above (xyz, as a mesh holds them; any count, no padding):
  // positions p3 and normals n3 read, colours rgb3 (and secondary spec3) written, albedo a3 read,
  // for points [0, count). Never with visibility, ao or projector streams.
  const float* p3 = nullptr;
  const float* n3 = nullptr;
  const float* a3 = nullptr;
  float* rgb3 = nullptr;
  float* spec3 = nullptr;
};

using ShadeFunction = void (*)(const Params&, const Transform*, const Streams&);

// x^s for `count` (a multiple of kMaxLanes) values with one pow method: the entry the tests use
// to check each tier on each ISA.
using PowFunction = void (*)(const PowSpec&, const float* x, float* out, std::size_t count);

// The box of n xyz triples, exact, when every coordinate is finite (else false: see box_triples).
using BoxFunction = bool (*)(const float* p, std::size_t n, float lo[3], float hi[3]);

// One per ISA file; each is compiled with that ISA's flags.
namespace sse2 {
void shade(const Params&, const Transform*, const Streams&);
void pow_array(const PowSpec&, const float*, float*, std::size_t);
bool box(const float* p, std::size_t n, float lo[3], float hi[3]);
}  // namespace sse2
namespace avx2 {
void shade(const Params&, const Transform*, const Streams&);
void pow_array(const PowSpec&, const float*, float*, std::size_t);
bool box(const float* p, std::size_t n, float lo[3], float hi[3]);
}  // namespace avx2
namespace avx512 {
void shade(const Params&, const Transform*, const Streams&);
void pow_array(const PowSpec&, const float*, float*, std::size_t);
bool box(const float* p, std::size_t n, float lo[3], float hi[3]);
}  // namespace avx512

}  // namespace facet::lighting::simd
