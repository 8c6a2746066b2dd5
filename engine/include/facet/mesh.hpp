// Triangle meshes: positions, per-vertex normals, counter-clockwise triangles (front faces wind
// counter-clockwise seen from outside, as in OpenGL), and optionally texture coordinates, vertex
// colours and material groups. Built from caller arrays, procedural shapes or Wavefront OBJ. A
// Mesh owns its data; a valid mesh has one normal per position, no or one uv and colour per
// position, every index < vertex_count() and groups that cover its triangles in order.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

inline constexpr float kDefaultCreaseAngleDeg = 60.0f;

// A run of triangles drawn with one material, named as the scene's materials are (OBJ `usemtl`).
struct MaterialGroup {
  std::string material;
  std::uint32_t first_triangle = 0;
  std::uint32_t triangle_count = 0;
};

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // unit length, or zero where no normal can be defined
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // Optional per-vertex data: empty, or one entry per position.
  std::vector<Vec2> uvs;        // texture coordinates; (0, 0) is the image's bottom-left corner, as in GL
  std::vector<Color3> colors;   // linear RGB in [0, 1]; replaces the material's ambient and diffuse colour
  // Tangent space for normal maps (glTF TANGENT): xyz the direction of increasing u, finite; w = +1
  // or -1, the bitangent being w cross(normal, xyz) (the direction of increasing v). Made by
  // generate_tangents when a file gives none.
  std::vector<Vec4> tangents;
  // Lightmap coordinates (a second uv set: glTF TEXCOORD_1, or made by unwrap_lightmap), finite;
  // read by an object with a lightmap (Instance::lightmap).
  std::vector<Vec2> lightmap_uvs;
  // Optional: empty (the object's material for every triangle), or consecutive runs that cover
  // every triangle in order. An object chooses whether to use them (scene.hpp, Object::materials).
  std::vector<MaterialGroup> groups;

  std::size_t vertex_count() const noexcept { return positions.size(); }
  std::size_t triangle_count() const noexcept { return triangles.size(); }
};

// Checks sizes, indices and finiteness. `field` prefixes the error's field name.
Status validate_mesh(const Mesh& mesh, const std::string& field = "mesh");

// From caller arrays: xyz triples and index triples. `normals_xyz` may be empty: then normals are
// computed with compute_vertex_normals(crease_angle_deg), which may split vertices along creases.
Result<Mesh> mesh_from_arrays(std::span<const float> positions_xyz, std::span<const float> normals_xyz,
                              std::span<const std::uint32_t> indices,
                              float crease_angle_deg = kDefaultCreaseAngleDeg);

// Vertex normals from the faces: at each corner, the angle-weighted average of the normals of the
// faces around that vertex whose normal lies within `crease_angle_deg` of the corner's own face.
// Corners of one vertex that end with different normals get separate vertices, so edges sharper
// than the crease angle stay hard. Positions that are bit-identical are treated as one vertex (so
// the seams of a UV-mapped mesh are smoothed). Degenerate triangles get no weight; a vertex with
// no usable face gets a zero normal. Triangles and their winding are kept; `normals` is replaced.
// `origin`, when given, holds one entry per vertex on entry; each vertex added by a split gets
// the entry of the vertex it copies (the identity 0..n-1 tells which input vertex each comes from).
void compute_vertex_normals(Mesh& mesh, float crease_angle_deg = kDefaultCreaseAngleDeg,
                            std::vector<std::uint32_t>* origin = nullptr);

// Tangents by the MikkTSpace algorithm (Mikkelsen 2008, the tangent space of glTF and Blender's
// bakers): per triangle the direction of increasing u in the plane of its positions, and the sign
// of its uv area (w); at each corner that direction projected into the plane of the vertex's
// normal and normalised; per vertex the sum over its corners of one orientation, weighted by the
// corner's angle, normalised. A vertex whose corners have both orientations (a mirrored UV seam
// through it) is split in two, as compute_vertex_normals splits creases. Triangles with a
// degenerate uv area or positions contribute nothing; a vertex left with no direction gets one
// perpendicular to its normal (any: its normal map then has no defined orientation). Needs uvs;
// `tangents` is replaced (triangles may be re-indexed, their order and winding kept). `origin`:
// as compute_vertex_normals's.
Status generate_tangents(Mesh& mesh, std::vector<std::uint32_t>* origin = nullptr);

// Procedural shapes, centred on the origin. Tessellation arguments are clamped to their minimum
// (noted per shape) and to 4096 per axis.
// Every shape has texture coordinates: sphere u = longitude / 360 deg from +x, counter-clockwise
// seen from +y, v = 1 at the north pole to 0 at the south pole; cube 0..1 across each face; plane
// 0..1 along +x and along -z; torus u around the y axis, v around the tube. Seams carry two
// vertices (u = 0 and u = 1).
Mesh make_uv_sphere(float radius, int segments, int rings);       // segments >= 3, rings >= 2; exact normals
Mesh make_cube(float size, int subdivisions);                     // subdivisions >= 1 per edge; face normals
Mesh make_plane(float size_x, float size_z, int subdivisions);    // in y = 0, normal +y
Mesh make_disc(float radius, int segments);                        // in y = 0, normal +y, a fan of segments >= 3
Mesh make_torus(float major_radius, float minor_radius, int segments, int sides);  // around y

// The memory a load may use unless told otherwise (LoadOptions, ObjOptions): 4 GiB.
inline constexpr std::uint64_t kDefaultLoadBudgetBytes = std::uint64_t{4} << 30;

struct ObjOptions {
  // Used when the file has no `vn` normals (or not for every corner).
  float crease_angle_deg = kDefaultCreaseAngleDeg;
  // load_obj refuses a file larger than this (ErrorCode::out_of_memory) before reading it, and a
  // mesh whose arrays would exceed it. 0 = no limit.
  std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes;
};

// Wavefront OBJ through tinyobjloader: polygons of any corner count are triangulated as fans from
// their first corner, `v`, `v/vt`, `v//vn`, `v/vt/vn` and negative (relative) indices are
// accepted, and all groups/objects are merged into one mesh. Texture coordinates (`vt u [v]`,
// when every corner has one), vertex colours (`v x y z r g b` on every `v` line, in [0, 1]) and
// `usemtl` runs (Mesh::groups, named by material; `mtllib` files are not read: the scene names
// the materials) are kept. Every number
// is read by facet (correctly rounded); NaN, infinities and values outside a float's range are
// errors. Errors name the file and line. Only regular files are read (not FIFOs or devices).
Result<Mesh> load_obj(const std::string& path, const ObjOptions& options = {});
// The same from text in memory; `source_name` is used in messages.
Result<Mesh> parse_obj(const std::string& text, const std::string& source_name,
                       const ObjOptions& options = {});

}  // namespace facet
