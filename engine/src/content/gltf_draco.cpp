// glTF 2.0 import: KHR_draco_mesh_compression, decoded by Debian's libdraco. The primitive's
// attributes then come from the Draco mesh (each named by its unique id in the extension), and
// its triangles from the Draco faces; the glTF accessors only describe them.
#include <draco/compression/decode.h>

#include "common/format.hpp"
#include "common/try.hpp"
#include "content/gltf_reader.hpp"

namespace facet::gltf {

Status Reader::draco_attributes(const Json& ext, const std::string& p, const std::map<std::string, int>& attributes,
                                std::map<std::string, Values>& values, std::vector<std::uint32_t>& indices) {
  FACET_TRY(f_.object(ext, p));
  int view = -1;
  FACET_TRY(f_.index(ext, p, "bufferView", doc_.view_count(), view, true));
  const Json* ids = nullptr;
  FACET_TRY(f_.object(ext, p, "attributes", ids));
  if (!ids) return f_.error(p + ".attributes", "required, missing");
  const View& v = doc_.view(static_cast<std::size_t>(view));
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(v.data), v.length);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) {
    return f_.error(p, "the Draco data cannot be decoded (" + quote(decoded.status().error_msg_string(), 120) + ")");
  }
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) return f_.error(p, "the Draco data holds no mesh");
  const std::size_t points = mesh->num_points(), faces = mesh->num_faces();
  FACET_TRY(reserve(std::uint64_t(faces) * 12, p));
  for (const char* name : {"POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "TANGENT"}) {
    if (!attributes.count(name)) continue;
    int id = -1;
    FACET_TRY(f_.index(*ids, p + ".attributes", name, 1u << 30, id, false));
    if (id < 0) {
      return f_.error(p + ".attributes." + name, "the primitive has this attribute, so the Draco extension must name it");
    }
    const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id));
    if (!a) return f_.error(p + ".attributes." + name, "no attribute with unique id " + std::to_string(id) + " in the Draco data");
    const std::string n = name;
    const int want = n == "TEXCOORD_0" || n == "TEXCOORD_1" ? 2 : n == "COLOR_0" ? (a->num_components() == 4 ? 4 : 3) : n == "TANGENT" ? 4 : 3;
    if (a->num_components() != want || (want != 2 && want != 3 && want != 4)) {
      return f_.error(p + ".attributes." + name, "the Draco attribute has " + std::to_string(a->num_components()) + " components");
    }
    FACET_TRY(reserve(std::uint64_t(points) * std::uint64_t(want) * 8, p + ".attributes." + name));
    Values& out = values[name];
    out.components = want;
    out.v.resize(points * std::size_t(want));
    float tmp[4];
    for (std::size_t i = 0; i < points; ++i) {
      const draco::AttributeValueIndex vi = a->mapped_index(draco::PointIndex(static_cast<std::uint32_t>(i)));
      if (!a->ConvertValue<float>(vi, static_cast<std::int8_t>(want), tmp)) {
        return f_.error(p + ".attributes." + name, "a Draco value cannot be read as numbers");
      }
      for (int c = 0; c < want; ++c) out.v[i * std::size_t(want) + std::size_t(c)] = tmp[c];
    }
    for (double x : out.v)
      if (!std::isfinite(x) || std::abs(x) > 3.0e38) return f_.error(p + ".attributes." + name, "holds a value that is not a finite float");
  }
  indices.resize(faces * 3);
  for (std::size_t i = 0; i < faces; ++i) {
    const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(static_cast<std::uint32_t>(i)));
    for (int c = 0; c < 3; ++c) indices[3 * i + std::size_t(c)] = face[c].value();
  }
  return {};
}

}  // namespace facet::gltf
