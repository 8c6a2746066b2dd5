// The texture samplers alone (Google Benchmark): the float sampler of the exact tier and the
// fixed-point sampler of the 16-bit tier (texture/sample_fixed_simd.hpp) on the same inputs, each
// ISA's kernel through the raster kernel table.
//   BM_Sampler/<float|fixed>/<nearest|bilinear|trilinear>/<isa>: 4096 samples of a 256 x 256 RGBA8
//   texture, coordinates marching along a row as a rasterized span does (a texel every 1.3
//   samples: minified by 1.3, trilinear reads levels 0 and 1), derivatives constant.
// Counter: samples/s. Both write their natural output (float: four planes of floats; fixed:
// packed RGBA8), which is what a pixel program of each tier reads next.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "context.hpp"
#include "facet/facet.hpp"
#include "tile/tile_raster.hpp"
#include "texture/sampler.hpp"

namespace {

constexpr std::size_t kSamples = 4096;

struct Streams {
  std::vector<float> planes[6];
  const float* in[6];
  explicit Streams(int size) {
    for (auto& p : planes) p.resize(kSamples);
    const float step = 1.3f / float(size);
    for (std::size_t i = 0; i < kSamples; ++i) {
      planes[0][i] = 0.1f + step * float(i % 512);
      planes[1][i] = 0.2f + step * float(i / 512);
      planes[2][i] = step, planes[3][i] = 0.0f, planes[4][i] = 0.0f, planes[5][i] = step;
    }
    for (int k = 0; k < 6; ++k) in[k] = planes[k].data();
  }
};

facet::Texture texture(facet::TextureFilter filter) {
  std::mt19937 rng(1);
  std::vector<std::uint8_t> rgba(256 * 256 * 4);
  for (auto& b : rgba) b = static_cast<std::uint8_t>(rng());
  return *facet::make_texture("noise", 256, 256, rgba, {filter, facet::TextureWrap::repeat});
}

void register_all() {
  for (facet::Isa isa : {facet::Isa::sse2, facet::Isa::avx2, facet::Isa::avx512}) {
    if (!facet::isa_supported(isa)) continue;
    const facet::tile::simd::Kernels* kernels = facet::tile::simd_raster_kernels(isa);
    for (facet::TextureFilter filter :
         {facet::TextureFilter::nearest, facet::TextureFilter::bilinear, facet::TextureFilter::trilinear}) {
      for (const bool fixed : {false, true}) {
        const std::string name = std::string("BM_Sampler/") + (fixed ? "fixed/" : "float/") + facet::to_string(filter) +
                                 "/" + facet::to_string(isa);
        facet::bench::with_spread(benchmark::RegisterBenchmark(name.c_str(), [kernels, filter, fixed](benchmark::State& state) {
          const facet::Texture t = texture(filter);
          const facet::texture::Sampler s = facet::texture::make_sampler(t);
          const Streams in(256);
          std::vector<float> out_planes[4];
          for (auto& p : out_planes) p.resize(kSamples);
          float* out[4] = {out_planes[0].data(), out_planes[1].data(), out_planes[2].data(), out_planes[3].data()};
          std::vector<std::uint32_t> packed(kSamples);
          for (auto _ : state) {
            if (fixed) {
              kernels->sample_fixed(s, kSamples, in.in, packed.data());
              benchmark::DoNotOptimize(packed.data());
            } else {
              kernels->sample(s, kSamples, in.in, out);
              benchmark::DoNotOptimize(out_planes[0].data());
            }
            benchmark::ClobberMemory();
          }
          state.counters["samples/s"] =
              benchmark::Counter(double(kSamples) * double(state.iterations()), benchmark::Counter::kIsRate);
        }));
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_all();
  facet::bench::add_facet_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
