// Look-at camera with a perspective or an orthographic projection. Conventions are OpenGL's:
// right-handed world, eye space looks down -z with +y up, clip-space depth in [-1, 1] before the
// viewport maps it.
#pragma once

#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

// gluPerspective's frustum, or glOrtho's box (glTF's orthographic camera): parallel rays, no
// foreshortening, the same size at every depth.
enum class Projection { perspective, orthographic };

struct Camera {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 target{0.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  Projection projection = Projection::perspective;
  float vertical_fov_deg = 45.0f;  // perspective: (0, 180)
  // orthographic: the box's half height in eye-space units (glTF's ymag), in (0, 1e30]; its half
  // width is half_height * aspect.
  float half_height = 1.0f;
  float aspect = 0.0f;             // width / height; 0 = take it from the image
  // Perspective: 0 < near < far. Orthographic: 0 <= near < far < +infinity (glTF's bounds; the
  // box's depth is linear, so a near plane at the eye costs no precision).
  float near = 0.1f;
  // +infinity (perspective only): an infinite projection (no far plane; glTF's camera without
  // zfar). Window depth is then 1 - near / w_eye, which is exact near the camera and coarse far
  // from it (float depth has 24 bits below 1).
  float far = 100.0f;
};

// World -> eye transform (a rigid motion).
Mat4 view_matrix(const Camera& camera);
// Eye -> clip transform, like gluPerspective or glOrtho. `aspect` must be > 0 (resolve
// Camera::aspect first).
Mat4 projection_matrix(const Camera& camera, float aspect);
const char* to_string(Projection projection) noexcept;

}  // namespace facet
