// pow(x, s) for the specular and spot exponents, on xsimd batches. Included only by the per-ISA
// kernel files: everything here is a template on the batch type, so no instantiation is shared
// between files built with different ISA flags (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
//
// Common to every tier: x is first clamped into [0, 1] (NaN -> 0, negative -> 0, 1 + ulp -> 1,
// decided on the bits);
// s = 0 gives 1 for every x (0^0 = 1, as GL says); s is a per-material (uniform) scalar.
// Subnormal x are read from their bits (integer conversion), so flush-to-zero / denormals-are-zero
// modes do not change any result. Results never are NaN, negative or above 1.
//
// Tiers (measured errors: tests/pow_tiers_test.cpp; the sweep covers 2^20 stratified floats of
// [0, 1], the 2^16 floats just below 1 and every power of two, for s in 0..1024):
//   exact    exp2(s * log2 x) with xsimd's full-precision exp2/log2.
//            Max abs error <= 2e-6 for s <= 1024 (measured 9.7e-8). 0^s = 0 for s > 0.
//   fast     The same identity with cheap polynomials: log2 m ~ (m - 1) q(m) on [sqrt(1/2),
//            sqrt(2)) (degree 4, relative error 5.2e-5) and 2^f ~ 1 + f r(f) on [0, 1) (degree 4,
//            relative error 2.9e-6); coefficients from tools/fit/fit_pow_coefficients.py
//            (least squares of the relative error at 4000 Chebyshev nodes). Because log2 keeps a
//            relative error near x = 1, pow's absolute error is <= 5.2e-5 / e + 2.9e-6 ~ 2.2e-5
//            for any s (measured 2.0e-5 for s in 0.25..256), far inside the 8-bit budget
//            (Delta8 <= 1 needs < 3.9e-3). 1^s = 1 exactly. Results below 2^-126 are 0.
//   integer  Repeated squaring for whole s in [0, 256]: at most 16 multiplications. Each squaring
//            doubles the relative error carried in, so it is about (s/2 + log2 s) ulp: 7.7e-6 at
//            s = 256 (measured max abs error 5.0e-6). Only chosen for whole exponents <= 256.
//   schlick  x / (s - s x + x): Schlick's rational lobe. A *different specular model*, not an
//            approximation of pow (it differs from x^s by up to 0.2); offered for comparison.
#pragma once

#include <cstdint>

#include <xsimd/xsimd.hpp>

namespace facet::fastmath {

// NaN -> 0, then clamp into [0, 1]. Operand order is deliberate: NaN fails `x > 0`.
template <class B>
B clamp01(const B& x) {
  return xsimd::select(x > B(0.0f), xsimd::select(x < B(1.0f), x, B(1.0f)), B(0.0f));
}

// clamp01 decided on the bits, so that denormals-are-zero mode cannot turn a subnormal into 0:
// sign set (negatives, -0, -NaN) -> 0; above 1.0's bits: NaN -> 0, otherwise (incl. +inf) 1.
template <class B>
B clamp_unit_bits(const B& x) {
  using I = xsimd::batch<std::int32_t, typename B::arch_type>;
  const I bits = xsimd::bitwise_cast<I>(x);
  const I one_bits(0x3f800000), inf_bits(0x7f800000);
  I r = xsimd::select(bits > one_bits, xsimd::select(bits > inf_bits, I(0), one_bits), bits);
  r = xsimd::select(bits < I(0), I(0), r);
  return xsimd::bitwise_cast<B>(r);
}

// Splits x in [0, 1] as m * 2^e with m in [sqrt(1/2), sqrt(2)), reading subnormals exactly whatever
// the FTZ/DAZ mode; `zero` marks x == 0 (whose log2 is -inf).
template <class B>
void split_exponent(const B& x, B& m, B& e, typename B::batch_bool_type& zero) {
  using I = xsimd::batch<std::int32_t, typename B::arch_type>;
  const I bits = xsimd::bitwise_cast<I>(x);
  const auto is_sub = (bits & I(0x7f800000)) == I(0);
  // A subnormal's value is bits * 2^-149: convert the integer (exact, below 2^23) and re-split.
  const B scaled = xsimd::to_float(bits);
  const I norm_bits = xsimd::select(is_sub, xsimd::bitwise_cast<I>(scaled), bits);
  const I exponent = ((norm_bits >> 23) & I(0xff)) - I(127) - xsimd::select(is_sub, I(149), I(0));
  B mant = xsimd::bitwise_cast<B>((norm_bits & I(0x007fffff)) | I(0x3f800000));  // [1, 2)
  B ex = xsimd::to_float(exponent);
  const auto high = mant > B(1.41421356f);
  mant = xsimd::select(high, mant * B(0.5f), mant);
  ex = xsimd::select(high, ex + B(1.0f), ex);
  m = mant;
  e = ex;
  zero = scaled == B(0.0f);  // the integer bits converted: 0 only for x == +0, whatever DAZ says
}

template <class B>
B pow_exact(B x, float s) {
  if (s == 0.0f) return B(1.0f);
  x = clamp_unit_bits(x);
  B m, e;
  typename B::batch_bool_type zero;
  split_exponent(x, m, e, zero);
  const B l = e + xsimd::log2(m);
  const B y = xsimd::exp2(B(s) * l);
  return xsimd::select(zero, B(0.0f), clamp01(y));
}

template <class B>
B pow_fast(B x, float s) {
  using I = xsimd::batch<std::int32_t, typename B::arch_type>;
  if (s == 0.0f) return B(1.0f);
  x = clamp_unit_bits(x);
  B m, e;
  typename B::batch_bool_type zero;
  split_exponent(x, m, e, zero);
  // log2 m = (m - 1) q(m)
  B q = B(2.556670160e-01f);
  q = xsimd::fma(q, m, B(-1.413791273e+00f));
  q = xsimd::fma(q, m, B(3.192585767e+00f));
  q = xsimd::fma(q, m, B(-3.887006986e+00f));
  q = xsimd::fma(q, m, B(3.295193051e+00f));
  const B l = xsimd::fma(m - B(1.0f), q, e);
  // 2^t, t <= 0: t = i + f, 2^f = 1 + f r(f)
  const B t = xsimd::max(B(s) * l, B(-126.0f));
  const B i = xsimd::floor(t);
  const B f = t - i;
  B r = B(1.342655110e-02f);
  r = xsimd::fma(r, f, B(5.224089699e-02f));
  r = xsimd::fma(r, f, B(2.412826881e-01f));
  r = xsimd::fma(r, f, B(6.930440083e-01f));
  const B p = xsimd::fma(f, r, B(1.0f));
  const B scale = xsimd::bitwise_cast<B>((xsimd::to_int(i) + I(127)) << 23);
  const auto underflow = t <= B(-126.0f);
  return xsimd::select(zero || underflow, B(0.0f), xsimd::min(p * scale, B(1.0f)));
}

// Repeated squaring of an x already in [0, 1] (the lighting kernel clamps n.h itself).
template <class B>
B pow_integer_unit(B x, int s) {
  B result(1.0f);
  for (; s > 0; s >>= 1) {
    if (s & 1) result *= x;
    x *= x;
  }
  return result;
}

template <class B>
B pow_integer(B x, int s) {
  return pow_integer_unit(clamp_unit_bits(x), s);
}

template <class B>
B pow_schlick(B x, float s) {
  if (s == 0.0f) return B(1.0f);
  x = clamp_unit_bits(x);
  return x / (B(s) - B(s) * x + x);
}

}  // namespace facet::fastmath
