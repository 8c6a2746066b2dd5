// facet compare-runs: two benchmark records (facet render --json, facet light --json, Google
// Benchmark JSON) compared measurement by measurement, with the spread of each ratio.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli.hpp"

namespace facet::cli {
namespace {

using nlohmann::json;

struct Measure {
  double value = 0, min = 0, max = 0;  // min and max: the spread of repeated measurements (= value if one)
  std::size_t count = 1;
  bool higher_is_better = false;
  std::string unit;
};

struct Run {
  json context;  // the first context found
  std::map<std::string, Measure> measures;
  std::vector<std::string> order;
};

void add(Run& run, const std::string& name, const Measure& m) {
  if (!run.measures.count(name)) run.order.push_back(name);
  run.measures[name] = m;
}

Measure from_spread(const json& spread, bool higher_is_better, const std::string& unit) {
  Measure m;
  m.value = spread.value("median", 0.0);
  m.min = spread.value("min", m.value);
  m.max = spread.value("max", m.value);
  m.count = spread.value("count", std::size_t{1});
  m.higher_is_better = higher_is_better;
  m.unit = unit;
  return m;
}

// One JSON document: facet light's, a Google Benchmark file, or one line of facet render's.
void read_document(const json& doc, Run& run) {
  if (!doc.is_object()) return;
  if (run.context.is_null() && doc.contains("context")) run.context = doc["context"];
  if (doc.contains("results") && doc["results"].is_array()) {  // facet light
    for (const json& r : doc["results"]) {
      if (!r.is_object() || !r.contains("path")) continue;
      const std::string name = "light " + r["path"].get<std::string>();
      if (r.contains("vertices_lit_per_s_per_pass")) {
        add(run, name, from_spread(r["vertices_lit_per_s_per_pass"], true, "vertices/s"));
      } else {
        Measure m;
        m.value = m.min = m.max = r.value("vertices_lit_per_s", 0.0);
        m.higher_is_better = true, m.unit = "vertices/s";
        add(run, name, m);
      }
    }
    return;
  }
  if (doc.contains("benchmarks") && doc["benchmarks"].is_array()) {  // Google Benchmark
    std::map<std::string, std::map<std::string, double>> aggregates;
    std::map<std::string, std::string> units;
    for (const json& b : doc["benchmarks"]) {
      if (!b.is_object()) continue;
      const std::string name = b.value("run_name", b.value("name", std::string()));
      const double t = b.value("real_time", 0.0);
      units[name] = b.value("time_unit", std::string("ns"));
      if (b.value("run_type", std::string()) == "aggregate") {
        aggregates[name][b.value("aggregate_name", std::string())] = t;
      } else {
        aggregates[name]["iterations"] = aggregates[name].count("iterations") ? aggregates[name]["iterations"] + 1 : 1;
        auto& a = aggregates[name];
        a["single_min"] = a.count("single_min") ? std::min(a["single_min"], t) : t;
        a["single_max"] = a.count("single_max") ? std::max(a["single_max"], t) : t;
        a["single_sum"] = (a.count("single_sum") ? a["single_sum"] : 0.0) + t;
      }
    }
    for (const auto& [name, a] : aggregates) {
      Measure m;
      m.unit = units[name] + " (real time)";
      if (a.count("median")) {
        m.value = a.at("median");
        m.min = a.count("min") ? a.at("min") : a.count("single_min") ? a.at("single_min") : m.value;
        m.max = a.count("max") ? a.at("max") : a.count("single_max") ? a.at("single_max") : m.value;
        m.count = a.count("iterations") ? static_cast<std::size_t>(a.at("iterations")) : 1;
      } else if (a.count("single_sum")) {
        m.count = static_cast<std::size_t>(a.at("iterations"));
        m.value = a.at("single_sum") / double(m.count);
        m.min = a.at("single_min"), m.max = a.at("single_max");
      } else {
        continue;
      }
      add(run, "benchmark " + name, m);
    }
    return;
  }
  if (doc.contains("frame_seconds") && doc["frame_seconds"].is_object()) {  // facet render (a frame or a summary)
    std::string name = "render";
    if (doc.value("summary", false)) {
      name += " turntable";
    } else {
      if (doc.contains("frame")) return;  // one frame of a turntable: its summary stands for it
      name += " " + std::to_string(doc.value("width", 0)) + "x" + std::to_string(doc.value("height", 0)) + " " +
              doc.value("shading", std::string()) + " " + doc.value("path", std::string());
    }
    add(run, name, from_spread(doc["frame_seconds"], false, "s/frame"));
  }
}

Run read_run(const std::string& path, std::string& error) {
  Run run;
  std::ifstream file(path);
  if (!file) {
    error = "cannot open '" + path + "'";
    return run;
  }
  std::stringstream text;
  text << file.rdbuf();
  const std::string all = text.str();
  json whole = json::parse(all, nullptr, false);
  if (!whole.is_discarded()) {
    read_document(whole, run);
  } else {  // one object per line
    std::istringstream lines(all);
    std::string line;
    int number = 0;
    while (std::getline(lines, line)) {
      ++number;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      json doc = json::parse(line, nullptr, false);
      if (doc.is_discarded()) {
        error = path + ":" + std::to_string(number) + ": not a JSON object";
        return run;
      }
      read_document(doc, run);
    }
  }
  if (run.measures.empty()) error = path + ": no measurements found (facet render --json, facet light --json or Google Benchmark JSON)";
  return run;
}

std::string human(double v) {
  char text[32];
  const double a = std::abs(v);
  if (a >= 1e9) std::snprintf(text, sizeof text, "%.3g G", v / 1e9);
  else if (a >= 1e6) std::snprintf(text, sizeof text, "%.3g M", v / 1e6);
  else if (a >= 1e3) std::snprintf(text, sizeof text, "%.4g", v);
  else if (a >= 1e-3) std::snprintf(text, sizeof text, "%.4g", v);
  else std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

int compare_runs(const std::string& a_path, const std::string& b_path, bool as_json) {
  std::string error;
  const Run a = read_run(a_path, error);
  if (!error.empty()) return fail(error);
  const Run b = read_run(b_path, error);
  if (!error.empty()) return fail(error);
  json rows = json::array();
  if (!as_json) {
    std::printf("A: %s\nB: %s\n", a_path.c_str(), b_path.c_str());
    for (const char* key : {"facet_version", "commit", "build_type", "compiler", "cpu", "cores", "isa", "pow", "threads"}) {
      const json va = a.context.is_object() && a.context.contains(key) ? a.context[key] : json();
      const json vb = b.context.is_object() && b.context.contains(key) ? b.context[key] : json();
      if (va != vb) std::printf("  context differs: %s: %s | %s\n", key, va.is_null() ? "-" : va.dump().c_str(), vb.is_null() ? "-" : vb.dump().c_str());
    }
    std::printf("\n%-62s %12s %12s %9s %19s\n", "measurement", "A", "B", "B / A", "spread of B / A");
  }
  int matched = 0;
  for (const std::string& name : a.order) {
    auto it = b.measures.find(name);
    if (it == b.measures.end()) continue;
    const Measure& ma = a.measures.at(name);
    const Measure& mb = it->second;
    if (!(ma.value > 0) || !(ma.min > 0)) continue;
    ++matched;
    const double ratio = mb.value / ma.value, low = mb.min / ma.max, high = mb.max / ma.min;
    const bool better = ma.higher_is_better ? ratio > 1 : ratio < 1;
    const bool clear = ma.higher_is_better ? low > 1 || high < 1 : low > 1 || high < 1;  // the spreads do not overlap
    if (as_json) {
      rows.push_back({{"name", name}, {"unit", ma.unit}, {"a", ma.value}, {"b", mb.value}, {"ratio", ratio}, {"ratio_min", low},
                      {"ratio_max", high}, {"a_count", ma.count}, {"b_count", mb.count}, {"b_better", better},
                      {"spreads_overlap", !clear}});
    } else {
      char spread[48];
      std::snprintf(spread, sizeof spread, "%.3f .. %.3f", low, high);
      std::printf("%-62s %12s %12s %8.3fx %19s  %s%s\n", name.c_str(), human(ma.value).c_str(), human(mb.value).c_str(), ratio, spread,
                  ratio == 1 ? "same" : better ? "B better" : "B worse", clear ? "" : " (within the spread)");
    }
  }
  if (matched == 0) return fail("no measurement appears in both '" + a_path + "' and '" + b_path + "'");
  if (as_json) {
    std::printf("%s\n", json({{"a", a_path}, {"b", b_path}, {"a_context", a.context}, {"b_context", b.context}, {"rows", rows}}).dump().c_str());
  } else {
    std::printf("\n%d measurements in both; B / A of the medians, and the smallest and largest ratio the spreads allow "
                "(B's min over A's max, B's max over A's min)\n", matched);
  }
  return 0;
}

}  // namespace

Command add_compare_runs(CLI::App& facet) {
  struct State {
    std::vector<std::string> files;
    bool json = false;
  };
  auto st = std::make_shared<State>();
  CLI::App* app = facet.add_subcommand("compare-runs", "compare two benchmark records: ratios of medians with their spread");
  app->footer(
      "Reads two records of the same measurements: facet render --json (one object per line; a turntable's\n"
      "summary), facet light --json, or Google Benchmark JSON (--benchmark_out; with repetitions, the median,\n"
      "min and max aggregates). Matches them by name and prints, for each, A, B, B / A of the medians and the\n"
      "range of B / A their spreads allow; says where the contexts (version, commit, CPU, ISA...) differ.");
  app->add_option("records", st->files, "A.json B.json")->required()->expected(2);
  app->add_flag("--json", st->json, "print the comparison as one JSON object");
  return {app, [st] { return compare_runs(st->files[0], st->files[1], st->json); }};
}

}  // namespace facet::cli
