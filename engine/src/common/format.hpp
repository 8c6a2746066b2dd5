// Internal: numbers in messages, shortest readable form ("0.5", "4096", "1e+09", "nan").
#pragma once

#include <cstdio>
#include <string>

namespace facet {

inline std::string format_number(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", value);
  return buf;
}

}  // namespace facet
