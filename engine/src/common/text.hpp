// Internal: the line-format readers' (OBJ, MTL) view of a line: trimmed, split at blanks.
#pragma once

#include <string_view>
#include <vector>

namespace facet::text {

inline std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\f\v");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\f\v");
  return s.substr(b, e - b + 1);
}

// The words of `s`, separated by spaces and tabs.
inline std::vector<std::string_view> split_ws(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

// `tok` without one leading '+' before a digit or '.': OBJ and MTL writers print "+1" and
// std::from_chars reads no '+'.
inline std::string_view without_plus(std::string_view tok) {
  if (tok.size() > 1 && tok[0] == '+' && ((tok[1] >= '0' && tok[1] <= '9') || tok[1] == '.')) tok.remove_prefix(1);
  return tok;
}

}  // namespace facet::text
