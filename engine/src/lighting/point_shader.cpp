#include "lighting/point_shader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "lighting/image_light.hpp"
#include "lighting/setup.hpp"
#include "common/look_at.hpp"
#include "lighting/soa.hpp"

namespace facet::lighting {

void SoaScratch::reserve_padded(std::size_t count) {
  const std::size_t n = simd::padded(count);
  for (auto* v : {&px, &py, &pz, &nx, &ny, &nz, &r, &g, &b, &ar, &ag, &ab, &sr, &sg, &sb, &ao, &pm, &pr}) {
    if (v->size() < n) v->resize(n);
  }
}

const SimdKernels* simd_kernels(Isa isa) noexcept {
  static constexpr SimdKernels kSse2{&simd::sse2::shade, &simd::sse2::pow_array, &simd::sse2::box};
  static constexpr SimdKernels kAvx2{&simd::avx2::shade, &simd::avx2::pow_array, &simd::avx2::box};
  static constexpr SimdKernels kAvx512{&simd::avx512::shade, &simd::avx512::pow_array, &simd::avx512::box};
  if (isa == Isa::best) isa = best_isa();
  if (!isa_supported(isa)) return nullptr;
  switch (isa) {
    case Isa::sse2: return &kSse2;
    case Isa::avx2: return &kAvx2;
    case Isa::avx512: return &kAvx512;
    case Isa::best: break;
  }
  return nullptr;
}

simd::PowSpec resolve_pow(float s, PowTier tier) noexcept {
  using simd::PowMethod;
  if (s == 0.0f) return {PowMethod::one, 0.0f, 0};
  const bool whole = s == std::floor(s) && s <= 256.0f;
  const simd::PowSpec integer{PowMethod::integer, s, whole ? static_cast<int>(s) : 0};
  switch (tier) {
    case PowTier::exact: return {PowMethod::exact, s, 0};
    case PowTier::fast: return {PowMethod::fast, s, 0};
    case PowTier::integer: return whole ? integer : simd::PowSpec{PowMethod::exact, s, 0};
    case PowTier::schlick: return {PowMethod::schlick, s, 0};
    case PowTier::automatic: break;
  }
  // The cheapest within the 8-bit budget: squaring for whole exponents, the fast polynomials up
  // to 256 (where their Delta8 <= 1 is tested), the exact tier above.
  if (whole) return integer;
  return {s <= 256.0f ? PowMethod::fast : PowMethod::exact, s, 0};
}

namespace {

template <class T>
void copy3(T (&dst)[3], const V3<T>& v) {
  dst[0] = v.x;
  dst[1] = v.y;
  dst[2] = v.z;
}

// The SIMD kernels' method for each light's spot exponent (or smooth cone's falloff) under `tier`;
// Schlick is a specular model, so spot exponents keep a real pow under it.
template <class T>
void resolve_spot_pows(std::vector<EyeLight<T>>& lights, PowTier tier) {
  const PowTier spot_tier = tier == PowTier::schlick ? PowTier::automatic : tier;
  for (EyeLight<T>& L : lights) {
    const T s = L.spot_shape == SpotShape::smooth_cone ? L.spot_falloff : L.spot_exponent;
    L.spot_pow = resolve_pow(static_cast<float>(s), spot_tier);
  }
}

// The PBR kernel's terms (simd::PbrParams): the scalar path's, which are the double set-up rounded once.
void set_pbr_params(const ShadeParams<float>& sp, simd::PbrParams& p) {
  p = simd::PbrParams{};
  const PbrTerms<float>& q = sp.pbr;
  if (!q.on) return;
  p.on = 1;
  p.metal_rough = sp.metal_rough ? 1 : 0;
  copy3(p.base_color, q.base_color);
  p.metallic = q.metallic, p.roughness = q.roughness, p.roughness_factor = q.roughness_factor, p.alpha = q.alpha;
  copy3(p.f0, q.f0);
  p.f90 = q.f90;
  copy3(p.ambient, q.ambient);
  p.intensity = q.intensity;
  std::copy(q.to_env, q.to_env + 9, p.to_env);
  p.image = q.image->view();  // (prepare refuses a PBR material without the image light)
}

}  // namespace

Status PointShader::prepare(const Scene& scene, const Eigen::Matrix4d& view, const Material& material,
                            const LightingOptions& options, const EyeSphere* bounds, LightingFeatures features,
                            const shadow::FrameShadows* shadows) {
  path_ = options.path;
  if (options.path == LightingPath::simd && !simd_kernels(options.isa)) {
    return {ErrorCode::unsupported, "isa",
            std::string("isa: this CPU has no ") + to_string(options.isa) + " (best available: " + to_string(best_isa()) + ")"};
  }
  if (material.model == MaterialModel::pbr && !features.image_light) {
    return {ErrorCode::invalid_argument, "image_light", "image_light: a PBR material needs the prepared DFG table"};
  }
  features_ = features;
  cull_ = options.cull_lights;
  // The frame plan decides once, in double, for every path, so all paths light the same lights.
  make_shade_params(scene, view, material, options.clamp, reference_, features);
  if (bounds && options.cull_lights) {
    lights_to_drop(reference_, *bounds, kLightCullBudget, drop_, candidates_);
  } else {
    drop_.assign(reference_.lights.size(), false);
  }
  const std::vector<bool>& drop = drop_;
  culled_ = remove_lights(reference_, drop);
  // Shadow slots, in light order (every path's list holds the same lights in the same order).
  caster_ = shadows ? shadows->caster : nullptr;
  volumes_ = shadows ? shadows->volumes : nullptr;
  visibility_output_ = false;
  shadow_slots_ = 0;
  for (EyeLight<double>& L : reference_.lights) {
    const std::size_t light = static_cast<std::size_t>(L.scene_light);
    const Shadow& sh = scene.lights[light].shadow;
    L.shadow = -1;
    if (!shadows || shadow_slots_ == kMaxShadowedLights) continue;
    const shadow::ShadowMap* map = sh.method == ShadowMethod::map ? shadows->map_of(light) : nullptr;
    const bool volume = sh.method == ShadowMethod::volume && volumes_ && volumes_->has(light);
    if (!map && !volume && !(sh.method == ShadowMethod::raycast && caster_)) continue;  // no shadow, or nothing casts one
    maps_[shadow_slots_] = map;
    volume_light_[shadow_slots_] = volume ? light : SIZE_MAX;
    slot_light_[shadow_slots_] = light;
    shadow::LightTarget& t = targets_[shadow_slots_];
    t.directional = L.type == LightType::directional;
    const V3<double>& at = t.directional ? L.to_light : L.position;
    t.x = static_cast<float>(at.x), t.y = static_cast<float>(at.y), t.z = static_cast<float>(at.z);
    offsets_[shadow_slots_] = map || volume ? 0.0f : sh.bias.normal * 1e-4f * caster_->radius();  // ray-cast: 1e-4 radii
    if (L.type == LightType::spot) {  // where the cone ends (SpotShape's zero), for skipping rays
      t.spot = true;
      t.axis_x = static_cast<float>(L.spot_axis.x), t.axis_y = static_cast<float>(L.spot_axis.y);
      t.axis_z = static_cast<float>(L.spot_axis.z);
      const bool cone = L.spot_shape == SpotShape::smooth_cone || L.has_cone;
      t.cos_outer = !cone ? -2.0f
                          : static_cast<float>(L.spot_shape == SpotShape::smooth_cone ? L.cos_outer : L.cos_cutoff);
    }
    if (L.inv_range > 0.0) t.range = static_cast<float>(1.0 / L.inv_range);
    if (L.linear_range) {  // zero from max + min on
      const float reach = static_cast<float>(L.range_max + L.range_min);
      t.range = t.range > 0.0f ? std::min(t.range, reach) : reach;
    }
    L.shadow = shadow_slots_++;
  }
  // Projector slots, in light order: spot lights with a picture, lit per pixel.
  projector_slots_ = 0;
  for (EyeLight<double>& L : reference_.lights) {
    L.projector = -1;
    const Light& light = scene.lights[static_cast<std::size_t>(L.scene_light)];
    if (!features.projectors || light.type != LightType::spot || light.projector.texture < 0 ||
        projector_slots_ == kMaxProjectors) {
      continue;
    }
    ProjectorSlot& slot = projectors_[projector_slots_];
    const Eigen::Vector3d forward = light.direction.cast<double>().normalized();
    const Eigen::Matrix4d to_light = look_along(light.position.cast<double>(), forward, light_up(forward)) * view.inverse();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) slot.to_light[4 * r + c] = static_cast<float>(to_light(r, c));
    const double cone = light.spot_shape == SpotShape::smooth_cone ? light.spot_outer_deg : light.spot_cutoff_deg;
    // A cone of 90 degrees or more (or GL's 180, no cone) throws the picture over 89 degrees.
    slot.inv_tan = static_cast<float>(1.0 / std::tan(std::min(cone, 89.0) * std::numbers::pi / 180.0));
    slot.picture = texture::make_sampler(scene.textures[static_cast<std::size_t>(light.projector.texture)]);
    slot.gobo = light.projector.mode == ProjectorMode::gobo;
    L.projector = projector_slots_++;
  }
  auto same_slots = [this](ShadeParams<float>& params) {
    for (std::size_t i = 0; i < params.lights.size(); ++i) {
      params.lights[i].shadow = reference_.lights[i].shadow;
      params.lights[i].projector = reference_.lights[i].projector;
    }
  };
  switch (path_) {
    case LightingPath::reference: break;
    case LightingPath::scalar:
      make_shade_params(scene, view, material, options.clamp, scalar_, features);
      remove_lights(scalar_, drop);
      same_slots(scalar_);
      break;
    case LightingPath::simd: {
      simd_shade_ = simd_kernels(options.isa)->shade;  // (checked above)
      make_shade_params(scene, view, material, options.clamp, scalar_, features);
      remove_lights(scalar_, drop);
      same_slots(scalar_);
      simd::Params& p = simd_params_;
      p.exact_math = options.pow_tier == PowTier::exact ? 1 : 0;
      resolve_spot_pows(scalar_.lights, options.pow_tier);
      resolve_spot_pows(reference_.lights, options.pow_tier);
      copy3(p.base, scalar_.base);
      copy3(p.base_d, reference_.base);
      p.occlusion = features.occlusion ? 1 : 0;
      copy3(p.emission, scalar_.emission);
      copy3(p.emission_d, reference_.emission);
      copy3(p.ambient, scalar_.ambient);
      copy3(p.ambient_d, reference_.ambient);
      p.color_material = features.color_material ? 1 : 0;
      copy3(p.scene_ambient, scalar_.scene_ambient);
      copy3(p.scene_ambient_d, reference_.scene_ambient);
      p.separate_specular = features.separate_specular ? 1 : 0;
      p.specular_pow = resolve_pow(scalar_.shininess, options.pow_tier);
      p.specular_on = material.specular.isZero() ? 0 : 1;
      p.phong_lobe = scalar_.phong_lobe ? 1 : 0;
      p.local_viewer = scalar_.local_viewer ? 1 : 0;
      p.clamp = options.clamp ? 1 : 0;
      p.lights = scalar_.lights.data();  // the kernels read the same lights as the scalar path
      p.lights_d = reference_.lights.data();
      p.light_count = static_cast<int>(scalar_.lights.size());
      set_pbr_params(scalar_, p.pbr);
      break;
    }
    default: return {ErrorCode::invalid_argument, "path", "path: unknown lighting path"};
  }
  return {};
}

bool PointShader::culls_per_part() const {
  if (!cull_) return false;
  for (const EyeLight<double>& L : reference_.lights)
    if (L.type != LightType::directional) return true;
  return false;
}

void PointShader::cull_from(const PointShader& whole, const EyeSphere& part) {
  *this = whole;  // the lists' copies reuse this shader's capacity
  if (!cull_) return;
  lights_to_drop(reference_, part, kLightCullBudget, drop_, candidates_);
  culled_ = whole.culled_ + remove_lights(reference_, drop_);
  if (path_ != LightingPath::reference) remove_lights(scalar_, drop_);
  if (path_ == LightingPath::simd) {  // the kernels read this shader's lists, not whole's
    simd_params_.lights = scalar_.lights.data();
    simd_params_.lights_d = reference_.lights.data();
    simd_params_.light_count = static_cast<int>(scalar_.lights.size());
  }
}

std::size_t PointShader::light_count() const {
  return path_ == LightingPath::reference ? reference_.lights.size() : scalar_.lights.size();
}

namespace {

// At most this many vertices go through the simd kernel at a time: 9 streams of 2048 floats are
// 72 KiB, which stays in L2 between the copy in, the kernel and the copy out.
constexpr std::size_t kSimdChunk = 2048;

// Copies `count` (position, normal) pairs into padded SoA chunks (normals times `normal_sign`),
// runs the kernel on each and writes the colours to `out` (albedo read and secondary written
// when the params use them). The copies are SSE2 transposes (soa.cpp), four vertices at a time.
// With `index`, element i of every array is
// element index[i] (a gather in, a scatter out).
// `visibility` (shadowed lights): slot k's value for point i at visibility[k * count + i].
void run_simd(simd::ShadeFunction shade, const simd::Params& params, const simd::Transform* xf, std::size_t count,
              const Vec3* positions, const Vec3* normals, float normal_sign, const Color3* albedo, Color3* out,
              Color3* secondary, SoaScratch& scratch, const std::uint32_t* index = nullptr,
              const float* visibility = nullptr, int slots = 0, const float* occlusion = nullptr,
              const float* filters = nullptr, int projector_slots = 0, float* filter_scratch = nullptr,
              const float* metal_rough = nullptr) {
  if (count == 0) return;
  if (xf && !index && slots == 0 && !params.occlusion && projector_slots == 0) {
    // The kernel reads and writes the triples itself: no copies. The back side's negated normals
    // are the normal matrix negated (exact: -(q n) = (-q) n in every rounding the kernel does).
    simd::Transform signed_xf = *xf;
    if (normal_sign < 0.0f) {
      for (float& q : signed_xf.normal) q = -q;
      for (double& q : signed_xf.normal_d) q = -q;
    }
    simd::Streams s{nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, count};
    s.p3 = positions->data();
    s.n3 = normals->data();
    s.rgb3 = out->data();
    if (params.color_material) s.a3 = albedo->data();
    if (params.separate_specular) s.spec3 = secondary->data();
    shade(params, &signed_xf, s);
    return;
  }
  scratch.reserve_padded(std::min(kSimdChunk, count));
  const std::size_t chunk_stride = simd::padded(std::min(kSimdChunk, count));
  const std::size_t visibility_at = static_cast<std::size_t>(slots) * count;  // the chunk copies follow the input
  const float* slot_streams[kMaxShadowedLights] = {};
  for (std::size_t start = 0; start < count; start += kSimdChunk) {
    const std::size_t n = std::min(kSimdChunk, count - start);
    const std::size_t padded = simd::padded(n);
    auto in = [&](const Vec3* src, float scale, std::vector<float>& x, std::vector<float>& y, std::vector<float>& z) {
      if (index) {
        deinterleave3(src, index + start, n, scale, x.data(), y.data(), z.data());
      } else {
        deinterleave3(src + start, n, scale, x.data(), y.data(), z.data());
      }
      for (auto* v : {&x, &y, &z})
        std::fill(v->begin() + static_cast<std::ptrdiff_t>(n), v->begin() + static_cast<std::ptrdiff_t>(padded),
                  0.0f);  // padding lanes: finite, no normal
    };
    auto result = [&](const std::vector<float>& x, const std::vector<float>& y, const std::vector<float>& z, Vec3* dst) {
      if (index) {
        interleave3(x.data(), y.data(), z.data(), n, index + start, dst);
      } else {
        interleave3(x.data(), y.data(), z.data(), n, dst + start);
      }
    };
    in(positions, 1.0f, scratch.px, scratch.py, scratch.pz);
    in(normals, normal_sign, scratch.nx, scratch.ny, scratch.nz);
    simd::Streams s{scratch.px.data(), scratch.py.data(), scratch.pz.data(), scratch.nx.data(),
                    scratch.ny.data(), scratch.nz.data(), scratch.r.data(),  scratch.g.data(),
                    scratch.b.data(),  padded};
    if (params.color_material) {
      in(albedo, 1.0f, scratch.ar, scratch.ag, scratch.ab);
      s.ar = scratch.ar.data(), s.ag = scratch.ag.data(), s.ab = scratch.ab.data();
    }
    if (params.separate_specular) s.sr = scratch.sr.data(), s.sg = scratch.sg.data(), s.sb = scratch.sb.data();
    if (params.occlusion) {  // (points, never indexed vertices)
      std::copy_n(occlusion + start, n, scratch.ao.data());
      std::fill(scratch.ao.begin() + static_cast<std::ptrdiff_t>(n), scratch.ao.begin() + static_cast<std::ptrdiff_t>(padded), 1.0f);
      s.ao = scratch.ao.data();
    }
    if (metal_rough && params.pbr.metal_rough) {  // (points: metallic at [i], roughness at [count + i])
      std::copy_n(metal_rough + start, n, scratch.pm.data());
      std::copy_n(metal_rough + count + start, n, scratch.pr.data());
      std::fill(scratch.pm.begin() + static_cast<std::ptrdiff_t>(n), scratch.pm.begin() + static_cast<std::ptrdiff_t>(padded), 1.0f);
      std::fill(scratch.pr.begin() + static_cast<std::ptrdiff_t>(n), scratch.pr.begin() + static_cast<std::ptrdiff_t>(padded), 1.0f);
      s.pm = scratch.pm.data(), s.pr = scratch.pr.data();
    }
    const float* filter_streams[3 * kMaxProjectors] = {};
    if (projector_slots > 0) {  // each slot's channels, padded with 0 (no light)
      for (int k = 0; k < 3 * projector_slots; ++k) {
        float* dst = filter_scratch + static_cast<std::size_t>(k) * chunk_stride;
        std::copy_n(filters + static_cast<std::size_t>(k) * count + start, n, dst);
        std::fill(dst + n, dst + padded, 0.0f);
        filter_streams[k] = dst;
      }
      s.projector = filter_streams;
    }
    if (slots > 0) {  // each slot's chunk, padded with 1 (lit)
      for (int k = 0; k < slots; ++k) {
        float* dst = scratch.visibility.data() + visibility_at + static_cast<std::size_t>(k) * chunk_stride;
        std::copy_n(visibility + static_cast<std::size_t>(k) * count + start, n, dst);
        std::fill(dst + n, dst + padded, 1.0f);
        slot_streams[k] = dst;
      }
      s.visibility = slot_streams;
    }
    shade(params, xf, s);
    result(scratch.r, scratch.g, scratch.b, out);
    if (params.separate_specular) result(scratch.sr, scratch.sg, scratch.sb, secondary);
  }
}

}  // namespace

void PointShader::light_mesh(const Mesh& mesh, const Eigen::Matrix4d& view, const Mat4& model, bool back_side,
                             std::size_t begin, std::size_t end, Color3* out, SoaScratch& scratch,
                             Color3* secondary, const std::uint32_t* index, const Vec3* normals) const {
  switch (path_) {
    case LightingPath::reference:
      lighting::light_mesh(reference_, make_eye_transform<double>(view, model), mesh, back_side, begin, end, out,
                           secondary, index, normals);
      return;
    case LightingPath::scalar:
      lighting::light_mesh(scalar_, make_eye_transform<float>(view, model), mesh, back_side, begin, end, out, secondary,
                           index, normals);
      return;
    case LightingPath::simd: break;
  }
  // One double-precision set-up; the float kernel reads it rounded (make_eye_transform<float>
  // rounds the same doubles).
  const EyeTransform<double> ed = make_eye_transform<double>(view, model);
  simd::Transform xf;
  std::copy(ed.position, ed.position + 12, xf.position_d);
  std::copy(ed.normal, ed.normal + 9, xf.normal_d);
  for (int k = 0; k < 12; ++k) xf.position[k] = static_cast<float>(ed.position[k]);
  for (int k = 0; k < 9; ++k) xf.normal[k] = static_cast<float>(ed.normal[k]);
  const float sign = back_side ? -1.0f : 1.0f;
  const Color3* albedo = features_.color_material ? mesh.colors.data() : nullptr;
  if (!normals) normals = mesh.normals.data();
  if (index) {
    run_simd(simd_shade_, simd_params_, &xf, end - begin, mesh.positions.data(), normals, sign, albedo, out,
             secondary, scratch, index + begin);
    return;
  }
  run_simd(simd_shade_, simd_params_, &xf, end - begin, mesh.positions.data() + begin, normals + begin, sign,
           albedo ? albedo + begin : nullptr, out + begin, secondary ? secondary + begin : nullptr, scratch);
}

void PointShader::output_visibility(const std::size_t (&lights)[3]) {
  visibility_output_ = true;
  for (int c = 0; c < 3; ++c) {
    channel_slot_[c] = -1;
    for (int k = 0; k < shadow_slots_; ++k) {
      if (slot_light_[k] == lights[c]) channel_slot_[c] = k;
    }
  }
}

void PointShader::find_visibility(std::size_t count, const float* px, const float* py, const float* pz,
                                  const float* nx, const float* ny, const float* nz, std::size_t stride,
                                  float* visibility) const {
  for (int k = 0; k < shadow_slots_; ++k) {
    float* out = visibility + static_cast<std::size_t>(k) * count;
    if (maps_[k]) {
      maps_[k]->visibility(count, px, py, pz, nx, ny, nz, stride, out);
    } else if (volume_light_[k] != SIZE_MAX) {
      volumes_->visibility(volume_light_[k], count, px, py, pz, stride, out);
    } else {
      caster_->visibility(targets_[k], offsets_[k], count, px, py, pz, nx, ny, nz, stride, out);
    }
  }
}

void PointShader::find_projector_filters(std::size_t count, const float* px, const float* py, const float* pz,
                                         std::size_t stride, float* filters) const {
  for (int k = 0; k < projector_slots_; ++k) {
    const ProjectorSlot& slot = projectors_[k];
    const float* m = slot.to_light;
    float* out[3];
    for (int c = 0; c < 3; ++c) out[c] = filters + static_cast<std::size_t>(3 * k + c) * count;
    for (std::size_t i = 0; i < count; ++i) {
      const float x = px[i * stride], y = py[i * stride], z = pz[i * stride];
      const float lx = m[0] * x + m[1] * y + m[2] * z + m[3];
      const float ly = m[4] * x + m[5] * y + m[6] * z + m[7];
      const float lz = m[8] * x + m[9] * y + m[10] * z + m[11];
      float rgb[3] = {0.0f, 0.0f, 0.0f};
      if (lz < 0.0f) {  // in front of the light
        const float scale = 0.5f * slot.inv_tan / -lz;
        const float s = 0.5f + lx * scale, t = 0.5f + ly * scale;
        if (s >= 0.0f && s <= 1.0f && t >= 0.0f && t <= 1.0f) {  // NaN fails: no light
          const auto texel = texture::sample_scalar(slot.picture, s, t, 0.0f);
          if (slot.gobo) {
            const float l = 0.2126f * texel[0] + 0.7152f * texel[1] + 0.0722f * texel[2];
            rgb[0] = rgb[1] = rgb[2] = l;
          } else {
            for (int c = 0; c < 3; ++c) rgb[c] = texel[static_cast<std::size_t>(c)];
          }
        }
      }
      for (int c = 0; c < 3; ++c) out[c][i] = rgb[c];
    }
  }
}

void PointShader::shade_points(std::size_t count, const Vec3* p_eye, const Vec3* n_eye, Color3* out,
                               SoaScratch& scratch, const Color3* albedo, Color3* secondary, const float* occlusion,
                               const float* metal_rough) const {
  const float* filters = nullptr;
  const std::size_t filter_floats = 3 * static_cast<std::size_t>(projector_slots_) * count;
  if (projector_slots_ > 0) {
    // The points' filters, then (simd path) room for their padded chunk copies.
    const std::size_t need = filter_floats + 3 * static_cast<std::size_t>(projector_slots_) * simd::padded(std::min(kSimdChunk, count));
    if (scratch.projector.size() < need) scratch.projector.resize(need);
    const float* p = p_eye->data();
    find_projector_filters(count, p, p + 1, p + 2, 3, scratch.projector.data());
    filters = scratch.projector.data();
  }
  const float* visibility = nullptr;
  if (shadow_slots_ > 0) {
    // The points' visibility, then (simd path) room for its padded chunk copies.
    const std::size_t slots = static_cast<std::size_t>(shadow_slots_);
    const std::size_t need = slots * (count + simd::padded(std::min(kSimdChunk, count)));
    if (scratch.visibility.size() < need) scratch.visibility.resize(need);
    const float* p = p_eye->data();
    const float* n = n_eye->data();
    find_visibility(count, p, p + 1, p + 2, n, n + 1, n + 2, 3, scratch.visibility.data());
    visibility = scratch.visibility.data();
  }
  if (visibility_output_) {
    for (std::size_t i = 0; i < count; ++i) {
      for (int c = 0; c < 3; ++c) out[i][c] = channel_slot_[c] < 0 ? 1.0f : visibility[std::size_t(channel_slot_[c]) * count + i];
    }
    return;
  }
  switch (path_) {
    case LightingPath::reference:
      lighting::shade_points(reference_, count, p_eye, n_eye, albedo, out, secondary, visibility, shadow_slots_, occlusion,
                             filters, projector_slots_, metal_rough);
      return;
    case LightingPath::scalar:
      lighting::shade_points(scalar_, count, p_eye, n_eye, albedo, out, secondary, visibility, shadow_slots_, occlusion,
                             filters, projector_slots_, metal_rough);
      return;
    case LightingPath::simd: break;
  }
  // The SIMD path lights these points (at most a tile batch's) in one padded chunk.
  run_simd(simd_shade_, simd_params_, nullptr, count, p_eye, n_eye, 1.0f, albedo, out, secondary, scratch, nullptr,
           visibility, shadow_slots_, occlusion, filters, projector_slots_,
           projector_slots_ > 0 ? scratch.projector.data() + filter_floats : nullptr, metal_rough);
}

void PointShader::shade_soa(const simd::Streams& streams, float* visibility, float* projector) const {
  simd::Streams s = streams;
  const float* filter_streams[3 * kMaxProjectors] = {};
  if (projector_slots_ > 0) {
    find_projector_filters(s.count, s.px, s.py, s.pz, 1, projector);
    for (int k = 0; k < 3 * projector_slots_; ++k) filter_streams[k] = projector + static_cast<std::size_t>(k) * s.count;
    s.projector = filter_streams;
  }
  const float* slot_streams[kMaxShadowedLights] = {};
  if (shadow_slots_ > 0) {
    find_visibility(s.count, s.px, s.py, s.pz, s.nx, s.ny, s.nz, 1, visibility);
    for (int k = 0; k < shadow_slots_; ++k) slot_streams[k] = visibility + static_cast<std::size_t>(k) * s.count;
    s.visibility = slot_streams;
  }
  if (visibility_output_) {
    float* const out[3] = {s.r, s.g, s.b};
    for (int c = 0; c < 3; ++c) {
      for (std::size_t i = 0; i < s.count; ++i) out[c][i] = channel_slot_[c] < 0 ? 1.0f : slot_streams[channel_slot_[c]][i];
    }
    return;
  }
  if (path_ == LightingPath::simd) {
    simd_shade_(simd_params_, nullptr, s);
    return;
  }
  for (std::size_t i = 0; i < s.count; ++i) {  // the other paths, one point at a time
    const Vec3 p(s.px[i], s.py[i], s.pz[i]), n(s.nx[i], s.ny[i], s.nz[i]);
    const Color3 albedo = s.ar ? Color3(s.ar[i], s.ag[i], s.ab[i]) : Color3(1.0f, 1.0f, 1.0f);
    float vis[kMaxShadowedLights];
    for (int k = 0; k < shadow_slots_; ++k) vis[k] = slot_streams[k][i];
    const float* ao = s.ao ? s.ao + i : nullptr;
    float filter[3 * kMaxProjectors];
    for (int k = 0; k < 3 * projector_slots_; ++k) filter[k] = filter_streams[k][i];
    Color3 c, spec;
    const float mr[2] = {s.pm ? s.pm[i] : 1.0f, s.pr ? s.pr[i] : 1.0f};
    const float* metal_rough = features_.metal_rough ? mr : nullptr;
    if (path_ == LightingPath::reference) {
      lighting::shade_points(reference_, 1, &p, &n, &albedo, &c, &spec, vis, shadow_slots_, ao, filter, projector_slots_, metal_rough);
    } else {
      lighting::shade_points(scalar_, 1, &p, &n, &albedo, &c, &spec, vis, shadow_slots_, ao, filter, projector_slots_, metal_rough);
    }
    s.r[i] = c.x(), s.g[i] = c.y(), s.b[i] = c.z();
    if (s.sr) s.sr[i] = spec.x(), s.sg[i] = spec.y(), s.sb[i] = spec.z();
  }
}

}  // namespace facet::lighting
