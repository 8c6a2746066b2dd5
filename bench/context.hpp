// The context every benchmark program adds to its Google Benchmark output (kept in the JSON): what
// a record needs so that another build, commit or machine can be compared with it (`facet
// compare-runs`). Google Benchmark adds the date, host, CPU count and caches itself.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "facet/facet.hpp"
#include "facet_commit.h"

namespace facet::bench {

inline void add_facet_context() {
  benchmark::AddCustomContext("facet_version", version());
#ifdef FACET_GIT_COMMIT
  benchmark::AddCustomContext("facet_commit", FACET_GIT_COMMIT);
#endif
  benchmark::AddCustomContext("facet_build_type", FACET_BUILD_TYPE);
#if defined(__GNUC__) && !defined(__clang__)
  benchmark::AddCustomContext("facet_compiler", std::string("gcc ") + __VERSION__);
#elif defined(__clang__)
  benchmark::AddCustomContext("facet_compiler", std::string("clang ") + __clang_version__);
#endif
  benchmark::AddCustomContext("facet_best_isa", to_string(best_isa()));
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      benchmark::AddCustomContext("cpu_model", line.substr(line.find_first_not_of(" \t", line.find(':') + 1)));
      break;
    }
  }
}

// With --benchmark_repetitions=N, Google Benchmark reports each benchmark's mean, median, standard
// deviation and coefficient of variation; this adds the smallest and largest repetition, so that a
// record carries median, min, max and count (the repetitions) as facet's own --json records do.
inline benchmark::internal::Benchmark* with_spread(benchmark::internal::Benchmark* b) {
  b->ComputeStatistics("min", [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); });
  b->ComputeStatistics("max", [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); });
  return b;
}

// main() for a program whose benchmarks are registered statically (BENCHMARK(...)).
inline int run_static_benchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  add_facet_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace facet::bench
