// facet's version: the macros of facet/version.h (FACET_VERSION_MAJOR, ...) for the headers a
// program was compiled with, facet::version() for the library it runs with.
#pragma once

#include "facet/version.h"

namespace facet {

// "MAJOR.MINOR.PATCH" of the library.
const char* version() noexcept;

}  // namespace facet
