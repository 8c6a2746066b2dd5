// The scalar path: the same lighting model in float, one vertex at a time. This file is compiled
// with FACET_NO_VECTORIZE_FLAGS (cmake/FacetCompilerFlags.cmake) so that it stays an honest
// scalar baseline for the SIMD paths.
#include "lighting/pbr_shade.hpp"
#include "lighting/shade.hpp"

namespace facet::lighting {
template void light_mesh<float>(const ShadeParams<float>&, const EyeTransform<float>&, const Mesh&, bool, std::size_t,
                                 std::size_t, Color3*, Color3*, const std::uint32_t*, const Vec3*);
template void shade_points<float>(const ShadeParams<float>&, std::size_t, const Vec3*, const Vec3*, const Color3*, Color3*,
                                 Color3*, const float*, int, const float*, const float*, int, const float*);
template V3<float> shade_pbr<float>(const ShadeParams<float>&, V3<float>, V3<float>, V3<float>, V3<float>*, const float*, float,
                                 const float*, const float*);
}  // namespace facet::lighting
