// Benchmark records as facet compare-runs reads them (facet render --json, facet light --json,
// Google Benchmark JSON): every field checked for its type, nesting bounded, so that a record
// nobody checked is an error naming its file, line and field, never an abort.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace facet::cli {

struct Measure {
  double value = 0, min = 0, max = 0;  // min and max: the spread of repeated measurements (= value if one)
  std::size_t count = 1;
  bool higher_is_better = false;  // throughputs (facet light); times are better lower
  std::string unit;
};

struct Run {
  nlohmann::json context;  // the first context found
  // The first "input" found ({"name", "hash", "files"}: what the record measured); null in
  // records older than it, and in Google Benchmark's.
  nlohmann::json input;
  std::map<std::string, Measure> measures;
  std::vector<std::string> order;
};

// The measurements of one record's text; `shown` names it in messages (its path, escaped).
// `error` is set (and the run incomplete) when the record is malformed or holds none.
Run read_records(const std::string& text, const std::string& shown, std::string& error);

}  // namespace facet::cli
