// Look-at camera with a perspective projection. Conventions are OpenGL's: right-handed world,
// eye space looks down -z with +y up, clip-space depth in [-1, 1] before the viewport maps it.
#pragma once

#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

struct Camera {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 target{0.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float vertical_fov_deg = 45.0f;  // (0, 180)
  float aspect = 0.0f;             // width / height; 0 = take it from the image
  float near = 0.1f;               // 0 < near < far
  // +infinity: an infinite projection (no far plane; glTF's camera without zfar). Window depth is
  // then 1 - near / w_eye, which is exact near the camera and coarse far from it (float depth
  // has 24 bits below 1).
  float far = 100.0f;
};

// World -> eye transform (a rigid motion).
Mat4 view_matrix(const Camera& camera);
// Eye -> clip transform, like gluPerspective. `aspect` must be > 0 (resolve Camera::aspect first).
Mat4 projection_matrix(const Camera& camera, float aspect);

}  // namespace facet
