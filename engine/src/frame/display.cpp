// Exposure and tone mapping (facet/display.hpp): the operators, and a frame with a display
// transform, rendered into floats and then exposed, tone-mapped and stored.
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/format.hpp"
#include "frame/frame.hpp"
#include "io/image_convert.hpp"
#include "io/rows.hpp"
#include "io/srgb.hpp"

namespace facet {

const char* to_string(ToneMapping mapping) noexcept {
  switch (mapping) {
    case ToneMapping::none: return "none";
    case ToneMapping::neutral: return "neutral";
    case ToneMapping::aces: return "aces";
  }
  return "unknown";
}

Status validate_display(const Display& display) {
  if (!(display.ev >= -30.0f && display.ev <= 30.0f)) {
    return {ErrorCode::invalid_argument, "display.ev", "display.ev: expected stops in [-30, 30], found " + format_number(display.ev)};
  }
  if (static_cast<unsigned>(display.tone_mapping) > static_cast<unsigned>(ToneMapping::aces)) {
    return {ErrorCode::invalid_argument, "display.tone_mapping", "display.tone_mapping: unknown operator"};
  }
  return {};
}

namespace {

float clamp01(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; }

// Khronos PBR Neutral, as its specification writes it (in float).
std::array<float, 3> neutral(std::array<float, 3> c) {
  constexpr float start = 0.8f - 0.04f, desaturation = 0.15f;
  const float x = std::min(c[0], std::min(c[1], c[2]));
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  for (float& v : c) v -= offset;
  const float peak = std::max(c[0], std::max(c[1], c[2]));
  if (peak < start) return c;
  constexpr float d = 1.0f - start;
  const float new_peak = 1.0f - d * d / (peak + d - start);
  for (float& v : c) v *= new_peak / peak;
  const float g = 1.0f - 1.0f / (desaturation * (peak - new_peak) + 1.0f);
  for (float& v : c) v = v + (new_peak - v) * g;
  return c;
}

// Narkowicz 2015: x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14).
float aces(float x) { return x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f); }

}  // namespace

std::array<float, 3> tone_map(ToneMapping mapping, std::array<float, 3> rgb) noexcept {
  for (float& v : rgb) v = v > 0.0f ? v : 0.0f;  // also NaN to 0
  if (mapping == ToneMapping::neutral) rgb = neutral(rgb);
  if (mapping == ToneMapping::aces) {
    for (float& v : rgb) v = aces(v);
  }
  for (float& v : rgb) v = clamp01(v);
  return rgb;
}

float highlight_ev(ToneMapping mapping, double peak) noexcept {
  if (!(peak > 0.0)) return 30.0f;
  // The linear value each operator maps to 0.95 (solved in double from the formulas above).
  const double white = mapping == ToneMapping::neutral ? 1.712 : mapping == ToneMapping::aces ? 2.863 : 0.95;
  return static_cast<float>(std::clamp(std::log2(white / peak), -30.0, 30.0));
}

float metered_ev(double log_average) noexcept {
  if (!(log_average > 0.0)) return 0.0f;
  const double ev = std::log2(0.18 / log_average);
  return static_cast<float>(std::clamp(ev, -30.0, 30.0));
}

// The frame in floats (unclamped light, the caller's clear colour, a depth view), then per pixel:
// background (far depth and exactly the clear colour) stored as the clear colour; anything else
// exposed, tone-mapped (unless HDR float output) and stored. Metering sums per row, rows added in
// order: the same ev for any thread count.
void Renderer::Impl::render_display(const Scene& scene, const RenderOptions& options, const ImageView& color,
                                    const DepthView* depth, bool composite) {
  const int w = color.width, h = color.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  display_color.resize(4 * pixels);
  const ImageView inner_color{display_color.data(), w, h, static_cast<std::size_t>(w) * 4 * sizeof(float), PixelFormat::rgba32f, false};
  DepthView inner_depth;
  if (depth) {
    inner_depth = *depth;
  } else {
    display_depth.resize(pixels);
    inner_depth = DepthView{display_depth.data(), w, h, static_cast<std::size_t>(w) * sizeof(float), false};
  }
  RenderOptions inner = options;
  inner.hdr = true;
  inner.srgb = false;
  if (composite) {
    render_composite(scene, inner, inner_color, &inner_depth);
  } else {
    render(scene, inner, inner_color, &inner_depth);
  }
  if (!frame_status.ok() || cancelled.load(std::memory_order_relaxed)) return;
  const auto store_start = Clock::now();
  const float far = depth_mode_for(scene.camera, options.depth) == DepthMode::reversed ? 0.0f : 1.0f;
  // With the surroundings behind the model (Scene::background), no pixel is stored as the clear
  // colour: the backdrop is exposed and tone-mapped with the surfaces (a NaN clear colour matches
  // no pixel), but only surfaces are metered.
  const bool backdrop = scene.background == Background::environment;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::array<float, 4> clear = backdrop ? std::array<float, 4>{nan, nan, nan, nan} : options.clear_color;
  // A pixel's colour and depth, the depth row found once per row by each pass.
  auto background = [&](const float* rgba, float z) {
    return z == far && rgba[0] == clear[0] && rgba[1] == clear[1] && rgba[2] == clear[2] && rgba[3] == clear[3];
  };
  auto unmetered = [&](const float* rgba, float z) { return backdrop ? z == far : background(rgba, z); };
  auto depth_row = [&](int y) { return reinterpret_cast<const float*>(io::row_bytes(inner_depth, y)); };
  float ev = scene.display.ev;
  if (scene.display.automatic) {
    display_rows.assign(static_cast<std::size_t>(h), {0.0, 0.0});
    display_peaks.assign(pixels, 0.0f);
    arena->parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows, int) {
      for (int y = rows.begin(); y != rows.end(); ++y) {
        double sum = 0.0, count = 0.0;
        const float* row = display_color.data() + 4 * static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
        const float* d = depth_row(y);
        float* peaks = display_peaks.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
        for (int x = 0; x < w; ++x) {
          const float* p = row + 4 * x;
          if (unmetered(p, d[x])) continue;
          const double lum = 0.2126 * double(p[0]) + 0.7152 * double(p[1]) + 0.0722 * double(p[2]);
          if (!(lum > 0.0 && std::isfinite(lum))) continue;  // unlit: says nothing about the exposure
          sum += std::log(1e-4 + lum);
          count += 1.0;
          peaks[x] = std::max(p[0], std::max(p[1], p[2]));
        }
        display_rows[static_cast<std::size_t>(y)] = {sum, count};
      }
    });
    double sum = 0.0, count = 0.0;
    for (const auto& [s, c] : display_rows) sum += s, count += c;
    ev = count > 0.0 ? metered_ev(std::exp(sum / count)) : 0.0f;
    // The highlight guard: the lit pixels' brightest channels, their 98th percentile (an order
    // statistic: the same value whatever order the threads left them in).
    std::size_t lit = 0;
    for (const float v : display_peaks)
      if (v > 0.0f) display_peaks[lit++] = v;
    if (lit > 0) {
      const std::size_t k = static_cast<std::size_t>(0.98 * double(lit - 1));
      std::nth_element(display_peaks.begin(), display_peaks.begin() + static_cast<std::ptrdiff_t>(k),
                       display_peaks.begin() + static_cast<std::ptrdiff_t>(lit));
      ev = std::min(ev, highlight_ev(scene.display.tone_mapping, display_peaks[k]));
    }
  }
  const float scale = std::exp2(ev);
  const bool float_out = color.format == PixelFormat::rgba32f;
  const bool hdr_out = float_out && options.hdr;
  const SrgbTable* srgb_table = options.srgb && !float_out ? &srgb : nullptr;
  const std::size_t bytes = float_out ? 16 : 4;
  const ToneMapping op = scene.display.tone_mapping;
  // 8-bit output: each channel encoded here (store_pixel's conversions, inline).
  const int red = color.format == PixelFormat::bgra8 ? 2 : 0;
  auto channel8 = [srgb_table](float v) { return srgb_table ? srgb_unorm8(*srgb_table, v) : to_unorm8(v); };
  arena->parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows, int) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      std::uint8_t* dst = io::row_bytes(color, y);
      float* const row = display_color.data() + 4 * static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
      const float* d = depth_row(y);
      if (backdrop) {  // over an opaque backdrop every pixel is opaque, whatever blending left in alpha
        for (int x = 0; x < w; ++x) row[4 * x + 3] = 1.0f;
      }
      if (!float_out) {
        int x = 0;
        if (simd_kernels) {  // the ISA's batches first (the same bytes), the scalar loop for the rest
          const tile::simd::DisplayRow args{row, d, w, far, {clear[0], clear[1], clear[2], clear[3]}, scale, op, srgb_table, red, dst};
          x = simd_kernels->display_row(args);
        }
        for (; x < w; ++x) {
          const float* p = row + 4 * x;
          std::uint8_t* out = dst + 4 * static_cast<std::size_t>(x);
          std::array<float, 3> t;
          if (background(p, d[x])) {
            t = {clamp01(p[0]), clamp01(p[1]), clamp01(p[2])};
          } else {
            t = tone_map(op, {p[0] * scale, p[1] * scale, p[2] * scale});
          }
          out[red] = channel8(t[0]), out[1] = channel8(t[1]), out[2 - red] = channel8(t[2]);
          out[3] = to_unorm8(p[3]);
        }
        continue;
      }
      for (int x = 0; x < w; ++x) {
        const float* p = row + 4 * x;
        float out[4];
        if (background(p, d[x])) {
          for (int c = 0; c < 4; ++c) out[c] = hdr_out ? p[c] : clamp01(p[c]);
        } else if (hdr_out) {
          for (int c = 0; c < 3; ++c) out[c] = p[c] * scale > 0.0f ? p[c] * scale : 0.0f;
          out[3] = p[3];
        } else {
          const std::array<float, 3> t = tone_map(op, {p[0] * scale, p[1] * scale, p[2] * scale});
          out[0] = t[0], out[1] = t[1], out[2] = t[2], out[3] = clamp01(p[3]);
        }
        tile::store_pixel(out, color.format, srgb_table, dst + static_cast<std::size_t>(x) * bytes);
      }
    }
  });
  stats.exposure_ev = ev;
  stats.seconds_resolve += seconds_since(store_start);
  stats.seconds_total += seconds_since(store_start);
}

}  // namespace facet
