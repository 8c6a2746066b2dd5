// Test helper: writes glTF 2.0 files (embedded, with an external .bin, or .glb) from arrays, so
// that tests and fuzz seeds need no binary files in the repository.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace facet::test {

inline std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 | (unsigned char)bytes[i + 2];
    out += k[v >> 18], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += k[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16;
    out += k[v >> 18], out += k[(v >> 12) & 63], out += "==";
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += k[v >> 18], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += '=';
  }
  return out;
}

struct GltfBuilder {
  nlohmann::json doc = {{"asset", {{"version", "2.0"}}}};
  std::string bin;

  // Appends raw bytes as a buffer view (4-byte aligned); returns its index.
  int view(const void* data, std::size_t bytes, int stride = 0) {
    while (bin.size() % 4) bin.push_back('\0');
    nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (stride) v["byteStride"] = stride;
    bin.append(static_cast<const char*>(data), bytes);
    doc["bufferViews"].push_back(v);
    return int(doc["bufferViews"].size()) - 1;
  }
  int accessor(int view_index, int component_type, std::size_t count, const char* type, bool normalized = false,
               std::size_t offset = 0) {
    nlohmann::json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
    if (view_index >= 0) a["bufferView"] = view_index;
    if (offset) a["byteOffset"] = offset;
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(a);
    return int(doc["accessors"].size()) - 1;
  }
  int floats(const std::vector<float>& v, const char* type, int per) {
    return accessor(view(v.data(), v.size() * 4), 5126, v.size() / std::size_t(per), type);
  }
  int vec3(const std::vector<float>& v) { return floats(v, "VEC3", 3); }
  int vec2(const std::vector<float>& v) { return floats(v, "VEC2", 2); }
  int vec4(const std::vector<float>& v) { return floats(v, "VEC4", 4); }
  int indices16(const std::vector<std::uint16_t>& v) { return accessor(view(v.data(), v.size() * 2), 5123, v.size(), "SCALAR"); }
  int indices32(const std::vector<std::uint32_t>& v) { return accessor(view(v.data(), v.size() * 4), 5125, v.size(), "SCALAR"); }

  int add(const char* array, nlohmann::json value) {
    doc[array].push_back(std::move(value));
    return int(doc[array].size()) - 1;
  }

  nlohmann::json with_buffer(const std::string& uri) const {
    nlohmann::json d = doc;
    if (bin.empty()) return d;
    d["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
    if (!uri.empty()) d["buffers"][0]["uri"] = uri;
    return d;
  }
  std::string embedded() const { return with_buffer("data:application/octet-stream;base64," + base64(bin)).dump(2); }
  std::string external(const std::string& bin_name) const { return with_buffer(bin_name).dump(2); }
  std::string glb() const { return glb_of(with_buffer("").dump(), bin); }
  // A .glb container of this JSON text and binary chunk.
  static std::string glb_of(std::string json, const std::string& bin) {
    while (json.size() % 4) json.push_back(' ');
    std::string body = bin;
    while (body.size() % 4) body.push_back('\0');
    std::string out;
    const bool has_bin = !body.empty();
    auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67u);  // "glTF"
    u32(2);
    u32(std::uint32_t(12 + 8 + json.size() + (has_bin ? 8 + body.size() : 0)));
    u32(std::uint32_t(json.size()));
    u32(0x4E4F534Au);  // JSON
    out += json;
    if (!has_bin) return out;
    u32(std::uint32_t(body.size()));
    u32(0x004E4942u);  // BIN
    out += body;
    return out;
  }
};

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

// A unit quad in z = 0 (two triangles), for the glTF tests.
inline const std::vector<float> kQuadPositions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
inline const std::vector<std::uint16_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

inline GltfBuilder quad() {
  GltfBuilder b;
  const int pos = b.vec3(kQuadPositions);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", b.indices16(kQuadIndices)}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.add("scenes", {{"nodes", {0}}});
  return b;
}

}  // namespace facet::test
