// The context of a measurement: what a --json record needs so that another machine, build or
// run can be compared with it.
#include <algorithm>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cli.hpp"
#include "facet_commit.h"

namespace facet::cli {

namespace {

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::string name = line.substr(colon + 1);
        name.erase(0, name.find_first_not_of(" \t"));
        return name;
      }
    }
  }
  return {};
}

}  // namespace

std::string json_context(const std::string& isa, const std::string& pow, int threads) {
  std::string out = "{\"facet_version\": \"" + json_escape(version()) + "\"";
#ifdef FACET_GIT_COMMIT
  out += ", \"commit\": \"" FACET_GIT_COMMIT "\"";
#endif
  out += ", \"build_type\": \"" + json_escape(FACET_BUILD_TYPE) + "\"";
#if defined(__clang__)
  out += ", \"compiler\": \"clang " + json_escape(__clang_version__) + "\"";
#elif defined(__GNUC__)
  out += ", \"compiler\": \"gcc " + json_escape(__VERSION__) + "\"";
#endif
  const std::string cpu = cpu_model();
  if (!cpu.empty()) out += ", \"cpu\": \"" + json_escape(cpu) + "\"";
  out += ", \"cores\": " + std::to_string(std::max(1u, std::thread::hardware_concurrency()));
  out += ", \"best_isa\": \"" + std::string(to_string(best_isa())) + "\"";
  if (!isa.empty()) out += ", \"isa\": \"" + json_escape(isa) + "\"";
  if (!pow.empty()) out += ", \"pow\": \"" + json_escape(pow) + "\"";
  if (threads >= 0) out += ", \"threads\": " + std::to_string(threads);  // as asked: 0 = all cores
  return out + "}";
}

std::string json_spread(std::vector<double> values) {
  if (values.empty()) return "null";
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  const double median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  char text[160];
  std::snprintf(text, sizeof text, "{\"median\": %.6g, \"min\": %.6g, \"max\": %.6g, \"count\": %zu}", median, values.front(),
                values.back(), n);
  return text;
}

}  // namespace facet::cli
