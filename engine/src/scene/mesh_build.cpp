// Mesh validation and construction from caller arrays.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "common/format.hpp"
#include "facet/mesh.hpp"
#include "scene/validate.hpp"

namespace facet {

// The fast check of validate_mesh: the same verdict (tested), as reductions without branches that
// the compiler vectorizes, because it runs on every mesh of every frame.
namespace {

std::uint32_t float_bits(float f) noexcept { return std::bit_cast<std::uint32_t>(f); }

// 1 when f is not finite (its exponent all ones), else 0.
std::uint32_t not_finite(float f) noexcept { return (float_bits(f) & 0x7f800000u) == 0x7f800000u; }

// 1 when f is outside [0, 1] or NaN. For non-negative floats the bit patterns order as the values
// do, and every negative float (but -0, mapped to +0) and every NaN has a pattern above 1.0's.
std::uint32_t outside_unit(float f) noexcept {
  const std::uint32_t b = float_bits(f);
  return (b == 0x80000000u ? 0u : b) > 0x3f800000u;
}

}  // namespace

bool mesh_is_valid(const Mesh& mesh) noexcept {
  const std::size_t n = mesh.positions.size();
  if (n > std::numeric_limits<std::uint32_t>::max() || mesh.normals.size() != n) return false;
  if ((!mesh.uvs.empty() && mesh.uvs.size() != n) || (!mesh.colors.empty() && mesh.colors.size() != n) ||
      (!mesh.tangents.empty() && mesh.tangents.size() != n) || (!mesh.lightmap_uvs.empty() && mesh.lightmap_uvs.size() != n)) {
    return false;
  }
  std::uint32_t bad = 0;
  for (const Vec4& t : mesh.tangents) {
    bad |= not_finite(t.x()) | not_finite(t.y()) | not_finite(t.z());
    bad |= (float_bits(t.w()) & 0x7fffffffu) != 0x3f800000u;  // w is 1 or -1
  }
  for (const Vec2& uv : mesh.uvs) bad |= not_finite(uv.x()) | not_finite(uv.y());
  for (const Vec2& uv : mesh.lightmap_uvs) bad |= not_finite(uv.x()) | not_finite(uv.y());
  for (const Color3& c : mesh.colors) bad |= outside_unit(c.x()) | outside_unit(c.y()) | outside_unit(c.z());
  if (bad) return false;
  std::uint64_t covered = 0;
  for (const MaterialGroup& g : mesh.groups) {
    if (g.first_triangle != covered || g.triangle_count == 0) return false;
    covered += g.triangle_count;
  }
  if (!mesh.groups.empty() && covered != mesh.triangles.size()) return false;
  // The indices as one flat array, so that the loop is a plain vectorizable reduction.
  static_assert(sizeof(mesh.triangles[0]) == 3 * sizeof(std::uint32_t));
  const std::uint32_t* index = mesh.triangles.empty() ? nullptr : mesh.triangles.data()->data();
  const std::size_t count = 3 * mesh.triangles.size();
  const auto vertices = static_cast<std::uint32_t>(n);
  for (std::size_t i = 0; i < count; ++i) bad |= index[i] >= vertices;
  return bad == 0;
}

Status validate_mesh(const Mesh& mesh, const std::string& field) {
  const std::size_t n = mesh.positions.size();
  if (n > std::numeric_limits<std::uint32_t>::max()) {
    return {ErrorCode::invalid_argument, field + ".positions",
            field + ".positions: " + std::to_string(n) + " vertices exceed the 32-bit index range"};
  }
  if (mesh.normals.size() != n) {
    return {ErrorCode::invalid_argument, field + ".normals",
            field + ".normals: expected one normal per position (" + std::to_string(n) + "), found " +
                std::to_string(mesh.normals.size())};
  }
  auto per_vertex = [&](const char* name, std::size_t size) -> Status {
    if (size == 0 || size == n) return {};
    const std::string f = field + "." + name;
    return {ErrorCode::invalid_argument, f,
            f + ": expected none or one per position (" + std::to_string(n) + "), found " + std::to_string(size)};
  };
  if (Status s = per_vertex("uvs", mesh.uvs.size()); !s.ok()) return s;
  if (Status s = per_vertex("colors", mesh.colors.size()); !s.ok()) return s;
  if (Status s = per_vertex("tangents", mesh.tangents.size()); !s.ok()) return s;
  if (Status s = per_vertex("lightmap_uvs", mesh.lightmap_uvs.size()); !s.ok()) return s;
  for (std::size_t i = 0; i < mesh.tangents.size(); ++i) {
    const Vec4& t = mesh.tangents[i];
    if (!t.allFinite() || (t.w() != 1.0f && t.w() != -1.0f)) {
      const std::string f = field + ".tangents[" + std::to_string(i) + "]";
      return {ErrorCode::invalid_argument, f, f + ": expected a finite direction and w = 1 or -1"};
    }
  }
  for (std::size_t i = 0; i < mesh.uvs.size(); ++i) {
    if (!mesh.uvs[i].allFinite()) {
      const std::string f = field + ".uvs[" + std::to_string(i) + "]";
      return {ErrorCode::invalid_argument, f, f + ": texture coordinates must be finite"};
    }
  }
  for (std::size_t i = 0; i < mesh.lightmap_uvs.size(); ++i) {
    if (!mesh.lightmap_uvs[i].allFinite()) {
      const std::string f = field + ".lightmap_uvs[" + std::to_string(i) + "]";
      return {ErrorCode::invalid_argument, f, f + ": lightmap coordinates must be finite"};
    }
  }
  for (std::size_t i = 0; i < mesh.colors.size(); ++i) {
    const Color3& c = mesh.colors[i];
    if (!(c.minCoeff() >= 0.0f && c.maxCoeff() <= 1.0f)) {  // NaN fails both
      const std::string f = field + ".colors[" + std::to_string(i) + "]";
      return {ErrorCode::invalid_argument, f,
              f + ": expected components in [0, 1], found (" + format_number(c[0]) + ", " + format_number(c[1]) + ", " +
                  format_number(c[2]) + ")"};
    }
  }
  std::uint64_t covered = 0;
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    const MaterialGroup& group = mesh.groups[g];
    if (group.first_triangle != covered || group.triangle_count == 0) {
      const std::string f = field + ".groups[" + std::to_string(g) + "]";
      return {ErrorCode::invalid_argument, f,
              f + ": groups must be non-empty runs that cover the triangles in order (expected first_triangle " +
                  std::to_string(covered) + ", found " + std::to_string(group.first_triangle) + " with " +
                  std::to_string(group.triangle_count) + " triangles)"};
    }
    covered += group.triangle_count;
  }
  if (!mesh.groups.empty() && covered != mesh.triangles.size()) {
    const std::string f = field + ".groups";
    return {ErrorCode::invalid_argument, f,
            f + ": the groups cover " + std::to_string(covered) + " triangles, the mesh has " +
                std::to_string(mesh.triangles.size())};
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::uint32_t index : mesh.triangles[t]) {
      if (index >= n) {
        const std::string f = field + ".triangles[" + std::to_string(t) + "]";
        return {ErrorCode::invalid_argument, f,
                f + ": index " + std::to_string(index) + " is out of range (" + std::to_string(n) + " vertices)"};
      }
    }
  }
  return {};
}

Result<Mesh> mesh_from_arrays(std::span<const float> positions_xyz, std::span<const float> normals_xyz,
                              std::span<const std::uint32_t> indices, float crease_angle_deg) {
  auto fail = [](const char* field, std::string what) {
    return Status{ErrorCode::invalid_argument, field, std::string(field) + ": " + what};
  };
  if (positions_xyz.size() % 3 != 0) {
    return fail("positions", "expected xyz triples, found " + std::to_string(positions_xyz.size()) + " floats");
  }
  if (indices.size() % 3 != 0) {
    return fail("indices", "expected index triples, found " + std::to_string(indices.size()) + " indices");
  }
  if (!normals_xyz.empty() && normals_xyz.size() != positions_xyz.size()) {
    return fail("normals", "expected none or one xyz triple per position (" + std::to_string(positions_xyz.size()) +
                               " floats), found " + std::to_string(normals_xyz.size()));
  }
  if (!(crease_angle_deg >= 0.0f && crease_angle_deg <= 180.0f)) {
    return fail("crease_angle_deg", "expected a number in [0, 180], found " + format_number(crease_angle_deg));
  }
  Mesh mesh;
  const std::size_t n = positions_xyz.size() / 3;
  mesh.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    mesh.positions[i] = Vec3(positions_xyz[3 * i], positions_xyz[3 * i + 1], positions_xyz[3 * i + 2]);
  }
  mesh.triangles.resize(indices.size() / 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    mesh.triangles[t] = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
  }
  if (normals_xyz.empty()) {
    mesh.normals.assign(n, Vec3::Zero());  // sized so validation can run before the normals exist
  } else {
    mesh.normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 v(normals_xyz[3 * i], normals_xyz[3 * i + 1], normals_xyz[3 * i + 2]);
      const float len = v.norm();
      mesh.normals[i] = (len > 0.0f && std::isfinite(len)) ? Vec3(v / len) : Vec3::Zero();
    }
  }
  if (Status s = validate_mesh(mesh, "mesh"); !s.ok()) {
    return Status{s.code(), "indices", "indices: " + s.message()};
  }
  if (normals_xyz.empty()) compute_vertex_normals(mesh, crease_angle_deg);
  return mesh;
}

}  // namespace facet
