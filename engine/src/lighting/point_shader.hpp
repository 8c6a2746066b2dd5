// Internal: one material under the scene's lights, prepared once for one lighting path, that
// lights meshes (model space, Gouraud) and eye-space points (Phong pixels, flat centroids). It
// hides which path runs; callers own the scratch memory, so one PointShader can serve several
// threads at once.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "facet/lighting.hpp"
#include "facet/scene.hpp"
#include "lighting/setup.hpp"
#include "lighting/shade.hpp"
#include "lighting/simd_types.hpp"
#include "shadow/frame.hpp"
#include "texture/sampler.hpp"

namespace facet::lighting {

// Structure-of-arrays buffers for the simd path, reused between calls.
struct SoaScratch {
  std::vector<float> px, py, pz, nx, ny, nz, r, g, b;
  std::vector<float> ar, ag, ab, sr, sg, sb;  // albedo in, secondary out (when the shader uses them)
  std::vector<float> ao;                      // ambient occlusion in (LightingFeatures::occlusion)
  std::vector<float> pm, pr;                  // PBR: metallic and roughness texels in (LightingFeatures::metal_rough)
  std::vector<float> projector;               // projectors: per slot and channel, per point
  std::vector<float> visibility;              // shadowed lights: per slot, per point
  void reserve_padded(std::size_t count);
};

class PointShader {
 public:
  // Fails (unsupported) if options.isa is not available on this CPU; nothing else can fail for a
  // validated scene. With `bounds` (and options.cull_lights) the frame plan drops the lights that
  // cannot reach them (see lights_to_drop).
  // With `shadows` (an object that receives shadows), the lights the frame shadows (ray-cast, or
  // with a shadow map that holds casters) are shadowed: shade_points and shade_soa find each
  // point's visibility of them first (up to kMaxShadowedLights).
  Status prepare(const Scene& scene, const Eigen::Matrix4d& view, const Material& material,
                 const LightingOptions& options, const EyeSphere* bounds = nullptr, LightingFeatures features = {},
                 const shadow::FrameShadows* shadows = nullptr);

  // Lights mesh vertices [begin, end) through model -> eye into out[begin, end); `back_side`
  // lights them with negated normals. Each vertex's colour does not depend on the range it was
  // lit in, so any split of the mesh gives the same bytes. With color_material the albedo is
  // mesh.colors; with separate_specular the specular sum goes to secondary[begin, end). With
  // `index`, lights vertices index[begin, end) instead (out and secondary still indexed by vertex).
  void light_mesh(const Mesh& mesh, const Eigen::Matrix4d& view, const Mat4& model, bool back_side, std::size_t begin,
                  std::size_t end, Color3* out, SoaScratch& scratch, Color3* secondary = nullptr,
                  const std::uint32_t* index = nullptr, const Vec3* normals = nullptr) const;

  // Lights `count` eye-space points (albedo read with color_material, secondary written with
  // separate_specular, each point's ambient occlusion read with LightingFeatures::occlusion).
  // `metal_rough` (LightingFeatures::metal_rough): point i's metallic texel at [i], roughness at [count + i].
  void shade_points(std::size_t count, const Vec3* p_eye, const Vec3* n_eye, Color3* out, SoaScratch& scratch,
                    const Color3* albedo = nullptr, Color3* secondary = nullptr, const float* occlusion = nullptr,
                    const float* metal_rough = nullptr) const;

  // Lights eye-space points given as padded structure-of-arrays streams (positions and normals in,
  // colours out; s.count a multiple of simd::kMaxLanes): what the SIMD rasterizer's Phong pixels use.
  // With shadowed lights, `visibility` holds shadow_slots() * s.count floats of scratch.
  // With projectors, `projector` holds 3 projector_slots() * s.count floats of scratch.
  void shade_soa(const simd::Streams& s, float* visibility = nullptr, float* projector = nullptr) const;
  int projector_slots() const { return projector_slots_; }
  int shadow_slots() const { return shadow_slots_; }
  // After prepare(): shade_points and shade_soa write each point's visibility of scene lights
  // lights[0..2] as its red, green and blue (1 for a light the point has no slot for: not
  // shadowed there) instead of lighting it; for flat and Gouraud shadows (the renderer's
  // visibility pass).
  void output_visibility(const std::size_t (&lights)[3]);

  const LightingFeatures& features() const { return features_; }

  // For a part of an object (light_instance's chunks of vertices): this shader becomes `whole`,
  // prepared without bounds (so with every light), less the lights that cannot reach `part`,
  // decided as prepare() decides for a whole object when `whole` was asked to cull lights; the
  // kept lights keep their shadow and projector slots. Allocates only while its lists grow.
  void cull_from(const PointShader& whole, const EyeSphere& part);
  // Whether cull_from can drop a light: the options ask for culling and a light has a position.
  bool culls_per_part() const;

  std::size_t light_count() const;    // lights evaluated per point
  std::size_t culled_lights() const { return culled_; }  // enabled lights the frame plan dropped

 private:
  LightingPath path_ = LightingPath::scalar;
  LightingFeatures features_;
  ShadeParams<float> scalar_;
  ShadeParams<double> reference_;
  simd::Params simd_params_;
  simd::ShadeFunction simd_shade_ = nullptr;
  std::size_t culled_ = 0;
  bool cull_ = false;  // LightingOptions::cull_lights
  // Shadows: per slot, the light's target in eye space and what answers for it: its map, or the
  // caster with the normal offset.
  const shadow::RayCaster* caster_ = nullptr;
  int shadow_slots_ = 0;
  shadow::LightTarget targets_[kMaxShadowedLights];
  const shadow::ShadowMap* maps_[kMaxShadowedLights] = {};
  const shadow::ShadowVolumes* volumes_ = nullptr;
  std::size_t volume_light_[kMaxShadowedLights] = {};  // a volume slot's scene light, else SIZE_MAX
  std::size_t slot_light_[kMaxShadowedLights] = {};    // each slot's scene light
  bool visibility_output_ = false;
  int channel_slot_[3] = {-1, -1, -1};
  float offsets_[kMaxShadowedLights] = {};
  // visibility[k * count + i]: point i's visibility of slot k's light (stride as RayCaster).
  void find_visibility(std::size_t count, const float* px, const float* py, const float* pz, const float* nx,
                       const float* ny, const float* nz, std::size_t stride, float* visibility) const;
  // Projectors (LightingFeatures::projectors): per slot, eye -> the light's view (3x4, row-major),
  // 1 / tan(cone), the picture and whether it is a gobo.
  struct ProjectorSlot {
    float to_light[12];
    float inv_tan;
    texture::Sampler picture;
    bool gobo;
  };
  int projector_slots_ = 0;
  ProjectorSlot projectors_[kMaxProjectors] = {};
  // filters[(3 k + c) * count + i]: channel c of point i's filter of slot k's light (stride as RayCaster).
  void find_projector_filters(std::size_t count, const float* px, const float* py, const float* pz, std::size_t stride,
                              float* filters) const;
  std::vector<bool> drop_;                // frame-plan scratch, kept between frames
  std::vector<CullCandidate> candidates_;
};

struct SimdKernels {
  simd::ShadeFunction shade;
  simd::PowFunction pow;
  simd::BoxFunction box;
};
// The kernels of an ISA (Isa::best resolved), or null if this CPU lacks it.
const SimdKernels* simd_kernels(Isa isa) noexcept;

// The pow method the simd path uses for exponent `s` under `tier` (see PowTier).
simd::PowSpec resolve_pow(float s, PowTier tier) noexcept;

}  // namespace facet::lighting
