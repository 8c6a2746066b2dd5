#include "shadow/raycast.hpp"

#include <algorithm>
#include <cmath>
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

void RayCaster::release() noexcept {
  if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
  scene_ = nullptr;
  device_ = nullptr;
  triangles_ = 0;
}

Status RayCaster::build(const Scene& scene, const Eigen::Matrix4d& view) {
  if (scene_) {
    rtcReleaseScene(static_cast<RTCScene>(scene_));
    scene_ = nullptr;
  }
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
    const Eigen::Matrix4d mv = view * inst.model.cast<double>();
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
      const Eigen::Vector4d e = mv * mesh.positions[i].cast<double>().homogeneous();
      for (int c = 0; c < 3; ++c) v[3 * i + c] = static_cast<float>(e[c]);
      // The radius counts what Embree keeps: a vertex beyond the rays' range makes its triangles
      // invalid there (and one stray vertex must not blow the normal offset up).
      if (e.head<3>().allFinite() && e.head<3>().cwiseAbs().maxCoeff() <= kMaxRayCoordinate) bounds.extend(e.head<3>());
    }
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      for (int c = 0; c < 3; ++c) t[3 * i + c] = mesh.triangles[i][static_cast<std::size_t>(c)];
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(rs, g);
    rtcReleaseGeometry(g);
    triangles_ += mesh.triangles.size();
  }
  rtcCommitScene(rs);
  if (error_code_ != 0) return failed("building the casters' hierarchy failed");
  if (!bounds.isEmpty()) radius_ = static_cast<float>(0.5 * bounds.diagonal().norm());
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
      const float ox = px[at] + scale * nx[at], oy = py[at] + scale * ny[at], oz = pz[at] + scale * nz[at];
      float dx, dy, dz, tfar;
      if (target.directional) {
        dx = target.x, dy = target.y, dz = target.z, tfar = kInf;
      } else {  // the segment to the light: t in [0, 1]
        dx = target.x - ox, dy = target.y - oy, dz = target.z - oz, tfar = 1.0f;
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
