// Internal: the lighting model on xsimd batches (one vertex or pixel per lane), the SIMD twin of
// shade.hpp with the same edge-case rules (see facet/lighting.hpp). Included only by the
// per-ISA files shade_simd_<isa>.cpp; everything is a template on Arch.
//
// Two kernels, chosen by the pow tier (shade_streams dispatches once per call):
//  - exact tier: the whole model in double lanes (half as many per register), with exact sqrt and
//    division, from the double-precision set-up (matrices, light positions, colours); only the
//    inputs and the stored colours are float. Float lanes left ~2e-6 (avx2) of error from the
//    model-view and normal matrices' rounding times the specular exponent; double lanes leave the
//    colours' own rounding (tests/lighting_random_test.cpp prints the measured maximum).
//  - every other tier: float lanes, with the hardware's reciprocal square root and reciprocal
//    estimates (rsqrtps / rcpps, 12 bits; rsqrt14 / rcp14 on avx512) refined by one Newton step,
//    relative error about 2^-22, far inside the Delta8 <= 1 budget of those tiers (facet accuracy:
//    the random-vertex maximum stays at 0.002 of an 8-bit step). A point light needed two sqrt and
//    three divisions per vertex, all on one divider. The estimates' low bits differ
//    between CPU vendors, so colours may differ by an ulp between an Intel and an AMD machine; on
//    one machine they are fixed (and the same for any thread count).
// With -mfma the compiler contracts a*b+c, so avx2/avx512 differ from sse2 by ulps.
#pragma once

#include <cfloat>
#include <limits>
#include <type_traits>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "fastmath/pow_simd.hpp"
#include "lighting/aos_simd.hpp"
#include "lighting/simd_types.hpp"

namespace facet::lighting::simd {

template <class B>
struct V {
  B x, y, z;
};

template <class B>
B dot3(const V<B>& a, const V<B>& b) {
  return xsimd::fma(a.x, b.x, xsimd::fma(a.y, b.y, a.z * b.z));
}

// 1/sqrt(x) and 1/x for the non-exact tiers: the hardware estimate and one Newton step.
// rsqrt_nr needs x in [FLT_MIN, FLT_MAX] (callers clamp); rcp_nr any x in [1e-6, FLT_MAX]
// (the estimate of 1/FLT_MAX flushes to 0, and the step keeps 0).
template <class B>
B rsqrt_estimate(const B& x) {
  using A = typename B::arch_type;
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    return B(_mm512_rsqrt14_ps(x));  // xsimd 8.1's rsqrt does not compile here (it calls _mm512_rsqrt23_ps, which GCC does not have)
  } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
    return B(_mm256_rsqrt_ps(x));
  } else {
    return B(_mm_rsqrt_ps(x));
  }
}

template <class B>
B rcp_estimate(const B& x) {
  using A = typename B::arch_type;
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    return B(_mm512_rcp14_ps(x));
  } else if constexpr (std::is_base_of_v<xsimd::avx, A>) {
    return B(_mm256_rcp_ps(x));
  } else {
    return B(_mm_rcp_ps(x));
  }
}

template <class B>
B rsqrt_nr(const B& x) {
  const B y = rsqrt_estimate(x);
  return y * xsimd::fnma(B(0.5f) * x, y * y, B(1.5f));  // y (3 - x y^2) / 2
}

template <class B>
B rcp_nr(const B& x) {
  const B y = rcp_estimate(x);
  return y * xsimd::fnma(x, y, B(2.0f));  // y (2 - x y)
}

// v / |v|, or zero when |v| is below 1e-6, infinite or NaN.
template <bool Exact, class B>
V<B> normalize_or_zero(const V<B>& v) {
  if constexpr (Exact) {
    const B len = xsimd::sqrt(dot3(v, v));
    const auto ok = (len > B(1e-6f)) && (len <= B(FLT_MAX));  // NaN and Inf fail
    const B inv = B(1.0f) / len;
    return {xsimd::select(ok, v.x * inv, B(0.0f)), xsimd::select(ok, v.y * inv, B(0.0f)),
            xsimd::select(ok, v.z * inv, B(0.0f))};
  } else {
    const B len2 = dot3(v, v);
    const auto ok = (len2 > B(1e-12f)) && (len2 <= B(FLT_MAX));
    const B inv = xsimd::select(ok, rsqrt_nr(xsimd::select(ok, len2, B(1.0f))), B(0.0f));
    return {v.x * inv, v.y * inv, v.z * inv};
  }
}

// x^s with the method fixed at compile time: the specular pow (one kernel instantiation per
// method); pow_spec picks the same functions at run time for spot exponents.
template <PowMethod M, class B>
[[gnu::always_inline]] inline B pow_fixed(const B& x, const PowSpec& p) {
  if constexpr (M == PowMethod::one) return B(1.0f);
  else if constexpr (M == PowMethod::exact) return fastmath::pow_exact(x, p.exponent);
  else if constexpr (M == PowMethod::fast) return fastmath::pow_fast(x, p.exponent);
  else if constexpr (M == PowMethod::integer) return fastmath::pow_integer(x, p.integer_exponent);
  else return fastmath::pow_schlick(x, p.exponent);
}

template <class B>
[[gnu::always_inline]] inline B pow_spec(const B& x, const PowSpec& p) {
  switch (p.method) {
    case PowMethod::one: return pow_fixed<PowMethod::one>(x, p);
    case PowMethod::exact: return pow_fixed<PowMethod::exact>(x, p);
    case PowMethod::fast: return pow_fixed<PowMethod::fast>(x, p);
    case PowMethod::integer: return pow_fixed<PowMethod::integer>(x, p);
    case PowMethod::schlick: return pow_fixed<PowMethod::schlick>(x, p);
  }
  return B(1.0f);
}

// cos(angle between a and b)^s for the exact tier, computed through delta = 1 - cos, which the
// identity |a x b|^2 = |a|^2 |b|^2 - (a.b)^2 gives with *relative* accuracy:
//   delta = |a x b|^2 / (q (q + a.b)),  q = |a| |b|,   x^s = exp2(s log1p(-delta) / ln 2).
// Forming cos = a.b / q first and then pow would carry the ~1e-7 absolute rounding of cos
// (normalisations, dot products) into the result multiplied by s (7.7e-6 at s = 256, measured);
// this way the error no longer grows with s. Non-positive cosines and zero vectors give 0
// (s > 0; s = 0 gives 1), like pow_exact of a clamped cosine.
template <class B>
B pow_cos_exact(const V<B>& a, const V<B>& b, float s) {
  if (s == 0.0f) return B(1.0f);
  const B c = dot3(a, b);
  const V<B> x{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  const B q = xsimd::sqrt(dot3(a, a) * dot3(b, b));
  const auto valid = (c > B(0.0f)) && (q > B(0.0f)) && (q <= B(std::numeric_limits<typename B::value_type>::max()));
  const B delta = xsimd::min(dot3(x, x) / (q * (q + c)), B(1.0f));
  // delta = 1 gives log1p(-1) = -inf, and a lane that is not valid may hold NaN: exp2's range
  // reduction converts its argument to an integer, which is undefined for either, so the argument
  // is held at or above -1100, where 2^x is already 0 in double and float alike.
  const B e = B(static_cast<typename B::value_type>(double(s) * 1.4426950408889634)) * xsimd::log1p(-delta);
  const B lowest(-1100.0f);
  const B y = xsimd::exp2(xsimd::select(e > lowest, e, lowest));
  return xsimd::select(valid, fastmath::clamp01(y), B(0.0f));
}

// x^s in double lanes for the exact kernel's smooth spot ramp (x already in [0, 1]); s = 0 gives
// 1, 0^s = 0 for s > 0: the exact tier's contract, with xsimd's double exp2 and log2.
template <class B>
B pow_unit_double(const B& x, float s) {
  if (s == 0.0f) return B(1.0);
  return xsimd::select(x > B(0.0), xsimd::exp2(B(static_cast<typename B::value_type>(s)) * xsimd::log2(xsimd::select(x > B(0.0), x, B(1.0)))), B(0.0));
}

// The stored colour: clamped to [0, 1], or (HDR) kept >= 0 and finite as a float.
template <class B>
B finish(const Params& prm, const B& c) {
  const B zero(0.0f);
  if (prm.clamp) return fastmath::clamp01(c);
  const B big(FLT_MAX);  // the float colour's limit, also for double lanes
  return xsimd::select(c > zero, xsimd::min(c, big), zero);
}

// The unit vector from each point p towards light L and L's attenuation there (distance, range
// window with Extras, spot cone), 0 where the position or the distance is not finite: the
// classic kernel's and the PBR kernel's lights. Exact: IEEE sqrt and division (the exact tier;
// double lanes in the classic kernel), else the estimates.
template <bool Exact, bool Extras, class B, class T>
[[gnu::always_inline]] inline V<B> light_vector(const EyeLight<T>& L, const V<B>& p, B& att) {
  const B zero(0.0f), one(1.0f);
// Spot exponents keep a run-time method: float lanes take any tier's, double lanes the exact
// tier's (exact, or one for s = 0).
auto pow_spot = [](const B& x, const PowSpec& spec) -> B {
  if constexpr (Exact) {
    return pow_unit_double(fastmath::clamp01(x), spec.method == PowMethod::one ? 0.0f : spec.exponent);
  } else {
    return pow_spec(x, spec);
  }
};
  V<B> vp;
  att = one;
  if (L.type == LightType::directional) {
    vp = {B(L.to_light.x), B(L.to_light.y), B(L.to_light.z)};
  } else {
    V<B> diff{B(L.position.x) - p.x, B(L.position.y) - p.y, B(L.position.z) - p.z};
    const B d2 = dot3(diff, diff);
    B d, inv_d;
    typename B::batch_bool_type finite, has_dir;
    if constexpr (Exact) {
      d = xsimd::sqrt(d2);
      finite = d <= B(std::numeric_limits<T>::max());  // NaN/Inf position or distance: no contribution
      has_dir = d > B(1e-6f);
      inv_d = one / d;
    } else {
      finite = d2 <= B(FLT_MAX);
      has_dir = finite && (d2 > B(1e-12f));
      // 1/d, or 0 where there is no direction: the products below are then 0 (a finite diff),
      // or NaN where the position or distance is not finite, which only lanes the selects on
      // `finite` (att) and `lit` (n.l > 0 fails for NaN) leave out; no select per product.
      inv_d = xsimd::select(has_dir, rsqrt_nr(xsimd::select(has_dir, d2, one)), zero);
      d = d2 * inv_d;  // below 1e-6 the distance counts as 0
    }
    if constexpr (Exact) {
      vp = {xsimd::select(has_dir, diff.x * inv_d, zero), xsimd::select(has_dir, diff.y * inv_d, zero),
            xsimd::select(has_dir, diff.z * inv_d, zero)};
    } else {
      vp = {diff.x * inv_d, diff.y * inv_d, diff.z * inv_d};
    }
    const B denom = xsimd::fma(B(L.k2), d2, xsimd::fma(B(L.k1), d, B(L.k0)));
    if (Extras && L.linear_range) {
      if constexpr (Exact) {
        att = fastmath::clamp01((B(L.range_max) - d + B(L.range_min)) / B(L.range_max));
      } else {
        att = fastmath::clamp01((B(L.range_max) - d + B(L.range_min)) * B(L.inv_range_max));
      }
    } else if constexpr (Exact) {
      att = one / xsimd::select(denom > B(1e-6f), denom, B(1e-6f));
    } else {
      // max(NaN, 1e-6) is 1e-6 (maxps returns its second operand); Inf becomes FLT_MAX.
      att = rcp_nr(xsimd::min(xsimd::max(denom, B(1e-6f)), B(FLT_MAX)));
    }
    if (L.inv_range > 0.0f) {
      const B x = d * B(L.inv_range), x2 = x * x;
      const B w = fastmath::clamp01(one - x2 * x2);
      att *= w * w;
    }
    if (L.type == LightType::spot) {
      const B cos_angle = -dot3(vp, V<B>{B(L.spot_axis.x), B(L.spot_axis.y), B(L.spot_axis.z)});
      B spot;
      if (L.spot_shape == SpotShape::cutoff_exponent) {
        if (!L.has_cone) {
          spot = one;
        } else {
          const B factor = L.spot_pow.method == PowMethod::exact
                               ? pow_cos_exact(V<B>{-diff.x, -diff.y, -diff.z}, V<B>{B(L.spot_axis.x), B(L.spot_axis.y), B(L.spot_axis.z)},
                                               L.spot_pow.exponent)
                               : pow_spot(cos_angle, L.spot_pow);
          spot = xsimd::select(cos_angle >= B(L.cos_cutoff), factor, zero);
        }
      } else {
        const B t = L.inv_cone_span > 0.0f ? fastmath::clamp01((cos_angle - B(L.cos_outer)) * B(L.inv_cone_span)) : one;
        spot = xsimd::select(cos_angle >= B(L.cos_outer), pow_spot(t, L.spot_pow), zero);
      }
      att *= spot;
    }
    att = xsimd::select(finite, att, zero);
  }
  return vp;
}

// Points [i, i + lanes) of `count` xyz triples as a batch of each coordinate; a last batch past
// `count` through a buffer padded with zeros (finite, no normal: what the streams' padding holds).
template <class B>
[[gnu::always_inline]] inline V<B> read_triples(const float* src, std::size_t i, std::size_t count) {
  constexpr std::size_t lanes = B::size;
  V<B> v;
  if (i + lanes <= count) {
    load_xyz(src + 3 * i, v.x, v.y, v.z);
  } else {
    alignas(64) float buf[3 * lanes] = {};
    for (std::size_t k = 0; k < 3 * (count - i); ++k) buf[k] = src[3 * i + k];
    load_xyz(buf, v.x, v.y, v.z);
  }
  return v;
}

// The other way: points [i, min(i + lanes, count)) written as xyz triples.
template <class B>
[[gnu::always_inline]] inline void write_triples(float* dst, std::size_t i, std::size_t count, const B& x, const B& y, const B& z) {
  constexpr std::size_t lanes = B::size;
  if (i + lanes <= count) {
    store_xyz(x, y, z, dst + 3 * i);
  } else {
    alignas(64) float buf[3 * lanes];
    store_xyz(x, y, z, buf);
    for (std::size_t k = 0; k < 3 * (count - i); ++k) dst[3 * i + k] = buf[k];
  }
}

// Point i's position and normal (batches of lanes points) from the streams or the triples, through
// the model -> eye transform (m: 3x4 rows, q: the normal's 3x3) when it is given.
template <class B, class T>
[[gnu::always_inline]] inline void load_point(const Streams& s, std::size_t i, const T* m, const T* q, V<B>& p, V<B>& n) {
  if (s.p3) {
    p = read_triples<B>(s.p3, i, s.count);
    n = read_triples<B>(s.n3, i, s.count);
  } else {
    p = {B::load_unaligned(s.px + i), B::load_unaligned(s.py + i), B::load_unaligned(s.pz + i)};
    n = {B::load_unaligned(s.nx + i), B::load_unaligned(s.ny + i), B::load_unaligned(s.nz + i)};
  }
  if (m) {
    p = {xsimd::fma(B(m[0]), p.x, xsimd::fma(B(m[1]), p.y, xsimd::fma(B(m[2]), p.z, B(m[3])))),
         xsimd::fma(B(m[4]), p.x, xsimd::fma(B(m[5]), p.y, xsimd::fma(B(m[6]), p.z, B(m[7])))),
         xsimd::fma(B(m[8]), p.x, xsimd::fma(B(m[9]), p.y, xsimd::fma(B(m[10]), p.z, B(m[11]))))};
    n = {xsimd::fma(B(q[0]), n.x, xsimd::fma(B(q[1]), n.y, B(q[2]) * n.z)),
         xsimd::fma(B(q[3]), n.x, xsimd::fma(B(q[4]), n.y, B(q[5]) * n.z)),
         xsimd::fma(B(q[6]), n.x, xsimd::fma(B(q[7]), n.y, B(q[8]) * n.z))};
  }
}

// Extras: the kernel reads the per-material and per-light options most scenes do not use
// (occlusion, Phong's lobe, linear range attenuation, projectors); without them those paths are
// compiled out, so a scene that uses none of them runs the kernel it ran before they existed.
template <class Arch, bool Exact, PowMethod Spec, bool Extras>
void shade_kernel(const Params& prm, const Transform* xf, const Streams& s) {
  static_assert(!Exact || Spec == PowMethod::one || Spec == PowMethod::exact, "the exact tier's methods");
  using T = std::conditional_t<Exact, double, float>;
  using B = xsimd::batch<T, Arch>;
  constexpr std::size_t lanes = B::size;
  const B zero(0.0f), one(1.0f);
  const EyeLight<T>* lights = nullptr;
  const T* base = nullptr;
  const T* scene_ambient = nullptr;
  const T *xf_position = nullptr, *xf_normal = nullptr;
  const T *emission = nullptr, *ambient_base = nullptr;  // occlusion: base = emission + ambient_base
  if constexpr (Exact) {
    emission = prm.emission_d, ambient_base = prm.ambient_d;
    lights = prm.lights_d, base = prm.base_d, scene_ambient = prm.scene_ambient_d;
    if (xf) xf_position = xf->position_d, xf_normal = xf->normal_d;
  } else {
    emission = prm.emission, ambient_base = prm.ambient;
    lights = prm.lights, base = prm.base, scene_ambient = prm.scene_ambient;
    if (xf) xf_position = xf->position, xf_normal = xf->normal;
  }
  // Triples (Streams::p3): whole batches straight from the caller's arrays, the last one through
  // a buffer padded with zeros (finite, no normal: what the streams' padding holds).
  const bool triples = s.p3 != nullptr;
  auto read3 = [&](const float* src, std::size_t i) { return read_triples<B>(src, i, s.count); };
  auto write3 = [&](float* dst, std::size_t i, const B& x, const B& y, const B& z) { write_triples(dst, i, s.count, x, y, z); };
  for (std::size_t i = 0; i < s.count; i += lanes) {
    V<B> p, n;
    load_point(s, i, xf_position, xf_normal, p, n);
    n = normalize_or_zero<Exact>(n);
    const V<B> eye = prm.local_viewer ? normalize_or_zero<Exact>(V<B>{-p.x, -p.y, -p.z}) : V<B>{zero, zero, one};
    const B n_dot_v = Extras && prm.phong_lobe ? dot3(n, eye) : zero;  // Phong's lobe
    // Colour material and separate specular keep the specular sum apart (spr, spg, spb).
    const bool split = prm.color_material || prm.separate_specular;
    const T* start = prm.color_material ? scene_ambient : base;
    B r(start[0]), g(start[1]), b(start[2]);
    B ao = one;  // the point's ambient occlusion (streams are float; double lanes widen them)
    if (Extras && prm.occlusion) {
      ao = B::load_unaligned(s.ao + i);
      if (prm.color_material) {
        r = ao * r, g = ao * g, b = ao * b;
      } else {
        const T* e = emission;
        const T* a = ambient_base;
        r = xsimd::fma(ao, B(a[0]), B(e[0])), g = xsimd::fma(ao, B(a[1]), B(e[1])), b = xsimd::fma(ao, B(a[2]), B(e[2]));
      }
    }
    B spr(0.0f), spg(0.0f), spb(0.0f);

    for (int li = 0; li < prm.light_count; ++li) {
      const EyeLight<T>& L = lights[li];
      B att;
      const V<B> vp = light_vector<Exact, Extras>(L, p, att);
      const B n_dot_l = dot3(n, vp);
      const auto lit = n_dot_l > zero;
      B sr = B(L.ambient.x), sg = B(L.ambient.y), sb = B(L.ambient.z);
      if (Extras && prm.occlusion) sr *= ao, sg *= ao, sb *= ao;
      // A shadowed light's visibility at each point (1 lit, 0 in shadow, between on a filtered
      // edge); only its diffuse and
      // specular terms are blocked.
      const bool shadowed = L.shadow >= 0 && s.visibility;
      const B vis = shadowed ? B::load_unaligned(s.visibility[L.shadow] + i) : one;
      // A projected picture's filter of this light per channel (three streams of its slot).
      const bool projected = Extras && L.projector >= 0 && s.projector;
      B fr = one, fg = one, fb = one;
      if (projected) {
        fr = B::load_unaligned(s.projector[3 * L.projector] + i);
        fg = B::load_unaligned(s.projector[3 * L.projector + 1] + i);
        fb = B::load_unaligned(s.projector[3 * L.projector + 2] + i);
      }
      if (xsimd::any(lit)) {
        B kd = xsimd::select(lit, n_dot_l, zero);
        if (shadowed) kd *= vis;
        if (projected) {
          sr = xsimd::fma(kd * fr, B(L.diffuse.x), sr);
          sg = xsimd::fma(kd * fg, B(L.diffuse.y), sg);
          sb = xsimd::fma(kd * fb, B(L.diffuse.z), sb);
        } else {
          sr = xsimd::fma(kd, B(L.diffuse.x), sr);
          sg = xsimd::fma(kd, B(L.diffuse.y), sg);
          sb = xsimd::fma(kd, B(L.diffuse.z), sb);
        }
        if (prm.specular_on) {
          const V<B> half{vp.x + eye.x, vp.y + eye.y, vp.z + eye.z};
          B pow_nh;
          if constexpr (Spec == PowMethod::one) {
            pow_nh = one;  // shininess 0: x^0 = 1, even at n.h = 0 (and at R.V <= 0)
          } else if constexpr (Spec == PowMethod::exact) {
            if (Extras && prm.phong_lobe) {
              const B k = n_dot_l + n_dot_l;  // R = 2 (n.L) n - L
              const V<B> refl{xsimd::fms(k, n.x, vp.x), xsimd::fms(k, n.y, vp.y), xsimd::fms(k, n.z, vp.z)};
              pow_nh = pow_cos_exact(refl, eye, prm.specular_pow.exponent);
            } else {
              pow_nh = pow_cos_exact(n, half, prm.specular_pow.exponent);
            }
          } else if (Extras && prm.phong_lobe) {
            // R.V = 2 (n.L)(n.V) - L.V: no reflected vector; n.V is the same for every light.
            // R and V are unit (to the normalisation's 2^-22), so R.V needs no division.
            const B r_dot_v = xsimd::fms(n_dot_l + n_dot_l, n_dot_v, dot3(vp, eye));
            pow_nh = pow_fixed<Spec>(fastmath::clamp01(r_dot_v), prm.specular_pow);
          } else {
            // n.h / |h|: one estimate and no normalised h. A zero h (L = -V) gives 0.
            const B h2 = dot3(half, half);
            const auto ok = h2 > B(1e-12f);
            const B n_dot_h = xsimd::select(ok, dot3(n, half) * rsqrt_nr(xsimd::select(ok, h2, one)), zero);
            if constexpr (Spec == PowMethod::integer) {
              // Whole s >= 1: the cheap clamp (max(NaN, 0) = 0, maxps returns its second operand)
              // instead of the bitwise one, whose care for subnormals cannot matter here: x^s <= x.
              pow_nh = fastmath::pow_integer_unit(xsimd::min(xsimd::max(n_dot_h, zero), one),
                                                  prm.specular_pow.integer_exponent);
            } else {
              pow_nh = pow_fixed<Spec>(n_dot_h, prm.specular_pow);
            }
          }
          B ks = xsimd::select(lit, pow_nh, zero);
          if (shadowed) ks *= vis;
          if (split) {
            const B aks = att * ks;
            spr = xsimd::fma(projected ? aks * fr : aks, B(L.specular.x), spr);
            spg = xsimd::fma(projected ? aks * fg : aks, B(L.specular.y), spg);
            spb = xsimd::fma(projected ? aks * fb : aks, B(L.specular.z), spb);
          } else {
            sr = xsimd::fma(projected ? ks * fr : ks, B(L.specular.x), sr);
            sg = xsimd::fma(projected ? ks * fg : ks, B(L.specular.y), sg);
            sb = xsimd::fma(projected ? ks * fb : ks, B(L.specular.z), sb);
          }
        }
      }
      r = xsimd::fma(att, sr, r);
      g = xsimd::fma(att, sg, g);
      b = xsimd::fma(att, sb, b);
    }
    if (split) {
      if (prm.color_material) {
        // Albedo streams are float; in double lanes they are widened (load_unaligned converts).
        const V<B> albedo = triples ? read3(s.a3, i)
                                    : V<B>{B::load_unaligned(s.ar + i), B::load_unaligned(s.ag + i), B::load_unaligned(s.ab + i)};
        r = xsimd::fma(albedo.x, r, B(base[0]));
        g = xsimd::fma(albedo.y, g, B(base[1]));
        b = xsimd::fma(albedo.z, b, B(base[2]));
      }
      if (!prm.separate_specular) {
        r += spr, g += spg, b += spb;
      } else if (triples) {
        write3(s.spec3, i, finish(prm, spr), finish(prm, spg), finish(prm, spb));
      } else {
        finish(prm, spr).store_unaligned(s.sr + i);
        finish(prm, spg).store_unaligned(s.sg + i);
        finish(prm, spb).store_unaligned(s.sb + i);
      }
    }
    if (triples) {
      write3(s.rgb3, i, finish(prm, r), finish(prm, g), finish(prm, b));
    } else {
      finish(prm, r).store_unaligned(s.r + i);
      finish(prm, g).store_unaligned(s.g + i);
      finish(prm, b).store_unaligned(s.b + i);
    }
  }
}

template <class Arch, bool Extras>
void shade_precision(const Params& prm, const Transform* xf, const Streams& s) {
  switch (prm.specular_pow.method) {
    case PowMethod::one: return shade_kernel<Arch, false, PowMethod::one, Extras>(prm, xf, s);
    case PowMethod::exact: return shade_kernel<Arch, false, PowMethod::exact, Extras>(prm, xf, s);
    case PowMethod::fast: return shade_kernel<Arch, false, PowMethod::fast, Extras>(prm, xf, s);
    case PowMethod::integer: return shade_kernel<Arch, false, PowMethod::integer, Extras>(prm, xf, s);
    case PowMethod::schlick: return shade_kernel<Arch, false, PowMethod::schlick, Extras>(prm, xf, s);
  }
}

// Whether the call uses any of the kernel's extras (shade_kernel).
template <class Arch>
bool uses_extras(const Params& prm, const Streams& s) {  // a template on Arch: no inline code crosses ISA files
  if (prm.occlusion || prm.phong_lobe || s.projector) return true;
  for (int i = 0; i < prm.light_count; ++i)
    if ((prm.exact_math ? prm.lights_d[i].linear_range : prm.lights[i].linear_range)) return true;
  return false;
}

template <class Arch>
void shade_streams(const Params& prm, const Transform* xf, const Streams& s) {
  const bool extras = uses_extras<Arch>(prm, s);
  if (prm.exact_math) {
    // The exact tier's specular method is exact, or one for shininess 0.
    if (prm.specular_pow.method == PowMethod::one) {
      extras ? shade_kernel<Arch, true, PowMethod::one, true>(prm, xf, s) : shade_kernel<Arch, true, PowMethod::one, false>(prm, xf, s);
    } else {
      extras ? shade_kernel<Arch, true, PowMethod::exact, true>(prm, xf, s)
             : shade_kernel<Arch, true, PowMethod::exact, false>(prm, xf, s);
    }
  } else if (extras) {
    shade_precision<Arch, true>(prm, xf, s);
  } else {
    shade_precision<Arch, false>(prm, xf, s);
  }
}

// The box of n xyz triples (Kernels' box): true with lo and hi exact when every coordinate is
// finite; false as soon as the data hold a NaN or an infinity (the caller's scalar pass then
// leaves those points out).
template <class Arch>
bool box_triples(const float* p, std::size_t n, float lo[3], float hi[3]) {
  // Three registers hold `lanes` triples as they lie (float e of the block is coordinate e % 3):
  // a minimum and a maximum per register, with no transpose; the coordinates are sorted out once.
  using B = xsimd::batch<float, Arch>;
  constexpr std::size_t lanes = B::size;
  B l[3] = {B(FLT_MAX), B(FLT_MAX), B(FLT_MAX)}, h[3] = {B(-FLT_MAX), B(-FLT_MAX), B(-FLT_MAX)};
  auto finite = xsimd::batch_bool<float, Arch>(true);
  std::size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    for (std::size_t r = 0; r < 3; ++r) {
      const B v = B::load_unaligned(p + 3 * i + r * lanes);
      finite = finite & (xsimd::abs(v) <= B(FLT_MAX));  // false for NaN and both infinities
      l[r] = xsimd::min(l[r], v), h[r] = xsimd::max(h[r], v);
    }
  }
  if (!xsimd::all(finite)) return false;
  for (int k = 0; k < 3; ++k) lo[k] = FLT_MAX, hi[k] = -FLT_MAX;
  for (std::size_t r = 0; r < 3; ++r) {
    alignas(64) float vl[lanes], vh[lanes];
    l[r].store_aligned(vl), h[r].store_aligned(vh);
    for (std::size_t e = 0; e < lanes; ++e) {
      const std::size_t k = (r * lanes + e) % 3;
      lo[k] = vl[e] < lo[k] ? vl[e] : lo[k];
      hi[k] = vh[e] > hi[k] ? vh[e] : hi[k];
    }
  }
  for (; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      const float v = p[3 * i + k];
      if (!(v >= -FLT_MAX && v <= FLT_MAX)) return false;
      lo[k] = v < lo[k] ? v : lo[k];
      hi[k] = v > hi[k] ? v : hi[k];
    }
  }
  return true;
}

template <class Arch>
void pow_streams(const PowSpec& spec, const float* x, float* out, std::size_t count) {
  using B = xsimd::batch<float, Arch>;
  for (std::size_t i = 0; i < count; i += B::size) pow_spec(B::load_unaligned(x + i), spec).store_unaligned(out + i);
}

}  // namespace facet::lighting::simd
