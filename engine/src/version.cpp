#include "facet/version.hpp"

namespace facet {

const char* version() noexcept { return FACET_VERSION_STRING; }

}  // namespace facet
