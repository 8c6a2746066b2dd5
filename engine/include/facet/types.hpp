// Vocabulary types of the scene side (Eigen, array-of-structs, user-facing).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace facet {

using Vec2 = Eigen::Matrix<float, 2, 1, Eigen::DontAlign>;  // texture coordinates (u, v)
using Vec3 = Eigen::Vector3f;
using Color3 = Eigen::Vector3f;  // linear RGB; components may exceed 1 (light intensities)
using Vec4 = Eigen::Matrix<float, 4, 1, Eigen::DontAlign>;  // a tangent: xyz and the bitangent's sign w
// Unaligned on purpose: Eigen aligns fixed-size vectorisable types to the host's widest vector
// (16 bytes by default, 32 under -mavx, 64 under -mavx512f), so an aligned Matrix4f would give a
// host built with -mavx2 or -march=native another layout of every struct holding one than the
// library (built for baseline x86-64) has. Unaligned, the layout is the same for any flags.
using Mat4 = Eigen::Matrix<float, 4, 4, Eigen::DontAlign>;
static_assert(sizeof(Mat4) == 64 && alignof(Mat4) == 4, "facet::Mat4 must not depend on compiler flags");
static_assert(sizeof(Vec2) == 8 && alignof(Vec2) == 4, "facet::Vec2 must not depend on compiler flags");
static_assert(sizeof(Vec3) == 12 && alignof(Vec3) == 4, "facet::Vec3 must not depend on compiler flags");
static_assert(sizeof(Vec4) == 16 && alignof(Vec4) == 4, "facet::Vec4 must not depend on compiler flags");

}  // namespace facet
