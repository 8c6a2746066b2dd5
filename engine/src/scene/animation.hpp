// Internal: glTF 2.0 animation samplers (the specification's section 3.11 and its Appendix C):
// keyframes of a node's translation, rotation, scale or morph weights, sampled at any time.
// The first piece of animation (issue: keyframes, skins and morph targets); the glTF reader and
// the pose of a model's nodes build on it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "facet/status.hpp"

namespace facet::animation {

enum class Interpolation : unsigned char { step, linear, cubic_spline };

// One sampler's keyframes. `times` strictly increasing and finite; `values` holds `components`
// floats per key (translation and scale 3, rotation 4 as x, y, z, w, weights one per morph
// target), or for cubic_spline three groups per key: in-tangent, value, out-tangent.
struct Track {
  Interpolation interpolation = Interpolation::linear;
  int components = 3;
  bool rotation = false;  // unit quaternions: slerp on the shortest arc, results renormalised
  std::vector<float> times;
  std::vector<float> values;
};

// The most keyframes a track may hold (each one a time and up to 3 x components values).
inline constexpr std::size_t kMaxKeys = std::size_t{1} << 24;

// Whether `track` can be sampled: at least one key and at most kMaxKeys, times finite and
// strictly increasing, as many values as keys need, every value finite. `where` names the track
// in messages (a JSON path: "animations[0].samplers[2]").
Status validate_track(const Track& track, const std::string& where);

// The track's value at time t into out[components] (a validated track): before the first key
// its first value, after the last its last; step: the value of the last key at or before t;
// linear: the straight blend of the two keys around t (rotations: slerp on the shortest arc);
// cubic_spline: the Hermite curve through the two keys with their tangents scaled by the keys'
// interval. Rotations come out unit length.
void sample(const Track& track, double t, float* out);

}  // namespace facet::animation
