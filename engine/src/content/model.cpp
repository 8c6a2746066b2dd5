// load_model's dispatch, and what a viewer needs around a model: its bounds, a camera that frames
// them, a default rig of lights, and why a frame drew nothing.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>

#include "common/format.hpp"
#include "common/try.hpp"
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

namespace {
struct AxisInfo {
  UpAxis axis;
  const char* name;
  float up[3], front[3];
};
constexpr AxisInfo kAxes[] = {
    {UpAxis::y, "y", {0, 1, 0}, {0, 0, 1}},      {UpAxis::z, "z", {0, 0, 1}, {0, -1, 0}},
    {UpAxis::x, "x", {1, 0, 0}, {0, 0, 1}},      {UpAxis::neg_x, "-x", {-1, 0, 0}, {0, 0, 1}},
    {UpAxis::neg_y, "-y", {0, -1, 0}, {0, 0, 1}}, {UpAxis::neg_z, "-z", {0, 0, -1}, {0, -1, 0}},
};
const AxisInfo* axis_info(UpAxis up) noexcept {
  for (const AxisInfo& a : kAxes)
    if (a.axis == up) return &a;
  return nullptr;
}
}  // namespace

const char* to_string(UpAxis up) noexcept {
  const AxisInfo* a = axis_info(up);
  return a ? a->name : "unknown";
}

bool parse_up_axis(std::string_view name, UpAxis& out) noexcept {
  for (const AxisInfo& a : kAxes) {
    if (name == a.name || (name.size() == 2 && name[0] == '+' && name.substr(1) == a.name)) {
      out = a.axis;
      return true;
    }
  }
  return false;
}

Vec3 up_vector(UpAxis up) noexcept {
  const AxisInfo* a = axis_info(up);
  return a ? Vec3(a->up[0], a->up[1], a->up[2]) : Vec3(0.0f, 1.0f, 0.0f);
}

Vec3 front_vector(UpAxis up) noexcept {
  const AxisInfo* a = axis_info(up);
  return a ? Vec3(a->front[0], a->front[1], a->front[2]) : Vec3(0.0f, 0.0f, 1.0f);
}

Status validate_view(const ViewOptions& v) {
  auto bad = [](const char* field, const std::string& what) {
    return Status{ErrorCode::invalid_argument, field, std::string(field) + ": " + what};
  };
  if (!(std::abs(v.azimuth_deg) <= 36000.0f)) return bad("azimuth_deg", "expected a number in [-36000, 36000], found " + format_number(v.azimuth_deg));
  if (!(v.elevation_deg > -90.0f && v.elevation_deg < 90.0f)) {
    return bad("elevation_deg", "expected a number in (-90, 90), found " + format_number(v.elevation_deg));
  }
  if (!axis_info(v.up)) return bad("up", "expected one of UpAxis's six axes");
  if (v.projection != Projection::perspective && v.projection != Projection::orthographic) {
    return bad("projection", "expected Projection::perspective or Projection::orthographic");
  }
  if (!(v.vertical_fov_deg > 0.0f && v.vertical_fov_deg < 180.0f)) {
    return bad("vertical_fov_deg", "expected a number in (0, 180), found " + format_number(v.vertical_fov_deg));
  }
  if (!(v.fill > 0.0f && v.fill <= 1.0f)) return bad("fill", "expected a number in (0, 1], found " + format_number(v.fill));
  return {};
}

namespace {

// Calls fn(p) for every world-space vertex of the scene's objects (non-finite ones skipped).
template <class Fn>
void for_each_world_vertex(const Scene& scene, Fn fn) {
  for (const Instance& inst : scene.objects) {
    if (inst.mesh >= scene.meshes.size()) continue;
    const Eigen::Matrix4d m = inst.model.cast<double>();
    for (const Vec3& p : scene.meshes[inst.mesh].mesh.positions) {
      const Eigen::Vector3d w = m.topLeftCorner<3, 3>() * p.cast<double>() + m.topRightCorner<3, 1>();
      if (w.allFinite()) fn(w);
    }
  }
}

// The refusal of a framing whose camera does not fit in float (`s`: validate_camera's reason).
Status too_large(double extent, const Status& s) {
  return Status{ErrorCode::unsupported, "", "cannot frame the model: its coordinates (up to " + format_number(static_cast<float>(extent)) +
                                                ") are too large for a camera in float (" + s.message() + ")"};
}

// The orthographic framing: parallel rays, so the box's centre across the view is the target,
// its half height the larger of the points' half extents (the width's over the aspect) over the
// fill, and the eye just in front of the nearest point.
template <class Each>
Result<Camera> frame_box(Each each, float aspect, const ViewOptions& view, Eigen::Vector3d target, double radius,
                         const Eigen::Vector3d& d, const Eigen::Vector3d& r, const Eigen::Vector3d& u) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Array3d lo = Eigen::Array3d::Constant(inf), hi = -lo;  // along r, u, d
  each([&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d rel = p - target;
    const Eigen::Array3d q(rel.dot(r), rel.dot(u), rel.dot(d));
    lo = lo.min(q), hi = hi.max(q);
  });
  const Eigen::Array3d mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  target += mid.x() * r + mid.y() * u;
  double half_height = std::max(half.y(), half.x() / double(aspect)) / double(view.fill);
  if (!(half_height > 0.0)) half_height = radius > 0.0 ? radius : 1.0;  // a point, or a line along the view
  const double margin = std::max(0.01 * radius, 1e-6 * std::max(std::abs(hi.z()), 1.0));
  const double distance = hi.z() + margin;  // the eye in front of the nearest point
  Camera c;
  c.projection = Projection::orthographic;
  c.half_height = static_cast<float>(half_height);
  c.eye = (target + distance * d).cast<float>();
  c.target = target.cast<float>();
  c.up = up_vector(view.up);
  c.near = 0.0f;
  c.far = static_cast<float>(distance - lo.z() + margin);
  if (Status s = validate_camera(c); !s.ok()) return too_large(std::max(target.cwiseAbs().maxCoeff(), radius), s);
  return c;
}

// The framing of frame_scene over the points `each(fn)` enumerates, in double. The camera looks
// along -d from target + D d. D is the least distance at which every point's projection lies
// within `fill` of the image's half-width and half-height: for a point at (x, y) across the view
// and z towards the eye (relative to the target), |x| <= fill tx (D - z), so D >= z + |x| / (fill tx),
// likewise for y. Each round first moves the target to the centre of the points' projection (so
// that the model sits in the middle of the image), then solves D again; four rounds bring the
// projection's centre to well under a percent of the image.
template <class Each>
Result<Camera> frame_points(Each each, float aspect, const ViewOptions& view) {
  FACET_TRY(validate_view(view));
  if (!(aspect > 0.0f && aspect < 1e6f)) {
    return Status{ErrorCode::invalid_argument, "aspect", "aspect: expected width / height > 0, found " + format_number(aspect)};
  }
  Eigen::Array3d lo = Eigen::Array3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  std::size_t count = 0;
  each([&](const Eigen::Vector3d& p) { lo = lo.min(p.array()), hi = hi.max(p.array()), ++count; });
  if (count == 0) return Status{ErrorCode::invalid_argument, "", "nothing to frame: the scene has no vertices"};
  const double deg = std::numbers::pi / 180.0;
  const Eigen::Vector3d up = up_vector(view.up).cast<double>();
  const Eigen::Vector3d front = front_vector(view.up).cast<double>();
  const Eigen::Vector3d right = up.cross(front);
  const double az = double(view.azimuth_deg) * deg, el = double(view.elevation_deg) * deg;
  const Eigen::Vector3d d = (std::cos(el) * (std::cos(az) * front + std::sin(az) * right) + std::sin(el) * up).normalized();
  const Eigen::Vector3d r = (-d).cross(up).normalized();
  const Eigen::Vector3d u = r.cross(-d);
  const double k = double(view.fill);
  const double radius = 0.5 * (hi - lo).matrix().norm();
  Eigen::Vector3d target = 0.5 * (lo + hi).matrix();
  if (view.projection == Projection::orthographic) return frame_box(each, aspect, view, target, radius, d, r, u);
  const double ty = std::tan(0.5 * double(view.vertical_fov_deg) * deg), tx = ty * double(aspect);
  double distance = 0.0;
  auto solve_distance = [&] {
    double need = -std::numeric_limits<double>::infinity(), z_max = need;
    each([&](const Eigen::Vector3d& p) {
      const Eigen::Vector3d rel = p - target;
      const double z = rel.dot(d);
      need = std::max(need, z + std::max(std::abs(rel.dot(r)) / (k * tx), std::abs(rel.dot(u)) / (k * ty)));
      z_max = std::max(z_max, z);
    });
    // Every point strictly in front of the eye, also one on the axis of view.
    distance = std::max(need, z_max + 0.01 * radius);
    if (!(distance > 0.0)) distance = 1.0;  // a single point: any distance frames it
  };
  solve_distance();
  for (int round = 0; round < 4 && radius > 0.0; ++round) {
    Eigen::Array2d nlo = Eigen::Array2d::Constant(std::numeric_limits<double>::infinity()), nhi = -nlo;
    each([&](const Eigen::Vector3d& p) {
      const Eigen::Vector3d rel = p - target;
      const double depth = distance - rel.dot(d);
      const Eigen::Array2d n(rel.dot(r) / (depth * tx), rel.dot(u) / (depth * ty));
      nlo = nlo.min(n), nhi = nhi.max(n);
    });
    const Eigen::Array2d mid = 0.5 * (nlo + nhi);
    target += distance * (mid.x() * tx * r + mid.y() * ty * u);
    solve_distance();
  }
  double near = std::numeric_limits<double>::infinity(), far = 0.0;
  each([&](const Eigen::Vector3d& p) {
    const double depth = distance - (p - target).dot(d);
    near = std::min(near, depth), far = std::max(far, depth);
  });
  far = std::max(1.1 * far, 1e-6);
  near = std::max(0.9 * near, 1e-5 * far);
  Camera c;
  c.vertical_fov_deg = view.vertical_fov_deg;
  c.eye = (target + distance * d).cast<float>();
  c.target = target.cast<float>();
  c.up = up.cast<float>();
  c.near = static_cast<float>(near);
  c.far = static_cast<float>(far);
  if (Status s = validate_camera(c); !s.ok()) return too_large(std::max(lo.abs().maxCoeff(), hi.abs().maxCoeff()), s);
  return c;
}

}  // namespace

Result<Camera> frame_scene(const Scene& scene, float aspect, const ViewOptions& view) {
  return frame_points([&](auto fn) { for_each_world_vertex(scene, fn); }, aspect, view);
}

Result<Camera> frame_animation(Model& model, float aspect, const ViewOptions& view, const PoseOptions& options, int count) {
  if (options.animation < 0 || options.animation >= static_cast<int>(model.motion.animations.size())) {
    if (Status s = pose_model(model, 0.0, options); !s.ok()) return s;
    return frame_scene(model.scene, aspect, view);
  }
  const PoseOptions was = model.pose;
  const double was_seconds = model.pose_seconds;
  const std::vector<double> times = animation_sample_times(model.motion.animations[std::size_t(options.animation)], count);
  Status failed;
  Result<Camera> framed = frame_points(
      [&](auto fn) {
        for (const double t : times) {
          if (!failed.ok()) return;
          if (Status s = pose_model(model, t, options); !s.ok()) {
            failed = s;
            return;
          }
          for_each_world_vertex(model.scene, fn);
        }
      },
      aspect, view);
  if (Status s = pose_model(model, was_seconds, was); !s.ok() && failed.ok()) failed = s;
  if (!failed.ok()) return failed;
  return framed;
}

Result<Camera> frame_bounds(const Bounds& bounds, float aspect, const ViewOptions& view) {
  return frame_points(
      [&](auto fn) {
        if (bounds.empty()) return;
        for (int corner = 0; corner < 8; ++corner) {
          fn(Eigen::Vector3d((corner & 1) ? bounds.max.x() : bounds.min.x(), (corner & 2) ? bounds.max.y() : bounds.min.y(),
                             (corner & 4) ? bounds.max.z() : bounds.min.z()));
        }
      },
      aspect, view);
}

Camera orbit_camera(const Camera& camera, const Vec3& centre, UpAxis up, float angle_deg) {
  const Eigen::AngleAxisd turn(double(angle_deg) * std::numbers::pi / 180.0, up_vector(up).cast<double>());
  const Eigen::Vector3d c = centre.cast<double>();
  Camera out = camera;
  out.eye = (c + turn * (camera.eye.cast<double>() - c)).cast<float>();
  out.target = centre;
  out.up = (turn * camera.up.cast<double>()).cast<float>();
  return out;
}

Light orbit_light(const Light& light, const Vec3& centre, UpAxis up, float angle_deg) {
  const Eigen::AngleAxisd turn(double(angle_deg) * std::numbers::pi / 180.0, up_vector(up).cast<double>());
  const Eigen::Vector3d c = centre.cast<double>();
  Light out = light;
  out.position = (c + turn * (light.position.cast<double>() - c)).cast<float>();
  out.direction = (turn * light.direction.cast<double>()).cast<float>();
  return out;
}

const char* add_default_lights(Scene& scene) {
  std::size_t pbr = 0;
  for (const Material& m : scene.materials) pbr += m.model == MaterialModel::pbr ? 1 : 0;
  if (pbr > 0) scene.environment_light.source = EnvironmentSource::studio;
  if (pbr > 0 && pbr == scene.materials.size()) {
    scene.global_ambient = Color3::Zero();
    return "facet's neutral studio (docs/pbr.md)";
  }
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
  return pbr > 0 ? "facet's default rig (a headlight and a key light, ambient 0.15) and its neutral studio"
                 : "facet's default rig (a headlight and a key light, ambient 0.15)";
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
    return "every triangle is outside the view: the camera does not look at the model (frame it: frame_scene, facet "
           "render --ignore-camera, or no \"camera\" in the scene file)";
  }
  if (culled == total) return "every triangle faces away from the camera and is culled (inverted winding? try --cull none)";
  if (small == total) return "every triangle falls between pixel centres: the model is too small in the image";
  if (s.triangles_nonfinite == total) return "every triangle has a vertex with non-finite coordinates (NaN or infinity)";
  if (s.triangles_degenerate == total) {
    return "every triangle has no area on screen: the model is seen edge-on (a flat model from its side: look from "
           "above, e.g. --view 0,30) or its triangles are collapsed to lines or points";
  }
  if (bad == total) {
    return "every triangle has no area on screen (" + std::to_string(s.triangles_degenerate) + ", seen edge-on or collapsed) or a "
           "non-finite vertex (" + std::to_string(s.triangles_nonfinite) + ")";
  }
  return "no triangle was drawn: " + std::to_string(outside) + " outside the view, " + std::to_string(culled) +
         " culled, " + std::to_string(small) + " between pixel centres, " + std::to_string(bad) +
         " degenerate or non-finite";
}

}  // namespace facet
