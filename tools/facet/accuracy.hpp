// The measurements of `facet accuracy` (cmd_accuracy.cpp describes each), one file a group:
// accuracy_lighting.cpp (vertices, pow), accuracy_images.cpp (images, textures),
// accuracy_shadows.cpp (shadows, environment maps), accuracy_surfaces.cpp (bump maps,
// multisampling, baking). Each appends its rows.
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "facet/facet.hpp"

namespace facet::cli {

// One measurement: what was measured (kind, method, case) and its numbers.
struct Row {
  std::string kind;    // "vertices", "special", "pow", "image"
  std::string method;  // e.g. "simd avx2 (pow fast)", "pow fast avx2", "phong"
  std::string item;    // e.g. "random", "light at vertex", "x=nan s=3", "segments=64"
  double max_lsb = 0;  // largest |error| in 8-bit steps
  double mean_lsb = 0;
  int max_step = 0;  // largest difference after rounding both to 8 bits
  long nans = 0;
  double psnr_db = 0;     // images
  double ms_per_frame = 0;  // images: the same frame on the default path (simd, best ISA), 1 thread
  double rate = 0;          // textures: samples per second, 1 thread
  double share = 0;         // shadows: share of receiver pixels that differ from ray-cast shadows
  double edge_px = 0;       // shadows: the farthest of them from a ray-cast shadow edge, pixels
  std::string verdict;    // "ok" or what failed
};

inline std::string number(double v) {
  if (std::isnan(v)) return "null";
  if (std::isinf(v)) return v > 0 ? "1e999" : "-1e999";
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

// The error of an RGBA8 image against its reference over the pixels `inside` marks: the largest
// and mean difference per channel in steps, and (share) the pixels whose every channel is within
// 2 steps.
void compare_inside(const std::vector<std::uint8_t>& rgba, const std::vector<std::uint8_t>& reference,
                    const std::vector<std::uint8_t>& inside, Row& row);

Status vertex_accuracy(bool quick, std::vector<Row>& rows);
void pow_sweep(std::vector<Row>& rows);
Status image_accuracy(bool quick, std::vector<Row>& rows);
void texture_accuracy(bool quick, std::vector<Row>& rows);
Status shadow_accuracy(bool quick, std::vector<Row>& rows);
Status environment_accuracy(bool quick, std::vector<Row>& rows);
Status relief_accuracy(bool quick, std::vector<Row>& rows);
Status msaa_accuracy(bool quick, std::vector<Row>& rows);
Status bake_accuracy(bool quick, std::vector<Row>& rows);
Status pbr_accuracy(bool quick, std::vector<Row>& rows);
Status ibl_accuracy(bool quick, std::vector<Row>& rows);
Status skin_accuracy(bool quick, std::vector<Row>& rows);

}  // namespace facet::cli
