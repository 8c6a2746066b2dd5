// Internal: numbers and untrusted text in messages.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace facet {

inline std::string format_number(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", value);
  return buf;
}

// A size for people: "512 bytes", "3 MiB", "1.5 MiB" (never rounded to a whole MiB it is not).
inline std::string format_bytes(std::uint64_t bytes) {
  constexpr std::uint64_t kMiB = std::uint64_t{1} << 20;
  char buf[48];
  if (bytes < kMiB) {
    std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(bytes));
  } else if (bytes % kMiB == 0) {
    std::snprintf(buf, sizeof buf, "%llu MiB", static_cast<unsigned long long>(bytes / kMiB));
  } else {
    std::snprintf(buf, sizeof buf, "%.1f MiB (%llu bytes)", double(bytes) / double(kMiB), static_cast<unsigned long long>(bytes));
  }
  return buf;
}

// Text from a file or a caller (a token, a name, a path) as a short, quoted, printable excerpt:
// control bytes, DEL and bytes >= 0x80 as \xNN (\n, \t, \r by name; a NUL does not cut the
// message), quotes and backslashes escaped, and at most `max_chars` characters of the original
// followed by "..." when it was longer. A message never carries a terminal escape or a whole line
// of a file that was not what it claimed to be. printable() is the same without the quotes.
inline std::string printable(std::string_view text, std::size_t max_chars = 48) {
  std::string out;
  const std::size_t n = text.size() < max_chars ? text.size() : max_chars;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\'' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (n < text.size()) out += "...";
  return out;
}

// printable() between single quotes.
inline std::string quote(std::string_view text, std::size_t max_chars = 48) {
  return "'" + printable(text, max_chars) + "'";
}

// True when the brackets of JSON text, outside its strings, nest deeper than `limit`: checked
// before parsing, since nlohmann's parser and its values recurse once a level.
inline bool json_nesting_exceeds(std::string_view text, std::size_t limit) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return false;
}

}  // namespace facet
