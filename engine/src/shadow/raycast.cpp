#include "shadow/raycast.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <embree3/rtcore.h>

namespace facet::shadow {

void record_error(void* user, int code, const char* message) {
  auto* caster = static_cast<RayCaster*>(user);
  if (caster->error_code_ == 0) {  // keep the first
    caster->error_code_ = code;
    caster->error_ = message ? message : "";
  }
}

namespace {

// Rays Embree accepts: |origin|, |direction| per coordinate below its FLT_LARGE (1.844e18).
constexpr float kMaxRayCoordinate = 1e18f;

void on_error(void* user, RTCError code, const char* message) { record_error(user, static_cast<int>(code), message); }

}  // namespace

RayCaster::~RayCaster() { release(); }

void RayCaster::release_scene() noexcept {
  for (void* g : geometries_) rtcReleaseGeometry(static_cast<RTCGeometry>(g));
  geometries_.clear();
  counts_.clear();
  if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
  scene_ = nullptr;
}

void RayCaster::release() noexcept {
  release_scene();
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
  device_ = nullptr;
  triangles_ = 0;
}

// A caster vertex in world space, as the hierarchy holds it.
inline void world_vertex(const Eigen::Matrix4d& model, const Vec3& p, float* out) {
  const Eigen::Vector4d e = model * p.cast<double>().homogeneous();
  for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(e[c]);
}

bool RayCaster::same_casters(const Scene& scene) const {
  std::size_t k = 0;
  for (const Instance& inst : scene.objects) {
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    if (!inst.cast_shadows || mesh.triangles.empty()) continue;
    if (k == geometries_.size()) return false;
    auto* g = static_cast<RTCGeometry>(geometries_[k++]);
    const auto* v = static_cast<const float*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0));
    const auto* t = static_cast<const std::uint32_t*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_INDEX, 0));
    const auto& counts = counts_[k - 1];  // the buffers' sizes
    if (!v || !t || counts[0] != mesh.positions.size() || counts[1] != mesh.triangles.size()) return false;
    if (std::memcmp(t, mesh.triangles.data(), mesh.triangles.size() * 3 * sizeof(std::uint32_t)) != 0) return false;
    const Eigen::Matrix4d model = inst.model.cast<double>();
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      float w[3];
      world_vertex(model, mesh.positions[i], w);
      if (std::memcmp(w, v + 3 * i, sizeof w) != 0) return false;
    }
  }
  return k == geometries_.size();
}

Status RayCaster::build(const Scene& scene, const Eigen::Matrix4d& view) {
  const Eigen::Matrix4d to_world = view.inverse();
  for (int i = 0; i < 12; ++i) to_world_[i] = static_cast<float>(to_world(i / 4, i % 4));
  reused_ = built_ && same_casters(scene);
  if (reused_) return {};
  release_scene();
  built_ = false;
  triangles_ = 0;
  radius_ = 0.0f;
  error_code_ = 0;
  error_.clear();
  if (!device_) {
    // No "threads=" setting: it would install a process-wide tbb::global_control.
    RTCDevice device = rtcNewDevice("verbose=0");
    if (!device) return {ErrorCode::out_of_memory, "", "shadows: could not create the Embree device"};
    rtcSetDeviceErrorFunction(device, on_error, this);
    device_ = device;
  }
  auto failed = [this](const char* what) -> Status {
    const ErrorCode code = error_code_ == RTC_ERROR_OUT_OF_MEMORY ? ErrorCode::out_of_memory : ErrorCode::unsupported;
    return {code, "", std::string("shadows: ") + what + (error_.empty() ? "" : ": " + error_)};
  };
  auto* device = static_cast<RTCDevice>(device_);
  RTCScene rs = rtcNewScene(device);
  if (!rs) return failed("could not create the Embree scene");
  scene_ = rs;
  rtcSetSceneFlags(rs, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(rs, RTC_BUILD_QUALITY_MEDIUM);
  Eigen::AlignedBox3d bounds;
  for (const Instance& inst : scene.objects) {
    if (!inst.cast_shadows) continue;
    const Mesh& mesh = scene.meshes[inst.mesh].mesh;
    if (mesh.triangles.empty()) continue;
    const Eigen::Matrix4d model = inst.model.cast<double>();
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g) return failed("could not create a geometry");
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.positions.size()));
    auto* t = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(std::uint32_t), mesh.triangles.size()));
    if (!v || !t) {
      rtcReleaseGeometry(g);
      return failed("could not allocate the casters' buffers");
    }
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      world_vertex(model, mesh.positions[i], v + 3 * i);
      // The radius counts what Embree keeps: a vertex beyond the rays' range makes its triangles
      // invalid there (and one stray vertex must not blow the normal offset up).
      const Eigen::Vector3d e(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      if (e.allFinite() && e.cwiseAbs().maxCoeff() <= kMaxRayCoordinate) bounds.extend(e);
    }
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      for (int c = 0; c < 3; ++c) t[3 * i + c] = mesh.triangles[i][static_cast<std::size_t>(c)];
    }
    counts_.push_back({mesh.positions.size(), mesh.triangles.size()});
    rtcCommitGeometry(g);
    rtcAttachGeometry(rs, g);
    geometries_.push_back(g);  // keeps its reference, for same_casters()
    triangles_ += mesh.triangles.size();
  }
  rtcCommitScene(rs);
  if (error_code_ != 0) return failed("building the casters' hierarchy failed");
  if (!bounds.isEmpty()) radius_ = static_cast<float>(0.5 * bounds.diagonal().norm());
  built_ = true;
  return {};
}

void RayCaster::visibility(const Target& target, float offset, std::size_t count, const float* px, const float* py,
                           const float* pz, const float* nx, const float* ny, const float* nz, std::size_t stride,
                           float* visible) const {
  if (!scene_ || triangles_ == 0) {
    for (std::size_t i = 0; i < count; ++i) visible[i] = 1.0f;
    return;
  }
  auto* rs = static_cast<RTCScene>(scene_);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // neighbouring pixels: rays of a packet travel together
  constexpr float kInf = std::numeric_limits<float>::infinity();
  // Rays are cast in world space (the hierarchy's): eye-space points through to_world_, the
  // light's direction or position likewise, once.
  const float* m = to_world_;
  auto point = [m](float x, float y, float z, float* out) {
    for (int r = 0; r < 3; ++r) out[r] = ((m[4 * r] * x + m[4 * r + 1] * y) + m[4 * r + 2] * z) + m[4 * r + 3];
  };
  float light[3];
  if (target.directional) {
    for (int r = 0; r < 3; ++r) light[r] = (m[4 * r] * target.x + m[4 * r + 1] * target.y) + m[4 * r + 2] * target.z;
  } else {
    point(target.x, target.y, target.z, light);
  }
  // Packets of 16 rays (Embree picks its widest kernel); whether a ray is blocked does not depend
  // on the packet it travels in.
  for (std::size_t first = 0; first < count; first += 16) {
    const std::size_t n = std::min<std::size_t>(16, count - first);
    alignas(64) RTCRay16 rays;
    alignas(64) int valid[16];
    for (std::size_t l = 0; l < 16; ++l) {
      valid[l] = 0;
      rays.tnear[l] = 0.0f, rays.tfar[l] = 0.0f, rays.time[l] = 0.0f;
      rays.org_x[l] = rays.org_y[l] = rays.org_z[l] = 0.0f;
      rays.dir_x[l] = rays.dir_y[l] = 0.0f, rays.dir_z[l] = 1.0f;
      rays.mask[l] = 0xffffffffu, rays.id[l] = static_cast<unsigned>(l), rays.flags[l] = 0;
      if (l >= n) continue;
      const std::size_t at = (first + l) * stride;
      const float n2 = nx[at] * nx[at] + ny[at] * ny[at] + nz[at] * nz[at];
      const float scale = n2 > 1e-12f ? offset / std::sqrt(n2) : 0.0f;  // the offset along the unit normal
      float o[3];
      point(px[at] + scale * nx[at], py[at] + scale * ny[at], pz[at] + scale * nz[at], o);
      const float ox = o[0], oy = o[1], oz = o[2];
      float dx, dy, dz, tfar;
      if (target.directional) {
        dx = light[0], dy = light[1], dz = light[2], tfar = kInf;
      } else {  // the segment to the light: t in [0, 1]
        dx = light[0] - ox, dy = light[1] - oy, dz = light[2] - oz, tfar = 1.0f;
      }
      if (!may_be_lit(target, px[at], py[at], pz[at], nx[at], ny[at], nz[at])) continue;
      // Embree takes rays whose origin and direction are within +-1.844e18 per coordinate (it
      // asserts otherwise: Debian's build aborts). Others are not cast: the point counts as lit.
      const float big = kMaxRayCoordinate;
      const bool castable = std::abs(ox) <= big && std::abs(oy) <= big && std::abs(oz) <= big && std::abs(dx) <= big &&
                            std::abs(dy) <= big && std::abs(dz) <= big;  // false for NaN too
      if (!castable) continue;
      valid[l] = -1;
      rays.org_x[l] = ox, rays.org_y[l] = oy, rays.org_z[l] = oz;
      rays.dir_x[l] = dx, rays.dir_y[l] = dy, rays.dir_z[l] = dz;
      rays.tfar[l] = tfar;
    }
    rtcOccluded16(valid, rs, &context, &rays);
    for (std::size_t l = 0; l < n; ++l) visible[first + l] = valid[l] && rays.tfar[l] == -kInf ? 0.0f : 1.0f;
  }
}

}  // namespace facet::shadow
