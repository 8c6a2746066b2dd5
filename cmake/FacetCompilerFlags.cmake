# Warnings for facet's own targets, and the flag set that keeps the scalar lighting path scalar.

add_library(facet_warnings INTERFACE)
target_compile_options(facet_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion>
  # GCC 12 warns on every `"literal" + std::string&&` (GCC PR 105329, a false positive).
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)

# The scalar path is the baseline users compare SIMD against, so the compiler must not vectorise
# it behind our back. GCC: -fno-tree-vectorize also turns off SLP (basic-block) vectorisation;
# Clang: both vectorisers are named.
set(FACET_NO_VECTORIZE_FLAGS
  $<$<CXX_COMPILER_ID:GNU>:-fno-tree-vectorize -fno-tree-slp-vectorize>
  $<$<CXX_COMPILER_ID:Clang>:-fno-vectorize -fno-slp-vectorize>)
