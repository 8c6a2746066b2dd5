// Fuzzes facet compare-runs' record reader (tools/facet/records.cpp) on any bytes: every record
// is read or refused with a message, never an abort (a wrong type, a deep nesting); the message
// holds no control character; a record read has at least one measurement.
#include <cstdint>
#include <string>

#include "facet/records.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string error;
  const facet::cli::Run run = facet::cli::read_records(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json", error);
  for (const char c : error)
    if (static_cast<unsigned char>(c) < 0x20) facet::fuzz::broken("a control character in a record's message");
  if (error.empty() && run.measures.empty()) facet::fuzz::broken("a record read without measurements");
  if (run.order.size() != run.measures.size()) facet::fuzz::broken("measurement names and values disagree");
  return 0;
}
