// Internal: read a whole file into memory with a Status that names the path on failure.
#pragma once

#include <string>

#include "facet/status.hpp"

namespace facet {

// `what` names the kind of file in messages ("scene file", "OBJ file").
Result<std::string> read_text_file(const std::string& path, const char* what);

}  // namespace facet
