// Per-vertex lighting of scene instances, in eye space, from the scene's camera.
//
// Paths (one algorithm, see README "Lighting model"):
//   reference: double precision, std::pow; the oracle of every test.
//   scalar:    float, one vertex at a time, built without auto-vectorisation: the honest baseline.
// Edge cases, identical on every path, never NaN:
//   - light at the vertex (distance <= 1e-6): no direction, so no diffuse/specular; the ambient
//     term stays, with the attenuation denominator floored at 1e-6;
//   - zero, NaN or Inf normal: treated as a zero normal (no diffuse, no specular);
//   - half vector of zero length (light exactly behind the vertex from the eye): n.h = 0;
//   - NaN or Inf position, or an infinite distance to a point/spot light: that light adds nothing;
//   - n.h is clamped into [0, 1] before pow; 0^0 = 1.
#pragma once

#include <cstddef>
#include <vector>

#include "facet/scene.hpp"
#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

enum class LightingPath { reference, scalar };

const char* to_string(LightingPath path) noexcept;

struct LightingOptions {
  LightingPath path = LightingPath::scalar;
  bool clamp = true;  // clamp each channel to [0, 1]; false keeps HDR values (still >= 0)
};

// Colours of one instance's vertices. `back` is filled only for two-sided scenes: the same
// vertices lit with the negated normal, for the faces seen from behind.
struct VertexColors {
  std::vector<Color3> front;
  std::vector<Color3> back;
};

// Lights every vertex of scene.objects[instance] into `out` (resized; its capacity is reused).
// Returns an error, leaving `out` untouched, if the scene is invalid or `instance` out of range.
Status light_instance(const Scene& scene, std::size_t instance, const LightingOptions& options,
                      VertexColors& out);

}  // namespace facet
