// Internal: where each value of a JSON text is. A SAX pass over the text records, for every value,
// the line it is on, keyed by its path in the scene-file form ("lights[2].position"). The same pass
// rejects duplicate keys and nesting deeper than kMaxJsonDepth (the scene schema needs 4 levels),
// and formats syntax errors as "file:line:column: ...".
#pragma once

#include <cstddef>
#include <string>
#include <unordered_map>

#include "facet/status.hpp"

namespace facet {

inline constexpr std::size_t kMaxJsonDepth = 64;

class JsonLines {
 public:
  // Scans `text`; a failed Status means the text is not acceptable JSON.
  Status scan(const std::string& text, const std::string& source_name);

  // Line of the value at `path`, or of its nearest recorded ancestor; 0 if none is known.
  std::size_t line_of(std::string path) const;

 private:
  std::unordered_map<std::string, std::size_t> line_of_path_;
};

}  // namespace facet
