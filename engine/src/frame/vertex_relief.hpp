// Internal: per-vertex relief (RenderOptions::vertex_relief). Gouraud shading lights the vertex
// normals; with the option, a normal- or bump-mapped draw lights each vertex with its normal
// perturbed as a pixel's is (pixel/stages.hpp, pixel_normal), the maps read at the vertex's
// texture coordinates with one level of detail for the whole mesh: the level whose texels are
// about the size of the mesh's triangles, so that the vertices sample the map prefiltered to
// their own spacing instead of aliasing level 0 (trilinear maps only; others read level 0).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "facet/mesh.hpp"
#include "facet/material.hpp"
#include "texture/sampler.hpp"

namespace facet::frame {

struct VertexRelief {
  const texture::Sampler* normal_map = nullptr;
  const texture::Sampler* bump_map = nullptr;
  float normal_scale = 1.0f, bump_scale = 1.0f;
  float bump_du = 0.0f, bump_dv = 0.0f;  // one level-0 texel of the bump map
  float uv_scale[2] = {1.0f, 1.0f};
  float lod = 0.0f;
};

// lambda for a mesh whose triangles cover `texels` texels of level 0 each on average: a triangle
// is about half a square of side sqrt(2 texels); the level whose texels are half that side, so
// that two texels span a vertex spacing (level 0 for meshes finer than that). Relief finer than
// the vertices is averaged away rather than point-sampled into noise; one level coarser blurred
// more than it removed (measured in docs/relief.md).
inline float vertex_relief_lod(const Mesh& mesh, const texture::Sampler& map, const float (&uv_scale)[2]) {
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec2 &a = mesh.uvs[t[0]], &b = mesh.uvs[t[1]], &c = mesh.uvs[t[2]];
    area += 0.5 * std::abs(double(b.x() - a.x()) * double(c.y() - a.y()) - double(c.x() - a.x()) * double(b.y() - a.y()));
  }
  if (mesh.triangles.empty()) return 0.0f;
  const double texels = area * std::abs(double(uv_scale[0]) * uv_scale[1]) * double(map.lod_width) * map.lod_height /
                        static_cast<double>(mesh.triangles.size());
  const double lod = texels > 2.0 ? 0.5 * std::log2(0.5 * texels) : 0.0;
  return static_cast<float>(std::clamp(lod, 0.0, 30.0));
}

// Vertex i's object-space normal perturbed by the maps (normalised; the unperturbed normal where
// the result has no length or is not finite).
inline Vec3 vertex_relief_normal(const VertexRelief& r, const Mesh& mesh, std::size_t i) {
  const Vec3& n = mesh.normals[i];
  const Vec4& t4 = mesh.tangents[i];
  const Vec3 t = t4.head<3>();
  const Vec3 b = t4.w() * n.cross(t);
  const float s = mesh.uvs[i].x() * r.uv_scale[0], v = mesh.uvs[i].y() * r.uv_scale[1];
  float mx = 0.0f, my = 0.0f, mz = 1.0f;
  if (r.normal_map) {
    const auto rgba = texture::sample_scalar(*r.normal_map, s, v, r.lod);
    mx = (2.0f * rgba[0] - 1.0f) * r.normal_scale, my = (2.0f * rgba[1] - 1.0f) * r.normal_scale;
    mz = 2.0f * rgba[2] - 1.0f;
  }
  if (r.bump_map) {
    const float h0 = texture::sample_scalar(*r.bump_map, s, v, r.lod)[0];
    const float hu = texture::sample_scalar(*r.bump_map, s + r.bump_du, v, r.lod)[0];
    const float hv = texture::sample_scalar(*r.bump_map, s, v + r.bump_dv, r.lod)[0];
    mx -= r.bump_scale * (hu - h0), my -= r.bump_scale * (hv - h0);
  }
  const Vec3 p = mx * t + my * b + mz * n;
  const float len = p.norm();
  return std::isfinite(len) && len > 0.0f ? Vec3(p / len) : n;
}

}  // namespace facet::frame
