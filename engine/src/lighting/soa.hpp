// Internal: array-of-structures <-> structure-of-arrays conversion for the lighting streams, and
// the bounding-radius pass, written with SSE2 shuffles (the x86-64 baseline). Out of line in a
// baseline file on purpose: an inline copy could be merged with one compiled under AVX flags
// (an inline function compiled into files with different ISA flags is merged by the linker, and the wider copy may run on a CPU without it).
#pragma once

#include <cstddef>
#include <cstdint>

#include "facet/mesh.hpp"

namespace facet::lighting {

// x[i] = scale * src[i].x() (and y, z) for i < n.
void deinterleave3(const Vec3* src, std::size_t n, float scale, float* x, float* y, float* z);

// dst[i] = (x[i], y[i], z[i]) for i < n.
void interleave3(const float* x, const float* y, const float* z, std::size_t n, Vec3* dst);

// The same through an index: x[i] = scale * src[index[i]].x(), and dst[index[i]] = (x[i], y[i], z[i]).
void deinterleave3(const Vec3* src, const std::uint32_t* index, std::size_t n, float scale, float* x, float* y,
                   float* z);
void interleave3(const float* x, const float* y, const float* z, std::size_t n, const std::uint32_t* index, Vec3* dst);

// Largest (p - c)^2 over the points, computed in float. NaN points are left out; an infinite
// coordinate, or a difference too large to square in float, gives +Inf.
float farthest_squared_float(const Vec3* p, std::size_t n, const float c[3]);

}  // namespace facet::lighting
