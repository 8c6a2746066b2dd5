// load_model's dispatch, and what a viewer needs around a model: its bounds, a camera that frames
// them, a default rig of lights, and why a frame drew nothing.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "common/format.hpp"
#include "facet/model.hpp"
#include "facet/render.hpp"

namespace facet {

Result<Model> load_model(const std::string& path, const ModelOptions& options) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".gltf" || ext == ".glb") return load_gltf(path, options);
  if (ext == ".obj") return load_obj_model(path, options);
  return Status{ErrorCode::unsupported, "", path + ": unknown model type " + quote(ext.empty() ? std::string("(none)") : ext, 16) +
                                               ": expected .gltf, .glb or .obj"};
}

Bounds scene_bounds(const Scene& scene) {
  Bounds b;
  Eigen::Array3d lo = Eigen::Array3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Instance& inst : scene.objects) {
    if (inst.mesh >= scene.meshes.size()) continue;
    const Eigen::Matrix4d m = inst.model.cast<double>();
    for (const Vec3& p : scene.meshes[inst.mesh].mesh.positions) {
      const Eigen::Vector3d w = m.topLeftCorner<3, 3>() * p.cast<double>() + m.topRightCorner<3, 1>();
      if (!w.allFinite()) continue;
      lo = lo.min(w.array());
      hi = hi.max(w.array());
    }
  }
  if ((lo <= hi).all()) {
    b.min = lo.cast<float>().matrix();
    b.max = hi.cast<float>().matrix();
  }
  return b;
}

Camera frame_bounds(const Bounds& bounds, float aspect, float vertical_fov_deg) {
  Camera c;
  c.vertical_fov_deg = vertical_fov_deg;
  if (bounds.empty()) return c;
  const Eigen::Vector3d lo = bounds.min.cast<double>(), hi = bounds.max.cast<double>();
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  double radius = 0.5 * (hi - lo).norm();
  if (!(radius > 0.0)) radius = std::max(1e-3, 1e-3 * centre.norm());
  const double v = double(vertical_fov_deg) * std::numbers::pi / 180.0;
  const double h = 2.0 * std::atan(std::tan(v / 2.0) * std::max(1e-3, double(aspect > 0.0f ? aspect : 1.0f)));
  const double half = std::min(v, h) / 2.0;
  const double distance = 1.05 * radius / std::sin(half);
  const Eigen::Vector3d dir = Eigen::Vector3d(0.0, 0.35, 1.0).normalized();
  const Eigen::Vector3d eye = centre + distance * dir;
  c.eye = eye.cast<float>();
  c.target = centre.cast<float>();
  c.up = Vec3(0.0f, 1.0f, 0.0f);
  c.near = static_cast<float>(std::max(distance - 1.5 * radius, 1e-3 * distance));
  c.far = static_cast<float>(distance + 1.5 * radius);
  return c;
}

void add_default_lights(Scene& scene) {
  const Eigen::Vector3d eye = scene.camera.eye.cast<double>(), target = scene.camera.target.cast<double>();
  Eigen::Vector3d forward = target - eye;
  if (!(forward.norm() > 0.0)) forward = Eigen::Vector3d(0, 0, -1);
  forward.normalize();
  Eigen::Vector3d up = scene.camera.up.cast<double>();
  Eigen::Vector3d right = forward.cross(up);
  if (!(right.norm() > 1e-9)) right = forward.unitOrthogonal();
  right.normalize();
  up = right.cross(forward);
  Light head;
  head.name = "headlight";
  head.type = LightType::directional;
  head.direction = forward.cast<float>();
  head.diffuse = Color3::Constant(0.5f);
  head.specular = Color3::Zero();
  Light key;
  key.name = "key light";
  key.type = LightType::directional;
  // From above, to the left and in front of the camera, travelling towards the model.
  key.direction = (-(-0.5 * right + 0.8 * up - 0.6 * forward).normalized()).cast<float>();
  key.diffuse = Color3::Constant(0.7f);
  key.specular = Color3::Constant(0.5f);
  scene.lights.push_back(head);
  scene.lights.push_back(key);
  scene.global_ambient = Color3::Constant(0.15f);
}

std::string explain_empty_frame(const FrameStats& s) {
  if (s.pixels_filled > 0) return {};
  if (s.triangles_in == 0) return "the scene has no triangles to draw (no objects, or only empty meshes)";
  if (s.triangles_drawn > 0) {
    return std::to_string(s.triangles_drawn) +
           " triangles reached the screen but no pixel passed the depth and alpha tests (alpha cutoff, or alpha 0)";
  }
  const std::uint64_t outside = s.triangles_outside, culled = s.triangles_culled, small = s.triangles_small,
                      bad = s.triangles_nonfinite + s.triangles_degenerate;
  const std::uint64_t total = outside + culled + small + bad;
  if (outside == total) {
    return "every triangle is outside the view: the camera does not look at the model (frame it: no \"camera\" in the "
           "scene, or facet render MODEL)";
  }
  if (culled == total) return "every triangle faces away from the camera and is culled (inverted winding? try --cull none)";
  if (small == total) return "every triangle falls between pixel centres: the model is too small in the image";
  if (bad == total) return "every triangle is degenerate or has non-finite coordinates";
  return "no triangle was drawn: " + std::to_string(outside) + " outside the view, " + std::to_string(culled) +
         " culled, " + std::to_string(small) + " between pixel centres, " + std::to_string(bad) +
         " degenerate or non-finite";
}

}  // namespace facet
