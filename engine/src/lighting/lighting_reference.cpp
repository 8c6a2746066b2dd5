// The reference path: the lighting model in double precision with std::pow. The oracle of the tests.
#include "lighting/pbr_shade.hpp"
#include "lighting/shade.hpp"

namespace facet::lighting {
template void light_mesh<double>(const ShadeParams<double>&, const EyeTransform<double>&, const Mesh&, bool, std::size_t,
                                 std::size_t, Color3*, Color3*, const std::uint32_t*, const Vec3*);
template void shade_points<double>(const ShadeParams<double>&, std::size_t, const Vec3*, const Vec3*, const Color3*, Color3*,
                                 Color3*, const float*, int, const float*, const float*, int, const float*);
template V3<double> shade_pbr<double>(const ShadeParams<double>&, V3<double>, V3<double>, V3<double>, V3<double>*, const float*, double,
                                 const float*, const float*);
}  // namespace facet::lighting
