// facet compare: two PNG images of the same size.
#include <cmath>

#include "cli.hpp"

namespace facet::cli {
namespace {

constexpr const char* kCompareUsage =
    "usage: facet compare A.png B.png [--tolerance N] [--json]\n"
    "\n"
    "Prints PSNR (dB), the largest channel difference and the mean absolute difference (in 8-bit\n"
    "steps, over R, G and B) and the number of pixels that differ. Exits 0 when no channel differs\n"
    "by more than --tolerance steps (default 0), 1 when one does, 2 on errors.\n";

}  // namespace

int run_compare(int argc, char** argv) {
  std::string files[2];
  int file_count = 0, tolerance = 0;
  bool json = false;
  Args args(argc, argv);
  std::string arg;
  while (args.next(arg)) {
    if (arg == "-h" || arg == "--help") {
      std::fputs(kCompareUsage, stdout);
      return 0;
    } else if (arg == "--tolerance") {
      const auto v = args.int_value(arg, 0, 255);
      if (!v) return 2;
      tolerance = *v;
    } else if (arg == "--json") {
      json = true;
    } else if (!arg.empty() && arg[0] == '-') {
      return fail("compare: unknown option '" + arg + "' (see 'facet compare --help')");
    } else if (file_count < 2) {
      files[file_count++] = arg;
    } else {
      return fail("compare: expected exactly two images");
    }
  }
  if (file_count != 2) return fail(std::string("compare: expected exactly two images\n") + kCompareUsage);
  Result<Rgba8Image> a = read_png(files[0]);
  if (!a) return fail(a.status().message());
  Result<Rgba8Image> b = read_png(files[1]);
  if (!b) return fail(b.status().message());
  Result<ImageDifference> d = compare_images(*a, *b);
  if (!d) return fail(files[0] + " vs " + files[1] + ": " + d.status().message());
  const bool match = d->max_channel_difference <= tolerance;
  const std::string psnr = std::isinf(d->psnr_db) ? "inf" : std::to_string(d->psnr_db);
  if (json) {
    std::printf("{\"psnr_db\": %s, \"max_channel_difference\": %d, \"mean_absolute_difference\": %.6g, "
                "\"differing_pixels\": %zu, \"pixels\": %zu, \"tolerance\": %d, \"match\": %s}\n",
                std::isinf(d->psnr_db) ? "null" : psnr.c_str(), d->max_channel_difference,
                d->mean_absolute_difference, d->differing_pixels,
                static_cast<std::size_t>(a->width) * static_cast<std::size_t>(a->height), tolerance,
                match ? "true" : "false");
  } else {
    std::printf("PSNR %s dB, largest difference %d, mean difference %.4g, %zu of %zu pixels differ: %s (tolerance %d)\n",
                psnr.c_str(), d->max_channel_difference, d->mean_absolute_difference, d->differing_pixels,
                static_cast<std::size_t>(a->width) * static_cast<std::size_t>(a->height),
                match ? "match" : "differ", tolerance);
  }
  return match ? 0 : 1;
}

}  // namespace facet::cli
