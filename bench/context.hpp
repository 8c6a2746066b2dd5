// The context every benchmark program adds to its Google Benchmark output (kept in the JSON): what
// a record needs so that another build, commit or machine can be compared with it (`facet
// compare-runs`). Google Benchmark adds the date, host, CPU count and caches itself.
#pragma once

#include <benchmark/benchmark.h>

#include <fstream>
#include <string>

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
