// Internal: reading a JSON document's fields with their file and line (JsonLines) in every
// message: the base of the scene-file reader (scene_file.cpp). Types are checked exactly (a number
// where a number belongs, finite and within float range), unknown fields are errors that name the
// nearest known one.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/format.hpp"
#include "common/try.hpp"
#include "facet/fields.hpp"
#include "facet/status.hpp"
#include "facet/types.hpp"
#include "content/json_lines.hpp"

namespace facet::scene_json {

using json = nlohmann::json;

std::size_t edit_distance(std::string_view a, std::string_view b);
// A JSON value described for a message: its type, and a short quoted excerpt of strings.
std::string describe(const json& j);
std::string join(const std::vector<std::string>& names);
// The path of member `key` of the object at `path`.
std::string child(const std::string& path, std::string_view key);

class JsonFields {
 public:
  JsonFields(std::string source, const JsonLines& lines) : source_(std::move(source)), lines_(lines) {}

  // "file:line: message" for a field path.
  Status located(const std::string& path, ErrorCode code, const std::string& message) const {
    const std::size_t line = lines_.line_of(path);
    return {code, path, source_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + message};
  }

  Status mismatch(const std::string& path, const std::string& expected, const json& found) const {
    return located(path, ErrorCode::invalid_argument,
                   (path.empty() ? std::string("top level") : path) + ": expected " + expected + ", found " +
                       describe(found));
  }
  Status invalid(const std::string& path, const std::string& what) const {
    return located(path, ErrorCode::invalid_argument, path + ": " + what);
  }

  Status expect_object(const json& j, const std::string& path, std::initializer_list<std::string_view> allowed) const {
    return expect_object(j, path, std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  Status expect_object(const json& j, const std::string& path, std::span<const std::string_view> allowed) const {
    if (!j.is_object()) return mismatch(path, "an object", j);
    for (const auto& [key, value] : j.items()) {
      bool known = false;
      for (auto a : allowed) known |= a == key;
      if (known) continue;
      std::string hint;
      std::size_t best = 3;
      std::vector<std::string> names;
      for (auto a : allowed) {
        names.emplace_back(a);
        if (const std::size_t d = edit_distance(key, a); d < best) {
          best = d;
          hint = " (did you mean '" + std::string(a) + "'?)";
        }
      }
      const std::string where = path.empty() ? std::string("top level") : path;
      return located(child(path, key), ErrorCode::invalid_argument,
                     where + ": unknown field " + quote(key, 32) + hint + "; known fields: " + join(names));
    }
    return {};
  }

  template <class Fn>
  Status read_list(const json& root, const char* key, Fn fn) {
    if (!root.contains(key)) return {};
    const json& list = root[key];
    if (!list.is_array()) return mismatch(key, "an array", list);
    for (std::size_t i = 0; i < list.size(); ++i) {
      FACET_TRY(fn(list[i], std::string(key) + "[" + std::to_string(i) + "]"));
    }
    return {};
  }

  Status read_number(const json& j, const std::string& path, float& out) const {
    if (!j.is_number()) return mismatch(path, "a number", j);
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::abs(v) > std::numeric_limits<float>::max()) {
      return mismatch(path, "a finite number within float range", j);
    }
    out = static_cast<float>(v);
    return {};
  }

  Status opt_number(const json& obj, const std::string& path, const char* key, float& out) const {
    return obj.contains(key) ? read_number(obj[key], child(path, key), out) : Status{};
  }
  // A finite number kept in double (a value written by facet with 17 digits reads back exactly).
  Status opt_number(const json& obj, const std::string& path, const char* key, double& out) const {
    if (!obj.contains(key)) return {};
    const json& j = obj[key];
    if (!j.is_number() || !std::isfinite(j.get<double>())) return mismatch(child(path, key), "a finite number", j);
    out = j.get<double>();
    return {};
  }

  Status opt_int(const json& obj, const std::string& path, const char* key, int lo, int hi, int& out) const {
    if (!obj.contains(key)) return {};
    const json& j = obj[key];
    const std::string p = child(path, key);
    if (!j.is_number_integer()) return mismatch(p, "an integer", j);
    const auto v = j.get<long long>();
    if (v < lo || v > hi) {
      return mismatch(p, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", j);
    }
    out = static_cast<int>(v);
    return {};
  }

  Status opt_bool(const json& obj, const std::string& path, const char* key, bool& out) const {
    if (!obj.contains(key)) return {};
    const json& j = obj[key];
    if (!j.is_boolean()) return mismatch(child(path, key), "true or false", j);
    out = j.get<bool>();
    return {};
  }

  Status opt_string(const json& obj, const std::string& path, const char* key, std::string& out) const {
    if (!obj.contains(key)) return {};
    const json& j = obj[key];
    if (!j.is_string()) return mismatch(child(path, key), "a string", j);
    out = j.get<std::string>();
    return {};
  }

  Status read_vec3(const json& j, const std::string& path, Vec3& out) const {
    if (!j.is_array() || j.size() != 3) return mismatch(path, "an array of 3 numbers", j);
    for (std::size_t i = 0; i < 3; ++i) {
      float v = 0;
      FACET_TRY(read_number(j[i], path + "[" + std::to_string(i) + "]", v));
      out[static_cast<Eigen::Index>(i)] = v;
    }
    return {};
  }

  Status opt_vec3(const json& obj, const std::string& path, const char* key, Vec3& out) const {
    return obj.contains(key) ? read_vec3(obj[key], child(path, key), out) : Status{};
  }

  // A colour is [r, g, b] or one number for a grey.
  Status opt_color(const json& obj, const std::string& path, const char* key, Color3& out) const {
    if (!obj.contains(key)) return {};
    const json& j = obj[key];
    const std::string p = child(path, key);
    if (j.is_number()) {
      float g = 0;
      FACET_TRY(read_number(j, p, g));
      out = Color3(g, g, g);
      return {};
    }
    if (!j.is_array()) return mismatch(p, "a colour: [r, g, b] or one number", j);
    return read_vec3(j, p, out);
  }

  Status read_enum(const json& j, const std::string& path, std::initializer_list<std::string_view> choices,
                   std::string& out) const {
    std::vector<std::string> names(choices.begin(), choices.end());
    const std::string expected = "one of \"" + join(names) + "\"";
    if (!j.is_string()) return mismatch(path, expected, j);
    out = j.get<std::string>();
    for (auto c : choices)
      if (c == out) return {};
    return mismatch(path, expected, j);
  }

  // Field `f` of the field table (facet/fields.hpp) at obj[key], when present, stored into `object`
  // (its range is validate_scene's to check, with the line): a colour as opt_color, a choice by
  // name (one with "on" and "off" also as true or false), a two-component vector as one number for
  // both, a texture by name.
  template <class T, class Named>
  Status opt_field(const json& obj, const std::string& path, const char* key, const FieldSpec<T>& f,
                   const std::vector<Named>& textures, T& object) const {
    if (!obj.contains(key)) return {};
    const json& j = obj[key];
    const std::string p = child(path, key);
    switch (f.type) {
      case FieldType::colour: {
        Color3 c;
        FACET_TRY(opt_color(obj, path, key, c));
        for (int k = 0; k < 3; ++k) f.set(object, k, c[k]);
        return {};
      }
      case FieldType::number: {
        float v = 0;
        FACET_TRY(read_number(j, p, v));
        f.set(object, 0, v);
        return {};
      }
      case FieldType::integer: {
        int v = 0;
        FACET_TRY(opt_int(obj, path, key, static_cast<int>(f.lo), static_cast<int>(f.hi), v));
        f.set(object, 0, v);
        return {};
      }
      case FieldType::boolean: {
        bool v = false;
        FACET_TRY(opt_bool(obj, path, key, v));
        f.set(object, 0, v ? 1.0 : 0.0);
        return {};
      }
      case FieldType::choice: {
        std::string name;
        if (j.is_boolean()) {
          name = j.get<bool>() ? "on" : "off";
        } else {
          std::vector<std::string> names(f.choices.begin(), f.choices.end());
          if (!j.is_string()) return mismatch(p, "one of \"" + join(names) + "\"", j);
          name = j.get<std::string>();
        }
        for (std::size_t i = 0; i < f.choices.size(); ++i) {
          if (name == f.choices[i]) {
            f.set(object, 0, double(i));
            return {};
          }
        }
        std::vector<std::string> names(f.choices.begin(), f.choices.end());
        return mismatch(p, "one of \"" + join(names) + "\"", j);
      }
      case FieldType::vector: {
        const auto n = static_cast<std::size_t>(f.components);
        if (n == 2 && j.is_number()) {
          float v = 0;
          FACET_TRY(read_number(j, p, v));
          f.set(object, 0, v), f.set(object, 1, v);
          return {};
        }
        if (!j.is_array() || j.size() != n) {
          return mismatch(p, "an array of " + std::to_string(n) + " numbers" + (n == 2 ? " or one number" : ""), j);
        }
        for (std::size_t i = 0; i < n; ++i) {
          float v = 0;
          FACET_TRY(read_number(j[i], p + "[" + std::to_string(i) + "]", v));
          f.set(object, static_cast<int>(i), v);
        }
        return {};
      }
      case FieldType::texture: {
        if (f.components != 1) return invalid(p, "a list of textures is read by its object's own rules");
        std::uint32_t index = 0;
        FACET_TRY(find_name(j, p, textures, "texture", index));
        f.set(object, 0, double(index));
        return {};
      }
    }
    return invalid(p, "unknown field type");
  }

  template <class Named>
  Status find_by_name(const json& obj, const std::string& path, const char* key, const std::vector<Named>& items,
                      const char* kind, std::uint32_t& out) const {
    const std::string p = child(path, key);
    if (!obj.contains(key)) return invalid(p, std::string("missing: every object names its ") + kind);
    return find_name(obj[key], p, items, kind, out);
  }

  // The index of the item named by string j (at path p).
  template <class Named>
  Status find_name(const json& j, const std::string& p, const std::vector<Named>& items, const char* kind,
                   std::uint32_t& out) const {
    if (!j.is_string()) return mismatch(p, std::string("the name of a ") + kind, j);
    const std::string name = j.get<std::string>();
    std::vector<std::string> names;
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (items[i].name == name) {
        out = static_cast<std::uint32_t>(i);
        return {};
      }
      names.push_back(quote(items[i].name, 32));
    }
    return invalid(p, std::string("no ") + kind + " named " + quote(name, 32) + " (defined: " +
                          (names.empty() ? std::string("none") : join(names)) + ")");
  }

  // A texture named by `key` (when present): its index in `textures` (Scene::textures).
  template <class Named>
  Status opt_texture(const json& j, const std::string& p, const char* key, const std::vector<Named>& textures,
                     std::int32_t& out) const {
    if (!j.contains(key)) return {};
    std::uint32_t index = 0;
    FACET_TRY(find_by_name(j, p, key, textures, "texture", index));
    out = static_cast<std::int32_t>(index);
    return {};
  }

 protected:
  std::string source_;
  const JsonLines& lines_;
};

}  // namespace facet::scene_json
