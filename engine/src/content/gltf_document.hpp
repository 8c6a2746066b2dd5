// Internal: a glTF 2.0 document as facet reads it, with its own bounds checks (facet does not use
// tinygltf: version 2.7 read past the end of a .glb whose BIN chunk claimed more bytes than the
// file held, let wrong JSON types pass as defaults and resolved `uri`s by its own rules). The
// container is checked before the JSON is parsed; every field facet reads is read through Fields,
// which checks its JSON type and range and names its JSON path in errors; buffers are read through
// the AssetFolder (facet/assets.hpp) within one memory budget; bufferViews are checked against
// their buffers, and EXT_meshopt_compression views decoded, before any accessor reads them.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "facet/status.hpp"
#include "io/assets.hpp"

namespace facet::gltf {

using Json = nlohmann::json;

// Strict reads of the fields of one document. Each getter leaves `out` as it is when the field is
// absent (its default) and fails when the field is present with the wrong JSON type or outside the
// given range. Paths are in the form "meshes[0].primitives[1].attributes.NORMAL".
class Fields {
 public:
  explicit Fields(std::string source) : source_(std::move(source)) {}
  const std::string& source() const noexcept { return source_; }

  Status error(const std::string& path, const std::string& what, ErrorCode code = ErrorCode::parse_error) const {
    return {code, path, source_ + ": " + path + ": " + what};
  }

  static std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }
  // "path.key", with a key from the file written so that no byte of it is raw.
  static std::string dot(const std::string& path, std::string_view key);

  // The member `key` of object `obj`, or nullptr when absent.
  static const Json* find(const Json& obj, std::string_view key);

  Status object(const Json& v, const std::string& path) const;
  Status object(const Json& obj, const std::string& path, std::string_view key, const Json*& out) const;
  Status array(const Json& obj, const std::string& path, std::string_view key, const Json*& out) const;
  Status index(const Json& obj, const std::string& path, std::string_view key, std::size_t count, int& out,
               bool required = false) const;
  Status integer(const Json& obj, const std::string& path, std::string_view key, std::uint64_t& out,
                 std::uint64_t lo, std::uint64_t hi, bool required = false) const;
  Status number(const Json& obj, const std::string& path, std::string_view key, double& out, double lo, double hi,
                bool required = false) const;
  // Exactly `n` numbers in [lo, hi].
  Status numbers(const Json& obj, const std::string& path, std::string_view key, std::size_t n, double* out,
                 double lo, double hi) const;
  Status string(const Json& obj, const std::string& path, std::string_view key, std::string& out,
                bool required = false) const;
  Status boolean(const Json& obj, const std::string& path, std::string_view key, bool& out) const;

 private:
  std::string source_;
};

// A bufferView's bytes once checked (and decoded, for EXT_meshopt_compression).
struct View {
  const std::uint8_t* data = nullptr;
  std::size_t length = 0;
  std::size_t stride = 0;  // 0: tightly packed
};

class Document {
 public:
  // Parses the container and the JSON. `bytes` must outlive the document (the .glb BIN chunk is
  // read in place).
  static Result<Document> parse(std::span<const std::uint8_t> bytes, const std::string& source_name);

  // Reads every buffer and checks and decodes every bufferView. `used` counts the bytes held
  // against `budget` (0 = none).
  Status load_buffers(const io::AssetFolder& folder, std::uint64_t budget, std::uint64_t& used);

  const Json& json() const noexcept { return json_; }
  const Fields& fields() const noexcept { return fields_; }
  std::size_t count(const char* array) const;
  const Json& item(const char* array, std::size_t i) const { return json_[array][i]; }
  const View& view(std::size_t i) const { return views_[i]; }
  std::size_t view_count() const noexcept { return views_.size(); }

  // Bytes of an image: its bufferView's or its uri's (data: or a file), at most `max_bytes`; `name`
  // is what messages call it (the file name, or "images[i]"). A file that cannot be read is
  // ErrorCode::io_error.
  Status image_bytes(std::size_t image, const io::AssetFolder& folder, std::uint64_t max_bytes, std::string& out,
                     std::string& name) const;

 private:
  explicit Document(std::string source) : fields_(std::move(source)) {}
  Status load_buffer(std::size_t i, const io::AssetFolder& folder, std::uint64_t budget, std::uint64_t& used);
  Status load_view(std::size_t i, std::uint64_t budget, std::uint64_t& used);

  Fields fields_;
  Json json_;
  std::span<const std::uint8_t> bin_;  // the .glb BIN chunk
  bool has_bin_ = false;
  std::vector<std::string> buffers_;        // each buffer's bytes (exactly its byteLength)
  std::vector<std::uint64_t> buffer_sizes_;  // declared byteLength
  std::vector<const std::uint8_t*> buffer_data_;
  std::vector<std::string> decoded_;  // decoded EXT_meshopt_compression views
  std::vector<View> views_;
};

// "data:[mediatype][;base64],..." to bytes (base64 only), or an error naming `path`.
Status decode_data_uri(std::string_view uri, const Fields& fields, const std::string& path, std::uint64_t max_bytes,
                       std::string& out);
// A URI reference's %XX escapes decoded (glTF uris are URIs); an error for a bad escape.
Status percent_decode(std::string_view uri, const Fields& fields, const std::string& path, std::string& out);

}  // namespace facet::gltf
