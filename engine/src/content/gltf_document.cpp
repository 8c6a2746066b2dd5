#include "content/gltf_document.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>

#include "common/format.hpp"
#include "common/try.hpp"

namespace facet::gltf {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534Au, kChunkBin = 0x004E4942u;
constexpr std::size_t kMaxDepth = 64;  // the glTF schema nests about 8 levels; extras may add some

std::uint32_t u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  std::memcpy(&v, p, 4);
  return v;
}

const char* type_name(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array";
    case Json::value_t::string: return "a string";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::number_integer: case Json::value_t::number_unsigned: return "an integer";
    case Json::value_t::number_float: return "a number";
    default: return "something else";
  }
}

bool whole(double v) { return std::isfinite(v) && std::floor(v) == v; }

}  // namespace

std::string Fields::dot(const std::string& path, std::string_view key) {
  bool plain = !key.empty();
  for (const char c : key) plain &= std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  const std::string k = plain ? std::string(key) : quote(key, 64);
  return path.empty() ? k : path + "." + k;
}

const Json* Fields::find(const Json& obj, std::string_view key) {
  if (!obj.is_object()) return nullptr;
  const auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

Status Fields::object(const Json& v, const std::string& path) const {
  if (!v.is_object()) return error(path, std::string("expected an object, found ") + type_name(v));
  return {};
}

Status Fields::object(const Json& obj, const std::string& path, std::string_view key, const Json*& out) const {
  out = find(obj, key);
  if (out && !out->is_object()) return error(dot(path, key), std::string("expected an object, found ") + type_name(*out));
  return {};
}

Status Fields::array(const Json& obj, const std::string& path, std::string_view key, const Json*& out) const {
  out = find(obj, key);
  if (out && !out->is_array()) return error(dot(path, key), std::string("expected an array, found ") + type_name(*out));
  return {};
}

Status Fields::integer(const Json& obj, const std::string& path, std::string_view key, std::uint64_t& out,
                       std::uint64_t lo, std::uint64_t hi, bool required) const {
  const Json* v = find(obj, key);
  if (!v) return required ? error(dot(path, key), "required, missing") : Status{};
  const std::string p = dot(path, key);
  if (!v->is_number()) return error(p, std::string("expected an integer, found ") + type_name(*v));
  const double d = v->get<double>();
  if (!whole(d)) return error(p, "expected an integer, found " + format_number(d));
  if (v->is_number_integer() && !v->is_number_unsigned() && v->get<std::int64_t>() < 0) {
    return error(p, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], found " +
                        std::to_string(v->get<std::int64_t>()));
  }
  if (!(d >= double(lo) && d <= double(hi))) {
    return error(p, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], found " + format_number(d));
  }
  out = v->is_number_unsigned() ? v->get<std::uint64_t>() : static_cast<std::uint64_t>(d);
  if (out < lo || out > hi) return error(p, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return {};
}

Status Fields::index(const Json& obj, const std::string& path, std::string_view key, std::size_t count, int& out,
                     bool required) const {
  const Json* v = find(obj, key);
  if (!v) return required ? error(dot(path, key), "required, missing") : Status{};
  const std::string p = dot(path, key);
  if (!v->is_number() || !whole(v->get<double>())) return error(p, std::string("expected an index, found ") + type_name(*v));
  const double d = v->get<double>();
  if (!(d >= 0.0 && d < double(count))) {
    return error(p, "index " + format_number(d) + " is out of range (" + std::to_string(count) + " " +
                        (count == 1 ? "item" : "items") + ")");
  }
  out = static_cast<int>(d);
  return {};
}

Status Fields::number(const Json& obj, const std::string& path, std::string_view key, double& out, double lo, double hi,
                      bool required) const {
  const Json* v = find(obj, key);
  if (!v) return required ? error(dot(path, key), "required, missing") : Status{};
  const std::string p = dot(path, key);
  if (!v->is_number()) return error(p, std::string("expected a number, found ") + type_name(*v));
  const double d = v->get<double>();
  if (!(d >= lo && d <= hi)) {
    return error(p, "expected a number in [" + format_number(lo) + ", " + format_number(hi) + "], found " + format_number(d));
  }
  out = d;
  return {};
}

Status Fields::numbers(const Json& obj, const std::string& path, std::string_view key, std::size_t n, double* out,
                       double lo, double hi) const {
  const Json* v = find(obj, key);
  if (!v) return {};
  const std::string p = dot(path, key);
  if (!v->is_array() || v->size() != n) {
    return error(p, "expected an array of " + std::to_string(n) + " numbers, found " +
                        (v->is_array() ? "an array of " + std::to_string(v->size()) : std::string(type_name(*v))));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Json& e = (*v)[i];
    if (!e.is_number()) return error(at(p, i), std::string("expected a number, found ") + type_name(e));
    const double d = e.get<double>();
    if (!(d >= lo && d <= hi)) {
      return error(at(p, i), "expected a number in [" + format_number(lo) + ", " + format_number(hi) + "], found " + format_number(d));
    }
    out[i] = d;
  }
  return {};
}

Status Fields::string(const Json& obj, const std::string& path, std::string_view key, std::string& out,
                      bool required) const {
  const Json* v = find(obj, key);
  if (!v) return required ? error(dot(path, key), "required, missing") : Status{};
  if (!v->is_string()) return error(dot(path, key), std::string("expected a string, found ") + type_name(*v));
  out = v->get<std::string>();
  return {};
}

Status Fields::boolean(const Json& obj, const std::string& path, std::string_view key, bool& out) const {
  const Json* v = find(obj, key);
  if (!v) return {};
  if (!v->is_boolean()) return error(dot(path, key), std::string("expected true or false, found ") + type_name(*v));
  out = v->get<bool>();
  return {};
}

Result<Document> Document::parse(std::span<const std::uint8_t> bytes, const std::string& source_name) {
  Document doc(source_name);
  const Fields& f = doc.fields_;
  auto fail = [&](const std::string& what) { return Status{ErrorCode::parse_error, "", source_name + ": " + what}; };
  std::span<const std::uint8_t> text = bytes;
  if (bytes.size() >= 4 && u32(bytes.data()) == kGlbMagic) {
    // The binary container (glTF 2.0 §4.4): a 12-byte header, a JSON chunk, an optional BIN chunk.
    if (bytes.size() < 20) return fail(".glb: the file ends inside its header");
    const std::uint32_t version = u32(bytes.data() + 4), length = u32(bytes.data() + 8);
    if (version != 2) {
      return Status{ErrorCode::unsupported, "", source_name + ": .glb container version " + std::to_string(version) +
                                                    "; facet reads version 2 (glTF 2.0)"};
    }
    if (length != bytes.size()) {
      return fail(".glb: the header's length " + std::to_string(length) + " differs from the file's size " +
                  std::to_string(bytes.size()));
    }
    std::size_t at = 12;
    bool first = true;
    while (at < bytes.size()) {
      if (bytes.size() - at < 8) return fail(".glb: the file ends inside a chunk header at byte " + std::to_string(at));
      const std::uint32_t chunk_length = u32(bytes.data() + at), type = u32(bytes.data() + at + 4);
      if (chunk_length > bytes.size() - at - 8) {
        return fail(".glb: the chunk at byte " + std::to_string(at) + " claims " + std::to_string(chunk_length) +
                    " bytes; the file has " + std::to_string(bytes.size() - at - 8) + " after its header");
      }
      const std::span<const std::uint8_t> data = bytes.subspan(at + 8, chunk_length);
      if (first) {
        if (type != kChunkJson) return fail(".glb: the first chunk is not JSON");
        text = data;
      } else if (type == kChunkBin) {
        if (doc.has_bin_) return fail(".glb: more than one BIN chunk");
        doc.bin_ = data;
        doc.has_bin_ = true;
      } else if (type == kChunkJson) {
        return fail(".glb: more than one JSON chunk");
      }  // other chunk types are skipped, as the specification asks
      first = false;
      at += 8 + std::size_t(chunk_length);
    }
    if (first) return fail(".glb: no JSON chunk");
  }
  // JSON, nested no deeper than kMaxDepth (checked by a scan of its brackets: nlohmann's
  // callback parser, which could check it while parsing, is quadratic in an array's length).
  const char* b = reinterpret_cast<const char*>(text.data());
  if (json_nesting_exceeds(std::string_view(b, text.size()), kMaxDepth)) {
    return fail("the JSON nests deeper than " + std::to_string(kMaxDepth) + " levels");
  }
  doc.json_ = Json::parse(b, b + text.size(), nullptr, false);
  if (doc.json_.is_discarded()) {
    try {
      const Json again = Json::parse(b, b + text.size());
      (void)again;
    } catch (const Json::parse_error& e) {
      const std::size_t upto = std::min<std::size_t>(e.byte, text.size());
      const auto line = 1 + std::count(b, b + upto, '\n');
      return fail("line " + std::to_string(line) + ": not valid JSON");
    } catch (...) {
    }
    return fail("not valid JSON");
  }
  if (!doc.json_.is_object()) return fail("expected a JSON object at the top level");
  // glTF 1.0 and 0.8 files: objects keyed by name where 2.0 has arrays, shaders and techniques, a
  // numeric version or none. Said plainly rather than as the first field that does not fit.
  const char* kOld = "; glTF 1.0 and older are not supported: facet reads glTF 2.0 (convert the file, e.g. with Blender's "
                     "importer or gltf-pipeline)";
  const Json* asset = nullptr;
  const Json* old_asset = Fields::find(doc.json_, "asset");
  const bool old_layout = Fields::find(doc.json_, "techniques") || Fields::find(doc.json_, "shaders") ||
                          Fields::find(doc.json_, "programs") ||
                          (Fields::find(doc.json_, "buffers") && Fields::find(doc.json_, "buffers")->is_object());
  if (old_asset && old_asset->is_object()) {
    const Json* v = Fields::find(*old_asset, "version");
    if (v && v->is_number()) return f.error("asset.version", "the number " + format_number(v->get<double>()) + kOld, ErrorCode::unsupported);
    if (v && v->is_string() && v->get<std::string>().rfind("1.", 0) == 0) {
      return f.error("asset.version", quote(v->get<std::string>(), 16) + kOld, ErrorCode::unsupported);
    }
  }
  if ((!old_asset || !old_asset->is_object()) && old_layout) return f.error("asset", "missing, and the file is laid out as glTF 1.0" + std::string(kOld), ErrorCode::unsupported);
  FACET_TRY(f.object(doc.json_, "", "asset", asset));
  if (!asset) return f.error("asset", "required, missing (a glTF file states its version there)");
  std::string version;
  FACET_TRY(f.string(*asset, "asset", "version", version, true));
  if (version.rfind("2.", 0) != 0) {
    return f.error("asset.version", "glTF " + quote(version, 16) + "; facet reads glTF 2.x", ErrorCode::unsupported);
  }
  std::string min_version = "2.0";
  FACET_TRY(f.string(*asset, "asset", "minVersion", min_version));
  if (min_version != "2.0") {
    return f.error("asset.minVersion", quote(min_version, 16) + " is newer than glTF 2.0, which facet reads",
                   ErrorCode::unsupported);
  }
  // The top-level arrays facet reads.
  for (const char* key : {"accessors", "bufferViews", "buffers", "cameras", "images", "materials", "meshes", "nodes",
                          "samplers", "scenes", "textures", "extensionsUsed", "extensionsRequired"}) {
    const Json* a = nullptr;
    FACET_TRY(f.array(doc.json_, "", key, a));
    if (a && std::string_view(key) != "extensionsUsed" && std::string_view(key) != "extensionsRequired") {
      for (std::size_t i = 0; i < a->size(); ++i) FACET_TRY(f.object((*a)[i], Fields::at(key, i)));
    }
  }
  return doc;
}

std::size_t Document::count(const char* array) const {
  const Json* a = Fields::find(json_, array);
  return a ? a->size() : 0;
}

Status decode_data_uri(std::string_view uri, const Fields& f, const std::string& path, std::uint64_t max_bytes,
                       std::string& out) {
  const std::size_t comma = uri.find(',');
  if (comma == std::string_view::npos) return f.error(path, "a data: URI without a comma");
  const std::string_view head = uri.substr(0, comma);
  if (head.size() < 7 || head.substr(head.size() - 7) != ";base64") {
    return f.error(path, "a data: URI that is not base64; facet reads base64 data: URIs only", ErrorCode::unsupported);
  }
  const std::string_view body = uri.substr(comma + 1);
  const std::uint64_t most = body.size() / 4 * 3 + 3;
  if (most > max_bytes) {
    return f.error(path, "a data: URI of about " + std::to_string(most) + " bytes, over the memory budget", ErrorCode::out_of_memory);
  }
  out.clear();
  out.reserve(static_cast<std::size_t>(most));
  std::uint32_t acc = 0;
  int bits = 0;
  std::size_t pad = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    const char c = body[i];
    int v;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+' || c == '-') v = 62;
    else if (c == '/' || c == '_') v = 63;
    else if (c == '=') { ++pad; continue; }
    else return f.error(path, "a data: URI with a character that is not base64 at offset " + std::to_string(comma + 1 + i));
    if (pad > 0) return f.error(path, "a data: URI with base64 after its padding");
    acc = (acc << 6) | std::uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xffu));
    }
  }
  if (pad > 2) return f.error(path, "a data: URI with more than two padding characters");
  return {};
}

Status percent_decode(std::string_view uri, const Fields& f, const std::string& path, std::string& out) {
  out.clear();
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      out.push_back(uri[i]);
      continue;
    }
    auto hex = [](char c) -> int {
      if (c >= '0' && c <= '9') return c - '0';
      if (c >= 'a' && c <= 'f') return c - 'a' + 10;
      if (c >= 'A' && c <= 'F') return c - 'A' + 10;
      return -1;
    };
    if (i + 2 >= uri.size()) return f.error(path, "a URI with a truncated % escape");
    const int a = hex(uri[i + 1]), b = hex(uri[i + 2]);
    if (a < 0 || b < 0) return f.error(path, "a URI with a bad % escape");
    out.push_back(static_cast<char>(a * 16 + b));
    i += 2;
  }
  return {};
}

Status Document::load_buffers(const io::AssetFolder& folder, std::uint64_t budget, std::uint64_t& used) {
  const std::size_t nb = count("buffers"), nv = count("bufferViews");
  buffers_.assign(nb, std::string());
  buffer_sizes_.assign(nb, 0);
  buffer_data_.assign(nb, nullptr);
  for (std::size_t i = 0; i < nb; ++i) FACET_TRY(load_buffer(i, folder, budget, used));
  views_.assign(nv, View{});
  decoded_.assign(nv, std::string());
  for (std::size_t i = 0; i < nv; ++i) FACET_TRY(load_view(i, budget, used));
  return {};
}

Status Document::load_buffer(std::size_t i, const io::AssetFolder& folder, std::uint64_t budget, std::uint64_t& used) {
  const Fields& f = fields_;
  const Json& b = item("buffers", i);
  const std::string p = Fields::at("buffers", i);
  std::uint64_t length = 0;
  FACET_TRY(f.integer(b, p, "byteLength", length, 1, std::numeric_limits<std::uint32_t>::max() * std::uint64_t{64}, true));
  buffer_sizes_[i] = length;
  const std::uint64_t left = budget == 0 ? io::kNoSizeLimit : budget - std::min(budget, used);
  std::string uri;
  FACET_TRY(f.string(b, p, "uri", uri));
  const Json* ext = nullptr;
  FACET_TRY(f.object(b, p, "extensions", ext));
  const Json* meshopt = ext ? Fields::find(*ext, "EXT_meshopt_compression") : nullptr;
  if (uri.empty() && !Fields::find(b, "uri")) {
    if (i == 0 && has_bin_) {
      if (bin_.size() < length) {
        return f.error(p, "holds " + std::to_string(bin_.size()) + " bytes, fewer than its byteLength " + std::to_string(length));
      }
      buffer_data_[i] = bin_.data();
      return {};
    }
    if (meshopt) {
      // A fallback buffer of EXT_meshopt_compression: only the compressed views read it, and
      // those are decoded from another buffer.
      bool fallback = false;
      FACET_TRY(f.boolean(*meshopt, Fields::dot(p, "extensions.EXT_meshopt_compression"), "fallback", fallback));
      return {};
    }
    return f.error(p, "no uri, and it is not the .glb's BIN chunk");
  }
  std::string bytes;
  if (uri.rfind("data:", 0) == 0) {
    FACET_TRY(decode_data_uri(uri, f, Fields::dot(p, "uri"), left, bytes));
  } else {
    std::string name;
    FACET_TRY(percent_decode(uri, f, Fields::dot(p, "uri"), name));
    Result<std::string> r = folder.read(name, f.source() + ": " + Fields::dot(p, "uri"), "glTF buffer", left);
    if (!r) return r.status();
    bytes = std::move(*r);
  }
  if (bytes.size() < length) {
    return f.error(p, "holds " + std::to_string(bytes.size()) + " bytes, fewer than its byteLength " + std::to_string(length));
  }
  bytes.resize(static_cast<std::size_t>(length));
  used += bytes.size();
  buffers_[i] = std::move(bytes);
  buffer_data_[i] = reinterpret_cast<const std::uint8_t*>(buffers_[i].data());
  return {};
}

Status Document::load_view(std::size_t i, std::uint64_t budget, std::uint64_t& used) {
  const Fields& f = fields_;
  const Json& v = item("bufferViews", i);
  const std::string p = Fields::at("bufferViews", i);
  int buffer = -1;
  FACET_TRY(f.index(v, p, "buffer", buffer_sizes_.size(), buffer, true));
  std::uint64_t offset = 0, length = 0, stride = 0;
  FACET_TRY(f.integer(v, p, "byteOffset", offset, 0, std::numeric_limits<std::uint64_t>::max() / 4));
  FACET_TRY(f.integer(v, p, "byteLength", length, 1, std::numeric_limits<std::uint64_t>::max() / 4, true));
  FACET_TRY(f.integer(v, p, "byteStride", stride, 4, 252));
  if (stride % 4 != 0) return f.error(Fields::dot(p, "byteStride"), "expected a multiple of 4 in [4, 252], found " + std::to_string(stride));
  const std::uint64_t size = buffer_sizes_[static_cast<std::size_t>(buffer)];
  if (offset > size || length > size - offset) {
    return f.error(p, "bytes [" + std::to_string(offset) + ", " + std::to_string(offset) + " + " + std::to_string(length) +
                          ") lie outside buffers[" + std::to_string(buffer) + "] (" + std::to_string(size) + " bytes)");
  }
  View view;
  view.length = static_cast<std::size_t>(length);
  view.stride = static_cast<std::size_t>(stride);
  const Json* ext = nullptr;
  FACET_TRY(f.object(v, p, "extensions", ext));
  const Json* mo = ext ? Fields::find(*ext, "EXT_meshopt_compression") : nullptr;
  if (mo) {
    // EXT_meshopt_compression: the compressed bytes live in another buffer; decoded here, once.
    const std::string mp = Fields::dot(p, "extensions.EXT_meshopt_compression");
    FACET_TRY(f.object(*mo, mp));
    int src = -1;
    FACET_TRY(f.index(*mo, mp, "buffer", buffer_sizes_.size(), src, true));
    std::uint64_t so = 0, sl = 0, es = 0, n = 0;
    FACET_TRY(f.integer(*mo, mp, "byteOffset", so, 0, std::numeric_limits<std::uint64_t>::max() / 4));
    FACET_TRY(f.integer(*mo, mp, "byteLength", sl, 1, std::numeric_limits<std::uint64_t>::max() / 4, true));
    FACET_TRY(f.integer(*mo, mp, "byteStride", es, 1, 256, true));
    FACET_TRY(f.integer(*mo, mp, "count", n, 1, std::uint64_t{1} << 32, true));
    std::string mode, filter = "NONE";
    FACET_TRY(f.string(*mo, mp, "mode", mode, true));
    FACET_TRY(f.string(*mo, mp, "filter", filter));
    const std::uint64_t ssize = buffer_sizes_[static_cast<std::size_t>(src)];
    const std::uint8_t* sdata = buffer_data_[static_cast<std::size_t>(src)];
    if (!sdata) return f.error(Fields::dot(mp, "buffer"), "names a buffer that holds no bytes");
    if (so > ssize || sl > ssize - so) return f.error(mp, "its bytes lie outside buffers[" + std::to_string(src) + "]");
    if (n * es != length) {
      return f.error(mp, "count " + std::to_string(n) + " x byteStride " + std::to_string(es) + " differs from the view's byteLength " +
                             std::to_string(length));
    }
    if (budget != 0 && (length > budget || used > budget - length)) {
      return f.error(mp, "decoding needs " + std::to_string(length) + " bytes, over the memory budget", ErrorCode::out_of_memory);
    }
    std::string out(static_cast<std::size_t>(length), '\0');
    auto* dst = reinterpret_cast<unsigned char*>(out.data());
    const unsigned char* in = sdata + so;
    int rc = -1;
    if (mode == "ATTRIBUTES") {
      if (es % 4 != 0) return f.error(Fields::dot(mp, "byteStride"), "ATTRIBUTES need a multiple of 4");
      rc = meshopt_decodeVertexBuffer(dst, static_cast<std::size_t>(n), static_cast<std::size_t>(es), in, static_cast<std::size_t>(sl));
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
      if (es != 2 && es != 4) return f.error(Fields::dot(mp, "byteStride"), mode + " need 2 or 4");
      if (mode == "TRIANGLES" && n % 3 != 0) return f.error(Fields::dot(mp, "count"), "TRIANGLES need a multiple of 3");
      rc = mode == "TRIANGLES"
               ? meshopt_decodeIndexBuffer(dst, static_cast<std::size_t>(n), static_cast<std::size_t>(es), in, static_cast<std::size_t>(sl))
               : meshopt_decodeIndexSequence(dst, static_cast<std::size_t>(n), static_cast<std::size_t>(es), in, static_cast<std::size_t>(sl));
    } else {
      return f.error(Fields::dot(mp, "mode"), "expected \"ATTRIBUTES\", \"TRIANGLES\" or \"INDICES\", found " + quote(mode, 32));
    }
    if (rc != 0) return f.error(mp, "the compressed data is malformed (meshoptimizer's decoder answered " + std::to_string(rc) + ")");
    if (filter == "OCTAHEDRAL") {
      if (es != 4 && es != 8) return f.error(Fields::dot(mp, "byteStride"), "the OCTAHEDRAL filter needs 4 or 8");
      meshopt_decodeFilterOct(dst, static_cast<std::size_t>(n), static_cast<std::size_t>(es));
    } else if (filter == "QUATERNION") {
      if (es != 8) return f.error(Fields::dot(mp, "byteStride"), "the QUATERNION filter needs 8");
      meshopt_decodeFilterQuat(dst, static_cast<std::size_t>(n), static_cast<std::size_t>(es));
    } else if (filter == "EXPONENTIAL") {
      if (es % 4 != 0) return f.error(Fields::dot(mp, "byteStride"), "the EXPONENTIAL filter needs a multiple of 4");
      meshopt_decodeFilterExp(dst, static_cast<std::size_t>(n), static_cast<std::size_t>(es));
    } else if (filter != "NONE") {
      return f.error(Fields::dot(mp, "filter"), "expected \"NONE\", \"OCTAHEDRAL\", \"QUATERNION\" or \"EXPONENTIAL\", found " + quote(filter, 32));
    }
    used += length;
    decoded_[i] = std::move(out);
    view.data = reinterpret_cast<const std::uint8_t*>(decoded_[i].data());
    views_[i] = view;
    return {};
  }
  const std::uint8_t* data = buffer_data_[static_cast<std::size_t>(buffer)];
  if (!data) {
    return f.error(Fields::dot(p, "buffer"), "names a buffer that holds no bytes (an EXT_meshopt_compression fallback)");
  }
  view.data = data + offset;
  views_[i] = view;
  return {};
}

Status Document::image_bytes(std::size_t image, const io::AssetFolder& folder, std::uint64_t max_bytes, std::string& out,
                             std::string& name) const {
  const Fields& f = fields_;
  const Json& im = item("images", image);
  const std::string p = Fields::at("images", image);
  std::string uri;
  FACET_TRY(f.string(im, p, "uri", uri));
  int view = -1;
  FACET_TRY(f.index(im, p, "bufferView", views_.size(), view));
  const bool has_uri = Fields::find(im, "uri") != nullptr;
  if (has_uri == (view >= 0)) return f.error(p, "expected either a uri or a bufferView");
  name = p;
  if (view >= 0) {
    const View& v = views_[static_cast<std::size_t>(view)];
    if (v.length > max_bytes) return f.error(p, "an image of " + std::to_string(v.length) + " bytes, over the memory budget", ErrorCode::out_of_memory);
    out.assign(reinterpret_cast<const char*>(v.data), v.length);
    return {};
  }
  if (uri.rfind("data:", 0) == 0) return decode_data_uri(uri, f, Fields::dot(p, "uri"), max_bytes, out);
  std::string file;
  FACET_TRY(percent_decode(uri, f, Fields::dot(p, "uri"), file));
  name = file;
  Result<std::string> r = folder.read(file, f.source() + ": " + Fields::dot(p, "uri"), "glTF image", max_bytes);
  if (!r) return r.status();
  out = std::move(*r);
  return {};
}

}  // namespace facet::gltf
