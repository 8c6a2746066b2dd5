// The SIMD tile rasterizer for avx512, built with: -mavx512f -mavx512bw -mavx512dq -mavx512vl -mavx512cd -mfma -ffp-contract=off (engine/CMakeLists.txt).
#if !defined(__AVX512F__) || !defined(__AVX512BW__)
#error "kernels_avx512.cpp must be compiled with its ISA flags"
#endif
#if !defined(FACET_NO_FP_CONTRACT)
#error "raster kernels must be compiled with -ffp-contract=off (byte-identical images on every ISA)"
#endif

#include "geometry/transform_simd.hpp"
#include "raster/place_simd.hpp"
#include "tile/raster_simd.hpp"
#include "tile/display_simd.hpp"
#include "tile/resolve_simd.hpp"
#include "shadow/map_simd.hpp"
#include "texture/sample_fixed_simd.hpp"
#include "texture/sample_simd.hpp"

namespace facet::tile::simd::avx512 {
void transform_vertices(const geometry::Mat4Rows& mvp, const float* positions, std::size_t begin, std::size_t end,
                        const geometry::ClipPlanes& planes, const geometry::Viewport& viewport, std::array<float, 4>* clip,
                        geometry::ScreenVertex* screen) {
  geometry::simd::Transform<xsimd::avx512bw>::run(mvp, positions, begin, end, planes, viewport, clip, screen);
}
void place_triangles(const std::uint32_t* triangles, const geometry::ScreenVertex* screen, const PlaceParams& params,
                     PlaceGroup& out) {
  raster::simd::Place<xsimd::avx512bw>::run(triangles, screen, params, out);
}
void raster_tile(const TileJob& job, const TileView& tile, TileCounters& counters) {
  TileKernel<xsimd::avx512bw>::raster(job, tile, counters);
}
void resolve_tile(const TileView& tile, int x0, int y0, int x1, int y1, const ImageView& color,
                  const DepthView* depth) {
  // The common 8-bit case 16 pixels at a time; the others on rows of 8 (the avx2 half).
  if (Resolve<xsimd::avx512bw>::fast_resolve(x0, x1, color, depth)) {
    Resolve<xsimd::avx512bw>::resolve_fast(tile, x0, y0, x1, y1, color);
    return;
  }
  Resolve<xsimd::fma3<xsimd::avx2>>::resolve(tile, x0, y0, x1, y1, color, depth);
}
void sample_texture(const texture::Sampler& sampler, std::size_t count, const float* const* in, float* const* out) {
  texture::simd::SampleSimd<xsimd::avx512bw>::sample_streams(sampler, count, in, out);
}
void sample_fixed(const texture::Sampler& sampler, std::size_t count, const float* const* in, std::uint32_t* out) {
  texture::simd::SampleFixed<xsimd::avx512bw>::sample_streams(sampler, count, in, out);
}
void shadow_map(const shadow::MapLookup& map, std::size_t count, const float* px, const float* py, const float* pz,
                const float* nx, const float* ny, const float* nz, std::size_t stride, float* visible) {
  shadow::simd::MapSimd<xsimd::avx512bw>::run(map, count, px, py, pz, nx, ny, nz, stride, visible);
}
int display_row(const DisplayRow& row) { return DisplayStore<xsimd::avx512bw>::row(row); }
}  // namespace facet::tile::simd::avx512
