#include "cli.hpp"

#include <cstdlib>

namespace facet::cli {

int fail(const std::string& message) {
  std::fprintf(stderr, "facet: %s\n", message.c_str());
  return 2;
}

std::optional<std::string> Args::value(const std::string& option) {
  if (i_ >= argc_) {
    fail(option + " needs a value");
    return std::nullopt;
  }
  return std::string(argv_[i_++]);
}

std::optional<int> Args::int_value(const std::string& option, int lo, int hi) {
  const auto v = value(option);
  if (!v) return std::nullopt;
  char* end = nullptr;
  const long n = std::strtol(v->c_str(), &end, 10);
  if (v->empty() || *end != '\0' || n < lo || n > hi) {
    fail(option + ": expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], found '" + *v + "'");
    return std::nullopt;
  }
  return static_cast<int>(n);
}

std::optional<double> Args::number_value(const std::string& option, double lo, double hi) {
  const auto v = value(option);
  if (!v) return std::nullopt;
  char* end = nullptr;
  const double n = std::strtod(v->c_str(), &end);
  if (v->empty() || *end != '\0' || !(n >= lo && n <= hi)) {
    fail(option + ": expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], found '" + *v + "'");
    return std::nullopt;
  }
  return n;
}

std::optional<Scene> load_scene_or_default(const std::string& path) {
  if (path.empty()) return make_default_scene();
  Result<Scene> loaded = load_scene_file(path);
  if (!loaded) {
    fail(loaded.status().message());
    return std::nullopt;
  }
  return std::move(*loaded);
}

}  // namespace facet::cli
