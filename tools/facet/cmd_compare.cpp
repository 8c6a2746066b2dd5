// facet compare: two PNG images of the same size.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include "cli.hpp"

namespace facet::cli {
namespace {
int compare(const std::vector<std::string>& files, int tolerance, bool json, const std::string& diff_path, int drawn_within,
            int silhouette);
}  // namespace

Command add_compare(CLI::App& facet) {
  struct State {
    std::vector<std::string> files;
    std::string diff;
    int tolerance = 0, drawn_within = -1, silhouette = -1;
    bool json = false;
  };
  auto st = std::make_shared<State>();
  CLI::App* app = facet.add_subcommand("compare", "compare two PNG images: PSNR, largest and mean difference, differing pixels");
  app->footer(
      "Prints PSNR (dB), the largest channel difference and the mean absolute difference (in 8-bit\n"
      "steps, over R, G and B) and the number of pixels that differ. Exits 0 when no channel differs\n"
      "by more than --tolerance steps, 1 when one does, 2 on errors.");
  app->add_option("images", st->files, "A.png B.png")->required()->expected(2);
  app->add_option("--tolerance", st->tolerance, "largest accepted channel difference in 8-bit steps (default 0)")
      ->check(int_in(0, 255));
  app->add_flag("--json", st->json, "print the result as one JSON object");
  app->add_option("--diff", st->diff,
                  "write a difference image (PNG): |A - B| per channel, scaled so that the largest difference is 255; "
                  "pixels within --tolerance are black");
  app->add_option("--drawn-within", st->drawn_within,
                  "N: also measure over the pixels either image draws (not pure black in both: a comparison with another "
                  "renderer on a black background): their mean difference and the share within N steps in every channel")
      ->check(int_in(0, 255));
  app->add_option("--silhouette", st->silhouette,
                  "N: also compare the silhouettes, the pixels with a channel above N steps (on a black background): "
                  "the intersection over union of the two")
      ->check(CLI::Range(0, 254));
  return {app, [st] { return compare(st->files, st->tolerance, st->json, st->diff, st->drawn_within, st->silhouette); }};
}

namespace {
// Over the pixels either image draws (not black in both): how many, their mean channel difference
// and the share whose every channel is within `within` steps.
struct Drawn {
  std::size_t pixels = 0, close = 0;
  double mean = 0.0;
};
Drawn drawn_difference(const Rgba8Image& a, const Rgba8Image& b, int within) {
  Drawn d;
  double sum = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
    const bool black_a = a.pixels[i] == 0 && a.pixels[i + 1] == 0 && a.pixels[i + 2] == 0;
    const bool black_b = b.pixels[i] == 0 && b.pixels[i + 1] == 0 && b.pixels[i + 2] == 0;
    if (black_a && black_b) continue;
    ++d.pixels;
    int worst = 0;
    for (std::size_t c = 0; c < 3; ++c) {
      const int delta = std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c]));
      sum += delta;
      worst = std::max(worst, delta);
    }
    d.close += worst <= within ? 1 : 0;
  }
  d.mean = d.pixels ? sum / (3.0 * double(d.pixels)) : 0.0;
  return d;
}

// The pixels each image draws (a channel above `above`): how many, and how many both draw.
struct Silhouettes {
  std::size_t a = 0, b = 0, both = 0;
  double iou() const { return a + b - both ? double(both) / double(a + b - both) : 1.0; }
};
Silhouettes silhouettes(const Rgba8Image& a, const Rgba8Image& b, int above) {
  Silhouettes s;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
    const bool in_a = std::max({a.pixels[i], a.pixels[i + 1], a.pixels[i + 2]}) > above;
    const bool in_b = std::max({b.pixels[i], b.pixels[i + 1], b.pixels[i + 2]}) > above;
    s.a += in_a, s.b += in_b, s.both += in_a && in_b;
  }
  return s;
}

int compare(const std::vector<std::string>& files, int tolerance, bool json, const std::string& diff_path, int drawn_within,
            int silhouette) {
  Result<Rgba8Image> a = read_png(files[0]);
  if (!a) return fail(a.status().message());
  Result<Rgba8Image> b = read_png(files[1]);
  if (!b) return fail(b.status().message());
  Result<ImageDifference> d = compare_images(*a, *b);
  if (!d) return fail(files[0] + " vs " + files[1] + ": " + d.status().message());
  const bool match = d->max_channel_difference <= tolerance;
  if (!diff_path.empty()) {
    Rgba8Image diff;
    diff.width = a->width, diff.height = a->height;
    diff.pixels.assign(a->pixels.size(), 0);
    const int largest = std::max(1, d->max_channel_difference);
    for (std::size_t i = 0; i < a->pixels.size(); i += 4) {
      int worst = 0;
      for (std::size_t c = 0; c < 3; ++c) {
        const int delta = std::abs(int(a->pixels[i + c]) - int(b->pixels[i + c]));
        worst = std::max(worst, delta);
        diff.pixels[i + c] = static_cast<std::uint8_t>((delta * 255 + largest / 2) / largest);
      }
      if (worst <= tolerance) diff.pixels[i] = diff.pixels[i + 1] = diff.pixels[i + 2] = 0;
      diff.pixels[i + 3] = 255;
    }
    const ImageView view{diff.pixels.data(), diff.width, diff.height, std::size_t(diff.width) * 4, PixelFormat::rgba8, false};
    if (Status s = write_png(diff_path, view); !s.ok()) return fail(s.message());
  }
  const std::string psnr = std::isinf(d->psnr_db) ? "inf" : std::to_string(d->psnr_db);
  const Drawn drawn = drawn_within >= 0 ? drawn_difference(*a, *b, drawn_within) : Drawn{};
  const double close_share = drawn.pixels ? 100.0 * double(drawn.close) / double(drawn.pixels) : 100.0;
  const Silhouettes shapes = silhouette >= 0 ? silhouettes(*a, *b, silhouette) : Silhouettes{};
  if (json) {
    std::string extra;
    if (silhouette >= 0) {
      char buffer[160];
      std::snprintf(buffer, sizeof buffer, ", \"silhouette_above\": %d, \"silhouette_pixels\": [%zu, %zu], \"silhouette_iou\": %.6g", silhouette,
                    shapes.a, shapes.b, shapes.iou());
      extra += buffer;
    }
    if (drawn_within >= 0) {
      char buffer[160];
      std::snprintf(buffer, sizeof buffer, ", \"drawn_pixels\": %zu, \"drawn_mean_difference\": %.6g, \"drawn_within\": %d, \"drawn_within_share\": %.6g",
                    drawn.pixels, drawn.mean, drawn_within, close_share / 100.0);
      extra += buffer;
    }
    std::printf("{\"psnr_db\": %s, \"max_channel_difference\": %d, \"mean_absolute_difference\": %.6g, "
                "\"differing_pixels\": %zu, \"pixels\": %zu, \"tolerance\": %d, \"match\": %s%s}\n",
                std::isinf(d->psnr_db) ? "null" : psnr.c_str(), d->max_channel_difference,
                d->mean_absolute_difference, d->differing_pixels,
                static_cast<std::size_t>(a->width) * static_cast<std::size_t>(a->height), tolerance,
                match ? "true" : "false", extra.c_str());
  } else {
    std::printf("PSNR %s dB, largest difference %d, mean difference %.4g, %zu of %zu pixels differ: %s (tolerance %d)\n",
                psnr.c_str(), d->max_channel_difference, d->mean_absolute_difference, d->differing_pixels,
                static_cast<std::size_t>(a->width) * static_cast<std::size_t>(a->height),
                match ? "match" : "differ", tolerance);
    if (drawn_within >= 0) {
      std::printf("drawn by either: %zu pixels, mean difference %.3g steps, %.1f %% within %d\n", drawn.pixels, drawn.mean,
                  close_share, drawn_within);
    }
    if (silhouette >= 0) {
      std::printf("silhouettes (a channel above %d): %zu and %zu pixels, %zu in both: intersection over union %.4f\n", silhouette,
                  shapes.a, shapes.b, shapes.both, shapes.iou());
    }
  }
  return match ? 0 : 1;
}
}  // namespace

}  // namespace facet::cli
