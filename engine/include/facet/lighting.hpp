// Per-vertex lighting of scene instances, in eye space, from the scene's camera.
//
// Paths (one algorithm, see README "Lighting model"):
//   reference: double precision, std::pow; the oracle of every test.
//   scalar:    float, one vertex at a time, built without auto-vectorisation: the honest baseline.
//   simd:      float, xsimd batches (4, 8 or 16 lanes), compiled once per ISA and chosen at run
//              time; the pow tier decides how the specular and spot exponents are evaluated.
// Edge cases, identical on every path, never NaN:
//   - light at the vertex (distance <= 1e-6): no direction, so no diffuse/specular; the ambient
//     term stays, with the attenuation denominator floored at 1e-6;
//   - zero, NaN or Inf normal: treated as a zero normal (no diffuse, no specular);
//   - half vector of zero length (light exactly behind the vertex from the eye): n.h = 0;
//   - NaN or Inf position, or an infinite distance to a point/spot light: that light adds nothing;
//   - n.h is clamped into [0, 1] before pow; 0^0 = 1.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "facet/scene.hpp"
#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

enum class LightingPath { reference, scalar, simd };

// Instruction sets of the simd path. `best` is the widest this CPU has (detected with GCC's
// __builtin_cpu_supports, which also checks that the OS saves the AVX/AVX-512 registers).
enum class Isa { best, sse2, avx2, avx512 };

// How the simd path evaluates x^s (specular shininess, spot exponent); see README "pow tiers".
// The reference and scalar paths always use std::pow.
enum class PowTier {
  automatic,  // per exponent, the cheapest tier within 1 step of 8-bit output: integer, fast or exact
  exact,      // full-precision exp2(s log2 x): <= 2e-6 absolute
  fast,       // cheap log2/exp2 polynomials: <= 2.2e-5 absolute, so Delta8 <= 1
  integer,    // repeated squaring; whole exponents <= 256 only (others use exact)
  schlick,    // Schlick's rational lobe: a different specular model, not an approximation
};

const char* to_string(LightingPath path) noexcept;
const char* to_string(Isa isa) noexcept;
const char* to_string(PowTier tier) noexcept;
bool isa_supported(Isa isa) noexcept;  // best is always supported
Isa best_isa() noexcept;               // never returns Isa::best

struct LightingOptions {
  LightingPath path = LightingPath::scalar;
  Isa isa = Isa::best;                     // simd path only
  PowTier pow_tier = PowTier::automatic;   // simd path only
  bool clamp = true;  // clamp each channel to [0, 1]; false keeps HDR values (still >= 0)
  // The frame plan: per object, skip the lights that cannot reach its bounding sphere (range
  // window) or whose contributions there add up to less than half an 8-bit step. See README.
  bool cull_lights = true;
  // Threads light_instance() splits the vertices over (its own tbb::task_arena for the call;
  // process-wide TBB settings are never touched): 1 = the calling thread only, 0 = one per
  // hardware thread. The colours are the same bytes for any count. Must be in [0, 1024].
  int threads = 1;
};

// Colours of one instance's vertices. `back` is filled only for two-sided scenes: the same
// vertices lit with the negated normal, for the faces seen from behind.
struct VertexColors {
  std::vector<Color3> front;
  std::vector<Color3> back;
};

// Lights every vertex of scene.objects[instance] into `out` (resized; its capacity is reused).
// Returns an error, leaving `out` untouched, if the scene is invalid, `instance` out of range,
// options.threads outside [0, 1024] or the requested ISA missing on this CPU.
Status light_instance(const Scene& scene, std::size_t instance, const LightingOptions& options,
                      VertexColors& out);

// light_instance() for a caller that lights again and again: a Lighter keeps its threads (a
// tbb::task_arena of its own, made again only when options.threads changes) and its working memory
// between calls, where light_instance() makes both per call. Same results, same errors. One
// Lighter serves one caller at a time; several Lighters may run at once.
class Lighter {
 public:
  Lighter();
  ~Lighter();
  Lighter(Lighter&&) noexcept;
  Lighter& operator=(Lighter&&) noexcept;

  Status light_instance(const Scene& scene, std::size_t instance, const LightingOptions& options, VertexColors& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facet
