// Shared helpers of the facet command-line program.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "facet/facet.hpp"

namespace facet::cli {

// Prints "facet: message" to stderr and returns the usage-error exit status (2).
int fail(const std::string& message);

// Walks argv, handing out options and their values with errors that name the option.
class Args {
 public:
  Args(int argc, char** argv) : argc_(argc), argv_(argv) {}
  bool next(std::string& arg) {
    if (i_ >= argc_) return false;
    arg = argv_[i_++];
    return true;
  }
  // The value after `option`; empty optional (and an error printed) if missing.
  std::optional<std::string> value(const std::string& option);
  std::optional<int> int_value(const std::string& option, int lo, int hi);
  std::optional<double> number_value(const std::string& option, double lo, double hi);

 private:
  int argc_;
  char** argv_;
  int i_ = 0;
};

std::optional<LightingPath> parse_path(const std::string& name);
std::optional<Isa> parse_isa(const std::string& name);  // "auto" -> Isa::best
std::optional<PowTier> parse_pow_tier(const std::string& name);
std::optional<ShadingMode> parse_shading(const std::string& name);  // flat, gouraud, phong
// --shadows: none, map, raycast (volume is refused by the scene's validation).
std::optional<ShadowMethod> parse_shadow_method(const std::string& name);
// Every light of `scene` casts shadows by `method` (none: no light does).
void override_shadows(Scene& scene, ShadowMethod method);
// "reference", "scalar", or "simd avx512 (pow auto)" with `best` resolved.
std::string describe_path(LightingPath path, Isa isa, PowTier tier);

// The scene named on the command line, or the built-in one when `path` is empty.
// `memory_budget_bytes`: LoadOptions::memory_budget_bytes (0 = no limit).
std::optional<Scene> load_scene_or_default(const std::string& path, std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes);

// True for the files `facet render` reads as models rather than scene files: .gltf, .glb, .obj.
bool is_model_path(const std::string& path);

struct InputOptions {
  std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes;
  bool allow_missing = false;  // --allow-missing
  float aspect = 16.0f / 9.0f; // of the image, for framing a model without a camera
};
// A scene file, a model (framed by a camera and lit by the default rig when the file has none;
// `notes` says so, with the model's warnings) or, for an empty path, the built-in scene. Prints
// the error and returns nothing on failure.
std::optional<Scene> load_input(const std::string& path, const InputOptions& options, std::vector<std::string>& notes);

// Lights every object of `scene` into out[i] (light_instance for each).
Status light_scene(const Scene& scene, const LightingOptions& options, std::vector<VertexColors>& out);

int run_light(int argc, char** argv);
int run_render(int argc, char** argv);
int run_compare(int argc, char** argv);
int run_check(int argc, char** argv);
int run_accuracy(int argc, char** argv);

}  // namespace facet::cli
