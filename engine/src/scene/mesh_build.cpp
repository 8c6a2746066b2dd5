// Mesh validation and construction from caller arrays.
#include <cmath>
#include <limits>
#include <string>

#include "common/format.hpp"
#include "facet/mesh.hpp"
#include "scene/validate.hpp"

namespace facet {

bool mesh_is_valid(const Mesh& mesh) noexcept {
  const std::size_t n = mesh.positions.size();
  if (n > std::numeric_limits<std::uint32_t>::max() || mesh.normals.size() != n) return false;
  for (const auto& t : mesh.triangles)
    if (t[0] >= n || t[1] >= n || t[2] >= n) return false;
  return true;
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
