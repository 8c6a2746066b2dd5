// facet accuracy: how far every fast method is from the exact one, at three levels.
//
//  1. Vertices: 10^5 random vertices (16 random materials, shininess 0..256, some black
//     specular; 8 random lights of every type) lit by every path x ISA x pow tier, against the
//     reference path (double precision): max and mean error in 8-bit steps, the largest
//     difference after rounding to 8 bits, NaN count. Then the special inputs (n.h = 1 at high
//     shininess, light at the vertex, zero normals, L = -V, 0^0, eye at the vertex).
//  2. Pow methods: every tier on every ISA over its failure inputs (NaN, negative, 0, subnormal,
//     1 - ulp, 1, 1 + ulp, +inf, huge exponents), against double-precision pow of the clamped
//     input: where each returns NaN, leaves [0, 1], or exceeds its stated contract.
//  3. Images: a scene of spheres on a plane, ray-cast per pixel in double precision from the
//     exact geometry (not its triangles) and lit by the reference path at the exact hit point and
//     normal; then facet's flat, Gouraud and Phong images at several tessellation levels: PSNR and
//     largest error over the pixels inside the silhouettes (covered in both images, and not on an
//     edge of either).
//  4. Texture filters: nearest, bilinear and trilinear samples of a 256x256 texture at random
//     coordinates (repeat wrap, -3..4) and derivatives (level of detail -2..7), by the scalar
//     sampler and each ISA's SIMD sampler, against the double-precision reference sampler: max
//     and mean error in 8-bit steps, and samples per second on one thread.
//  5. Shadows: a sphere and a cube on a plane under one light at a time (directional, spot,
//     point), each shadow method against ray-cast shadows (exact visibility): per method x
//     resolution x filter, the share of receiver pixels (pixels the light reaches) whose colour
//     differs from the ray-cast image by more than one step, how far (in pixels) the farthest of
//     them lies from a ray-cast shadow edge, PSNR against the ray-cast image, and ms per frame.
//  6-7. Environment and bump maps per vertex and per pixel (see their functions).
//  8. Multisampling: edge pixels at 1, 4, 8 and 16 samples against a 64-sample reference.
//  9-12. Baking, PBR per vertex and per pixel, the prefilter, and skinned normals (cofactor
//     against the plain 3x3, accuracy_skin.cpp).
// Output: a table, or JSON (--json FILE) and CSV (--csv FILE). The measurements themselves are in
// accuracy_*.cpp (accuracy.hpp lists them).
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <ostream>

#include "accuracy.hpp"
#include "cli.hpp"

namespace facet::cli {
namespace {

void write_json(std::ostream& o, const std::vector<Row>& rows) {
  o << "{\n  \"machine\": \"" << json_escape(to_string(best_isa())) << "\",\n  \"rows\": [\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    o << "    {\"kind\": \"" << r.kind << "\", \"method\": \"" << json_escape(r.method) << "\", \"item\": \""
      << json_escape(r.item) << "\", \"max_lsb\": " << number(r.max_lsb) << ", \"mean_lsb\": " << number(r.mean_lsb)
      << ", \"max_step\": " << r.max_step << ", \"nans\": " << r.nans << ", \"psnr_db\": " << number(r.psnr_db) << ", \"ms_per_frame\": " << number(r.ms_per_frame)
      << ", \"rate\": " << number(r.rate) << ", \"share\": " << number(r.share) << ", \"edge_px\": " << number(r.edge_px)
      << ", \"verdict\": \"" << json_escape(r.verdict) << "\"}" << (i + 1 < rows.size() ? "," : "") << "\n";
  }
  o << "  ]\n}\n";
}

void write_csv(std::ostream& o, const std::vector<Row>& rows) {
  o << "kind,method,item,max_lsb,mean_lsb,max_step,nans,psnr_db,ms_per_frame,rate,share,edge_px,verdict\n";
  auto q = [](const std::string& s) { return "\"" + s + "\""; };
  for (const Row& r : rows) {
    o << r.kind << "," << q(r.method) << "," << q(r.item) << "," << number(r.max_lsb) << "," << number(r.mean_lsb)
      << "," << r.max_step << "," << r.nans << "," << number(r.psnr_db) << "," << number(r.ms_per_frame) << ","
      << number(r.rate) << "," << number(r.share) << "," << number(r.edge_px) << "," << q(r.verdict) << "\n";
  }
}

}  // namespace

int accuracy(const std::string& only, bool quick, bool check, const std::string& json_path, const std::string& csv_path);

Command add_accuracy(CLI::App& facet) {
  struct State {
    std::string only, json_path, csv_path;
    bool quick = false, check = false;
  };
  auto st = std::make_shared<State>();
  CLI::App* app = facet.add_subcommand("accuracy", "every fast method against its exact reference: vertices, pow, images, textures, shadows, environment and bump maps, multisampling");
  app->footer(
      "Measures every lighting path, ISA and pow tier against the exact reference: vertex colours\n"
      "(random and special inputs), the pow methods over their failure inputs, whole images against a\n"
      "ray-cast reference of exact spheres, the texture filters against the reference sampler, and\n"
      "the shadow methods against ray-cast shadows, environment maps per vertex and per pixel against\n"
      "exact reflection rays, bump maps per vertex and per pixel against per-pixel bump on the\n"
      "reference path, multisampled edges against a 64-sample reference, and radiosity's convergence in the\n"
      "white furnace (B = E / (1 - albedo)) against the shots and time spent.");
  app->add_option("--only", st->only,
                  "vertices | pow | images | textures | shadows | environment | relief | msaa | bake | pbr | ibl (default: all eleven)")
      ->check(one_of({"vertices", "pow", "images", "textures", "shadows", "environment", "relief", "msaa", "bake", "pbr", "ibl", "skin"}, "part"));
  app->add_flag("--quick", st->quick, "fewer vertices (10^4) and tessellation levels, for tests");
  app->add_option("--json", st->json_path, "write all results as JSON to FILE");
  app->add_option("--csv", st->csv_path, "write all results as CSV (one row per measurement) to FILE");
  app->add_flag("--check", st->check, "exit with status 1 if any measurement is outside its contract (for tests)");
  return {app, [st] { return accuracy(st->only, st->quick, st->check, st->json_path, st->csv_path); }};
}

int accuracy(const std::string& only, bool quick, bool check, const std::string& json_path, const std::string& csv_path) {
  std::vector<Row> rows;
  if (only.empty() || only == "vertices") {
    if (Status s = vertex_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "pow") pow_sweep(rows);
  if (only.empty() || only == "images") {
    if (Status s = image_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "textures") texture_accuracy(quick, rows);
  if (only.empty() || only == "shadows") {
    if (Status s = shadow_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "environment") {
    if (Status s = environment_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "relief") {
    if (Status s = relief_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "msaa") {
    if (Status s = msaa_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "bake") {
    if (Status s = bake_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "pbr") {
    if (Status s = pbr_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "ibl") {
    if (Status s = ibl_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }
  if (only.empty() || only == "skin") {
    if (Status s = skin_accuracy(quick, rows); !s.ok()) return fail(s.message());
  }

  int failures = 0;
  // The pow sweep has hundreds of rows: print only its failures and the worst case of each method
  // (all of them with --csv or --json).
  std::map<std::string, std::size_t> worst_pow;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].kind != "pow") continue;
    auto [it, fresh] = worst_pow.emplace(rows[i].method, i);
    if (!fresh && rows[i].max_lsb > rows[it->second].max_lsb) it->second = i;
  }
  std::printf("%-9s %-28s %-36s %9s %9s %5s %5s %8s  %s\n", "kind", "method", "case", "max LSB", "mean LSB", "step",
              "NaN", "PSNR dB", "verdict");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const bool bad = r.verdict.rfind("ok", 0) != 0;
    failures += bad;
    if (r.kind == "pow" && !bad && worst_pow[r.method] != i) continue;
    std::printf("%-9s %-28s %-36s %9.3g %9.3g %5d %5ld %8s  %s", r.kind.c_str(), r.method.c_str(), r.item.c_str(),
                r.max_lsb, r.mean_lsb, r.max_step, r.nans,
                r.kind == "image" || r.kind == "shadow" ? number(r.psnr_db).c_str() : "", r.verdict.c_str());
    if (r.kind == "texture") std::printf(" (%.1f M samples/s)", r.rate / 1e6);
    if (r.kind == "environment" || r.kind == "relief" || r.kind == "pbr") std::printf(" (%.1f %% of pixels within 2 steps; %.2f ms/frame)", 100.0 * r.share, r.ms_per_frame);
    if (r.kind == "ibl") std::printf(" (relative error in %%, not LSB; the build %.1f ms on one thread)", r.ms_per_frame);
    if (r.kind == "skin") std::printf(" (normal angle in degrees, not LSB; %.1f M vertices skinned/s on one thread)", r.rate / 1e6);
    if (r.kind == "msaa") std::printf(" (%.1f %% of edge pixels within 8 steps; %.2f ms/frame)", 100.0 * r.share, r.ms_per_frame);
    if (r.kind == "bake") std::printf(" (%.3g %% of the power unshot; %.1f ms)", 100.0 * r.share, r.ms_per_frame);
    if (r.kind == "shadow") {
      std::printf(" (%.3f %% of receivers differ, farthest %.0f px from an edge; %.2f ms/frame)", 100.0 * r.share, r.edge_px,
                  r.ms_per_frame);
    }
    std::printf("\n");
  }
  std::printf("%zu measurements, %d outside their contract%s\n", rows.size(), failures,
              failures ? " (see the verdicts above)" : "");
  if (!json_path.empty()) {
    std::ofstream f(json_path);
    write_json(f, rows);
    if (!f) return fail("cannot write " + json_path);
  }
  if (!csv_path.empty()) {
    std::ofstream f(csv_path);
    write_csv(f, rows);
    if (!f) return fail("cannot write " + csv_path);
  }
  return check && failures > 0 ? 1 : 0;
}

}  // namespace facet::cli
