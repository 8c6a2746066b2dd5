// Posing a model (facet/animation.hpp, scene/rig.hpp).
#include "scene/rig.hpp"

#include <algorithm>
#include <cmath>

#include "common/format.hpp"
#include "common/try.hpp"
#include "facet/model.hpp"
#include "geometry/skin.hpp"

namespace facet {

void pose_nodes(const Rig& rig, int clip, double seconds, std::vector<Eigen::Matrix4d>& world,
                std::vector<std::vector<float>>& weights) {
  const std::size_t n = rig.nodes.size();
  std::vector<Eigen::Vector3d> t(n), s(n);
  std::vector<Eigen::Quaterniond> r(n);
  weights.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = rig.nodes[i].translation, s[i] = rig.nodes[i].scale, r[i] = rig.nodes[i].rotation;
    weights[i] = rig.nodes[i].weights;
  }
  if (clip >= 0) {
    const Rig::Clip& c = rig.clips[static_cast<std::size_t>(clip)];
    float v[256];
    for (const Rig::Channel& ch : c.channels) {
      const animation::Track& track = c.tracks[ch.track];
      animation::sample(track, seconds, v);
      switch (ch.path) {
        case Rig::Path::translation: t[ch.node] = Eigen::Vector3d(v[0], v[1], v[2]); break;
        case Rig::Path::scale: s[ch.node] = Eigen::Vector3d(v[0], v[1], v[2]); break;
        case Rig::Path::rotation: r[ch.node] = Eigen::Quaterniond(v[3], v[0], v[1], v[2]).normalized(); break;
        case Rig::Path::weights: {
          std::vector<float>& w = weights[ch.node];
          w.assign(v, v + std::min<std::size_t>(w.size(), std::size_t(track.components)));
          w.resize(rig.nodes[ch.node].weights.size(), 0.0f);
          break;
        }
      }
    }
  }
  world.resize(n);
  for (const std::uint32_t i : rig.order) {
    const Rig::Node& node = rig.nodes[i];
    Eigen::Matrix4d local = node.rest;
    if (!node.matrix) {
      local.setIdentity();
      local.topLeftCorner<3, 3>() = r[i].toRotationMatrix() * s[i].asDiagonal();
      local.topRightCorner<3, 1>() = t[i];
    }
    world[i] = node.parent < 0 ? local : Eigen::Matrix4d(world[static_cast<std::size_t>(node.parent)] * local);
  }
}

namespace {

Status mismatch(const std::string& what) {
  return {ErrorCode::invalid_argument, "scene", "pose_model: the model's scene no longer matches what was read (" + what + ")"};
}

Status check_scene(const Rig& rig, const Scene& scene) {
  for (const Rig::Placed& p : rig.placed)
    if (p.object >= scene.objects.size()) return mismatch("objects");
  for (const Rig::Deform& d : rig.deforms) {
    if (d.object >= scene.objects.size() || d.mesh >= scene.meshes.size()) return mismatch("objects or meshes");
    const Mesh& m = scene.meshes[d.mesh].mesh;
    if (m.positions.size() != d.count || (!d.rest[3].empty() && m.normals.size() != d.count) ||
        (!d.rest[6].empty() && m.tangents.size() != d.count)) {
      return mismatch("the vertices of " + quote(scene.meshes[d.mesh].name, 64));
    }
  }
  for (const Rig::NodeLight& l : rig.lights)
    if (l.light >= scene.lights.size()) return mismatch("lights");
  return {};
}

// A deformed mesh at the nodes' pose: morph targets (those of non-zero weight), then the skin (a
// mesh that is only morphed has one joint, the identity, which renormalises its normals and
// tangents).
void deform(const Rig& rig, const Rig::Deform& d, const std::vector<Eigen::Matrix4d>& world,
            const std::vector<float>& weights, const PoseOptions& options, Mesh& mesh) {
  const std::size_t n = d.count;
  const bool scalar = options.path != PosePath::simd;
  std::vector<float> morphed[9];
  const float* in[9];
  for (int c = 0; c < 9; ++c) in[c] = d.rest[c].empty() ? nullptr : d.rest[c].data();
  std::vector<geometry::MorphTarget> targets;
  for (int group = 0; group < 3; ++group) {  // positions, normals, tangents
    if (!in[3 * group]) continue;
    targets.clear();
    for (std::size_t t = 0; t < d.targets.size() && t < weights.size(); ++t) {
      if (weights[t] == 0.0f || !((d.target_kinds[t] >> group) & 1)) continue;  // a frame pays only for what it shows
      geometry::MorphTarget mt;
      mt.weight = weights[t];
      for (int c = 0; c < 3; ++c) mt.delta[c] = d.targets[t].data() + std::size_t(3 * group + c) * n;
      targets.push_back(mt);
    }
    if (targets.empty()) continue;
    geometry::MorphJob job;
    job.count = n;
    for (int c = 0; c < 3; ++c) {
      morphed[3 * group + c].resize(n);
      job.base[c] = in[3 * group + c];
      job.out[c] = morphed[3 * group + c].data();
      in[3 * group + c] = job.out[c];
    }
    job.targets = targets.data();
    job.target_count = targets.size();
    if (scalar) geometry::morph_scalar(job);
    else geometry::morph(job, Isa::best);
  }
  static constexpr float kIdentity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  std::vector<float> matrices(kIdentity, kIdentity + 12);
  std::vector<double> matrices_d(kIdentity, kIdentity + 12);
  if (d.skin >= 0) {
    const Rig::Skin& skin = rig.skins[static_cast<std::size_t>(d.skin)];
    matrices.resize(12 * skin.joints.size());
    matrices_d.resize(12 * skin.joints.size());
    for (std::size_t j = 0; j < skin.joints.size(); ++j) {
      const Eigen::Matrix4d m = world[skin.joints[j]] * skin.inverse_bind[j];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) matrices_d[12 * j + 4 * r + c] = m(r, c), matrices[12 * j + 4 * r + c] = float(m(r, c));
    }
  }
  geometry::SkinJob job;
  job.count = n;
  for (int c = 0; c < 3; ++c) job.position[c] = in[c], job.normal[c] = in[3 + c], job.tangent[c] = in[6 + c];
  job.normals = options.normals;
  job.influences = d.influences;
  job.joints = d.joints.data();
  job.weights = d.weights.data();
  job.matrices = matrices.data();
  job.joint_count = matrices.size() / 12;
  job.out_position = mesh.positions.data()->data();
  job.out_normal = in[3] ? mesh.normals.data()->data() : nullptr;
  job.out_tangent = in[6] ? mesh.tangents.data()->data() : nullptr;
  switch (options.path) {
    case PosePath::simd: geometry::skin(job, Isa::best); break;
    case PosePath::scalar: geometry::skin_scalar(job); break;
    case PosePath::reference: {
      std::vector<double> p(3 * n), nn(in[3] ? 3 * n : 0), tt(in[6] ? 4 * n : 0);
      geometry::skin_reference(job, matrices_d.data(), p.data(), in[3] ? nn.data() : nullptr, in[6] ? tt.data() : nullptr);
      for (std::size_t i = 0; i < n; ++i) {
        for (int r = 0; r < 3; ++r) {
          mesh.positions[i][r] = float(p[3 * i + r]);
          if (in[3]) mesh.normals[i][r] = float(nn[3 * i + r]);
          if (in[6]) mesh.tangents[i][r] = float(tt[4 * i + r]);
        }
      }
      break;
    }
  }
}

Mat4 to_float(const Eigen::Matrix4d& m) { return m.cast<float>(); }

}  // namespace

Status pose_scene(Scene& scene, const Rig* rig_in, bool file_camera, double seconds, const PoseOptions& options) {
  if (!std::isfinite(seconds)) return {ErrorCode::invalid_argument, "seconds", "pose_model: the time is not finite"};
  const int clips = rig_in ? static_cast<int>(rig_in->clips.size()) : 0;
  if (options.animation < -1 || options.animation >= clips) {
    return {ErrorCode::invalid_argument, "animation",
            "pose_model: animation " + std::to_string(options.animation) + " is out of range (the model has " +
                std::to_string(clips) + ")"};
  }
  if (options.normals != NormalTransform::cofactor && options.normals != NormalTransform::linear) {
    return {ErrorCode::invalid_argument, "normals", "pose_model: unknown normal transform"};
  }
  if (options.path != PosePath::simd && options.path != PosePath::scalar && options.path != PosePath::reference) {
    return {ErrorCode::invalid_argument, "path", "pose_model: unknown path"};
  }
  if (!rig_in) return {};
  const Rig& rig = *rig_in;
  if (Status s = check_scene(rig, scene); !s.ok()) return s;
  std::vector<Eigen::Matrix4d> world;
  std::vector<std::vector<float>> weights;
  pose_nodes(rig, options.animation, seconds, world, weights);
  // A pose that takes something out of float's range (keys or bind matrices so large their
  // products overflow) is an error naming what, not a scene that fails to draw later.
  const auto out_of_range = [&](const std::string& what) {
    return Status{ErrorCode::invalid_argument, "seconds",
                  "pose_model: at " + format_number(seconds) + " s the pose puts " + what + " out of float's range"};
  };
  for (const Rig::Placed& p : rig.placed) {
    const Mat4 m = to_float(world[p.node] * p.local);
    if (!m.allFinite()) return out_of_range("an object (node " + std::to_string(p.node) + ")");
    scene.objects[p.object].model = m;
  }
  for (const Rig::Deform& d : rig.deforms) {
    const Mat4 m = d.skin >= 0 ? Mat4(Mat4::Identity()) : to_float(world[d.node]);
    if (!m.allFinite()) return out_of_range("an object (node " + std::to_string(d.node) + ")");
    scene.objects[d.object].model = m;
    Mesh& mesh = scene.meshes[d.mesh].mesh;
    deform(rig, d, world, weights[d.node], options, mesh);
    for (const Vec3& v : mesh.positions)
      if (!v.allFinite()) return out_of_range("vertices of " + quote(scene.meshes[d.mesh].name, 64));
  }
  for (const Rig::NodeLight& l : rig.lights) {
    const Eigen::Matrix4d& w = world[l.node];
    Light& light = scene.lights[l.light];
    const Eigen::Vector3d dir = -w.block<3, 1>(0, 2);
    if (dir.norm() > 1e-12) light.direction = dir.normalized().cast<float>();
    if (light.type != LightType::directional) light.position = w.topRightCorner<3, 1>().cast<float>();
  }
  if (rig.camera_node >= 0 && file_camera) {
    const Eigen::Matrix4d& w = world[static_cast<std::size_t>(rig.camera_node)];
    const Eigen::Vector3d eye = w.topRightCorner<3, 1>(), forward = -w.block<3, 1>(0, 2), up = w.block<3, 1>(0, 1);
    if (forward.norm() > 1e-12 && up.norm() > 1e-12) {
      scene.camera.eye = eye.cast<float>();
      scene.camera.target = (eye + forward.normalized()).cast<float>();
      scene.camera.up = up.normalized().cast<float>();
    }
  }
  return {};
}

Status pose_model(Model& model, double seconds, const PoseOptions& options) {
  FACET_TRY(pose_scene(model.scene, model.rig.get(), model.has_camera, seconds, options));
  model.pose = options;
  model.pose_seconds = seconds;
  return {};
}

Result<int> find_animation(const Model& model, std::string_view key) { return find_animation(model.motion, key); }

Result<int> find_animation(const MotionInfo& motion, std::string_view key) {
  const auto& list = motion.animations;
  std::string names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (list[i].name == key || std::to_string(i) == key) return static_cast<int>(i);
    names += (names.empty() ? "" : ", ") + std::to_string(i) + " " + quote(list[i].name, 64);
  }
  return Status{ErrorCode::invalid_argument, "animation",
                "no animation " + quote(std::string(key), 64) + ": " + (names.empty() ? "the model has none" : "the model has " + names)};
}

std::vector<double> animation_sample_times(const AnimationInfo& a, int count) {
  count = std::max(count, 2);
  std::vector<double> t(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) t[std::size_t(k)] = k + 1 == count ? a.end_s : a.start_s + (a.end_s - a.start_s) * k / (count - 1);
  return t;
}

Result<Bounds> animation_bounds(Model& model, const PoseOptions& options, int count) {
  const PoseOptions was = model.pose;
  const double was_seconds = model.pose_seconds;
  Bounds box;
  if (options.animation < 0 || !model.rig || options.animation >= static_cast<int>(model.motion.animations.size())) {
    if (Status s = pose_model(model, 0.0, options); !s.ok()) return s;
    box = scene_bounds(model.scene);
  } else {
    for (const double t : animation_sample_times(model.motion.animations[std::size_t(options.animation)], count)) {
      if (Status s = pose_model(model, t, options); !s.ok()) return s;
      const Bounds b = scene_bounds(model.scene);
      if (b.empty()) continue;
      if (box.empty()) box = b;
      else box.min = box.min.cwiseMin(b.min), box.max = box.max.cwiseMax(b.max);
    }
  }
  if (Status s = pose_model(model, was_seconds, was); !s.ok()) return s;
  return box;
}

}  // namespace facet
