#include "records.hpp"

#include <cmath>
#include <sstream>

#include "common/format.hpp"

namespace facet::cli {
namespace {

using nlohmann::json;

void add(Run& run, const std::string& name, const Measure& m) {
  if (!run.measures.count(name)) run.order.push_back(name);
  run.measures[name] = m;
}

const char* type_name(const json& v) {
  switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "a boolean";
    case json::value_t::number_integer: case json::value_t::number_unsigned: case json::value_t::number_float: return "a number";
    default: return "something else";
  }
}

// A record's fields, each checked for its type: the first that is wrong becomes the error, naming
// the file (and line), the field's path and what was found.
struct Fields {
  std::string source;  // "a.json" or "a.json:3"
  std::string error;

  bool bad(const std::string& path, const char* expected, const json& found) {
    if (error.empty()) error = source + ": " + printable(path, 120) + ": expected " + expected + ", found " + type_name(found);
    return false;
  }
  static std::string at(const std::string& path, const char* key) { return path.empty() ? key : path + "." + key; }
  // The number `o[key]` (def when absent); false when it is there and not a finite number (or,
  // with `positive_count`, not a whole number >= 1).
  bool number(const json& o, const std::string& path, const char* key, double def, double& out) {
    out = def;
    if (!o.contains(key)) return true;
    const json& v = o[key];
    if (!v.is_number()) return bad(at(path, key), "a finite number", v);
    if (!std::isfinite(v.get<double>())) return bad(at(path, key), "a finite number", v);
    out = v.get<double>();
    return true;
  }
  bool count(const json& o, const std::string& path, const char* key, std::size_t& out) {
    if (!o.contains(key)) return true;
    const json& v = o[key];
    const double d = v.is_number() ? v.get<double>() : 0;
    if (!v.is_number() || !(d >= 1 && d <= 1e15) || std::floor(d) != d) return bad(at(path, key), "a whole number >= 1", v);
    out = static_cast<std::size_t>(d);
    return true;
  }
  bool text(const json& o, const std::string& path, const char* key, std::string& out) {
    if (!o.contains(key)) return true;
    if (!o[key].is_string()) return bad(at(path, key), "a string", o[key]);
    out = o[key].get<std::string>();
    return true;
  }
  bool flag(const json& o, const std::string& path, const char* key, bool& out) {
    if (!o.contains(key)) return true;
    if (!o[key].is_boolean()) return bad(at(path, key), "true or false", o[key]);
    out = o[key].get<bool>();
    return true;
  }
  // {"median", "min", "max", "count"}.
  bool spread(const json& o, const std::string& path, const char* key, bool higher_is_better, const std::string& unit, Measure& m) {
    const json& s = o[key];
    if (!s.is_object()) return bad(at(path, key), "an object {\"median\", \"min\", \"max\", \"count\"}", s);
    const std::string p = at(path, key);
    if (!s.contains("median")) return bad(at(p, "median"), "a finite number", json());
    m.higher_is_better = higher_is_better;
    m.unit = unit;
    return number(s, p, "median", 0.0, m.value) && number(s, p, "min", m.value, m.min) && number(s, p, "max", m.value, m.max) &&
           count(s, p, "count", m.count);
  }
};

// One JSON document: facet light's, a Google Benchmark file, or one line of facet render's.
bool read_document(const json& doc, Run& run, Fields& f) {
  if (!doc.is_object()) return f.bad("(the document)", "a JSON object", doc);
  if (run.context.is_null() && doc.contains("context")) {
    if (!doc["context"].is_object()) return f.bad("context", "an object", doc["context"]);
    run.context = doc["context"];
  }
  if (run.input.is_null() && doc.contains("input")) {
    const json& in = doc["input"];
    std::string name, hash;
    double files = 0;
    if (!in.is_object()) return f.bad("input", "an object {\"name\", \"hash\", \"files\"}", in);
    if (!f.text(in, "input", "name", name) || !f.text(in, "input", "hash", hash) || !f.number(in, "input", "files", 0.0, files)) return false;
    run.input = {{"name", name}, {"hash", hash}, {"files", files}};
  }
  if (doc.contains("results")) {  // facet light: throughput, higher is better
    if (!doc["results"].is_array()) return f.bad("results", "an array", doc["results"]);
    for (std::size_t i = 0; i < doc["results"].size(); ++i) {
      const json& r = doc["results"][i];
      const std::string p = "results[" + std::to_string(i) + "]";
      if (!r.is_object()) return f.bad(p, "an object", r);
      std::string path;
      if (!r.contains("path")) return f.bad(p + ".path", "a string", json());
      if (!f.text(r, p, "path", path)) return false;
      const std::string name = "light " + path;
      Measure m;
      if (r.contains("vertices_lit_per_s_per_pass")) {
        if (!f.spread(r, p, "vertices_lit_per_s_per_pass", true, "vertices/s", m)) return false;
      } else {
        if (!f.number(r, p, "vertices_lit_per_s", 0.0, m.value)) return false;
        m.min = m.max = m.value;
        m.higher_is_better = true, m.unit = "vertices/s";
      }
      add(run, name, m);
    }
    return true;
  }
  if (doc.contains("benchmarks")) {  // Google Benchmark: times, lower is better
    if (!doc["benchmarks"].is_array()) return f.bad("benchmarks", "an array", doc["benchmarks"]);
    std::map<std::string, std::map<std::string, double>> aggregates;
    std::map<std::string, std::string> units;
    for (std::size_t i = 0; i < doc["benchmarks"].size(); ++i) {
      const json& b = doc["benchmarks"][i];
      const std::string p = "benchmarks[" + std::to_string(i) + "]";
      if (!b.is_object()) return f.bad(p, "an object", b);
      std::string name, run_type, aggregate, unit = "ns";
      double t = 0;
      if (!f.text(b, p, "name", name) || !f.text(b, p, "run_name", name) || !f.text(b, p, "run_type", run_type) ||
          !f.text(b, p, "aggregate_name", aggregate) || !f.text(b, p, "time_unit", unit) || !f.number(b, p, "real_time", 0.0, t)) {
        return false;
      }
      units[name] = unit;
      auto& a = aggregates[name];
      if (run_type == "aggregate") {
        a[aggregate] = t;
      } else {
        a["iterations"] = a.count("iterations") ? a["iterations"] + 1 : 1;
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
    return true;
  }
  if (doc.contains("frame_seconds")) {  // facet render (a frame or a summary): seconds, lower is better
    std::string name = "render";
    bool summary = false;
    if (!f.flag(doc, "", "summary", summary)) return false;
    if (summary) {
      name += " turntable";
    } else {
      if (doc.contains("frame")) return true;  // one frame of a turntable: its summary stands for it
      double width = 0, height = 0;
      std::string shading, path;
      if (!f.number(doc, "", "width", 0.0, width) || !f.number(doc, "", "height", 0.0, height) ||
          !f.text(doc, "", "shading", shading) || !f.text(doc, "", "path", path)) {
        return false;
      }
      name += " " + format_number(width) + "x" + format_number(height) + " " + shading + " " + path;
    }
    Measure m;
    if (!f.spread(doc, "", "frame_seconds", false, "s/frame", m)) return false;
    add(run, name, m);
  }
  return true;
}

// Records nest no deeper than this (a context is a flat object; Google Benchmark's files are 3 deep).
constexpr std::size_t kMaxRecordDepth = 64;

}  // namespace

Run read_records(const std::string& all, const std::string& shown, std::string& error) {
  Run run;
  if (json_nesting_exceeds(all, kMaxRecordDepth)) {
    error = shown + ": the JSON nests deeper than " + std::to_string(kMaxRecordDepth) + " levels";
    return run;
  }
  Fields f{shown, {}};
  json whole = json::parse(all, nullptr, false);
  if (!whole.is_discarded()) {
    if (!read_document(whole, run, f)) error = f.error;
  } else {  // one object per line
    std::istringstream lines(all);
    std::string line;
    int number = 0;
    while (std::getline(lines, line)) {
      ++number;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      f.source = shown + ":" + std::to_string(number);
      json doc = json::parse(line, nullptr, false);
      if (doc.is_discarded()) {
        error = f.source + ": not a JSON object";
        return run;
      }
      if (!read_document(doc, run, f)) {
        error = f.error;
        return run;
      }
    }
  }
  if (error.empty() && run.measures.empty()) {
    error = shown + ": no measurements found (facet render --json, facet light --json or Google Benchmark JSON)";
  }
  return run;
}

}  // namespace facet::cli
