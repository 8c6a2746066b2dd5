// glTF 2.0 import: what moves (scene/rig.hpp): skins, morph targets, animations and the node
// tree they act on. Every field is checked and named by its JSON path; every buffer taken is
// counted against the memory budget before it is allocated.
#include <algorithm>
#include <cmath>
#include <deque>

#include "common/format.hpp"
#include "common/try.hpp"
#include "content/gltf_reader.hpp"

namespace facet::gltf {
namespace {

// The most joints a skin may have (JOINTS_n are 8- or 16-bit) and morph targets a mesh may have.
constexpr std::size_t kMaxJoints = 65536;
constexpr std::size_t kMaxTargets = 256;
// A vertex whose weights add up to further than this from 1 is renormalised (with a warning):
// more than the rounding of four 8-bit normalised weights (4 x 1/510).
constexpr double kWeightTolerance = 0.01;

std::size_t target_count(const Json& mesh) {
  const Json* prims = Fields::find(mesh, "primitives");
  if (!prims || !prims->is_array() || prims->empty() || !(*prims)[0].is_object()) return 0;
  const Json* t = Fields::find((*prims)[0], "targets");
  return t && t->is_array() ? t->size() : 0;
}

}  // namespace

Status Reader::deforms(int mesh, int skin, bool& out) {
  out = false;
  const Json* prims = Fields::find(doc_.item("meshes", static_cast<std::size_t>(mesh)), "primitives");
  if (!prims || !prims->is_array()) return {};  // add_mesh_instances names it
  const std::size_t targets = target_count(doc_.item("meshes", static_cast<std::size_t>(mesh)));
  for (std::size_t k = 0; k < prims->size(); ++k) {
    const Json& prim = (*prims)[k];
    if (!prim.is_object()) continue;
    const Json* t = Fields::find(prim, "targets");
    if (t) {
      const std::string tp = Fields::at("meshes", std::size_t(mesh)) + ".primitives[" + std::to_string(k) + "].targets";
      if (!t->is_array()) return f_.error(tp, "expected an array");
      if (t->size() != targets) {
        return f_.error(tp, std::to_string(t->size()) + " morph targets where primitives[0] has " + std::to_string(targets) +
                                " (glTF: every primitive of a mesh has as many)");
      }
      if (t->size() > kMaxTargets) return f_.error(tp, std::to_string(t->size()) + " morph targets, at most " + std::to_string(kMaxTargets));
      out = out || !t->empty();
    }
    const Json* a = Fields::find(prim, "attributes");
    if (skin >= 0 && a && a->is_object() && Fields::find(*a, "JOINTS_0") && Fields::find(*a, "WEIGHTS_0")) out = true;
  }
  return {};
}

Status Reader::read_skin(int skin, int& rig_skin) {
  if (auto it = skins_.find(skin); it != skins_.end()) {
    rig_skin = it->second;
    return {};
  }
  const std::string sp = Fields::at("skins", static_cast<std::size_t>(skin));
  const Json& s = doc_.item("skins", static_cast<std::size_t>(skin));
  FACET_TRY(f_.object(s, sp));
  const Json* joints = nullptr;
  FACET_TRY(f_.array(s, sp, "joints", joints));
  if (!joints || joints->empty()) return f_.error(sp + ".joints", "required, an array of at least one node");
  if (joints->size() > kMaxJoints) {
    return f_.error(sp + ".joints", std::to_string(joints->size()) + " joints, at most " + std::to_string(kMaxJoints));
  }
  FACET_TRY(reserve(std::uint64_t(joints->size()) * (sizeof(Eigen::Matrix4d) + 4 + 48), sp + ".joints"));
  Rig::Skin out;
  out.joints.resize(joints->size());
  const std::size_t nodes = doc_.count("nodes");
  for (std::size_t j = 0; j < joints->size(); ++j) {
    const Json& v = (*joints)[j];
    if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= nodes) {
      return f_.error(Fields::at(sp + ".joints", j), "expected a node index below " + std::to_string(nodes));
    }
    out.joints[j] = static_cast<std::uint32_t>(v.get<std::uint64_t>());
  }
  out.inverse_bind.assign(joints->size(), Eigen::Matrix4d::Identity());
  int ibm = -1;
  FACET_TRY(f_.index(s, sp, "inverseBindMatrices", doc_.count("accessors"), ibm));
  if (ibm >= 0) {
    Values v;
    FACET_TRY(read_accessor(ibm, sp + ".inverseBindMatrices", "MATRIX", v));
    if (v.count() < joints->size()) {
      return f_.error(sp + ".inverseBindMatrices", std::to_string(v.count()) + " matrices for " + std::to_string(joints->size()) + " joints");
    }
    for (std::size_t j = 0; j < joints->size(); ++j)
      for (int e = 0; e < 16; ++e) out.inverse_bind[j](e % 4, e / 4) = v.v[16 * j + std::size_t(e)];  // column-major
  }
  SkinInfo info;
  FACET_TRY(f_.string(s, sp, "name", info.name));
  if (info.name.empty()) info.name = sp;
  info.joints = joints->size();
  info.influences = 0;
  out_.motion.skins.push_back(info);
  rig_->skins.push_back(std::move(out));
  rig_skin = static_cast<int>(rig_->skins.size() - 1);
  skins_[skin] = rig_skin;
  return {};
}

// The file's per-vertex values (count_in of them) for the mesh's vertices (origin[i]: the file's).
Status Reader::read_skin_weights(std::size_t m, std::size_t k, const std::vector<std::uint32_t>& origin, std::size_t joints,
                                 Rig::Deform& d) {
  const Json& prim = doc_.item("meshes", m)["primitives"][k];
  const std::string p = Fields::at("meshes", m) + ".primitives[" + std::to_string(k) + "].attributes";
  const Json& attrs = prim["attributes"];
  const int sets = Fields::find(attrs, "JOINTS_1") && Fields::find(attrs, "WEIGHTS_1") ? 2 : 1;
  if (sets == 1 && (Fields::find(attrs, "JOINTS_1") || Fields::find(attrs, "WEIGHTS_1"))) {
    warn(p + ": JOINTS_1 without WEIGHTS_1 (or the reverse); 4 influences used");
  }
  const std::size_t n = d.count, influences = 4 * std::size_t(sets);
  FACET_TRY(reserve(std::uint64_t(n) * influences * 6, p));
  d.influences = static_cast<int>(influences);
  d.joints.assign(influences * n, 0);
  d.weights.assign(influences * n, 0.0f);
  std::size_t file_count = 0;
  for (int set = 0; set < sets; ++set) {
    Values jv, wv;
    const std::string jn = "JOINTS_" + std::to_string(set), wn = "WEIGHTS_" + std::to_string(set);
    int ja = -1, wa = -1;
    FACET_TRY(f_.index(attrs, p, jn, doc_.count("accessors"), ja, true));
    FACET_TRY(f_.index(attrs, p, wn, doc_.count("accessors"), wa, true));
    FACET_TRY(read_accessor(ja, p + "." + jn, "JOINTS", jv));
    FACET_TRY(read_accessor(wa, p + "." + wn, "WEIGHTS", wv));
    file_count = jv.count();
    if (wv.count() != file_count) return f_.error(p + "." + wn, "count differs from " + jn + "'s");
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t src = origin[i];
      if (src >= file_count) return f_.error(p + "." + jn, "count differs from POSITION's");
      for (int c = 0; c < 4; ++c) {
        const double w = wv.v[4 * src + std::size_t(c)], j = jv.v[4 * src + std::size_t(c)];
        if (w < 0.0) return f_.error(p + "." + wn, "element " + std::to_string(src) + " has a negative weight " + format_number(w));
        const std::size_t slot = std::size_t(4 * set + c) * n + i;
        if (j >= double(joints)) {
          if (w > 0.0) {
            return f_.error(p + "." + jn, "element " + std::to_string(src) + ": joint " + format_number(j) + " is out of range (the skin has " +
                                              std::to_string(joints) + " joints)");
          }
          continue;  // no weight: joint 0, times zero
        }
        d.joints[slot] = static_cast<std::uint16_t>(j);
        d.weights[slot] = static_cast<float>(w);
      }
    }
  }
  std::size_t renormalised = 0, weightless = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (std::size_t c = 0; c < influences; ++c) sum += d.weights[c * n + i];
    if (sum == 0.0) {
      ++weightless;
    } else if (std::abs(sum - 1.0) > kWeightTolerance) {
      ++renormalised;
      for (std::size_t c = 0; c < influences; ++c) d.weights[c * n + i] = static_cast<float>(d.weights[c * n + i] / sum);
    }
  }
  if (renormalised) {
    warn(p + ".WEIGHTS_0: " + std::to_string(renormalised) + " vertices' weights do not add up to 1 (within " +
         format_number(kWeightTolerance) + "); renormalised");
  }
  if (weightless) warn(p + ".WEIGHTS_0: " + std::to_string(weightless) + " vertices have no weight; drawn at the origin, as three.js draws them");
  return {};
}

Status Reader::read_targets(std::size_t m, std::size_t k, const std::vector<std::uint32_t>& origin, Rig::Deform& d) {
  const Json& prim = doc_.item("meshes", m)["primitives"][k];
  const std::string tp = Fields::at("meshes", m) + ".primitives[" + std::to_string(k) + "].targets";
  const Json& targets = prim["targets"];
  const std::size_t n = d.count;
  for (std::size_t t = 0; t < targets.size(); ++t) {
    const std::string p = Fields::at(tp, t);
    FACET_TRY(f_.object(targets[t], p));
    FACET_TRY(reserve(std::uint64_t(n) * 9 * sizeof(float), p));
    std::vector<float> streams(9 * n, 0.0f);
    std::uint8_t kinds = 0;
    const char* names[3] = {"POSITION", "NORMAL", "TANGENT"};
    const char* semantics[3] = {"TARGET_POSITION", "TARGET_NORMAL", "TARGET_TANGENT"};
    for (int group = 0; group < 3; ++group) {
      int a = -1;
      FACET_TRY(f_.index(targets[t], p, names[group], doc_.count("accessors"), a));
      if (a < 0 || d.rest[3 * group].empty()) continue;
      Values v;
      FACET_TRY(read_accessor(a, p + "." + names[group], semantics[group], v));
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t src = origin[i];
        if (src >= v.count()) return f_.error(p + "." + names[group], "count differs from POSITION's");
        for (int c = 0; c < 3; ++c) streams[std::size_t(3 * group + c) * n + i] = static_cast<float>(v.v[3 * src + std::size_t(c)]);
      }
      kinds |= std::uint8_t(1u << group);
    }
    d.targets.push_back(std::move(streams));
    d.target_kinds.push_back(kinds);
  }
  return {};
}

Status Reader::add_deformed(int mesh_id, int skin, std::size_t node, const std::string& node_path, const Eigen::Matrix4d& world) {
  int rig_skin = -1;
  if (skin >= 0) FACET_TRY(read_skin(skin, rig_skin));
  const Json& mesh = doc_.item("meshes", static_cast<std::size_t>(mesh_id));
  const std::size_t prims = mesh["primitives"].size();
  for (std::size_t k = 0; k < prims; ++k) {
    std::uint32_t mesh_index = 0, material_index = 0;
    bool double_sided = false;
    FACET_TRY(primitive(static_cast<std::size_t>(mesh_id), k, mesh_index, material_index, double_sided));
    if (mesh_index == kSkipped) continue;
    const auto origin = origins_.find({static_cast<std::size_t>(mesh_id), k});
    const Json& prim = mesh["primitives"][k];
    const Json* attrs = Fields::find(prim, "attributes");
    const bool skinned = rig_skin >= 0 && attrs && Fields::find(*attrs, "JOINTS_0") && Fields::find(*attrs, "WEIGHTS_0");
    const Json* targets = Fields::find(prim, "targets");
    const bool morphed = targets && !targets->empty();
    // Placed by the node's matrix (a skinned mesh is placed by its joints instead): a singular one
    // draws nothing, as add_mesh_instances says.
    if (!skinned && !(std::abs(world.topLeftCorner<3, 3>().determinant()) > 1e-30)) {
      warn(node_path + ": its world matrix is singular (a zero scale); its mesh is not drawn");
      continue;
    }
    if (origin == origins_.end() || (!skinned && !morphed)) {  // this primitive is drawn rigid
      Instance inst;
      inst.mesh = mesh_index, inst.material = material_index, inst.double_sided = double_sided;
      inst.model = world.cast<float>();
      if (animated_) rig_->placed.push_back({static_cast<std::uint32_t>(out_.scene.objects.size()), static_cast<std::uint32_t>(node)});
      out_.scene.objects.push_back(inst);
      continue;
    }
    const Mesh& rest = out_.scene.meshes[mesh_index].mesh;
    Rig::Deform d;
    d.node = static_cast<std::uint32_t>(node);
    d.skin = skinned ? rig_skin : -1;
    d.count = rest.positions.size();
    const std::size_t n = d.count;
    FACET_TRY(reserve(std::uint64_t(n) * (9 * sizeof(float) + sizeof(Vec3) * 2 + sizeof(Vec4) + sizeof(Vec2) * 2 + sizeof(Color3)),
                      node_path + ".mesh"));
    for (int c = 0; c < 3; ++c) {
      d.rest[c].resize(n);
      for (std::size_t i = 0; i < n; ++i) d.rest[c][i] = rest.positions[i][c];
      if (rest.normals.size() == n) {
        d.rest[3 + c].resize(n);
        for (std::size_t i = 0; i < n; ++i) d.rest[3 + c][i] = rest.normals[i][c];
      }
      if (rest.tangents.size() == n) {
        d.rest[6 + c].resize(n);
        for (std::size_t i = 0; i < n; ++i) d.rest[6 + c][i] = rest.tangents[i][c];
      }
    }
    if (morphed) FACET_TRY(read_targets(static_cast<std::size_t>(mesh_id), k, origin->second, d));
    if (skinned) {
      FACET_TRY(read_skin_weights(static_cast<std::size_t>(mesh_id), k, origin->second, rig_->skins[std::size_t(rig_skin)].joints.size(), d));
      SkinInfo& info = out_.motion.skins[std::size_t(rig_skin)];
      info.vertices += n;
      info.influences = std::max(info.influences, d.influences);
    }
    if (!skinned) {  // one joint, the identity, at weight 1: the skin kernel renormalises the morphed normals
      FACET_TRY(reserve(std::uint64_t(n) * 6, node_path + ".mesh"));
      d.influences = 1;
      d.joints.assign(n, 0);
      d.weights.assign(n, 1.0f);
    }
    if (morphed) {
      ++out_.motion.morphed_meshes;
      out_.motion.morph_targets += d.targets.size();
    }
    NamedMesh copy = out_.scene.meshes[mesh_index];  // the pose's output; the rest mesh stays for rigid users
    out_.scene.meshes.push_back(std::move(copy));
    d.mesh = static_cast<std::uint32_t>(out_.scene.meshes.size() - 1);
    Instance inst;
    inst.mesh = d.mesh, inst.material = material_index, inst.double_sided = double_sided;
    inst.model = skinned ? Mat4(Mat4::Identity()) : Mat4(world.cast<float>());
    d.object = static_cast<std::uint32_t>(out_.scene.objects.size());
    out_.scene.objects.push_back(inst);
    rig_->deforms.push_back(std::move(d));
  }
  return {};
}

Status Reader::place(std::size_t node, std::size_t first, const Eigen::Matrix4d& world) {
  const std::size_t count = out_.scene.objects.size() - first;
  FACET_TRY(reserve(std::uint64_t(count) * sizeof(Rig::Placed), Fields::at("nodes", node)));
  const Eigen::Matrix4d inverse = world.inverse();
  for (std::size_t o = first; o < out_.scene.objects.size(); ++o) {
    Rig::Placed placed{static_cast<std::uint32_t>(o), static_cast<std::uint32_t>(node), Eigen::Matrix4d::Identity()};
    // EXT_mesh_gpu_instancing's instances: their matrix within the node's.
    const Eigen::Matrix4d local = inverse * out_.scene.objects[o].model.cast<double>();
    if (!local.isIdentity(1e-6)) placed.local = local;
    rig_->placed.push_back(placed);
  }
  return {};
}

// Every node of the file: its parent, its rest transform and morph weights, and an order with
// parents first. A node with two parents or in a cycle is an error (glTF's nodes form trees).
Status Reader::rig_nodes() {
  const std::size_t count = doc_.count("nodes");
  FACET_TRY(reserve(std::uint64_t(count) * (sizeof(Rig::Node) + 3 * sizeof(Eigen::Matrix4d)), "nodes"));
  rig_->nodes.assign(count, Rig::Node{});
  std::vector<std::vector<std::uint32_t>> children(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Json& node = doc_.item("nodes", i);
    const std::string p = Fields::at("nodes", i);
    FACET_TRY(f_.object(node, p));
    Rig::Node& out = rig_->nodes[i];
    if (Fields::find(node, "matrix")) {
      out.matrix = true;
      FACET_TRY(local_matrix(node, p, out.rest));
    } else {
      const double big = 3.0e38;
      double t[3] = {0, 0, 0}, s[3] = {1, 1, 1}, r[4] = {0, 0, 0, 1};
      FACET_TRY(f_.numbers(node, p, "translation", 3, t, -big, big));
      FACET_TRY(f_.numbers(node, p, "scale", 3, s, -big, big));
      FACET_TRY(f_.numbers(node, p, "rotation", 4, r, -1.0001, 1.0001));
      Eigen::Quaterniond q(r[3], r[0], r[1], r[2]);
      if (!(q.norm() > 1e-6)) return f_.error(p + ".rotation", "expected a unit quaternion");
      out.translation = Eigen::Vector3d(t[0], t[1], t[2]);
      out.scale = Eigen::Vector3d(s[0], s[1], s[2]);
      out.rotation = q.normalized();
    }
    int mesh = -1;
    FACET_TRY(f_.index(node, p, "mesh", doc_.count("meshes"), mesh));
    const std::size_t targets = mesh >= 0 ? target_count(doc_.item("meshes", std::size_t(mesh))) : 0;
    if (targets > 0) {
      out.weights.assign(targets, 0.0f);
      for (const auto& [json, path] : {std::pair{&doc_.item("meshes", std::size_t(mesh)), Fields::at("meshes", std::size_t(mesh))},
                                       std::pair{&node, p}}) {
        const Json* w = Fields::find(*json, "weights");
        if (!w) continue;
        if (!w->is_array() || w->size() != targets) {
          return f_.error(path + ".weights", "expected " + std::to_string(targets) + " numbers, one per morph target");
        }
        double values[kMaxTargets];
        FACET_TRY(f_.numbers(*json, path, "weights", targets, values, -1e30, 1e30));
        for (std::size_t t = 0; t < targets; ++t) out.weights[t] = static_cast<float>(values[t]);
      }
    }
    const Json* kids = nullptr;
    FACET_TRY(f_.array(node, p, "children", kids));
    if (!kids) continue;
    for (std::size_t c = 0; c < kids->size(); ++c) {
      const Json& v = (*kids)[c];
      if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= count) {
        return f_.error(Fields::at(p + ".children", c), "expected a node index below " + std::to_string(count));
      }
      const auto child = static_cast<std::uint32_t>(v.get<std::uint64_t>());
      if (rig_->nodes[child].parent >= 0 || child == i) {
        return f_.error(Fields::at(p + ".children", c), Fields::at("nodes", child) + " has two parents, or is its own: glTF's nodes form trees");
      }
      rig_->nodes[child].parent = static_cast<int>(i);
      children[i].push_back(child);
    }
  }
  std::deque<std::uint32_t> queue;
  for (std::size_t i = 0; i < count; ++i)
    if (rig_->nodes[i].parent < 0) queue.push_back(static_cast<std::uint32_t>(i));
  while (!queue.empty()) {
    const std::uint32_t i = queue.front();
    queue.pop_front();
    rig_->order.push_back(i);
    for (const std::uint32_t c : children[i]) queue.push_back(c);
  }
  if (rig_->order.size() != count) {  // a node no root reaches: in a cycle
    std::vector<char> reached(count, 0);
    for (const std::uint32_t i : rig_->order) reached[i] = 1;
    for (std::size_t i = 0; i < count; ++i) {
      if (!reached[i]) return f_.error(Fields::at("nodes", i), "is in a cycle of nodes: glTF's nodes form trees");
    }
  }
  return {};
}

Status Reader::read_animation(std::size_t a) {
  const Json& anim = doc_.item("animations", a);
  const std::string ap = Fields::at("animations", a);
  FACET_TRY(f_.object(anim, ap));
  const Json *channels = nullptr, *samplers = nullptr;
  FACET_TRY(f_.array(anim, ap, "channels", channels));
  FACET_TRY(f_.array(anim, ap, "samplers", samplers));
  if (!channels || channels->empty()) return f_.error(ap + ".channels", "required, an array of at least one channel");
  if (!samplers || samplers->empty()) return f_.error(ap + ".samplers", "required, an array of at least one sampler");
  Rig::Clip clip;
  AnimationInfo info;
  FACET_TRY(f_.string(anim, ap, "name", info.name));
  if (info.name.empty()) info.name = ap;
  std::map<std::size_t, std::pair<std::uint32_t, Rig::Path>> made;  // sampler -> track, and the path it was read for
  double start = 0.0, end = 0.0;
  bool any = false;
  for (std::size_t c = 0; c < channels->size(); ++c) {
    const Json& ch = (*channels)[c];
    const std::string cp = Fields::at(ap + ".channels", c);
    FACET_TRY(f_.object(ch, cp));
    int sampler = -1;
    FACET_TRY(f_.index(ch, cp, "sampler", samplers->size(), sampler, true));
    const Json* target = nullptr;
    FACET_TRY(f_.object(ch, cp, "target", target));
    if (!target) return f_.error(cp + ".target", "required, missing");
    int node = -1;
    std::string path;
    FACET_TRY(f_.index(*target, cp + ".target", "node", doc_.count("nodes"), node));
    FACET_TRY(f_.string(*target, cp + ".target", "path", path, true));
    Rig::Path kind;
    if (path == "translation") kind = Rig::Path::translation;
    else if (path == "rotation") kind = Rig::Path::rotation;
    else if (path == "scale") kind = Rig::Path::scale;
    else if (path == "weights") kind = Rig::Path::weights;
    else if (path == "pointer") {
      warn(cp + ".target.path: \"pointer\" (KHR_animation_pointer) is not supported; the channel is ignored");
      continue;
    } else {
      return f_.error(cp + ".target.path", "expected translation, rotation, scale or weights, found " + quote(path, 32));
    }
    if (node < 0) continue;  // glTF: a channel without a node is ignored (an extension may target something else)
    const Rig::Node& rn = rig_->nodes[std::size_t(node)];
    if (rn.matrix) {
      return f_.error(cp + ".target.node", Fields::at("nodes", std::size_t(node)) + " has a matrix: glTF animates only nodes given by translation, rotation and scale");
    }
    if (kind == Rig::Path::weights && rn.weights.empty()) {
      warn(cp + ": animates the morph weights of " + Fields::at("nodes", std::size_t(node)) + ", whose mesh has no morph targets; ignored");
      continue;
    }
    const std::size_t s = static_cast<std::size_t>(sampler);
    auto it = made.find(s);
    if (it == made.end()) {
      const Json& sm = (*samplers)[s];
      const std::string sp = Fields::at(ap + ".samplers", s);
      FACET_TRY(f_.object(sm, sp));
      int input = -1, output = -1;
      std::string interpolation = "LINEAR";
      FACET_TRY(f_.index(sm, sp, "input", doc_.count("accessors"), input, true));
      FACET_TRY(f_.index(sm, sp, "output", doc_.count("accessors"), output, true));
      FACET_TRY(f_.string(sm, sp, "interpolation", interpolation));
      animation::Track track;
      if (interpolation == "LINEAR") track.interpolation = animation::Interpolation::linear;
      else if (interpolation == "STEP") track.interpolation = animation::Interpolation::step;
      else if (interpolation == "CUBICSPLINE") track.interpolation = animation::Interpolation::cubic_spline;
      else return f_.error(sp + ".interpolation", "expected LINEAR, STEP or CUBICSPLINE, found " + quote(interpolation, 32));
      // The key count before any memory is taken for the keys.
      std::uint64_t keys = 0;
      FACET_TRY(f_.integer(doc_.item("accessors", std::size_t(input)), Fields::at("accessors", std::size_t(input)), "count", keys, 1,
                           std::uint64_t{1} << 40, true));
      if (keys > animation::kMaxKeys) {
        return f_.error(sp + ".input", std::to_string(keys) + " keyframes, at most " + std::to_string(animation::kMaxKeys));
      }
      track.rotation = kind == Rig::Path::rotation;
      track.components = kind == Rig::Path::rotation ? 4 : kind == Rig::Path::weights ? static_cast<int>(rn.weights.size()) : 3;
      Values times, values;
      FACET_TRY(read_accessor(input, sp + ".input", "TIME", times));
      const char* semantic = kind == Rig::Path::translation ? "KEY_TRANSLATION" : kind == Rig::Path::rotation ? "KEY_ROTATION"
                             : kind == Rig::Path::scale ? "KEY_SCALE" : "KEY_WEIGHTS";
      FACET_TRY(read_accessor(output, sp + ".output", semantic, values));
      FACET_TRY(reserve((times.v.size() + values.v.size()) * sizeof(float), sp));
      track.times.assign(times.v.begin(), times.v.end());
      track.values.assign(values.v.begin(), values.v.end());
      if (Status st = animation::validate_track(track, sp); !st.ok()) return {st.code(), st.field(), f_.source() + ": " + st.message()};
      clip.tracks.push_back(std::move(track));
      it = made.emplace(s, std::pair{static_cast<std::uint32_t>(clip.tracks.size() - 1), kind}).first;
    } else if (it->second.second != kind &&
               (it->second.second == Rig::Path::rotation || kind == Rig::Path::rotation || kind == Rig::Path::weights ||
                it->second.second == Rig::Path::weights)) {
      return f_.error(cp + ".sampler", "the sampler is read by another channel as a different kind of value");
    }
    const animation::Track& track = clip.tracks[it->second.first];
    if (kind == Rig::Path::weights && track.components != static_cast<int>(rn.weights.size())) {
      return f_.error(cp + ".sampler", "its output has " + std::to_string(track.components) + " weights per key where " +
                                           Fields::at("nodes", std::size_t(node)) + "'s mesh has " + std::to_string(rn.weights.size()) + " morph targets");
    }
    start = any ? std::min(start, double(track.times.front())) : double(track.times.front());
    end = any ? std::max(end, double(track.times.back())) : double(track.times.back());
    any = true;
    clip.channels.push_back({static_cast<std::uint32_t>(node), kind, it->second.first});
  }
  info.start_s = start;
  info.end_s = end;
  info.channels = clip.channels.size();
  out_.motion.animations.push_back(info);
  rig_->clips.push_back(std::move(clip));
  return {};
}

Status Reader::finish_rig() {
  if (!animated_ && rig_->deforms.empty()) {
    origins_.clear();
    return {};
  }
  FACET_TRY(rig_nodes());
  for (std::size_t a = 0; a < doc_.count("animations"); ++a) FACET_TRY(read_animation(a));
  if (!animated_) rig_->placed.clear();
  rig_->lights = node_lights_;
  rig_->camera_node = camera_node_;
  // Rest meshes that only deformed objects used: drawn by nobody, dropped.
  Scene& scene = out_.scene;
  std::vector<char> used(scene.meshes.size(), 0);
  for (const Instance& o : scene.objects) used[o.mesh] = 1;
  std::vector<std::uint32_t> remap(scene.meshes.size(), 0);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    if (!used[i]) continue;
    remap[i] = static_cast<std::uint32_t>(kept);
    if (kept != i) scene.meshes[kept] = std::move(scene.meshes[i]);
    ++kept;
  }
  scene.meshes.resize(kept);
  for (Instance& o : scene.objects) o.mesh = remap[o.mesh];
  for (Rig::Deform& d : rig_->deforms) d.mesh = remap[d.mesh];
  origins_.clear();
  if (out_.motion.any()) out_.rig = rig_;
  return {};
}

}  // namespace facet::gltf
