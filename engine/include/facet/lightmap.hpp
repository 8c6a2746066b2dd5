// Lightmap texture coordinates: a mesh cut into planar charts, each laid flat at a chosen texel
// density and packed into one atlas with padding between charts, so that every triangle owns its
// own texels (a lightmap needs that; a material's uvs may repeat or mirror). docs/baking.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "facet/mesh.hpp"
#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

struct Scene;

struct LightmapUvOptions {
  // Texels per unit of length in the mesh's own coordinates (the object's scale is the caller's).
  double texels_per_unit = 16.0;
  // Empty texels between any two charts and between a chart and the atlas's edge: at least 1 so
  // that bilinear filtering never mixes two charts; 2 (the default) also leaves room to dilate.
  int padding = 2;
  // A triangle joins a chart (grown across shared edges) when its normal is within this angle of
  // the chart's first triangle's normal; degrees in (0, 90).
  double chart_angle_deg = 45.0;
  // Largest atlas side in texels; a mesh that needs more at this density is refused before any
  // memory is allocated for the atlas.
  int max_size = 8192;
};

// The result: a new vertex list (the input's vertices, split where charts meet), the input's
// triangles over it in the same order, and a lightmap uv per new vertex.
struct LightmapUnwrap {
  int width = 0, height = 0;                                // the atlas, in texels
  std::vector<std::uint32_t> source_vertex;                 // per new vertex: the input vertex it copies
  std::vector<std::array<std::uint32_t, 3>> triangles;      // per input triangle, over the new vertices
  std::vector<Vec2> uvs;                                    // per new vertex; (0, 0) the atlas's bottom-left corner
  std::vector<std::uint32_t> chart_of_triangle;             // per triangle: its chart
  // Per chart: its texels, [x0, x0 + w) x [y0, y0 + h); every texel a triangle of the chart
  // touches lies inside, and no two charts' rectangles come closer than `padding` texels.
  struct Chart {
    int x0 = 0, y0 = 0, w = 0, h = 0;
  };
  std::vector<Chart> charts;
};

// Cuts `mesh` into charts and packs them (docs/baking.md: how charts grow, how they are laid flat
// and packed, and the density each triangle gets: between cos(chart_angle_deg) and 1 times the
// requested texels per unit of area). Triangles of zero area share one chart of one texel. Errors:
// an invalid mesh or option (the field named), an atlas larger than max_size (the size it would
// need and the density that would fit).
Result<LightmapUnwrap> unwrap_lightmap(const Mesh& mesh, const LightmapUvOptions& options = {});

// Whether scene.objects[object] can carry a lightmap: not with vertex colours, nor with a material
// (or any of its per-face materials) that has an environment, normal or bump map, or a texture
// environment other than modulate (the error, on objects[i].lightmap, names which). What
// validate_scene asks of a lightmapped object, and bake_lightmaps of every object before any work.
Status check_lightmap_object(const Scene& scene, std::size_t object);

// `mesh` placed by `model` (positions through the matrix in double, rounded to float; normals
// through its inverse transpose, unit length): what bake_lightmaps unwraps and lights, so that
// unwrap_lightmap(world_space_mesh(mesh, model), options) gives the charts a bake made.
Mesh world_space_mesh(const Mesh& mesh, const Mat4& model);

// `mesh` split as `unwrap` splits it (every per-vertex array copied from its source vertex, the
// triangles and material groups kept), with the unwrap's uvs as its lightmap_uvs. `unwrap` must
// come from this mesh (or its world_space_mesh): the triangle counts must match.
Result<Mesh> with_lightmap_uvs(const Mesh& mesh, const LightmapUnwrap& unwrap);

// An atlas over the lightmap coordinates a mesh brings (Mesh::lightmap_uvs, a glTF's TEXCOORD_1)
// instead of generated charts: the vertices and triangles as they are, one chart over the whole
// atlas, and a square atlas whose side gives `texels_per_unit` on average (the side n with
// n^2 x the uv area the triangles cover = texels_per_unit^2 x their area in `mesh`, which should
// be in world space), at most max_size. Coordinates that overlap share texels. Errors: a mesh
// without lightmap_uvs or with any outside [0, 1] (the vertex named), an invalid mesh or option,
// a side over max_size (the density that fits).
Result<LightmapUnwrap> lightmap_from_mesh_uvs(const Mesh& mesh, double texels_per_unit, int max_size);

}  // namespace facet
