// glTF 2.0 import: nodes, accessors and meshes (gltf_reader.hpp says how the pieces fit).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>

#include "common/format.hpp"
#include "common/try.hpp"
#include "content/gltf_reader.hpp"
#include "content/import.hpp"
#include "facet/model.hpp"
#include "io/assets.hpp"

namespace facet {
namespace gltf {
namespace {

// The extensions facet reads; any other that a file requires is an error, any other it uses a warning.
constexpr const char* kSupportedExtensions[] = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_unlit", "KHR_materials_ior",
    "KHR_materials_specular", "KHR_mesh_quantization",
    "KHR_texture_transform", "EXT_meshopt_compression", "KHR_draco_mesh_compression", "EXT_mesh_gpu_instancing"};

bool supported_extension(const std::string& name) {
  for (const char* s : kSupportedExtensions)
    if (name == s) return true;
  return false;
}

int component_size(int type) {
  switch (type) {
    case kByte: case kUnsignedByte: return 1;
    case kShort: case kUnsignedShort: return 2;
    case kUnsignedInt: case kFloat: return 4;
    default: return 0;
  }
}

const char* component_name(int type) {
  switch (type) {
    case kByte: return "BYTE";
    case kUnsignedByte: return "UNSIGNED_BYTE";
    case kShort: return "SHORT";
    case kUnsignedShort: return "UNSIGNED_SHORT";
    case kUnsignedInt: return "UNSIGNED_INT";
    default: return "FLOAT";
  }
}

double fetch(const std::uint8_t* p, int type, bool normalized) {
  switch (type) {
    case kByte: { std::int8_t v; std::memcpy(&v, p, 1); return normalized ? std::max(v / 127.0, -1.0) : v; }
    case kUnsignedByte: { std::uint8_t v; std::memcpy(&v, p, 1); return normalized ? v / 255.0 : v; }
    case kShort: { std::int16_t v; std::memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0, -1.0) : v; }
    case kUnsignedShort: { std::uint16_t v; std::memcpy(&v, p, 2); return normalized ? v / 65535.0 : v; }
    case kUnsignedInt: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    default: { float v; std::memcpy(&v, p, 4); return v; }
  }
}

int components_of(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

// Which accessor forms each attribute facet reads may take: the core specification's, and
// KHR_mesh_quantization's (integer positions and texture coordinates, normalized or not;
// normalized normals).
struct Form {
  int component;
  int normalized;  // 0: must not be, 1: must be, 2: either
};
bool allowed(const char* semantic, int components, int component, bool normalized) {
  const std::string s = semantic;
  std::vector<Form> forms;
  if (s == "POSITION") {
    if (components != 3) return false;
    forms = {{kFloat, 0}, {kByte, 2}, {kUnsignedByte, 2}, {kShort, 2}, {kUnsignedShort, 2}};
  } else if (s == "NORMAL") {
    if (components != 3) return false;
    forms = {{kFloat, 0}, {kByte, 1}, {kShort, 1}};
  } else if (s == "TEXCOORD_0" || s == "TEXCOORD_1") {
    if (components != 2) return false;
    forms = {{kFloat, 0}, {kByte, 2}, {kUnsignedByte, 2}, {kShort, 2}, {kUnsignedShort, 2}};
  } else if (s == "TANGENT") {
    if (components != 4) return false;
    forms = {{kFloat, 0}, {kByte, 1}, {kShort, 1}};
  } else if (s == "TRANSLATION" || s == "SCALE") {  // EXT_mesh_gpu_instancing (quantized forms as KHR_mesh_quantization)
    if (components != 3) return false;
    forms = {{kFloat, 0}, {kByte, 2}, {kShort, 2}};
  } else if (s == "ROTATION") {
    if (components != 4) return false;
    forms = {{kFloat, 0}, {kByte, 1}, {kShort, 1}};
  } else if (s == "JOINTS") {  // skins: JOINTS_0, JOINTS_1
    if (components != 4) return false;
    forms = {{kUnsignedByte, 0}, {kUnsignedShort, 0}};
  } else if (s == "WEIGHTS" || s == "KEY_WEIGHTS") {  // skins; animated morph weights (one per key and target)
    if (components != (s == "WEIGHTS" ? 4 : 1)) return false;
    forms = {{kFloat, 0}, {kUnsignedByte, 1}, {kUnsignedShort, 1}};
    if (s == "KEY_WEIGHTS") forms.insert(forms.end(), {{kByte, 1}, {kShort, 1}});
  } else if (s == "TARGET_POSITION") {  // morph targets' deltas (KHR_mesh_quantization's forms too)
    if (components != 3) return false;
    forms = {{kFloat, 0}, {kByte, 2}, {kShort, 2}};
  } else if (s == "TARGET_NORMAL" || s == "TARGET_TANGENT") {
    if (components != 3) return false;
    forms = {{kFloat, 0}, {kByte, 1}, {kShort, 1}};
  } else if (s == "TIME") {  // an animation sampler's input
    if (components != 1) return false;
    forms = {{kFloat, 0}};
  } else if (s == "KEY_TRANSLATION" || s == "KEY_SCALE") {
    if (components != 3) return false;
    forms = {{kFloat, 0}, {kByte, 2}, {kUnsignedByte, 2}, {kShort, 2}, {kUnsignedShort, 2}};
  } else if (s == "KEY_ROTATION") {
    if (components != 4) return false;
    forms = {{kFloat, 0}, {kByte, 1}, {kShort, 1}};
  } else if (s == "MATRIX") {  // a skin's inverse bind matrices
    if (components != 16) return false;
    forms = {{kFloat, 0}};
  } else if (s == "COLOR_0") {
    if (components != 3 && components != 4) return false;
    forms = {{kFloat, 0}, {kUnsignedByte, 1}, {kUnsignedShort, 1}};
  } else {  // indices
    if (components != 1) return false;
    forms = {{kUnsignedByte, 0}, {kUnsignedShort, 0}, {kUnsignedInt, 0}};
  }
  for (const Form& f : forms)
    if (f.component == component && (f.normalized == 2 || (f.normalized == 1) == normalized)) return true;
  return false;
}

}  // namespace

Status Reader::reserve(std::uint64_t bytes, const std::string& p) {
  const std::uint64_t budget = options_.memory_budget_bytes;
  if (budget != 0 && (bytes > budget || used_ > budget - bytes)) {
    return f_.error(p, "needs " + format_bytes(bytes) + ", which takes the model over the memory budget of " +
                           format_bytes(budget) + " (ModelOptions::memory_budget_bytes, facet --memory-budget-mb)",
                    ErrorCode::out_of_memory);
  }
  used_ += bytes;
  return {};
}

Status Reader::read(std::uint64_t bytes_used) {
  used_ = bytes_used;
  FACET_TRY(check_extensions());
  const Json& j = doc_.json();
  animated_ = doc_.count("animations") > 0;
  // ModelOptions::camera names a camera the drawn scene does not have: an error listing those it has.
  const auto camera_found = [&]() -> Status {
    if (options_.camera.empty() || out_.has_camera) return {};
    std::string list;
    for (const std::string& c : out_.cameras) list += (list.empty() ? "" : "; ") + c;
    return f_.error("cameras", "no camera " + quote(options_.camera, 64) + " in the drawn scene (ModelOptions::camera, " +
                                   "facet --camera): " + (list.empty() ? std::string("it has none") : "it has " + list),
                    ErrorCode::invalid_argument);
  };
  if (doc_.count("scenes") == 0) {
    if (doc_.count("nodes") > 0) warn("the file has no scenes: nothing to draw (glTF draws only a scene's nodes)");
    return camera_found();
  }
  int scene_index = 0;
  FACET_TRY(f_.index(j, "", "scene", doc_.count("scenes"), scene_index));
  if (doc_.count("scenes") > 1) {
    warn("the file has " + std::to_string(doc_.count("scenes")) + " scenes; scenes[" + std::to_string(scene_index) + "] is drawn");
  }
  FACET_TRY(walk(static_cast<std::size_t>(scene_index)));
  FACET_TRY(finish_rig());
  return camera_found();
}

Status Reader::check_extensions() {
  const Json& j = doc_.json();
  std::vector<std::string> required, used;
  for (auto [key, list] : {std::pair{"extensionsRequired", &required}, std::pair{"extensionsUsed", &used}}) {
    const Json* a = Fields::find(j, key);
    if (!a) continue;
    for (std::size_t i = 0; i < a->size(); ++i) {
      if (!(*a)[i].is_string()) return f_.error(Fields::at(key, i), "expected a string");
      list->push_back((*a)[i].get<std::string>());
    }
  }
  std::string missing;
  for (const std::string& r : required)
    if (!supported_extension(r)) missing += (missing.empty() ? "" : ", ") + quote(r, 64);
  if (!missing.empty()) {
    return f_.error("extensionsRequired", "the file requires extensions facet does not support: " + missing,
                    ErrorCode::unsupported);
  }
  std::string ignored;
  for (const std::string& e : used)
    if (!supported_extension(e)) ignored += (ignored.empty() ? "" : ", ") + quote(e, 64);
  if (!ignored.empty()) warn("extensionsUsed: not supported, ignored: " + ignored);
  return {};
}

// Depth first from the scene's roots, each node's world matrix in double. A node reached twice (a
// cycle, or a node with two parents) is an error: glTF's nodes form a forest.
Status Reader::walk(std::size_t scene_index) {
  const Json& scene = doc_.item("scenes", scene_index);
  const std::string sp = Fields::at("scenes", scene_index);
  const std::size_t node_count = doc_.count("nodes");
  std::vector<char> seen(node_count, 0);
  struct Item {
    const Json* index;
    Eigen::Matrix4d parent;
    std::string path;
  };
  std::vector<Item> stack;
  const Json* roots = nullptr;
  FACET_TRY(f_.array(scene, sp, "nodes", roots));
  if (roots) {
    for (std::size_t r = roots->size(); r-- > 0;) stack.push_back({&(*roots)[r], Eigen::Matrix4d::Identity(), Fields::at(sp + ".nodes", r)});
  }
  while (!stack.empty()) {
    Item item = std::move(stack.back());
    stack.pop_back();
    const Json& iv = *item.index;
    if (!iv.is_number() || !(iv.get<double>() >= 0.0 && iv.get<double>() < double(node_count)) ||
        std::floor(iv.get<double>()) != iv.get<double>()) {
      return f_.error(item.path, "node index " + (iv.is_number() ? format_number(iv.get<double>()) : std::string("(not a number)")) +
                                     " is out of range (" + std::to_string(node_count) + " nodes)");
    }
    const auto n = static_cast<std::size_t>(iv.get<double>());
    const std::string p = Fields::at("nodes", n);
    if (seen[n]) return f_.error(item.path, p + " is reached twice (a cycle, or a node with two parents): glTF's nodes must form trees");
    seen[n] = 1;
    const Json& node = doc_.item("nodes", n);
    Eigen::Matrix4d local;
    FACET_TRY(local_matrix(node, p, local));
    const Eigen::Matrix4d world = item.parent * local;
    if (!world.allFinite()) return f_.error(p, "the world matrix is not finite");
    int mesh = -1, camera = -1, skin = -1;
    FACET_TRY(f_.index(node, p, "mesh", doc_.count("meshes"), mesh));
    FACET_TRY(f_.index(node, p, "camera", doc_.count("cameras"), camera));
    FACET_TRY(f_.index(node, p, "skin", doc_.count("skins"), skin));
    const Json* ext = nullptr;
    FACET_TRY(f_.object(node, p, "extensions", ext));
    const Json* instancing = ext ? Fields::find(*ext, "EXT_mesh_gpu_instancing") : nullptr;
    bool deformed = false;
    if (mesh >= 0) FACET_TRY(deforms(mesh, skin, deformed));
    if (deformed) {
      if (instancing) warn(p + ".extensions.EXT_mesh_gpu_instancing: not read for a skinned or morphed mesh; drawn once");
      FACET_TRY(add_deformed(mesh, skin, n, p, world));
    } else {
      const std::size_t first = out_.scene.objects.size();
      if (mesh >= 0 && instancing) FACET_TRY(add_gpu_instances(mesh, p, world, *instancing));
      if (mesh >= 0 && !instancing) FACET_TRY(add_mesh_instances(mesh, p, world));
      if (animated_) FACET_TRY(place(n, first, world));
      if (skin >= 0) warn(p + ".skin: the node's mesh has no JOINTS_0 and WEIGHTS_0; drawn unskinned");
    }
    const bool had_camera = out_.has_camera;
    if (camera >= 0) FACET_TRY(add_camera(camera, n, p, world));
    if (out_.has_camera && !had_camera) camera_node_ = static_cast<int>(n);
    if (ext) {
      if (const Json* l = Fields::find(*ext, "KHR_lights_punctual")) {
        FACET_TRY(add_light(*l, p, world));
        if (animated_) node_lights_.push_back({static_cast<std::uint32_t>(out_.scene.lights.size() - 1), static_cast<std::uint32_t>(n)});
      }
    }
    const Json* children = nullptr;
    FACET_TRY(f_.array(node, p, "children", children));
    if (children) {
      for (std::size_t c = children->size(); c-- > 0;) stack.push_back({&(*children)[c], world, Fields::at(p + ".children", c)});
    }
  }
  return {};
}

Status Reader::local_matrix(const Json& node, const std::string& p, Eigen::Matrix4d& out) const {
  out.setIdentity();
  const double big = 3.0e38;
  if (Fields::find(node, "matrix")) {
    for (const char* k : {"translation", "rotation", "scale"}) {
      if (Fields::find(node, k)) return f_.error(p, std::string("has both a matrix and a ") + k + ": glTF allows one or the other");
    }
    double m[16];
    FACET_TRY(f_.numbers(node, p, "matrix", 16, m, -big, big));
    for (int i = 0; i < 16; ++i) out(i % 4, i / 4) = m[i];  // column-major
    return {};
  }
  double t[3] = {0, 0, 0}, s[3] = {1, 1, 1}, r[4] = {0, 0, 0, 1};
  FACET_TRY(f_.numbers(node, p, "translation", 3, t, -big, big));
  FACET_TRY(f_.numbers(node, p, "scale", 3, s, -big, big));
  FACET_TRY(f_.numbers(node, p, "rotation", 4, r, -1.0001, 1.0001));
  Eigen::Quaterniond q(r[3], r[0], r[1], r[2]);
  const double norm = q.norm();
  if (!(norm > 1e-6)) return f_.error(p + ".rotation", "expected a unit quaternion, found length " + format_number(norm));
  q.normalize();
  // T * R * S, as glTF composes them.
  out.topLeftCorner<3, 3>() = q.toRotationMatrix() * Eigen::Vector3d(s[0], s[1], s[2]).asDiagonal();
  out.topRightCorner<3, 1>() = Eigen::Vector3d(t[0], t[1], t[2]);
  return {};
}

// Checks that `count` elements of `element_bytes` at `offset` with `stride` fit bufferViews[view].
Status Reader::view_span(int view, std::uint64_t offset, std::uint64_t count, std::size_t element_bytes,
                         std::size_t stride, const std::string& p, const std::uint8_t*& data) const {
  const View& v = doc_.view(static_cast<std::size_t>(view));
  if (count > 0) {
    const double need = double(offset) + double(count - 1) * double(stride) + double(element_bytes);
    if (need > double(v.length)) {
      return f_.error(p, std::to_string(count) + " elements of " + std::to_string(element_bytes) + " bytes (stride " +
                             std::to_string(stride) + ") from byte " + std::to_string(offset) + " need " + format_number(need) +
                             " bytes; bufferViews[" + std::to_string(view) + "] has " + std::to_string(v.length));
    }
  }
  data = v.data + offset;
  return {};
}

// Accessor `index` as count x components doubles, sparse substitution applied, checked against
// the forms `semantic` may take (null: indices).
Status Reader::read_accessor(int index, const std::string& p, const char* semantic, Values& out) {
  if (index < 0 || static_cast<std::size_t>(index) >= doc_.count("accessors")) {
    return f_.error(p, "accessor index " + std::to_string(index) + " is out of range (" +
                           std::to_string(doc_.count("accessors")) + " accessors)");
  }
  const Json& a = doc_.item("accessors", static_cast<std::size_t>(index));
  const std::string ap = Fields::at("accessors", static_cast<std::size_t>(index));
  std::uint64_t ct = 0, n = 0, offset = 0;
  std::string type;
  bool normalized = false;
  FACET_TRY(f_.integer(a, ap, "componentType", ct, kByte, kFloat, true));
  FACET_TRY(f_.integer(a, ap, "count", n, 1, std::uint64_t{1} << 40, true));
  FACET_TRY(f_.string(a, ap, "type", type, true));
  FACET_TRY(f_.boolean(a, ap, "normalized", normalized));
  FACET_TRY(f_.integer(a, ap, "byteOffset", offset, 0, std::uint64_t{1} << 40));
  const int component = static_cast<int>(ct);
  const int csize = component_size(component);
  if (csize == 0) return f_.error(ap + ".componentType", "unknown component type " + std::to_string(ct));
  const int components = components_of(type);
  if (components == 0) return f_.error(ap + ".type", "unknown type " + quote(type, 16));
  if (normalized && (component == kUnsignedInt || component == kFloat)) {
    return f_.error(ap + ".normalized", std::string("true is not allowed for ") + component_name(component) + " components");
  }
  // glTF 2.0, 3.6.2.4: an accessor's offset is a multiple of its component's size.
  if (offset % std::uint64_t(csize) != 0) {
    return f_.error(ap + ".byteOffset", std::to_string(offset) + " is not a multiple of the component size (" + std::to_string(csize) + ")");
  }
  const char* use = semantic ? semantic : "indices";
  if (!allowed(use, components, component, normalized)) {
    return f_.error(ap, type + " of " + (normalized ? "normalized " : "") + component_name(component) + " cannot be used for " + p);
  }
  int view = -1;
  FACET_TRY(f_.index(a, ap, "bufferView", doc_.view_count(), view));
  const std::size_t element = std::size_t(csize) * std::size_t(components);
  const std::uint8_t* data = nullptr;
  std::size_t stride = element;
  // Where the bytes are, before any memory is taken for them.
  if (view >= 0) {
    const View& v = doc_.view(static_cast<std::size_t>(view));
    stride = v.stride != 0 ? v.stride : element;
    if (stride < element) {
      return f_.error(ap, "bufferViews[" + std::to_string(view) + "].byteStride " + std::to_string(stride) +
                              " is smaller than an element (" + std::to_string(element) + " bytes)");
    }
    FACET_TRY(view_span(view, offset, n, element, stride, ap, data));
  }
  FACET_TRY(reserve(n * std::uint64_t(components) * 8, ap));
  out.components = components;
  out.v.assign(static_cast<std::size_t>(n) * std::size_t(components), 0.0);
  if (data) {
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < components; ++c)
        out.v[i * components + c] = fetch(data + i * stride + std::size_t(c) * csize, component, normalized);
  }
  const Json* sparse = nullptr;
  FACET_TRY(f_.object(a, ap, "sparse", sparse));
  if (sparse) {
    const std::string sp = ap + ".sparse";
    std::uint64_t count = 0;
    FACET_TRY(f_.integer(*sparse, sp, "count", count, 1, n, true));
    const Json *ind = nullptr, *val = nullptr;
    FACET_TRY(f_.object(*sparse, sp, "indices", ind));
    FACET_TRY(f_.object(*sparse, sp, "values", val));
    if (!ind || !val) return f_.error(sp, "needs indices and values");
    std::uint64_t itype = 0, io = 0, vo = 0;
    int iv = -1, vv = -1;
    FACET_TRY(f_.integer(*ind, sp + ".indices", "componentType", itype, 0, kFloat, true));
    if (itype != kUnsignedByte && itype != kUnsignedShort && itype != kUnsignedInt) {
      return f_.error(sp + ".indices.componentType", "expected an unsigned integer type");
    }
    FACET_TRY(f_.index(*ind, sp + ".indices", "bufferView", doc_.view_count(), iv, true));
    FACET_TRY(f_.integer(*ind, sp + ".indices", "byteOffset", io, 0, std::uint64_t{1} << 40));
    FACET_TRY(f_.index(*val, sp + ".values", "bufferView", doc_.view_count(), vv, true));
    FACET_TRY(f_.integer(*val, sp + ".values", "byteOffset", vo, 0, std::uint64_t{1} << 40));
    const int isize = component_size(static_cast<int>(itype));
    const std::uint8_t *ip = nullptr, *vp = nullptr;
    if (io % std::uint64_t(isize) != 0) return f_.error(sp + ".indices.byteOffset", "not a multiple of the component size");
    if (vo % std::uint64_t(csize) != 0) return f_.error(sp + ".values.byteOffset", "not a multiple of the component size");
    FACET_TRY(view_span(iv, io, count, std::size_t(isize), std::size_t(isize), sp + ".indices", ip));
    FACET_TRY(view_span(vv, vo, count, element, element, sp + ".values", vp));
    for (std::size_t k = 0; k < count; ++k) {
      const double target = fetch(ip + k * isize, static_cast<int>(itype), false);
      if (!(target < double(n))) {
        return f_.error(sp + ".indices", "index " + format_number(target) + " is out of range (count " + std::to_string(n) + ")");
      }
      const auto t = static_cast<std::size_t>(target);
      for (int c = 0; c < components; ++c) out.v[t * components + c] = fetch(vp + k * element + std::size_t(c) * csize, component, normalized);
    }
  }
  for (double v : out.v) {
    if (!std::isfinite(v) || std::abs(v) > 3.0e38) return f_.error(ap, "holds a value that is not a finite float");
  }
  return {};
}

Status Reader::add_mesh_instances(int mesh_id, const std::string& node_path, const Eigen::Matrix4d& world) {
  const Json& mesh = doc_.item("meshes", static_cast<std::size_t>(mesh_id));
  const std::string mp = Fields::at("meshes", static_cast<std::size_t>(mesh_id));
  const Json* prims = nullptr;
  FACET_TRY(f_.array(mesh, mp, "primitives", prims));
  if (!prims || prims->empty()) return f_.error(mp + ".primitives", "required, an array of at least one primitive");
  const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
  if (!(std::abs(linear.determinant()) > 1e-30)) {
    warn(node_path + ": its world matrix is singular (a zero scale); its mesh is not drawn");
    return {};
  }
  for (std::size_t k = 0; k < prims->size(); ++k) {
    std::uint32_t mesh_index = 0, material_index = 0;
    bool double_sided = false;
    FACET_TRY(primitive(static_cast<std::size_t>(mesh_id), k, mesh_index, material_index, double_sided));
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

// EXT_mesh_gpu_instancing: the node's mesh once per instance, at world x T x R x S of the
// instance's TRANSLATION, ROTATION and SCALE (each optional, all of one count).
Status Reader::add_gpu_instances(int mesh_id, const std::string& node_path, const Eigen::Matrix4d& world, const Json& x) {
  const std::string xp = node_path + ".extensions.EXT_mesh_gpu_instancing";
  FACET_TRY(f_.object(x, xp));
  const Json* attributes = nullptr;
  FACET_TRY(f_.object(x, xp, "attributes", attributes));
  if (!attributes) return f_.error(xp + ".attributes", "required, missing");
  Values t, r, s;
  std::size_t count = 0;
  for (auto [key, values] : {std::pair{"TRANSLATION", &t}, std::pair{"ROTATION", &r}, std::pair{"SCALE", &s}}) {
    int index = -1;
    const std::string ap = xp + ".attributes." + key;
    FACET_TRY(f_.index(*attributes, xp + ".attributes", key, doc_.count("accessors"), index));
    if (index < 0) continue;
    FACET_TRY(read_accessor(index, ap, key, *values));
    if (count != 0 && values->count() != count) {
      return f_.error(ap, "has " + std::to_string(values->count()) + " instances where another attribute has " + std::to_string(count));
    }
    count = values->count();
  }
  if (count == 0) return f_.error(xp + ".attributes", "expected at least one of TRANSLATION, ROTATION and SCALE");
  const Json& mesh = doc_.item("meshes", static_cast<std::size_t>(mesh_id));
  const Json* prims = Fields::find(mesh, "primitives");
  const std::size_t per_instance = prims && prims->is_array() ? prims->size() : 1;
  FACET_TRY(reserve(std::uint64_t(count) * per_instance * sizeof(Instance), xp));
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::Matrix4d local = Eigen::Matrix4d::Identity();
    Eigen::Vector3d scale(1, 1, 1);
    if (!s.v.empty()) scale = Eigen::Vector3d(s.v[3 * i], s.v[3 * i + 1], s.v[3 * i + 2]);
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    if (!r.v.empty()) {
      Eigen::Quaterniond q(r.v[4 * i + 3], r.v[4 * i], r.v[4 * i + 1], r.v[4 * i + 2]);
      if (!(q.norm() > 1e-6)) {
        return f_.error(xp + ".attributes.ROTATION", "instance " + std::to_string(i) + ": expected a unit quaternion");
      }
      rotation = q.normalized().toRotationMatrix();
    }
    local.topLeftCorner<3, 3>() = rotation * scale.asDiagonal();
    if (!t.v.empty()) local.topRightCorner<3, 1>() = Eigen::Vector3d(t.v[3 * i], t.v[3 * i + 1], t.v[3 * i + 2]);
    const Eigen::Matrix4d model = world * local;
    if (!model.allFinite()) return f_.error(xp, "instance " + std::to_string(i) + ": the world matrix is not finite");
    FACET_TRY(add_mesh_instances(mesh_id, node_path + " (instance " + std::to_string(i) + ")", model));
  }
  return {};
}

// The facet mesh of meshes[m].primitives[k] (made once, shared by every node that uses it).
Status Reader::primitive(std::size_t m, std::size_t k, std::uint32_t& mesh_index, std::uint32_t& material_index,
                         bool& double_sided) {
  const auto key = std::make_pair(m, k);
  if (auto it = primitives_.find(key); it != primitives_.end()) {
    std::tie(mesh_index, material_index, double_sided) = it->second;
    return {};
  }
  const Json& gm = doc_.item("meshes", m);
  const Json& prim = gm["primitives"][k];
  const std::string p = Fields::at("meshes", m) + ".primitives[" + std::to_string(k) + "]";
  FACET_TRY(f_.object(prim, p));
  auto skip = [&](const std::string& why) -> Status {
    warn(p + ": " + why);
    primitives_[key] = {kSkipped, 0, false};
    mesh_index = kSkipped;
    return {};
  };
  std::uint64_t mode = 4;
  FACET_TRY(f_.integer(prim, p, "mode", mode, 0, 6));
  static constexpr const char* kModes[] = {"points", "lines", "line loops", "line strips"};
  if (mode <= 3) return skip(std::string(kModes[mode]) + " (mode " + std::to_string(mode) + ") are not drawn: facet draws triangles only");
  // The material first: vertex colours are multiplied by its base colour.
  int material_id = -1;
  FACET_TRY(f_.index(prim, p, "material", doc_.count("materials"), material_id));
  MaterialInfo info;
  FACET_TRY(material(material_id, info));
  const Json* attrs = nullptr;
  FACET_TRY(f_.object(prim, p, "attributes", attrs));
  if (!attrs) return f_.error(p + ".attributes", "required, missing");
  std::map<std::string, int> attributes;
  for (const auto& [name, value] : attrs->items()) {
    int a = -1;
    FACET_TRY(f_.index(*attrs, p + ".attributes", name, doc_.count("accessors"), a, true));
    attributes[name] = a;
    if (name != "POSITION" && name != "NORMAL" && name != "TEXCOORD_0" && name != "TEXCOORD_1" && name != "COLOR_0" && name != "TANGENT" &&
        name != "JOINTS_0" && name != "JOINTS_1" && name != "WEIGHTS_0" && name != "WEIGHTS_1" && name.rfind("_", 0) != 0) {
      const std::string shown = Fields::dot(p + ".attributes", name);
      if (ignored_attributes_.insert(name).second) warn(shown + ": not used by facet");
    }
  }
  if (!attributes.count("POSITION")) return f_.error(p + ".attributes", "no POSITION attribute");
  // Values of each attribute facet reads, from accessors or from the Draco-compressed data.
  std::map<std::string, Values> values;
  std::vector<std::uint32_t> idxs;
  bool have_indices = false;
  const Json* ext = nullptr;
  FACET_TRY(f_.object(prim, p, "extensions", ext));
  const Json* draco = ext ? Fields::find(*ext, "KHR_draco_mesh_compression") : nullptr;
  if (draco) {
    // Draco holds triangle faces: a strip or fan mode would read them again as something else.
    if (mode != 4) return f_.error(p + ".mode", "a Draco-compressed primitive holds triangles (mode 4), found mode " + std::to_string(mode));
    FACET_TRY(draco_attributes(*draco, p + ".extensions.KHR_draco_mesh_compression", attributes, values, idxs));
    // Each decoded attribute has as many components as its accessor says (COLOR_0: VEC3 or VEC4).
    auto accessor_components = [&](int index) -> int {
      if (index < 0 || static_cast<std::size_t>(index) >= doc_.count("accessors")) return 0;
      const Json* t = Fields::find(doc_.item("accessors", static_cast<std::size_t>(index)), "type");
      return t && t->is_string() ? components_of(t->get<std::string>()) : 0;
    };
    for (const auto& [name, accessor] : attributes) {
      const auto it = values.find(name);
      if (it == values.end()) continue;
      const int want = accessor_components(accessor);
      if (want != 0 && it->second.components != want) {
        return f_.error(p + ".attributes." + name, "the Draco attribute has " + std::to_string(it->second.components) +
                                                        " components, its accessor " + std::to_string(want));
      }
    }
    have_indices = true;
  } else {
    for (const char* name : {"POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "TANGENT"}) {
      if (std::string(name) == "TANGENT" && !info.normal_map) continue;  // read only for a normal map
      if (auto it = attributes.find(name); it != attributes.end()) {
        FACET_TRY(read_accessor(it->second, p + ".attributes." + name, name, values[name]));
      }
    }
  }
  const Values& pos = values["POSITION"];
  const std::size_t n = pos.count();
  if (n > 0xffffffffu) return f_.error(p + ".attributes.POSITION", "more vertices than 32-bit indices reach");
  FACET_TRY(reserve(std::uint64_t(n) * (2 * sizeof(Vec3) + sizeof(Vec2) + sizeof(Color3)), p));
  Mesh mesh;
  mesh.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) mesh.positions[i] = Vec3(float(pos.v[3 * i]), float(pos.v[3 * i + 1]), float(pos.v[3 * i + 2]));
  for (const char* name : {"NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "TANGENT"}) {
    if (values.count(name) && values[name].count() != n) return f_.error(p + ".attributes." + name, "count differs from POSITION's");
  }
  if (values.count("TANGENT") && values.count("NORMAL")) {  // without NORMAL the normals are the faces': tangents generated
    const std::vector<double>& v = values["TANGENT"].v;
    FACET_TRY(reserve(std::uint64_t(n) * sizeof(Vec4), p + ".attributes.TANGENT"));
    mesh.tangents.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double w = v[4 * i + 3];
      // glTF: w is +1 or -1; within 1e-3 of either is taken as it (quantized files round).
      if (!(std::abs(std::abs(w) - 1.0) <= 1e-3)) {
        warn(p + ".attributes.TANGENT: element " + std::to_string(i) + " has w = " + format_number(w) +
             ", not +1 or -1; tangents generated instead (MikkTSpace)");
        mesh.tangents.clear();
        break;
      }
      mesh.tangents[i] = Vec4(float(v[4 * i]), float(v[4 * i + 1]), float(v[4 * i + 2]), w > 0 ? 1.0f : -1.0f);
    }
  }
  if (values.count("NORMAL")) {
    const std::vector<double>& v = values["NORMAL"].v;
    mesh.normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 d{static_cast<float>(v[3 * i]), static_cast<float>(v[3 * i + 1]), static_cast<float>(v[3 * i + 2])};
      const float len = d.norm();
      mesh.normals[i] = len > 1e-20f ? Vec3(d / len) : Vec3::Zero();
    }
  }
  if (values.count("TEXCOORD_0")) {
    const std::vector<double>& v = values["TEXCOORD_0"].v;
    const double* t = info.uv_transform.m;
    mesh.uvs.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      // KHR_texture_transform in glTF's coordinates, then glTF's (0, 0), the image's top-left
      // corner, to facet's (GL's) bottom-left.
      const double u = v[2 * i], w = v[2 * i + 1];
      const double tu = t[0] * u + t[1] * w + t[2], tv = t[3] * u + t[4] * w + t[5];
      mesh.uvs[i] = Vec2(float(tu), float(1.0 - tv));
    }
  }
  if (values.count("TEXCOORD_1")) {  // a second uv set: the lightmap's coordinates (Mesh::lightmap_uvs)
    const std::vector<double>& v = values["TEXCOORD_1"].v;
    FACET_TRY(reserve(std::uint64_t(n) * sizeof(Vec2), p + ".attributes.TEXCOORD_1"));
    mesh.lightmap_uvs.resize(n);
    for (std::size_t i = 0; i < n; ++i) mesh.lightmap_uvs[i] = Vec2(float(v[2 * i]), float(1.0 - v[2 * i + 1]));
  }
  if (values.count("COLOR_0")) {
    const Values& col = values["COLOR_0"];
    const int comps = col.components;
    mesh.colors.resize(n);
    bool alpha_dropped = false;
    for (std::size_t i = 0; i < n; ++i) {
      Color3 c{static_cast<float>(col.v[i * comps]), static_cast<float>(col.v[i * comps + 1]), static_cast<float>(col.v[i * comps + 2])};
      // facet's vertex colours replace the material's ambient and diffuse colour; glTF's multiply
      // the base colour: the product is taken here.
      mesh.colors[i] = c.cwiseProduct(info.vertex_color_scale).cwiseMax(0.0f).cwiseMin(1.0f);
      if (comps == 4 && col.v[i * comps + 3] < 254.5 / 255.0) alpha_dropped = true;  // below what 8-bit alpha rounds to 1
    }
    if (alpha_dropped && info.uses_alpha) warn(p + ".attributes.COLOR_0: vertex alpha is not supported; ignored (colours are used)");
  }
  values.clear();
  if (!have_indices) {
    int ind = -1;
    FACET_TRY(f_.index(prim, p, "indices", doc_.count("accessors"), ind));
    if (ind >= 0) {
      Values v;
      FACET_TRY(read_accessor(ind, p + ".indices", nullptr, v));
      idxs.resize(v.v.size());
      for (std::size_t i = 0; i < v.v.size(); ++i) {
        if (!(v.v[i] < double(n))) {
          return f_.error(p + ".indices", "index " + format_number(v.v[i]) + " (element " + std::to_string(i) +
                                              ") is out of range (" + std::to_string(n) + " vertices)");
        }
        idxs[i] = static_cast<std::uint32_t>(v.v[i]);
      }
    } else {
      idxs.resize(n);
      for (std::size_t i = 0; i < n; ++i) idxs[i] = static_cast<std::uint32_t>(i);
    }
  }
  for (const std::uint32_t i : idxs) {
    if (i >= n) return f_.error(p, "a vertex index " + std::to_string(i) + " is out of range (" + std::to_string(n) + " vertices)");
  }
  if (mode == 4) {
    if (idxs.size() % 3 != 0) warn(p + ": " + std::to_string(idxs.size() % 3) + " trailing indices do not make a triangle; ignored");
    for (std::size_t i = 0; i + 2 < idxs.size(); i += 3) mesh.triangles.push_back({idxs[i], idxs[i + 1], idxs[i + 2]});
  } else if (mode == 5) {
    for (std::size_t i = 0; i + 2 < idxs.size(); ++i) {
      if (i % 2 == 0) mesh.triangles.push_back({idxs[i], idxs[i + 1], idxs[i + 2]});
      else mesh.triangles.push_back({idxs[i], idxs[i + 2], idxs[i + 1]});
    }
  } else {
    for (std::size_t i = 1; i + 1 < idxs.size(); ++i) mesh.triangles.push_back({idxs[i], idxs[i + 1], idxs[0]});
  }
  if (mesh.triangles.empty()) return skip("no triangles; not drawn");
  // A mesh that may be deformed keeps which file vertex each of its vertices comes from (normals
  // and tangents made here may split vertices): its joints, weights and targets are the file's.
  std::vector<std::uint32_t> origin;
  const bool may_deform = Fields::find(prim, "targets") || attributes.count("JOINTS_0");
  if (may_deform) {
    FACET_TRY(reserve(std::uint64_t(n) * 8, p));
    origin.resize(n);
    for (std::size_t i = 0; i < n; ++i) origin[i] = static_cast<std::uint32_t>(i);
  }
  std::vector<std::uint32_t>* keep = may_deform ? &origin : nullptr;
  // glTF: without normals, flat shading (each triangle its own normal).
  if (mesh.normals.empty()) compute_vertex_normals(mesh, 0.0f, keep);
  if (info.needs_uvs && mesh.uvs.empty()) {
    warn(p + ": its material is textured but it has no TEXCOORD_0; drawn untextured");
    info.index = untextured_twin(info.index);
    mesh.tangents.clear();
  } else if (info.normal_map && mesh.tangents.empty()) {
    FACET_TRY(reserve(std::uint64_t(n) * sizeof(Vec4), p + ".attributes.TANGENT"));
    if (Status s = generate_tangents(mesh, keep); !s.ok()) return f_.error(p, s.message(), s.code());
  }
  if (may_deform) origins_[key] = std::move(origin);
  std::string name;
  FACET_TRY(f_.string(gm, Fields::at("meshes", m), "name", name));
  NamedMesh named;
  named.name = (name.empty() ? Fields::at("meshes", m) : name) +
               (gm["primitives"].size() > 1 ? "#" + std::to_string(k) : std::string());
  named.mesh = std::move(mesh);
  out_.scene.meshes.push_back(std::move(named));
  mesh_index = static_cast<std::uint32_t>(out_.scene.meshes.size() - 1);
  material_index = info.index;
  double_sided = info.double_sided;
  primitives_[key] = {mesh_index, material_index, double_sided};
  return {};
}

}  // namespace gltf

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

namespace {

Result<Model> parse_in(std::span<const std::uint8_t> bytes, const std::string& source_name, const io::AssetFolder& folder,
                       const ModelOptions& options) {
  try {
    Result<gltf::Document> doc = gltf::Document::parse(bytes, source_name);
    if (!doc) return doc.status();
    std::uint64_t used = bytes.size();
    FACET_TRY(doc->load_buffers(folder, options.memory_budget_bytes, used));
    Model model;
    // glTF asks renderers to draw BLEND primitives sorted back to front (alphaMode's notes).
    model.scene.transparent_order = TransparentOrder::back_to_front;
    gltf::Reader reader(*doc, folder, options, model);
    FACET_TRY(reader.read(used));
    // Skinned meshes are drawn where their joints put them, even at rest.
    if (model.rig) FACET_TRY(pose_model(model, 0.0, model.pose));
    // As a glTF viewer shows it: the neutral operator, and lights in physical units metered.
    model.scene.display.tone_mapping = ToneMapping::neutral;
    model.scene.display.automatic = model.has_lights;
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

}  // namespace

Result<Model> parse_gltf(std::span<const std::uint8_t> bytes, const std::string& source_name, const std::string& base_dir,
                         const ModelOptions& options) {
  const io::AssetFolder folder(options.assets, base_dir);
  return parse_in(bytes, source_name, folder, options);
}

Result<Model> load_gltf(const std::string& path, const ModelOptions& options) {
  Result<std::string> text = io::read_named_by_host(options.assets, path, "glTF file",
                                                    options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes);
  if (!text) return text.status();
  const io::AssetFolder folder(options.assets, std::filesystem::path(path).parent_path().string());
  return parse_in(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text->data()), text->size()), path,
                  folder, options);
}

}  // namespace facet
