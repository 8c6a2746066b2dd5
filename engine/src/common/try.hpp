// Internal: early return of a failed Status.
#pragma once

#define FACET_TRY(expr)                 \
  do {                                  \
    if (::facet::Status s_ = (expr); !s_.ok()) \
      return s_;                        \
  } while (0)
