// The pow tiers on every ISA this CPU has: contracts swept over their domain, and the special
// inputs of the lighting model (0, 1, tiny and huge exponents), including where a tier is documented not to
// approximate.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <xmmintrin.h>

#include <gtest/gtest.h>

#include "lighting/point_shader.hpp"

namespace facet {
namespace {

using lighting::resolve_pow;
using lighting::simd::PowMethod;
using lighting::simd::PowSpec;

// Sample points of [0, 1]: 2^20 stratified, the 2^16 floats just below 1, every power of two
// down to the smallest subnormal, and the special values.
std::vector<float> sweep_points() {
  std::vector<float> x;
  std::mt19937 rng(5);
  for (int i = 0; i < (1 << 20); ++i) {
    x.push_back((static_cast<float>(i) + std::uniform_real_distribution<float>(0, 1)(rng)) / float(1 << 20));
  }
  float v = 1.0f;
  for (int i = 0; i < (1 << 16); ++i) x.push_back(v = std::nextafter(v, 0.0f));
  for (int e = 0; e >= -149; --e) x.push_back(std::ldexp(1.0f, e));
  x.push_back(0.0f);
  x.push_back(1.0f);
  while (x.size() % lighting::simd::kMaxLanes) x.push_back(0.5f);
  return x;
}

class PowTiers : public ::testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam())) GTEST_SKIP() << "this CPU has no " << to_string(GetParam());
    pow_ = lighting::simd_kernels(GetParam())->pow;
  }
  std::vector<float> run(const PowSpec& spec, const std::vector<float>& x) const {
    std::vector<float> y(x.size());
    pow_(spec, x.data(), y.data(), x.size());
    return y;
  }
  float one(const PowSpec& spec, float x) const {
    std::vector<float> in(lighting::simd::kMaxLanes, x);
    return run(spec, in)[0];
  }
  lighting::simd::PowFunction pow_ = nullptr;
};

double max_abs_error(const std::vector<float>& x, const std::vector<float>& y, double s) {
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(double(y[i]) - std::pow(double(x[i]), s)));
  return worst;
}

TEST_P(PowTiers, ExactIsWithin2e6UpTo1024) {
  const auto x = sweep_points();
  double worst = 0;
  for (float s : {0.5f, 1.0f, 2.5f, 8.0f, 16.0f, 64.0f, 127.3f, 128.0f, 256.0f, 512.0f, 1024.0f}) {
    worst = std::max(worst, max_abs_error(x, run({PowMethod::exact, s, 0}, x), s));
  }
  EXPECT_LE(worst, 2e-6);
  std::printf("exact tier (%s): max abs error %.3g over s in 0.5..1024\n", to_string(GetParam()), worst);
}

TEST_P(PowTiers, FastIsWithinItsContractAndOneEightBitStep) {
  const auto x = sweep_points();
  double worst = 0;
  int worst_delta8 = 0;
  for (float s = 0.25f; s <= 256.0f; s = s < 4 ? s + 0.25f : s * 1.19f) {
    const auto y = run({PowMethod::fast, s, 0}, x);
    worst = std::max(worst, max_abs_error(x, y, s));
    for (std::size_t i = 0; i < x.size(); ++i) {
      const long ref = std::lround(255.0 * std::pow(double(x[i]), double(s)));
      worst_delta8 = std::max<int>(worst_delta8, std::abs(int(std::lround(255.0 * y[i]) - ref)));
    }
  }
  EXPECT_LE(worst, 2.2e-5) << "documented in pow_simd.hpp";
  EXPECT_LE(worst_delta8, 1);
  std::printf("fast tier (%s): max abs error %.3g, max 8-bit difference %d over s in 0.25..256\n",
              to_string(GetParam()), worst, worst_delta8);
}

TEST_P(PowTiers, IntegerIsWithinItsContract) {
  // Documented: about (s/2 + log2 s) ulp of relative error (each squaring doubles what it carries).
  const auto x = sweep_points();
  for (int s : {1, 2, 3, 7, 16, 33, 64, 100, 128, 255, 256}) {
    const double bound = (s / 2.0 + std::log2(double(s)) + 1) * std::ldexp(1.0, -24);
    EXPECT_LE(max_abs_error(x, run({PowMethod::integer, float(s), s}, x), s), bound) << "s = " << s;
  }
}

TEST_P(PowTiers, SchlickIsADifferentLobeNotAnApproximation) {
  // Documented: bounded, monotone, 0 at 0 and 1 at 1, but up to ~0.2 away from x^s.
  const auto x = sweep_points();
  const auto y = run({PowMethod::schlick, 32.0f, 0}, x);
  for (float v : y) ASSERT_TRUE(v >= 0.0f && v <= 1.0f);
  EXPECT_EQ(one({PowMethod::schlick, 32.0f, 0}, 0.0f), 0.0f);
  EXPECT_EQ(one({PowMethod::schlick, 32.0f, 0}, 1.0f), 1.0f);
  EXPECT_GT(max_abs_error(x, y, 32.0), 0.1);
}

TEST_P(PowTiers, SpecialInputs) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float above_one = std::nextafter(1.0f, 2.0f);
  const float subnormal = 1e-40f;
  for (PowMethod m : {PowMethod::exact, PowMethod::fast, PowMethod::integer, PowMethod::schlick}) {
    SCOPED_TRACE(static_cast<int>(m));
    auto spec = [&](float s) { return PowSpec{m, s, static_cast<int>(s)}; };
    EXPECT_EQ(one(spec(0), 0.0f), 1.0f) << "0^0 = 1";
    EXPECT_EQ(one(spec(5), 0.0f), 0.0f) << "0^s = 0";
    EXPECT_EQ(one(spec(256), 1.0f), 1.0f) << "1^s = 1";
    EXPECT_EQ(one(spec(256), above_one), 1.0f) << "1 + ulp is clamped to 1";
    EXPECT_EQ(one(spec(3), -0.5f), 0.0f) << "negative is clamped to 0";
    EXPECT_EQ(one(spec(3), nan), 0.0f) << "NaN gives 0";
    EXPECT_EQ(one(spec(3), std::numeric_limits<float>::infinity()), 1.0f) << "+inf is clamped to 1";
  }
  // 1^s for s far above 256 stays 1 in the tiers that take any exponent.
  EXPECT_EQ(one({PowMethod::exact, 4096.0f, 0}, 1.0f), 1.0f);
  EXPECT_EQ(one({PowMethod::fast, 4096.0f, 0}, 1.0f), 1.0f);
  // Subnormal input, tiny exponent: x^0.01 = 0.398 is far from 0; FTZ/DAZ must not change it.
  const double expected = std::pow(double(subnormal), 0.01);
  for (bool flush : {false, true}) {
    const unsigned saved = _mm_getcsr();
    if (flush) _mm_setcsr(saved | 0x8040);  // FTZ | DAZ on this thread, restored below
    const float exact = one({PowMethod::exact, 0.01f, 0}, subnormal);
    const float fast = one({PowMethod::fast, 0.01f, 0}, subnormal);
    _mm_setcsr(saved);
    EXPECT_NEAR(exact, expected, 2e-6) << "FTZ/DAZ " << flush;
    EXPECT_NEAR(fast, expected, 2.2e-5) << "FTZ/DAZ " << flush;
  }
}

INSTANTIATE_TEST_SUITE_P(Isas, PowTiers, ::testing::Values(Isa::sse2, Isa::avx2, Isa::avx512),
                         [](const auto& param_info) { return std::string(to_string(param_info.param)); });

TEST(PowTierChoice, AutoPicksTheCheapestWithinBudget) {
  EXPECT_EQ(resolve_pow(0.0f, PowTier::automatic).method, PowMethod::one);
  EXPECT_EQ(resolve_pow(64.0f, PowTier::automatic).method, PowMethod::integer);
  EXPECT_EQ(resolve_pow(64.0f, PowTier::automatic).integer_exponent, 64);
  EXPECT_EQ(resolve_pow(37.5f, PowTier::automatic).method, PowMethod::fast);
  EXPECT_EQ(resolve_pow(300.0f, PowTier::automatic).method, PowMethod::exact);
  EXPECT_EQ(resolve_pow(300.0f, PowTier::integer).method, PowMethod::exact) << "integer only up to 256";
  EXPECT_EQ(resolve_pow(2.5f, PowTier::integer).method, PowMethod::exact) << "integer only for whole exponents";
}

}  // namespace
}  // namespace facet
