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
#include "records.hpp"
#include "common/format.hpp"
#include "io/file_access.hpp"

namespace facet::cli {
namespace {

using nlohmann::json;

Run read_run(const std::string& path, std::string& error) {
  Result<std::string> read = io::read_file(path, "record", std::uint64_t{1} << 30);
  if (!read) {
    error = read.status().message();
    return {};
  }
  return read_records(*read, printable(path, 200), error);
}

// "model.glb (fnv1a64:..., 3 files)", or "-" for a record that does not say.
std::string describe_input(const json& in) {
  if (!in.is_object()) return "-";
  if (in.value("files", 0.0) == 0.0) return printable(in.value("name", std::string()), 80) + " (no file)";
  return printable(in.value("name", std::string()), 80) + " (" + printable(in.value("hash", std::string()), 40) + ", " +
         format_number(in.value("files", 0.0)) + " files)";
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
    std::printf("A: %s\nB: %s\n", printable(a_path, 200).c_str(), printable(b_path, 200).c_str());
    for (const char* key : {"facet_version", "commit", "build_type", "compiler", "cpu", "cores", "isa", "pow", "threads"}) {
      const json va = a.context.is_object() && a.context.contains(key) ? a.context[key] : json();
      const json vb = b.context.is_object() && b.context.contains(key) ? b.context[key] : json();
      if (va != vb) {
        std::printf("  context differs: %s: %s | %s\n", key, va.is_null() ? "-" : printable(va.dump(-1, ' ', false, json::error_handler_t::replace), 120).c_str(),
                    vb.is_null() ? "-" : printable(vb.dump(-1, ' ', false, json::error_handler_t::replace), 120).c_str());
      }
    }
    if (a.input != b.input) {
      std::printf("  %s: %s | %s\n",
                  a.input.is_null() || b.input.is_null() ? "input" : "INPUTS DIFFER (different files or contents)",
                  describe_input(a.input).c_str(), describe_input(b.input).c_str());
    }
  }
  // Measurements by name; and when none match, the single frames of two renders (one in each
  // record: Gouraud against Phong, one size against another), with what differs in the name.
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const std::string& name : a.order)
    if (b.measures.count(name)) pairs.emplace_back(name, name);
  if (pairs.empty()) {
    const auto single_render = [](const Run& r) {
      std::string found;
      int n = 0;
      for (const std::string& name : r.order)
        if (name.rfind("render ", 0) == 0) found = name, ++n;
      return n == 1 ? found : std::string();
    };
    const std::string ra = single_render(a), rb = single_render(b);
    if (!ra.empty() && !rb.empty()) pairs.emplace_back(ra, rb);
  }
  if (!as_json) std::printf("\n%-62s %12s %12s %9s %19s\n", "measurement", "A", "B", "B / A", "spread of B / A");
  int matched = 0;
  for (const auto& [name, b_name] : pairs) {
    const Measure& ma = a.measures.at(name);
    const Measure& mb = b.measures.at(b_name);
    if (!(ma.value > 0) || !(ma.min > 0)) continue;
    ++matched;
    const double ratio = mb.value / ma.value, low = mb.min / ma.max, high = mb.max / ma.min;
    const bool better = ma.higher_is_better ? ratio > 1 : ratio < 1;
    const bool clear = ma.higher_is_better ? low > 1 || high < 1 : low > 1 || high < 1;  // the spreads do not overlap
    const std::string shown = name == b_name ? name : name + " | " + b_name.substr(b_name.find(' ') + 1);
    if (as_json) {
      rows.push_back({{"name", shown}, {"unit", ma.unit}, {"a", ma.value}, {"b", mb.value}, {"ratio", ratio}, {"ratio_min", low},
                      {"ratio_max", high}, {"a_count", ma.count}, {"b_count", mb.count}, {"b_better", better},
                      {"spreads_overlap", !clear}});
    } else {
      char spread[48];
      std::snprintf(spread, sizeof spread, "%.3f .. %.3f", low, high);
      std::printf("%-62s %12s %12s %8.3fx %19s  %s%s\n", printable(shown, 120).c_str(), human(ma.value).c_str(), human(mb.value).c_str(), ratio, spread,
                  ratio == 1 ? "same" : better ? "B better" : "B worse", clear ? "" : " (within the spread)");
    }
  }
  if (matched == 0) return fail("no measurement appears in both " + quote(a_path, 200) + " and " + quote(b_path, 200));
  if (as_json) {
    std::printf("%s\n", json({{"a", a_path}, {"b", b_path}, {"a_context", a.context}, {"b_context", b.context}, {"a_input", a.input},
                              {"b_input", b.input}, {"same_input", a.input == b.input && !a.input.is_null()}, {"rows", rows}}).dump(-1, ' ', true, json::error_handler_t::replace).c_str());
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
