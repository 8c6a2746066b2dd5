// The reference path: the lighting model in double precision with std::pow. The oracle of the tests.
#include "lighting/shade.hpp"

namespace facet::lighting {
template void light_mesh<double>(const ShadeParams<double>&, const EyeTransform<double>&, const Mesh&, bool, Color3*);
}  // namespace facet::lighting
