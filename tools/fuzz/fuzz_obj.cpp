// Fuzzes the OBJ loader: any text either fails with a message or gives a valid mesh.
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const facet::Result<facet::Mesh> mesh = facet::parse_obj(text, "fuzz.obj");
  if (mesh.ok()) {
    if (!facet::validate_mesh(*mesh).ok()) facet::fuzz::broken("parse_obj returned an invalid mesh");
    for (const auto& n : mesh->normals)
      if (!n.allFinite()) facet::fuzz::broken("parse_obj returned a non-finite normal");
  } else if (mesh.status().message().empty()) {
    facet::fuzz::broken("an error without a message");
  }
  return 0;
}
