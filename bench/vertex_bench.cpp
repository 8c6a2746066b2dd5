// The vertex work of animated models (geometry/skin.hpp): linear blend skinning and morph targets,
// per path (the double reference, the scalar twin, the SIMD kernel per ISA), one thread.
//   BM_Skin/<path>/influences:{4,8}/normals:<cofactor|linear>/vertices:{4096,65536,1048576}:
//     positions and normals of a mesh bent by 64 joints, random joints and weights per vertex
//     (the linear normal transform at 65536 vertices only);
//   BM_Morph/<path>/targets:{1,8}/vertices:{65536,1048576}: positions plus the weighted deltas of
//     every target (all weights non-zero).
// Counters: vertices_skinned/s or vertices_morphed/s (and vertices/s, either), and the shares of the machine's limits
// measured at start (bench/roofline.hpp): bw_share = the bytes a vertex must stream / triad
// bandwidth (skin: 24 + 6 k in, 24 out for k influences; morph: 12 (1 + targets) in, 12 out);
// flop_share = counted flops / peak FMA rate (skin: 12 + 24 (k - 1) for the blend, 18 for the
// position, 47 for the cofactor normal or 15 for the linear one, 9 to normalise). Compare with
// facet_bench_lighting's vertices_lit/s for the same vertex counts.
//   build/bin/facet_bench_vertex --benchmark_filter=BM_Skin/simd
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "facet/facet.hpp"
#include "geometry/skin.hpp"
#include "roofline.hpp"

namespace {

using facet::geometry::MorphJob;
using facet::geometry::MorphTarget;
using facet::geometry::SkinJob;

constexpr std::size_t kJoints = 64;

struct SkinData {
  std::size_t n;
  int k;
  std::vector<float> in[6], weights, matrices, out_p, out_n;
  std::vector<double> matrices_d, ref_p, ref_n;
  std::vector<std::uint16_t> joints;
  SkinData(std::size_t count, int influences) : n(count), k(influences) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (auto& s : in) {
      s.resize(n);
      for (float& v : s) v = u(rng);
    }
    joints.resize(std::size_t(k) * n);
    weights.resize(std::size_t(k) * n);
    for (std::size_t i = 0; i < n; ++i) {
      float sum = 0;
      for (int c = 0; c < k; ++c) {
        joints[std::size_t(c) * n + i] = static_cast<std::uint16_t>(rng() % kJoints);
        sum += weights[std::size_t(c) * n + i] = 0.5f + 0.5f * u(rng);
      }
      for (int c = 0; c < k; ++c) weights[std::size_t(c) * n + i] /= sum;
    }
    matrices.resize(12 * kJoints);
    for (float& v : matrices) v = u(rng);
    matrices_d.assign(matrices.begin(), matrices.end());
    out_p.resize(3 * n), out_n.resize(3 * n);
  }
  SkinJob job(facet::NormalTransform normals) {
    SkinJob j;
    j.count = n;
    for (int c = 0; c < 3; ++c) j.position[c] = in[c].data(), j.normal[c] = in[3 + c].data();
    j.influences = k;
    j.joints = joints.data();
    j.weights = weights.data();
    j.matrices = matrices.data();
    j.joint_count = kJoints;
    j.normals = normals;
    j.out_position = out_p.data();
    j.out_normal = out_n.data();
    return j;
  }
};

// path: "reference", "scalar" or an ISA's name.
void run_skin(benchmark::State& state, const std::string& path, int k, facet::NormalTransform normals, std::size_t n) {
  SkinData d(n, k);
  SkinJob job = d.job(normals);
  if (path == "reference") d.ref_p.resize(3 * n), d.ref_n.resize(3 * n);
  const facet::Isa isa = path == "sse2" ? facet::Isa::sse2 : path == "avx2" ? facet::Isa::avx2 : facet::Isa::avx512;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    if (path == "reference") facet::geometry::skin_reference(job, d.matrices_d.data(), d.ref_p.data(), d.ref_n.data(), nullptr);
    else if (path == "scalar") facet::geometry::skin_scalar(job);
    else facet::geometry::skin(job, isa);
    benchmark::DoNotOptimize(d.out_p.data());
    benchmark::ClobberMemory();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double rate = double(state.iterations()) * double(n) / seconds;
  const facet::bench::Roofline& roof = facet::bench::roofline();
  using benchmark::Counter;
  state.counters["vertices_skinned/s"] = Counter(double(n), Counter::kIsIterationInvariantRate);
  state.counters["vertices/s"] = Counter(double(n), Counter::kIsIterationInvariantRate);
  state.counters["bw_share"] = rate * (48.0 + 6.0 * k) / roof.triad_bytes_per_s;
  const double flops = 12.0 + 24.0 * (k - 1) + 18.0 + (normals == facet::NormalTransform::cofactor ? 47.0 : 15.0) + 9.0;
  state.counters["flop_share"] = rate * flops / roof.peak_flops;
}

void run_morph(benchmark::State& state, const std::string& path, int targets, std::size_t n) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> base[3], out[3];
  std::vector<std::vector<float>> deltas(3 * std::size_t(targets));
  for (int c = 0; c < 3; ++c) {
    base[c].resize(n), out[c].resize(n);
    for (float& v : base[c]) v = u(rng);
  }
  for (auto& dl : deltas) {
    dl.resize(n);
    for (float& v : dl) v = 0.1f * u(rng);
  }
  std::vector<MorphTarget> list(static_cast<std::size_t>(targets));
  for (int t = 0; t < targets; ++t) {
    list[std::size_t(t)].weight = 0.5f + 0.4f * u(rng);
    for (int c = 0; c < 3; ++c) list[std::size_t(t)].delta[c] = deltas[std::size_t(3 * t + c)].data();
  }
  MorphJob job;
  job.count = n;
  for (int c = 0; c < 3; ++c) job.base[c] = base[c].data(), job.out[c] = out[c].data();
  job.targets = list.data();
  job.target_count = list.size();
  const facet::Isa isa = path == "sse2" ? facet::Isa::sse2 : path == "avx2" ? facet::Isa::avx2 : facet::Isa::avx512;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    if (path == "scalar") facet::geometry::morph_scalar(job);
    else facet::geometry::morph(job, isa);
    benchmark::DoNotOptimize(out[0].data());
    benchmark::ClobberMemory();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double rate = double(state.iterations()) * double(n) / seconds;
  const facet::bench::Roofline& roof = facet::bench::roofline();
  using benchmark::Counter;
  state.counters["vertices_morphed/s"] = Counter(double(n), Counter::kIsIterationInvariantRate);
  state.counters["vertices/s"] = Counter(double(n), Counter::kIsIterationInvariantRate);
  state.counters["bw_share"] = rate * 12.0 * (2.0 + targets) / roof.triad_bytes_per_s;
  state.counters["flop_share"] = rate * 6.0 * targets / roof.peak_flops;
}

void register_all() {
  std::vector<std::string> paths = {"reference", "scalar"};
  for (const facet::Isa isa : {facet::Isa::sse2, facet::Isa::avx2, facet::Isa::avx512}) {
    if (facet::isa_supported(isa)) paths.push_back(std::string("simd_") + facet::to_string(isa));
  }
  for (const std::string& p : paths) {
    const std::string isa = p.rfind("simd_", 0) == 0 ? p.substr(5) : p;
    for (const int k : {4, 8}) {
      for (const std::size_t n : {std::size_t{4096}, std::size_t{65536}, std::size_t{1} << 20}) {
        for (const facet::NormalTransform nt : {facet::NormalTransform::cofactor, facet::NormalTransform::linear}) {
          if (nt == facet::NormalTransform::linear && n != 65536) continue;
          const std::string name = "BM_Skin/" + p + "/influences:" + std::to_string(k) + "/normals:" +
                                   (nt == facet::NormalTransform::cofactor ? "cofactor" : "linear") + "/vertices:" + std::to_string(n);
          facet::bench::with_spread(benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
            run_skin(state, isa, k, nt, n);
          }))->Unit(benchmark::kMicrosecond);
        }
      }
    }
    if (p == "reference") continue;
    for (const int targets : {1, 8}) {
      for (const std::size_t n : {std::size_t{65536}, std::size_t{1} << 20}) {
        const std::string name = "BM_Morph/" + p + "/targets:" + std::to_string(targets) + "/vertices:" + std::to_string(n);
        facet::bench::with_spread(benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
          run_morph(state, isa, targets, n);
        }))->Unit(benchmark::kMicrosecond);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) { return facet::bench::run_benchmarks(argc, argv, register_all); }
