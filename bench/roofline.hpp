// The machine's limits, measured once at start so that every benchmark can report its share of
// them: streaming read and triad (a = b + s c) bandwidth over arrays far larger than the caches,
// and the peak rate of independent fused multiply-adds (avx2+fma when the CPU has it, else sse2
// multiplies and adds). Single thread, like the lighting benchmarks; the frame benchmarks report
// against the same figures times their thread count.
#pragma once

#include "context.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <immintrin.h>

#include "facet/lighting.hpp"

namespace facet::bench {

struct Roofline {
  double read_bytes_per_s = 0;   // sum of a 128 MiB array
  double triad_bytes_per_s = 0;  // 3 x 48 MiB arrays, counting 3 x 4 bytes per element
  double image_store_bytes_per_s = 0;  // filling one 1920x1080 RGBA8 image (8 MB) with 32-byte stores
  double peak_flops = 0;         // fused multiply-add = 2 flops
};

namespace detail {

template <class Fn>
double best_seconds(Fn&& fn, int repeats = 5) {
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

__attribute__((target("avx2,fma"))) inline double fma_loop_avx2(long iterations) {
  __m256 a[10];
  for (int k = 0; k < 10; ++k) a[k] = _mm256_set1_ps(1.0f + 1e-3f * float(k));
  const __m256 m = _mm256_set1_ps(0.999999f), c = _mm256_set1_ps(1e-7f);
  for (long i = 0; i < iterations; ++i) {
    for (int k = 0; k < 10; ++k) a[k] = _mm256_fmadd_ps(a[k], m, c);
  }
  __m256 s = a[0];
  for (int k = 1; k < 10; ++k) s = _mm256_add_ps(s, a[k]);
  float out[8];
  _mm256_storeu_ps(out, s);
  benchmark::DoNotOptimize(out);
  return double(iterations) * 10 * 8 * 2;
}

inline void fill_image(std::uint32_t* p, std::size_t n, std::uint32_t value) {
  const __m128i v = _mm_set1_epi32(static_cast<int>(value));
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) _mm_storeu_si128(reinterpret_cast<__m128i*>(p + i), v);
  for (; i < n; ++i) p[i] = value;
}

inline double fma_loop_sse2(long iterations) {
  __m128 a[10];
  for (int k = 0; k < 10; ++k) a[k] = _mm_set1_ps(1.0f + 1e-3f * float(k));
  const __m128 m = _mm_set1_ps(0.999999f), c = _mm_set1_ps(1e-7f);
  for (long i = 0; i < iterations; ++i) {
    for (int k = 0; k < 10; ++k) a[k] = _mm_add_ps(_mm_mul_ps(a[k], m), c);
  }
  __m128 s = a[0];
  for (int k = 1; k < 10; ++k) s = _mm_add_ps(s, a[k]);
  float out[4];
  _mm_storeu_ps(out, s);
  benchmark::DoNotOptimize(out);
  return double(iterations) * 10 * 4 * 2;
}

inline Roofline measure() {
  Roofline r;
  {
    std::vector<float> a(std::size_t(32) << 20, 1.0f);  // 128 MiB
    float sum = 0;
    const double s = best_seconds([&] {
      float acc[8] = {};
      for (std::size_t i = 0; i < a.size(); i += 8)
        for (int k = 0; k < 8; ++k) acc[k] += a[i + static_cast<std::size_t>(k)];
      for (float v : acc) sum += v;
      benchmark::DoNotOptimize(sum);
    });
    r.read_bytes_per_s = double(a.size() * sizeof(float)) / s;
  }
  {
    const std::size_t n = std::size_t(12) << 20;  // 48 MiB per array
    std::vector<float> a(n), b(n, 1.0f), c(n, 2.0f);
    const double s = best_seconds([&] {
      for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + 0.5f * c[i];
      benchmark::DoNotOptimize(a.data());
    });
    r.triad_bytes_per_s = double(3 * n * sizeof(float)) / s;
  }
  {
    // What a resolve at memory speed would reach: the frame benchmarks' output image, written
    // whole (it is the size a resolve writes each frame, so it may sit in a large last-level cache).
    std::vector<std::uint32_t> image(std::size_t(1920) * 1080, 0u);
    std::uint32_t value = 1;
    const double s = best_seconds([&] {
      fill_image(image.data(), image.size(), value++);
      benchmark::DoNotOptimize(image.data());
    }, 20);
    r.image_store_bytes_per_s = double(image.size() * sizeof(std::uint32_t)) / s;
  }
  {
    const long iterations = 20'000'000;
    const bool avx2 = isa_supported(Isa::avx2);
    double flops = 0;
    const double s = best_seconds([&] { flops = avx2 ? fma_loop_avx2(iterations) : fma_loop_sse2(iterations); }, 3);
    r.peak_flops = flops / s;
  }
  return r;
}

}  // namespace detail

// Measured at first use (about a second), then shared by every benchmark of the program.
inline const Roofline& roofline() {
  static const Roofline r = detail::measure();
  return r;
}

// Adds the roofline to the benchmark context (printed once and kept in the JSON output).
inline void add_roofline_context() {
  const Roofline& r = roofline();
  benchmark::AddCustomContext("roofline_read_GB/s", std::to_string(r.read_bytes_per_s / 1e9));
  benchmark::AddCustomContext("roofline_triad_GB/s", std::to_string(r.triad_bytes_per_s / 1e9));
  benchmark::AddCustomContext("roofline_image_store_GB/s", std::to_string(r.image_store_bytes_per_s / 1e9));
  benchmark::AddCustomContext("roofline_peak_GFLOP/s", std::to_string(r.peak_flops / 1e9));
}

// main() of a benchmark program whose benchmarks `register_all` registers at run time.
inline int run_benchmarks(int argc, char** argv, void (*register_all)()) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  add_roofline_context();
  add_facet_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace facet::bench
