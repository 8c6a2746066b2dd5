// Internal: per-frame set-up of the lighting kernels. Everything here is computed in double from
// the scene's float data and then rounded once to the kernel's precision T.
#pragma once

#include <Eigen/Core>

#include "facet/lighting.hpp"
#include "facet/scene.hpp"
#include "lighting/shade.hpp"

namespace facet::lighting {

template <class T>
ShadeParams<T> make_shade_params(const Scene& scene, const Eigen::Matrix4d& view, const Material& material,
                                 bool clamp);

template <class T>
EyeTransform<T> make_eye_transform(const Eigen::Matrix4d& view, const Mat4& model);

}  // namespace facet::lighting
