// Internal: the vertex kernels of animated meshes, in structure-of-arrays batches.
//
//  - morph: out = base + sum_t w_t delta_t over the targets with a non-zero weight, in the
//    targets' order (one multiply and one add per target and value);
//  - skin: linear blend skinning, M = sum_k w_k J[joint_k] over 4 or 8 influences (3x4 joint
//    matrices), position M (p, 1), normal by M's cofactor matrix (its sign made det M's) or by M's
//    3x3 (NormalTransform), tangent by M's 3x3, both normalised (zero stays zero).
//
// Every path makes the same IEEE operations in the same order: the scalar twin (skin.cpp) and the
// per-ISA files (skin_{sse2,avx2,avx512}.cpp) are compiled with -ffp-contract=off and divide and
// take square roots correctly rounded, so their outputs are bit-identical on every ISA (tested:
// tests/skin_test.cpp), and an image of a skinned model is the same bytes on every machine.
// skin_reference (double) is the oracle for their accuracy.
#pragma once

#include <cstddef>
#include <cstdint>

#include "facet/animation.hpp"
#include "facet/lighting.hpp"

namespace facet::geometry {

struct MorphTarget {
  const float* delta[3] = {nullptr, nullptr, nullptr};  // x, y, z streams; all null: no delta of this kind
  float weight = 0.0f;
};

// out[c][i] = base[c][i] + sum_t targets[t].weight * targets[t].delta[c][i] for c < 3, i < count
// (targets whose delta[c] is null skipped). `out` may be `base`.
struct MorphJob {
  std::size_t count = 0;
  const float* base[3] = {};
  float* out[3] = {};
  const MorphTarget* targets = nullptr;
  std::size_t target_count = 0;
};

struct SkinJob {
  std::size_t count = 0;
  // Input streams (SoA): positions, and normals and tangents (xyz) when non-null.
  const float* position[3] = {};
  const float* normal[3] = {};
  const float* tangent[3] = {};
  int influences = 4;                    // 1 to 8 (1: a morphed mesh, renormalised through the identity)
  const std::uint16_t* joints = nullptr;  // joints[k * count + i] < joint_count
  const float* weights = nullptr;         // weights[k * count + i]
  const float* matrices = nullptr;        // 12 floats per joint: a 3x4 matrix by rows
  std::size_t joint_count = 0;
  NormalTransform normals = NormalTransform::cofactor;
  // Outputs, interleaved as facet::Mesh holds them: xyz triples (positions, normals) and xyzw
  // quadruples (tangents; w is not written).
  float* out_position = nullptr;
  float* out_normal = nullptr;
  float* out_tangent = nullptr;
};

void morph_scalar(const MorphJob& job);
void skin_scalar(const SkinJob& job);
// The same on the widest ISA `isa` allows (Isa::best: this CPU's).
void morph(const MorphJob& job, Isa isa);
void skin(const SkinJob& job, Isa isa);
// In double from double joint matrices (12 per joint), for tests and the accuracy chart.
void skin_reference(const SkinJob& job, const double* matrices, double* out_position, double* out_normal,
                    double* out_tangent);

namespace simd {
#define FACET_SKIN_ISA(isa)                  \
  namespace isa {                            \
  void morph(const MorphJob& job);           \
  void skin(const SkinJob& job);             \
  }
FACET_SKIN_ISA(sse2)
FACET_SKIN_ISA(avx2)
FACET_SKIN_ISA(avx512)
#undef FACET_SKIN_ISA
}  // namespace simd

}  // namespace facet::geometry
