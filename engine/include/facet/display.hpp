// What a picture does with the light of a scene, as a camera does: an exposure, and a tone-mapping
// operator that takes the exposed light into the output's [0, 1] (docs/color.md).
//
// A frame with Display's defaults (exposure 0, not automatic, ToneMapping::none) is GL's: lighting
// clamps to [0, 1] where GL clamps it, and nothing else happens. Any other setting renders the
// scene's light unclamped (as RenderOptions::hdr does), then per pixel: the colour times 2^ev,
// the operator, a clamp to [0, 1], and the output's encoding (sRGB for 8-bit outputs unless
// RenderOptions::srgb is false). Pixels no triangle reached keep the clear colour exactly: the
// background is a colour of the picture, not light of the scene. RGBA32F output with
// RenderOptions::hdr gets the exposure alone (no operator, no clamp). Alpha is never changed.
#pragma once

#include <array>

#include "facet/status.hpp"

namespace facet {

enum class ToneMapping {
  none,     // clamp to [0, 1] (GL's, the default for scene files)
  neutral,  // Khronos PBR Neutral (2024): hue and base colour kept up to about 0.8, then a soft shoulder
  aces,     // Narkowicz's 2015 fit of the ACES filmic curve, per channel, as published (no input scale)
};
const char* to_string(ToneMapping mapping) noexcept;

struct Display {
  // Stops: the scene's linear light is multiplied by 2^ev before tone mapping (+1 doubles it).
  float ev = 0.0f;
  // Meter the frame instead: ev is chosen so that the log-average luminance (Rec. 709 weights) of
  // the lit pixels a triangle reached maps to middle grey, 0.18, as a camera's meter does:
  // ev = log2(0.18 / exp(mean(ln(1e-4 + L)))) over the drawn pixels with L > 0 (black, unlit
  // pixels, say nothing about the light: a half-lit sphere would otherwise be over-exposed),
  // clamped to [-30, 30]; 0 when no such pixel was drawn.
  // The frame is rendered first and metered over every pixel in a fixed order, so the result is
  // the same bytes for any thread count. FrameStats::exposure_ev reports the ev used.
  bool automatic = false;
  ToneMapping tone_mapping = ToneMapping::none;
  // GL's fixed function: nothing to do beyond clamping.
  bool identity() const noexcept { return ev == 0.0f && !automatic && tone_mapping == ToneMapping::none; }
};

// ev within [-30, 30] and a known operator; names display.ev / display.tone_mapping.
Status validate_display(const Display& display);

// The operators on linear RGB (>= 0), in float as the renderer applies them; the result is clamped
// to [0, 1].
std::array<float, 3> tone_map(ToneMapping mapping, std::array<float, 3> rgb) noexcept;

// The middle-grey exposure for a log-average luminance `log_average` (exp of the mean of ln(1e-4 + L)):
// log2(0.18 / log_average), clamped to [-30, 30].
float metered_ev(double log_average) noexcept;

// The highlight guard of automatic exposure: the largest ev at which a colour channel of `peak`
// (the 98th percentile of the lit pixels' brightest channel) still maps to 0.95 after `mapping`
// (none: 0.95 itself; neutral: 1.712; aces: 2.863), clamped to [-30, 30]. Metering takes the
// smaller of this and metered_ev, so that a bright subject in a dark frame (a spot light's pool
// on a dark floor) is not clipped white by the dark pixels' pull on the average.
float highlight_ev(ToneMapping mapping, double peak) noexcept;

}  // namespace facet
