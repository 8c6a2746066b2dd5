// glTF 2.0 import. tinygltf parses the JSON (or the .glb container) and loads buffers and images
// through facet's own file callbacks (regular files only, one memory budget for all of them, no
// `~` expansion or environment look-ups); images are kept as bytes and decoded by facet's decoder
// (texture.hpp) with its limits. Every index, accessor and buffer range is checked here before it
// is used, and errors name the JSON path. docs/content.md documents the mapping onto facet's model.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "common/format.hpp"
#include "common/try.hpp"
#include "content/import.hpp"
#include "facet/model.hpp"
#include "io/file_access.hpp"

namespace facet {
namespace {

constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123, kUnsignedInt = 5125,
              kFloat = 5126;

// The extensions facet reads; any other that a file requires is an error, any other it uses a warning.
constexpr const char* kSupportedExtensions[] = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                                                "KHR_materials_unlit"};

bool supported_extension(const std::string& name) {
  for (const char* s : kSupportedExtensions)
    if (name == s) return true;
  return false;
}

// tinygltf's file callbacks: regular files only, every byte counted against one budget.
struct FileState {
  std::string dir;           // files are read from this folder only (tinygltf also tries ".")
  std::uint64_t budget = 0;  // 0 = no limit
  std::uint64_t used = 0;
  ErrorCode failure = ErrorCode::ok;  // the first failed read's category (tinygltf only keeps text)
};

bool fs_exists(const std::string& path, void* user) {
  const std::string& dir = static_cast<const FileState*>(user)->dir;
  if (path.compare(0, dir.size(), dir) != 0) return false;  // not "./name" for a file beside the glTF
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}
std::string fs_expand(const std::string& path, void*) { return path; }
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* state = static_cast<FileState*>(user);
  const std::uint64_t left = state->budget == 0 ? io::kNoSizeLimit : state->budget - std::min(state->budget, state->used);
  Result<std::string> bytes = io::read_file(path, "glTF resource", left);
  if (!bytes) {
    if (state->failure == ErrorCode::ok) state->failure = bytes.status().code();
    if (err) *err = bytes.status().message();
    return false;
  }
  state->used += bytes->size();
  try {
    out->assign(bytes->begin(), bytes->end());
  } catch (const std::bad_alloc&) {
    if (state->failure == ErrorCode::ok) state->failure = ErrorCode::out_of_memory;
    if (err) *err = "out of memory";
    return false;
  }
  return true;
}
bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "facet never writes through tinygltf";
  return false;
}
// Keeps the encoded bytes; facet decodes them later, only the images a material uses. An image in
// a bufferView is not read here: tinygltf 2.7 hands over the view's range without checking it
// against its buffer (found by fuzz_gltf: a .glb whose BIN chunk is shorter than the view), so
// those bytes are read later, from views checked against their buffers.
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0) return true;
  image->image.assign(bytes, bytes + size);
  image->width = image->height = image->component = 0;
  return true;
}

std::string idx(const char* array, std::size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

// When tinygltf refuses a file its message may not say where: the JSON is read again here to name
// the line of a syntax error, or the path of the references tinygltf checks without naming them.
std::string locate_failure(std::span<const std::uint8_t> bytes) {
  std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::optional<std::uint64_t> bin_chunk;  // .glb: the BIN chunk's length, if there is one
  if (bytes.size() >= 20 && std::memcmp(bytes.data(), "glTF", 4) == 0) {  // .glb: the JSON chunk
    std::uint32_t length = 0, type = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    std::memcpy(&type, bytes.data() + 16, 4);
    if (type != 0x4E4F534Au || length > bytes.size() - 20) return "the .glb container's JSON chunk is malformed";
    text = text.substr(20, length);
    const std::size_t bin_at = 20 + std::size_t(length);
    if (bytes.size() >= bin_at + 8) {
      std::uint32_t bin_length = 0;
      std::memcpy(&bin_length, bytes.data() + bin_at, 4);
      bin_chunk = std::min<std::uint64_t>(bin_length, bytes.size() - bin_at - 8);
    }
  }
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_discarded()) {
    try {
      const nlohmann::json again = nlohmann::json::parse(text);
      (void)again;
    } catch (const nlohmann::json::parse_error& e) {
      const std::size_t at = std::min<std::size_t>(e.byte, text.size());
      const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
      return "line " + std::to_string(line) + ": not valid JSON";
    } catch (...) {
    }
    return "not valid JSON";
  }
  if (!doc.is_object()) return "the document is not a JSON object";
  // Buffers shorter than their byteLength: a data URI's bytes, or the .glb's BIN chunk.
  if (doc.contains("buffers") && doc["buffers"].is_array()) {
    for (std::size_t i = 0; i < doc["buffers"].size(); ++i) {
      const nlohmann::json& b = doc["buffers"][i];
      if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number_unsigned()) continue;
      const auto declared = b["byteLength"].get<std::uint64_t>();
      std::optional<std::uint64_t> held;
      if (b.contains("uri") && b["uri"].is_string()) {
        const std::string& uri = b["uri"].get_ref<const std::string&>();
        const std::size_t comma = uri.find(',');
        if (uri.rfind("data:", 0) == 0 && comma != std::string::npos && uri.find(";base64", 0) < comma) {
          const std::size_t chars = uri.size() - comma - 1;
          std::size_t pad = 0;
          for (std::size_t k = uri.size(); k > comma + 1 && uri[k - 1] == '=' && pad < 2; --k) ++pad;
          held = chars / 4 * 3 - pad;
        }
      } else if (i == 0 && bin_chunk) {
        held = *bin_chunk;
      }
      if (held && *held < declared) {
        return idx("buffers", i) + ": holds " + std::to_string(*held) + " bytes, fewer than its byteLength " +
               std::to_string(declared);
      }
    }
  }
  const std::size_t accessors = doc.contains("accessors") && doc["accessors"].is_array() ? doc["accessors"].size() : 0;
  const std::size_t views = doc.contains("bufferViews") && doc["bufferViews"].is_array() ? doc["bufferViews"].size() : 0;
  if (doc.contains("meshes") && doc["meshes"].is_array()) {
    for (std::size_t m = 0; m < doc["meshes"].size(); ++m) {
      const nlohmann::json& mesh = doc["meshes"][m];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (std::size_t k = 0; k < mesh["primitives"].size(); ++k) {
        const nlohmann::json& prim = mesh["primitives"][k];
        if (!prim.is_object() || !prim.contains("indices") || !prim["indices"].is_number_integer()) continue;
        const std::string p = idx("meshes", m) + ".primitives[" + std::to_string(k) + "].indices";
        const auto a = prim["indices"].get<long long>();
        if (a < 0 || static_cast<std::size_t>(a) >= accessors) {
          return p + ": accessor index " + std::to_string(a) + " is out of range (" + std::to_string(accessors) + " accessors)";
        }
        const nlohmann::json& acc = doc["accessors"][static_cast<std::size_t>(a)];
        if (acc.is_object() && (!acc.contains("bufferView") || !acc["bufferView"].is_number_integer() ||
                                acc["bufferView"].get<long long>() < 0 || acc["bufferView"].get<long long>() >= static_cast<long long>(views))) {
          return p + ": accessors[" + std::to_string(a) + "] has no valid bufferView (" + std::to_string(views) + " bufferViews)";
        }
      }
    }
  }
  return {};
}

class GltfReader {
 public:
  GltfReader(const tinygltf::Model& m, std::string source, std::string base_dir, const ModelOptions& options,
             Model& out)
      : m_(m), source_(std::move(source)), base_dir_(std::move(base_dir)), options_(options), out_(out) {}

  Status read(std::uint64_t bytes_used) {
    used_ = bytes_used;
    FACET_TRY(check_extensions());
    FACET_TRY(check_buffer_views());
    if (!m_.animations.empty()) {
      warn("animations: " + std::to_string(m_.animations.size()) + " animation(s) not supported; the nodes are drawn as the file places them");
    }
    int scene_index = m_.defaultScene;
    if (m_.scenes.empty()) {
      if (!m_.nodes.empty()) warn("the file has no scenes: nothing to draw (glTF draws only a scene's nodes)");
      return {};
    }
    if (scene_index < 0) scene_index = 0;
    if (scene_index >= static_cast<int>(m_.scenes.size())) {
      return error("scene", "index " + std::to_string(scene_index) + " is out of range (" +
                                std::to_string(m_.scenes.size()) + " scenes)");
    }
    if (m_.scenes.size() > 1) {
      warn("the file has " + std::to_string(m_.scenes.size()) + " scenes; scenes[" + std::to_string(scene_index) +
           "] is drawn");
    }
    return walk(static_cast<std::size_t>(scene_index));
  }

 private:
  Status error(const std::string& path, const std::string& what, ErrorCode code = ErrorCode::parse_error) const {
    return {code, path, source_ + ": " + path + ": " + what};
  }
  void warn(const std::string& what) { out_.warnings.push_back(what); }

  Status check_extensions() {
    for (const std::string& e : m_.extensionsRequired) {
      if (!supported_extension(e)) {
        std::string list;
        for (const std::string& r : m_.extensionsRequired)
          if (!supported_extension(r)) list += (list.empty() ? "" : ", ") + quote(r, 64);
        return error("extensionsRequired", "the file requires extensions facet does not support: " + list,
                     ErrorCode::unsupported);
      }
    }
    std::string ignored;
    for (const std::string& e : m_.extensionsUsed)
      if (!supported_extension(e)) ignored += (ignored.empty() ? "" : ", ") + quote(e, 64);
    if (!ignored.empty()) warn("extensionsUsed: not supported, ignored: " + ignored);
    return {};
  }

  Status check_buffer_views() {
    for (std::size_t i = 0; i < m_.bufferViews.size(); ++i) {
      const tinygltf::BufferView& v = m_.bufferViews[i];
      const std::string p = idx("bufferViews", i);
      if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= m_.buffers.size()) {
        return error(p + ".buffer", "index " + std::to_string(v.buffer) + " is out of range (" +
                                        std::to_string(m_.buffers.size()) + " buffers)");
      }
      const std::size_t size = m_.buffers[static_cast<std::size_t>(v.buffer)].data.size();
      if (v.byteOffset > size || v.byteLength > size - v.byteOffset) {
        return error(p, "bytes [" + std::to_string(v.byteOffset) + ", " + std::to_string(v.byteOffset) + " + " +
                            std::to_string(v.byteLength) + ") lie outside buffers[" + std::to_string(v.buffer) +
                            "] (" + std::to_string(size) + " bytes)");
      }
      if (v.byteStride != 0 && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4 != 0)) {
        return error(p + ".byteStride", "expected a multiple of 4 in [4, 252], found " + std::to_string(v.byteStride));
      }
    }
    return {};
  }

  // Scene graph: depth first from the scene's roots, each node's world matrix in double. A node
  // reached twice (a cycle, or a node with two parents) is an error: glTF's nodes form a forest.
  Status walk(std::size_t scene_index) {
    const tinygltf::Scene& scene = m_.scenes[scene_index];
    std::vector<char> seen(m_.nodes.size(), 0);
    struct Item {
      int node;
      Eigen::Matrix4d parent;
      std::string path;
    };
    std::vector<Item> stack;
    for (std::size_t r = scene.nodes.size(); r-- > 0;) {
      stack.push_back({scene.nodes[r], Eigen::Matrix4d::Identity(),
                       "scenes[" + std::to_string(scene_index) + "].nodes[" + std::to_string(r) + "]"});
    }
    while (!stack.empty()) {
      Item item = std::move(stack.back());
      stack.pop_back();
      if (item.node < 0 || static_cast<std::size_t>(item.node) >= m_.nodes.size()) {
        return error(item.path, "node index " + std::to_string(item.node) + " is out of range (" +
                                    std::to_string(m_.nodes.size()) + " nodes)");
      }
      const auto n = static_cast<std::size_t>(item.node);
      const std::string p = idx("nodes", n);
      if (seen[n]) {
        return error(item.path, p + " is reached twice (a cycle, or a node with two parents): glTF's nodes must form trees");
      }
      seen[n] = 1;
      const tinygltf::Node& node = m_.nodes[n];
      Eigen::Matrix4d local;
      FACET_TRY(local_matrix(node, p, local));
      const Eigen::Matrix4d world = item.parent * local;
      if (!world.allFinite()) return error(p, "the world matrix is not finite");
      if (node.mesh >= 0) FACET_TRY(add_mesh_instances(node, p, world));
      if (node.mesh < -1 || (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) >= m_.meshes.size())) {
        return error(p + ".mesh", "index " + std::to_string(node.mesh) + " is out of range");
      }
      if (node.camera >= 0) FACET_TRY(add_camera(node, p, world));
      if (node.skin >= 0) warn(p + ": skins are not supported; the mesh is drawn in its bind pose");
      if (!node.weights.empty()) warn(p + ": morph target weights are not supported; the base mesh is drawn");
      if (auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end()) {
        FACET_TRY(add_light(it->second, p, world));
      }
      for (std::size_t c = node.children.size(); c-- > 0;) {
        stack.push_back({node.children[c], world, p + ".children[" + std::to_string(c) + "]"});
      }
    }
    return {};
  }

  Status local_matrix(const tinygltf::Node& node, const std::string& p, Eigen::Matrix4d& out) const {
    out.setIdentity();
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) return error(p + ".matrix", "expected 16 numbers");
      for (int i = 0; i < 16; ++i) out(i % 4, i / 4) = node.matrix[static_cast<std::size_t>(i)];  // column-major
      if (!out.allFinite()) return error(p + ".matrix", "expected finite numbers");
      return {};
    }
    Eigen::Vector3d t = Eigen::Vector3d::Zero(), s = Eigen::Vector3d::Ones();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) return error(p + ".translation", "expected 3 numbers");
      t = Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]);
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) return error(p + ".scale", "expected 3 numbers");
      s = Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]);
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) return error(p + ".rotation", "expected a quaternion of 4 numbers (x, y, z, w)");
      q = Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
      const double norm = q.norm();
      if (!(norm > 1e-6) || !std::isfinite(norm)) return error(p + ".rotation", "expected a unit quaternion, found length " + format_number(norm));
      q.normalize();
    }
    if (!t.allFinite() || !s.allFinite()) return error(p, "translation and scale must be finite");
    out.topLeftCorner<3, 3>() = q.toRotationMatrix() * s.asDiagonal();
    out.topRightCorner<3, 1>() = t;
    return {};
  }

  // ---- accessors -------------------------------------------------------------------------------

  static int component_size(int type) {
    switch (type) {
      case kByte: case kUnsignedByte: return 1;
      case kShort: case kUnsignedShort: return 2;
      case kUnsignedInt: case kFloat: return 4;
      default: return 0;
    }
  }

  static double fetch(const unsigned char* p, int type, bool normalized) {
    switch (type) {
      case kByte: { std::int8_t v; std::memcpy(&v, p, 1); return normalized ? std::max(v / 127.0, -1.0) : v; }
      case kUnsignedByte: { std::uint8_t v; std::memcpy(&v, p, 1); return normalized ? v / 255.0 : v; }
      case kShort: { std::int16_t v; std::memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0, -1.0) : v; }
      case kUnsignedShort: { std::uint16_t v; std::memcpy(&v, p, 2); return normalized ? v / 65535.0 : v; }
      case kUnsignedInt: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
      default: { float v; std::memcpy(&v, p, 4); return v; }
    }
  }

  // Checks that `count` elements of `element_bytes` at `offset` with `stride` fit bufferViews[view].
  Status view_span(int view, std::size_t offset, std::size_t count, std::size_t element_bytes, std::size_t stride,
                   const std::string& p, const unsigned char*& data) const {
    if (view < 0 || static_cast<std::size_t>(view) >= m_.bufferViews.size()) {
      return error(p + ".bufferView", "index " + std::to_string(view) + " is out of range (" +
                                          std::to_string(m_.bufferViews.size()) + " bufferViews)");
    }
    const tinygltf::BufferView& v = m_.bufferViews[static_cast<std::size_t>(view)];
    if (count > 0) {
      const double need = double(offset) + double(count - 1) * double(stride) + double(element_bytes);
      if (need > double(v.byteLength)) {
        return error(p, std::to_string(count) + " elements of " + std::to_string(element_bytes) + " bytes (stride " +
                            std::to_string(stride) + ") from byte " + std::to_string(offset) + " need " +
                            format_number(need) + " bytes; bufferViews[" + std::to_string(view) + "] has " +
                            std::to_string(v.byteLength));
      }
    }
    data = m_.buffers[static_cast<std::size_t>(v.buffer)].data.data() + v.byteOffset + offset;
    return {};
  }

  // Accessor `index` as count x components doubles, sparse substitution applied.
  Status read_accessor(int index, const std::string& p, std::initializer_list<int> allowed_types,
                       std::vector<double>& values, int& components) {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.accessors.size()) {
      return error(p, "accessor index " + std::to_string(index) + " is out of range (" +
                          std::to_string(m_.accessors.size()) + " accessors)");
    }
    const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
    const std::string ap = idx("accessors", static_cast<std::size_t>(index));
    bool type_ok = false;
    for (int t : allowed_types) type_ok |= a.type == t;
    components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    if (!type_ok || components <= 0) return error(ap + ".type", "this type cannot be used for " + p);
    const int csize = component_size(a.componentType);
    if (csize == 0) return error(ap + ".componentType", "unknown component type " + std::to_string(a.componentType));
    const std::size_t n = a.count;
    if (n > (std::size_t{1} << 40)) return error(ap + ".count", std::to_string(n) + " elements is more than facet reads (2^40)");
    const std::uint64_t bytes = std::uint64_t(n) * std::uint64_t(components) * 8;
    FACET_TRY(reserve(bytes, ap));
    values.assign(n * static_cast<std::size_t>(components), 0.0);
    const std::size_t element = std::size_t(csize) * std::size_t(components);
    if (a.bufferView >= 0) {
      if (static_cast<std::size_t>(a.bufferView) >= m_.bufferViews.size()) {
        return error(ap + ".bufferView", "index " + std::to_string(a.bufferView) + " is out of range (" +
                                             std::to_string(m_.bufferViews.size()) + " bufferViews)");
      }
      const tinygltf::BufferView& v = m_.bufferViews[static_cast<std::size_t>(a.bufferView)];
      const std::size_t stride = v.byteStride != 0 ? v.byteStride : element;
      if (stride < element) {
        return error(ap, "bufferViews[" + std::to_string(a.bufferView) + "].byteStride " + std::to_string(stride) +
                             " is smaller than an element (" + std::to_string(element) + " bytes)");
      }
      const unsigned char* data = nullptr;
      FACET_TRY(view_span(a.bufferView, a.byteOffset, n, element, stride, ap, data));
      for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < components; ++c)
          values[i * components + c] = fetch(data + i * stride + std::size_t(c) * csize, a.componentType, a.normalized);
    }
    if (a.sparse.isSparse) {
      const std::string sp = ap + ".sparse";
      const auto count = static_cast<std::size_t>(std::max(a.sparse.count, 0));
      if (count > n) return error(sp + ".count", "larger than the accessor's count");
      const int itype = a.sparse.indices.componentType;
      if (itype != kUnsignedByte && itype != kUnsignedShort && itype != kUnsignedInt) {
        return error(sp + ".indices.componentType", "expected an unsigned integer type");
      }
      const unsigned char* ind = nullptr;
      const unsigned char* val = nullptr;
      FACET_TRY(view_span(a.sparse.indices.bufferView, a.sparse.indices.byteOffset, count,
                          std::size_t(component_size(itype)), std::size_t(component_size(itype)), sp + ".indices", ind));
      FACET_TRY(view_span(a.sparse.values.bufferView, a.sparse.values.byteOffset, count, element, element,
                          sp + ".values", val));
      for (std::size_t k = 0; k < count; ++k) {
        const double target = fetch(ind + k * component_size(itype), itype, false);
        if (!(target < double(n))) {
          return error(sp + ".indices", "index " + format_number(target) + " is out of range (count " + std::to_string(n) + ")");
        }
        const auto t = static_cast<std::size_t>(target);
        for (int c = 0; c < components; ++c)
          values[t * components + c] = fetch(val + k * element + std::size_t(c) * csize, a.componentType, a.normalized);
      }
    }
    for (double v : values) {
      if (!std::isfinite(v) || std::abs(v) > 3.0e38) return error(ap, "holds a value that is not a finite float");
    }
    return {};
  }

  Status reserve(std::uint64_t bytes, const std::string& p) {
    const std::uint64_t budget = options_.memory_budget_bytes;
    if (budget != 0 && (bytes > budget || used_ > budget - bytes)) {
      return error(p, "needs " + std::to_string(bytes >> 20) + " MiB, which takes the model over the memory budget of " +
                          std::to_string(budget >> 20) + " MiB (ModelOptions::memory_budget_bytes, facet --memory-budget-mb)",
                   ErrorCode::out_of_memory);
    }
    used_ += bytes;
    return {};
  }

  // ---- meshes ----------------------------------------------------------------------------------

  Status add_mesh_instances(const tinygltf::Node& node, const std::string& node_path, const Eigen::Matrix4d& world) {
    if (static_cast<std::size_t>(node.mesh) >= m_.meshes.size()) {
      return error(node_path + ".mesh", "index " + std::to_string(node.mesh) + " is out of range (" +
                                            std::to_string(m_.meshes.size()) + " meshes)");
    }
    const tinygltf::Mesh& mesh = m_.meshes[static_cast<std::size_t>(node.mesh)];
    const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
    if (!(std::abs(linear.determinant()) > 1e-30)) {
      warn(node_path + ": its world matrix is singular (a zero scale); its mesh is not drawn");
      return {};
    }
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
      std::uint32_t mesh_index = 0, material_index = 0;
      bool double_sided = false;
      FACET_TRY(primitive(static_cast<std::size_t>(node.mesh), k, mesh_index, material_index, double_sided));
      if (mesh_index == kSkipped) continue;
      Instance inst;
      inst.mesh = mesh_index;
      inst.material = material_index;
      inst.model = world.cast<float>();
      inst.double_sided = double_sided;
      out_.scene.objects.push_back(inst);
    }
    return {};
  }

  static constexpr std::uint32_t kSkipped = ~std::uint32_t{0};

  // The facet mesh of meshes[m].primitives[k] (made once, shared by every node that uses it).
  Status primitive(std::size_t m, std::size_t k, std::uint32_t& mesh_index, std::uint32_t& material_index,
                   bool& double_sided) {
    const auto key = std::make_pair(m, k);
    if (auto it = primitives_.find(key); it != primitives_.end()) {
      std::tie(mesh_index, material_index, double_sided) = it->second;
      return {};
    }
    const tinygltf::Primitive& prim = m_.meshes[m].primitives[k];
    const std::string p = idx("meshes", m) + ".primitives[" + std::to_string(k) + "]";
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
        mode == TINYGLTF_MODE_LINE_STRIP) {
      return error(p + ".mode", std::string("points and lines (mode ") + std::to_string(mode) +
                                    ") are not supported: facet draws triangles only", ErrorCode::unsupported);
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      return error(p + ".mode", "unknown mode " + std::to_string(mode));
    }
    if (!prim.targets.empty()) warn(p + ": morph targets are not supported; the base mesh is drawn");
    // The material first: vertex colours are multiplied by its base colour.
    MaterialInfo info;
    FACET_TRY(material(prim.material, p + ".material", info));
    auto attribute = [&](const char* name) -> int {
      auto it = prim.attributes.find(name);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    for (const auto& [name, accessor] : prim.attributes) {
      (void)accessor;
      if (name != "POSITION" && name != "NORMAL" && name != "TEXCOORD_0" && name != "COLOR_0" && name != "TANGENT" &&
          name.rfind("_", 0) != 0) {
        if (ignored_attributes_.insert(name).second) warn(p + ".attributes." + name + ": not used by facet");
      }
    }
    const int pos = attribute("POSITION");
    if (pos < 0) return error(p + ".attributes", "no POSITION attribute");
    Mesh mesh;
    std::vector<double> v;
    int comps = 0;
    FACET_TRY(read_accessor(pos, p + ".attributes.POSITION", {TINYGLTF_TYPE_VEC3}, v, comps));
    const std::size_t n = v.size() / 3;
    if (n > 0xffffffffu) return error(p + ".attributes.POSITION", "more vertices than 32-bit indices reach");
    FACET_TRY(reserve(std::uint64_t(n) * (2 * sizeof(Vec3) + sizeof(Vec2) + sizeof(Color3)), p));
    mesh.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) mesh.positions[i] = Vec3(float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2]));
    const int nrm = attribute("NORMAL");
    if (nrm >= 0) {
      FACET_TRY(read_accessor(nrm, p + ".attributes.NORMAL", {TINYGLTF_TYPE_VEC3}, v, comps));
      if (v.size() / 3 != n) return error(p + ".attributes.NORMAL", "count differs from POSITION's");
      mesh.normals.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3 d{static_cast<float>(v[3 * i]), static_cast<float>(v[3 * i + 1]), static_cast<float>(v[3 * i + 2])};
        const float len = d.norm();
        mesh.normals[i] = len > 1e-20f ? Vec3(d / len) : Vec3::Zero();
      }
    }
    const int uv = attribute("TEXCOORD_0");
    if (uv >= 0) {
      FACET_TRY(read_accessor(uv, p + ".attributes.TEXCOORD_0", {TINYGLTF_TYPE_VEC2}, v, comps));
      if (v.size() / 2 != n) return error(p + ".attributes.TEXCOORD_0", "count differs from POSITION's");
      mesh.uvs.resize(n);
      // glTF's (0, 0) is the image's top-left corner, facet's (GL's) its bottom-left.
      for (std::size_t i = 0; i < n; ++i) mesh.uvs[i] = Vec2(float(v[2 * i]), float(1.0 - v[2 * i + 1]));
    }
    const int col = attribute("COLOR_0");
    if (col >= 0) {
      FACET_TRY(read_accessor(col, p + ".attributes.COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, v, comps));
      if (v.size() / std::size_t(comps) != n) return error(p + ".attributes.COLOR_0", "count differs from POSITION's");
      mesh.colors.resize(n);
      bool alpha_dropped = false;
      for (std::size_t i = 0; i < n; ++i) {
        Color3 c{static_cast<float>(v[i * comps]), static_cast<float>(v[i * comps + 1]), static_cast<float>(v[i * comps + 2])};
        // facet's vertex colours replace the material's ambient and diffuse colour; glTF's
        // multiply the base colour: the product is taken here.
        c = c.cwiseProduct(info.vertex_color_scale).cwiseMax(0.0f).cwiseMin(1.0f);
        mesh.colors[i] = c;
        if (comps == 4 && v[i * comps + 3] < 254.5 / 255.0) alpha_dropped = true;  // below what 8-bit alpha rounds to 1
      }
      // OPAQUE materials ignore alpha anyway; MASK and BLEND would need it.
      if (alpha_dropped && info.uses_alpha) warn(p + ".attributes.COLOR_0: vertex alpha is not supported; ignored (colours are used)");
    }
    // Indices.
    std::vector<std::uint32_t> idxs;
    if (prim.indices >= 0) {
      FACET_TRY(read_accessor(prim.indices, p + ".indices", {TINYGLTF_TYPE_SCALAR}, v, comps));
      const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(prim.indices)];
      if (a.componentType != kUnsignedByte && a.componentType != kUnsignedShort && a.componentType != kUnsignedInt) {
        return error(idx("accessors", static_cast<std::size_t>(prim.indices)) + ".componentType",
                     "indices must be unsigned bytes, shorts or ints");
      }
      idxs.resize(v.size());
      for (std::size_t i = 0; i < v.size(); ++i) {
        if (!(v[i] < double(n))) {
          return error(p + ".indices", "index " + format_number(v[i]) + " (element " + std::to_string(i) +
                                           ") is out of range (" + std::to_string(n) + " vertices)");
        }
        idxs[i] = static_cast<std::uint32_t>(v[i]);
      }
    } else {
      idxs.resize(n);
      for (std::size_t i = 0; i < n; ++i) idxs[i] = static_cast<std::uint32_t>(i);
    }
    std::vector<double>().swap(v);
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (idxs.size() % 3 != 0) warn(p + ": " + std::to_string(idxs.size() % 3) + " trailing indices do not make a triangle; ignored");
      for (std::size_t i = 0; i + 2 < idxs.size(); i += 3) mesh.triangles.push_back({idxs[i], idxs[i + 1], idxs[i + 2]});
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (std::size_t i = 0; i + 2 < idxs.size(); ++i) {
        if (i % 2 == 0) mesh.triangles.push_back({idxs[i], idxs[i + 1], idxs[i + 2]});
        else mesh.triangles.push_back({idxs[i], idxs[i + 2], idxs[i + 1]});
      }
    } else {
      for (std::size_t i = 1; i + 1 < idxs.size(); ++i) mesh.triangles.push_back({idxs[i], idxs[i + 1], idxs[0]});
    }
    if (mesh.triangles.empty()) {
      warn(p + ": no triangles; not drawn");
      primitives_[key] = {kSkipped, 0, false};
      mesh_index = kSkipped;
      return {};
    }
    // glTF: without normals, flat shading (each triangle its own normal).
    if (mesh.normals.empty()) compute_vertex_normals(mesh, 0.0f);
    if (info.needs_uvs && mesh.uvs.empty()) {
      warn(p + ": its material is textured but it has no TEXCOORD_0; drawn untextured");
      info.index = untextured_twin(info.index);
    }
    NamedMesh named;
    named.name = (m_.meshes[m].name.empty() ? idx("meshes", m) : m_.meshes[m].name) +
                 (m_.meshes[m].primitives.size() > 1 ? "#" + std::to_string(k) : std::string());
    named.mesh = std::move(mesh);
    out_.scene.meshes.push_back(std::move(named));
    mesh_index = static_cast<std::uint32_t>(out_.scene.meshes.size() - 1);
    material_index = info.index;
    double_sided = info.double_sided;
    primitives_[key] = {mesh_index, material_index, double_sided};
    return {};
  }

  // ---- materials and textures ------------------------------------------------------------------

  struct MaterialInfo {
    std::uint32_t index = 0;
    Color3 vertex_color_scale{1.0f, 1.0f, 1.0f};
    bool double_sided = false;
    bool needs_uvs = false;
    bool uses_alpha = false;  // alphaMode MASK or BLEND
  };

  std::uint32_t untextured_twin(std::uint32_t index) {
    if (auto it = untextured_.find(index); it != untextured_.end()) return it->second;
    Material copy = out_.scene.materials[index];
    copy.diffuse_texture = copy.emissive_texture = kNoTexture;
    copy.name += " (untextured)";
    out_.scene.materials.push_back(copy);
    const auto twin = static_cast<std::uint32_t>(out_.scene.materials.size() - 1);
    untextured_[index] = twin;
    return twin;
  }

  static Color3 color3(const std::vector<double>& c, Color3 fallback) {
    return c.size() >= 3 ? Color3(float(c[0]), float(c[1]), float(c[2])) : fallback;
  }

  Status material(int index, const std::string& ref_path, MaterialInfo& info) {
    if (auto it = materials_.find(index); it != materials_.end()) {
      info = it->second;
      return {};
    }
    Material mat;
    if (index < 0) {
      // No material: facet's default (GL's), not glTF's default metal (docs/content.md).
      mat.name = "default";
    } else {
      if (static_cast<std::size_t>(index) >= m_.materials.size()) {
        return error(ref_path, "index " + std::to_string(index) + " is out of range (" +
                                   std::to_string(m_.materials.size()) + " materials)");
      }
      const tinygltf::Material& g = m_.materials[static_cast<std::size_t>(index)];
      const std::string p = idx("materials", static_cast<std::size_t>(index));
      mat.name = g.name.empty() ? p : g.name;
      const auto& pbr = g.pbrMetallicRoughness;
      const std::vector<double>& bc = pbr.baseColorFactor;
      if (bc.size() != 4) return error(p + ".pbrMetallicRoughness.baseColorFactor", "expected 4 numbers");
      for (double c : bc)
        if (!(c >= 0.0 && c <= 1.0)) return error(p + ".pbrMetallicRoughness.baseColorFactor", "expected numbers in [0, 1]");
      const double metallic = pbr.metallicFactor, roughness = pbr.roughnessFactor;
      if (!(metallic >= 0.0 && metallic <= 1.0)) return error(p + ".pbrMetallicRoughness.metallicFactor", "expected a number in [0, 1]");
      if (!(roughness >= 0.0 && roughness <= 1.0)) return error(p + ".pbrMetallicRoughness.roughnessFactor", "expected a number in [0, 1]");
      const Color3 base = color3(bc, Color3::Ones());
      const PbrMapping map = map_metallic_roughness(base, float(metallic), float(roughness));
      mat.diffuse = map.diffuse;
      mat.ambient = map.diffuse;
      mat.specular = map.specular;
      mat.shininess = map.shininess;
      info.vertex_color_scale = map.diffuse;
      Color3 emissive = color3(g.emissiveFactor, Color3::Zero());
      if (!emissive.allFinite() || emissive.minCoeff() < 0.0f) return error(p + ".emissiveFactor", "expected non-negative numbers");
      if (auto it = g.extensions.find("KHR_materials_emissive_strength"); it != g.extensions.end()) {
        const tinygltf::Value& ext = it->second;
        if (ext.Has("emissiveStrength") && ext.Get("emissiveStrength").IsNumber()) {
          const tinygltf::Value& s = ext.Get("emissiveStrength");
          const double k = s.GetNumberAsDouble();
          if (!(k >= 0.0 && k < 1e30)) return error(p + ".extensions.KHR_materials_emissive_strength.emissiveStrength", "expected a number >= 0");
          emissive *= float(k);
        }
      }
      mat.emissive = emissive;
      if (g.extensions.count("KHR_materials_unlit")) {
        // Unlit: the base colour as emission, nothing from lights.
        mat.emissive = base;
        mat.ambient = mat.diffuse = mat.specular = Color3::Zero();
        info.vertex_color_scale = Color3::Zero();
        warn(p + ": KHR_materials_unlit: drawn as emission of the base colour (vertex colours are not applied)");
      }
      mat.alpha = float(bc[3]);
      if (g.alphaMode == "MASK") {
        mat.alpha_cutoff = float(std::clamp(g.alphaCutoff, 0.0, 1.0));
      } else if (g.alphaMode == "BLEND") {
        mat.blend = BlendMode::alpha;
      } else if (g.alphaMode == "OPAQUE" || g.alphaMode.empty()) {
        mat.alpha = 1.0f;
      } else {
        return error(p + ".alphaMode", "expected \"OPAQUE\", \"MASK\" or \"BLEND\", found " + quote(g.alphaMode, 32));
      }
      info.double_sided = g.doubleSided;
      info.uses_alpha = g.alphaMode == "MASK" || g.alphaMode == "BLEND";
      // A texture of the material read from TEXCOORD_0 without a transform; others are drawn
      // without it, with a warning.
      auto texture_of = [&](const tinygltf::TextureInfo& ti, const std::string& tp, std::int32_t& t) -> Status {
        if (ti.texCoord != 0) {
          warn(tp + ": texCoord " + std::to_string(ti.texCoord) +
               " is not supported (facet reads TEXCOORD_0 only); drawn without it");
        } else if (ti.extensions.count("KHR_texture_transform")) {
          warn(tp + ": KHR_texture_transform is not supported; drawn without it");
        } else {
          FACET_TRY(texture(ti.index, tp + ".index", t));
        }
        return {};
      };
      if (pbr.baseColorTexture.index >= 0) {
        std::int32_t t = kNoTexture;
        FACET_TRY(texture_of(pbr.baseColorTexture, p + ".pbrMetallicRoughness.baseColorTexture", t));
        if (t != kNoTexture) {
          mat.diffuse_texture = t;
          mat.texture_mode = TextureMode::modulate;
          info.needs_uvs = true;
        }
      }
      if (g.extensions.count("KHR_materials_unlit")) {
        if (g.emissiveTexture.index >= 0) warn(p + ".emissiveTexture: ignored by KHR_materials_unlit");
      } else {
        // glTF adds the emission after the base colour: not modulated by the base colour texture.
        mat.emission_after_texture = true;
        if (g.emissiveTexture.index >= 0) {
          std::int32_t t = kNoTexture;
          FACET_TRY(texture_of(g.emissiveTexture, p + ".emissiveTexture", t));
          if (t != kNoTexture) {
            mat.emissive_texture = t;
            info.needs_uvs = true;
          }
        }
      }
      auto ignored = [&](const char* what, int tex) {
        if (tex >= 0) warn(p + "." + what + ": not supported; ignored");
      };
      ignored("normalTexture", g.normalTexture.index);
      ignored("occlusionTexture", g.occlusionTexture.index);
      ignored("pbrMetallicRoughness.metallicRoughnessTexture", pbr.metallicRoughnessTexture.index);
    }
    out_.scene.materials.push_back(std::move(mat));
    info.index = static_cast<std::uint32_t>(out_.scene.materials.size() - 1);
    materials_[index] = info;
    return {};
  }

  Status texture(int index, const std::string& ref_path, std::int32_t& out) {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.textures.size()) {
      return error(ref_path, "index " + std::to_string(index) + " is out of range (" +
                                 std::to_string(m_.textures.size()) + " textures)");
    }
    const tinygltf::Texture& t = m_.textures[static_cast<std::size_t>(index)];
    const std::string p = idx("textures", static_cast<std::size_t>(index));
    if (t.source < 0 || static_cast<std::size_t>(t.source) >= m_.images.size()) {
      if (t.source < 0 && !t.extensions.empty()) {
        warn(p + ": its image is only given by an extension facet does not read; drawn untextured");
        return {};
      }
      return error(p + ".source", "index " + std::to_string(t.source) + " is out of range (" +
                                      std::to_string(m_.images.size()) + " images)");
    }
    TextureOptions topt;
    if (t.sampler >= 0) {
      if (static_cast<std::size_t>(t.sampler) >= m_.samplers.size()) {
        return error(p + ".sampler", "index " + std::to_string(t.sampler) + " is out of range");
      }
      const tinygltf::Sampler& s = m_.samplers[static_cast<std::size_t>(t.sampler)];
      const std::string sp = idx("samplers", static_cast<std::size_t>(t.sampler));
      topt.filter = sampler_filter(s.minFilter, s.magFilter);
      auto wrap = [&](int w, const char* field, TextureWrap& out_wrap) -> Status {
        switch (w) {
          case TINYGLTF_TEXTURE_WRAP_REPEAT: case -1: out_wrap = TextureWrap::repeat; return {};
          case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: out_wrap = TextureWrap::clamp; return {};
          case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: out_wrap = TextureWrap::mirror; return {};
          default: return error(sp + "." + field, "unknown wrap mode " + std::to_string(w));
        }
      };
      TextureWrap ws = TextureWrap::repeat, wt = TextureWrap::repeat;
      FACET_TRY(wrap(s.wrapS, "wrapS", ws));
      FACET_TRY(wrap(s.wrapT, "wrapT", wt));
      if (ws != wt) warn(sp + ": wrapS and wrapT differ; facet has one wrap mode per texture and uses wrapS's");
      topt.wrap = ws;
    }
    const auto key = std::make_tuple(t.source, topt.filter, topt.wrap);
    if (auto it = textures_.find(key); it != textures_.end()) {
      out = it->second;
      return {};
    }
    const tinygltf::Image& image = m_.images[static_cast<std::size_t>(t.source)];
    const std::string ip = idx("images", static_cast<std::size_t>(t.source));
    std::vector<unsigned char> view_bytes;
    const std::vector<unsigned char>* bytes = &image.image;
    if (image.bufferView >= 0) {
      const tinygltf::BufferView* v = nullptr;
      if (static_cast<std::size_t>(image.bufferView) < m_.bufferViews.size()) v = &m_.bufferViews[static_cast<std::size_t>(image.bufferView)];
      if (v == nullptr) return error(ip + ".bufferView", "index " + std::to_string(image.bufferView) + " is out of range");
      const unsigned char* data = m_.buffers[static_cast<std::size_t>(v->buffer)].data.data() + v->byteOffset;
      view_bytes.assign(data, data + v->byteLength);
      bytes = &view_bytes;
    }
    const std::string name = image.uri.empty() || image.uri.rfind("data:", 0) == 0 ? ip : image.uri;
    if (bytes->empty()) {
      const std::string what = ip + (image.uri.empty() ? std::string() : " (" + quote(image.uri, 80) + ")") +
                               ": the image could not be read";
      if (!options_.allow_missing) return error(ip, what + " (ModelOptions::allow_missing, facet --allow-missing: draw untextured)", ErrorCode::io_error);
      warn(what + "; drawn untextured");
      textures_[key] = kNoTexture;
      return {};
    }
    topt.memory_budget_bytes = options_.memory_budget_bytes == 0 ? 0 : std::max<std::uint64_t>(1, options_.memory_budget_bytes - std::min(used_, options_.memory_budget_bytes));
    Result<Texture> decoded = decode_texture(std::span<const std::uint8_t>(bytes->data(), bytes->size()), source_ + ": " + ip, name, topt);
    if (!decoded) return {decoded.status().code(), ip, decoded.status().message()};
    FACET_TRY(reserve(decoded->texels.size() * 4, ip));
    out_.scene.textures.push_back(std::move(*decoded));
    out = static_cast<std::int32_t>(out_.scene.textures.size() - 1);
    textures_[key] = out;
    return {};
  }

  static TextureFilter sampler_filter(int min, int mag) {
    switch (min) {
      case TINYGLTF_TEXTURE_FILTER_NEAREST:
        return mag == TINYGLTF_TEXTURE_FILTER_LINEAR ? TextureFilter::bilinear : TextureFilter::nearest;
      case TINYGLTF_TEXTURE_FILTER_LINEAR: return TextureFilter::bilinear;
      default: return TextureFilter::trilinear;  // the mipmapped filters, or none given
    }
  }

  // ---- cameras and lights ----------------------------------------------------------------------

  Status add_camera(const tinygltf::Node& node, const std::string& p, const Eigen::Matrix4d& world) {
    if (static_cast<std::size_t>(node.camera) >= m_.cameras.size()) {
      return error(p + ".camera", "index " + std::to_string(node.camera) + " is out of range (" +
                                      std::to_string(m_.cameras.size()) + " cameras)");
    }
    const tinygltf::Camera& c = m_.cameras[static_cast<std::size_t>(node.camera)];
    const std::string cp = idx("cameras", static_cast<std::size_t>(node.camera));
    if (out_.has_camera) {
      if (!cameras_noted_) warn("the file has more than one camera node; the first in the scene's order is used");
      cameras_noted_ = true;
      return {};
    }
    if (c.type != "perspective") {
      warn(cp + ": " + quote(c.type, 32) + " cameras are not supported (facet projects in perspective only); not used");
      return {};
    }
    const auto& pc = c.perspective;
    if (!(pc.yfov > 0.0 && pc.yfov < std::numbers::pi)) return error(cp + ".perspective.yfov", "expected radians in (0, pi)");
    if (!(pc.znear > 0.0 && std::isfinite(pc.znear))) return error(cp + ".perspective.znear", "expected a number > 0");
    Camera cam;
    const Eigen::Vector3d eye = world.topRightCorner<3, 1>();
    Eigen::Vector3d forward = -world.block<3, 1>(0, 2), up = world.block<3, 1>(0, 1);
    if (!(forward.norm() > 1e-12) || !(up.norm() > 1e-12)) return error(p, "the camera node's matrix is singular");
    forward.normalize();
    up.normalize();
    cam.eye = eye.cast<float>();
    cam.target = (eye + forward).cast<float>();
    cam.up = up.cast<float>();
    cam.vertical_fov_deg = float(pc.yfov * 180.0 / std::numbers::pi);
    cam.aspect = pc.aspectRatio > 0.0 ? float(pc.aspectRatio) : 0.0f;
    cam.near = float(pc.znear);
    if (pc.zfar > pc.znear && std::isfinite(pc.zfar)) {
      cam.far = float(pc.zfar);
    } else {
      // Infinite projection: facet needs a far plane; one is put beyond the model (the caller's
      // framing knows the bounds; here, a million times the near plane).
      cam.far = float(pc.znear * 1e6);
      warn(cp + ": an infinite far plane is not supported; far = 1e6 x near is used");
    }
    out_.scene.camera = cam;
    out_.has_camera = true;
    return {};
  }

  Status add_light(const tinygltf::Value& ext, const std::string& p, const Eigen::Matrix4d& world) {
    const std::string lp = p + ".extensions.KHR_lights_punctual.light";
    if (!ext.Has("light") || !ext.Get("light").IsNumber()) return error(lp, "expected a light index");
    const tinygltf::Value& li = ext.Get("light");
    const int index = li.GetNumberAsInt();
    if (index < 0 || static_cast<std::size_t>(index) >= m_.lights.size()) {
      return error(lp, "index " + std::to_string(index) + " is out of range (" + std::to_string(m_.lights.size()) + " lights)");
    }
    const tinygltf::Light& g = m_.lights[static_cast<std::size_t>(index)];
    const std::string gp = "extensions.KHR_lights_punctual.lights[" + std::to_string(index) + "]";
    Light l;
    l.name = g.name.empty() ? gp : g.name;
    const Color3 color = color3(g.color, Color3::Ones());
    if (!color.allFinite() || color.minCoeff() < 0.0f) return error(gp + ".color", "expected non-negative numbers");
    if (!(g.intensity >= 0.0 && g.intensity < 1e30)) return error(gp + ".intensity", "expected a number >= 0");
    // Units (docs/content.md): directional lux and point/spot candela both map to facet's light
    // colour one to one; point and spot lights fall off as 1 / d^2 (quadratic attenuation 1).
    l.diffuse = l.specular = color * float(g.intensity);
    const Eigen::Vector3d pos = world.topRightCorner<3, 1>();
    Eigen::Vector3d dir = -world.block<3, 1>(0, 2);
    if (!(dir.norm() > 1e-12)) return error(p, "the light node's matrix is singular");
    dir.normalize();
    if (g.type == "directional") {
      l.type = LightType::directional;
      l.direction = dir.cast<float>();
    } else if (g.type == "point" || g.type == "spot") {
      l.type = g.type == "point" ? LightType::point : LightType::spot;
      l.position = pos.cast<float>();
      l.constant_attenuation = 0.0f;
      l.quadratic_attenuation = 1.0f;
      if (g.range > 0.0) l.range = float(g.range);
      if (l.type == LightType::spot) {
        l.direction = dir.cast<float>();
        const double inner = g.spot.innerConeAngle, outer = g.spot.outerConeAngle;
        if (!(inner >= 0.0 && inner < outer && outer <= std::numbers::pi / 2)) {
          return error(gp + ".spot", "expected 0 <= innerConeAngle < outerConeAngle <= pi/2");
        }
        l.spot_shape = SpotShape::smooth_cone;
        l.spot_inner_deg = float(inner * 180.0 / std::numbers::pi);
        l.spot_outer_deg = float(outer * 180.0 / std::numbers::pi);
        l.spot_falloff = 2.0f;
      }
    } else {
      return error(gp + ".type", "expected \"directional\", \"point\" or \"spot\", found " + quote(g.type, 32));
    }
    out_.scene.lights.push_back(l);
    out_.has_lights = true;
    return {};
  }

  const tinygltf::Model& m_;
  std::string source_;
  std::string base_dir_;
  const ModelOptions& options_;
  Model& out_;
  std::uint64_t used_ = 0;
  bool cameras_noted_ = false;
  std::map<std::pair<std::size_t, std::size_t>, std::tuple<std::uint32_t, std::uint32_t, bool>> primitives_;
  std::map<int, MaterialInfo> materials_;
  std::map<std::uint32_t, std::uint32_t> untextured_;
  std::map<std::tuple<int, TextureFilter, TextureWrap>, std::int32_t> textures_;
  std::set<std::string> ignored_attributes_;
};

}  // namespace

PbrMapping map_metallic_roughness(const Color3& base, float metallic, float roughness) {
  PbrMapping m;
  // How mirror-like the metal is: a rough metal scatters like a diffuse surface of its colour, a
  // polished one only reflects (docs/content.md).
  const float mirror = metallic * (1.0f - roughness);
  m.diffuse = base * (1.0f - mirror);
  const Color3 f0 = Color3::Constant(0.04f) * (1.0f - metallic) + base * metallic;
  m.specular = f0 * (1.0f - roughness);
  const float alpha = roughness * roughness;
  const float s = alpha > 0.0f ? 2.0f / (alpha * alpha) - 2.0f : kMaxShininess;
  m.shininess = std::clamp(s, 1.0f, kMaxShininess);
  return m;
}

Result<Model> parse_gltf(std::span<const std::uint8_t> bytes, const std::string& source_name, const std::string& base_dir,
                         const ModelOptions& options) {
  try {
    tinygltf::TinyGLTF loader;
    FileState files;
    files.budget = options.memory_budget_bytes;
    files.used = bytes.size();
    tinygltf::FsCallbacks fs{};
    fs.FileExists = &fs_exists;
    fs.ExpandFilePath = &fs_expand;
    fs.ReadWholeFile = &fs_read;
    fs.WriteWholeFile = &fs_write;
    fs.user_data = &files;
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(&keep_image_bytes, nullptr);
    tinygltf::Model gm;
    std::string err, warn;
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    if (bytes.size() > 0x7fffffffu) {
      return Status{ErrorCode::unsupported, "", source_name + ": larger than 2 GiB, which tinygltf cannot read"};
    }
    const std::string dir = base_dir.empty() ? std::string(".") : base_dir;
    files.dir = dir;
    const bool ok = binary
                        ? loader.LoadBinaryFromMemory(&gm, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()), dir)
                        : loader.LoadASCIIFromString(&gm, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                                     static_cast<unsigned>(bytes.size()), dir);
    if (!ok) {
      while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
      for (char& c : err)
        if (c == '\n') c = ';';
      const ErrorCode code = files.failure != ErrorCode::ok ? files.failure : ErrorCode::parse_error;
      const std::string where = code == ErrorCode::parse_error ? locate_failure(bytes) : std::string();
      return Status{code, "", source_name + ": " + (where.empty() ? std::string() : where + " (tinygltf: ") +
                                  (err.empty() ? std::string("not a valid glTF file") : quote(err, 400)) +
                                  (where.empty() ? "" : ")")};
    }
    Model model;
    // glTF asks renderers to draw BLEND primitives sorted back to front (alphaMode's notes).
    model.scene.transparent_order = TransparentOrder::back_to_front;
    GltfReader reader(gm, source_name, base_dir, options, model);
    FACET_TRY(reader.read(files.used));
    if (!warn.empty()) {
      std::size_t b = 0;
      while (b < warn.size()) {
        std::size_t e = warn.find('\n', b);
        if (e == std::string::npos) e = warn.size();
        if (e > b) model.warnings.push_back("tinygltf: " + quote(std::string_view(warn).substr(b, e - b), 200));
        b = e + 1;
      }
    }
    if (Status s = validate_scene(model.scene); !s.ok()) {
      return Status{s.code(), s.field(), source_name + ": the imported scene is not valid: " + s.message()};
    }
    return model;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", source_name + ": out of memory while reading the model"};
  } catch (const std::exception& e) {
    return Status{ErrorCode::parse_error, "", source_name + ": " + quote(e.what(), 200)};
  }
}

Result<Model> load_gltf(const std::string& path, const ModelOptions& options) {
  Result<std::string> text = io::read_file(path, "glTF file", options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes);
  if (!text) return text.status();
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_gltf(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text->data()), text->size()), path,
                    base, options);
}

}  // namespace facet
