// Wavefront OBJ loading. tinyobjloader parses; before it runs, a line-by-line check rejects what it
// would accept silently (unknown statements, non-numeric coordinates, bad or out-of-range face
// indices), so every error names the file and line. tinyobjloader then reads the *checked* text
// (comments and blank lines removed), not the original: it does not treat a '#' in the middle of
// a line as a comment, so it once resolved indices the check never saw (found by fuzz_obj; the
// input is in tests/data/fuzz/obj/). Every index it returns is bounds-checked again all the same.
// Polygons are triangulated here, as fans from their first corner (exact for convex polygons).
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <tiny_obj_loader.h>

#include "common/format.hpp"
#include "facet/mesh.hpp"
#include "io/read_file.hpp"

namespace facet {
namespace {

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\f\v");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\f\v");
  return s.substr(b, e - b + 1);
}

std::vector<std::string_view> split_ws(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

bool parse_float(std::string_view tok, float& out) {
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

bool parse_int(std::string_view tok, long long& out) {
  if (tok.empty()) return false;
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

// Statements tinyobjloader reads or that are harmless to ignore (free-form geometry, display attributes).
bool known_statement(std::string_view k) {
  static constexpr std::string_view kKnown[] = {
      "v", "vt", "vn", "vp", "f", "l", "p", "o", "g", "s", "usemtl", "mtllib", "t", "vw",
      "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp",
      "end", "con", "mg", "bevel", "c_interp", "d_interp", "lod", "usemap", "maplib", "shadow_obj",
      "trace_obj", "ctech", "stech", "call", "csh"};
  for (auto s : kKnown)
    if (s == k) return true;
  return false;
}

class ObjChecker {
 public:
  explicit ObjChecker(std::string source) : source_(std::move(source)) {}

  // Checks `text` and writes the lines it checked, without comments, to `clean`.
  Status check(const std::string& text, std::string& clean) {
    clean.clear();
    clean.reserve(text.size());
    std::size_t line_no = 0, pos = 0;
    while (pos <= text.size()) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      ++line_no;
      std::string_view line(text.data() + pos, end - pos);
      pos = end + 1;
      if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
      line = trim(line);
      if (line.empty()) continue;
      if (line.back() == '\\') return error(line_no, "line continuations ('\\') are not supported");
      if (Status s = check_line(line_no, split_ws(line)); !s.ok()) return s;
      clean.append(line);
      clean.push_back('\n');
      if (end == text.size()) break;
    }
    if (face_count_ == 0) return error(line_no, "no faces: the file defines no triangle or polygon");
    return {};
  }

 private:
  Status error(std::size_t line, const std::string& what) const {
    return {ErrorCode::parse_error, "line " + std::to_string(line),
            source_ + ":" + std::to_string(line) + ": " + what};
  }

  Status check_numbers(std::size_t line_no, const std::vector<std::string_view>& tok, std::size_t lo,
                       std::size_t hi) const {
    const std::size_t n = tok.size() - 1;
    if (n < lo || n > hi) {
      return error(line_no, "'" + std::string(tok[0]) + "' expects " + std::to_string(lo) +
                                (lo == hi ? "" : " to " + std::to_string(hi)) + " numbers, found " +
                                std::to_string(n));
    }
    for (std::size_t i = 1; i < tok.size(); ++i) {
      float value = 0.0f;
      if (!parse_float(tok[i], value)) {
        return error(line_no, "'" + std::string(tok[0]) + "' value " + std::to_string(i) + " is not a number: '" +
                                  std::string(tok[i]) + "'");
      }
    }
    return {};
  }

  // One index of a face corner; `count` is how many elements of that kind exist so far.
  Status check_index(std::size_t line_no, std::string_view part, const char* kind, std::size_t count) const {
    long long idx = 0;
    if (!parse_int(part, idx) || idx == 0) {
      return error(line_no, std::string("bad ") + kind + " index '" + std::string(part) + "' (indices start at 1)");
    }
    const long long resolved = idx > 0 ? idx : static_cast<long long>(count) + idx + 1;
    if (resolved < 1 || resolved > static_cast<long long>(count)) {
      return error(line_no, std::string(kind) + " index " + std::to_string(idx) + " is out of range (" +
                                std::to_string(count) + " defined so far)");
    }
    return {};
  }

  Status check_line(std::size_t line_no, const std::vector<std::string_view>& tok) {
    const std::string_view k = tok[0];
    if (k == "v") {
      ++v_;
      return check_numbers(line_no, tok, 3, 7);  // x y z [w] or x y z r g b
    }
    if (k == "vn") {
      ++vn_;
      return check_numbers(line_no, tok, 3, 3);
    }
    if (k == "vt") {
      ++vt_;
      return check_numbers(line_no, tok, 1, 3);
    }
    if (k == "f") {
      if (tok.size() < 4) return error(line_no, "a face needs at least 3 vertices, found " + std::to_string(tok.size() - 1));
      for (std::size_t i = 1; i < tok.size(); ++i) {
        const std::string_view c = tok[i];
        const auto s1 = c.find('/');
        const std::string_view vpart = c.substr(0, s1);
        if (Status s = check_index(line_no, vpart, "vertex", v_); !s.ok()) return s;
        if (s1 == std::string_view::npos) continue;
        const std::string_view rest = c.substr(s1 + 1);
        const auto s2 = rest.find('/');
        const std::string_view tpart = rest.substr(0, s2);
        if (!tpart.empty())
          if (Status s = check_index(line_no, tpart, "texture coordinate", vt_); !s.ok()) return s;
        if (s2 == std::string_view::npos) continue;
        const std::string_view npart = rest.substr(s2 + 1);
        if (Status s = check_index(line_no, npart, "normal", vn_); !s.ok()) return s;
      }
      ++face_count_;
      return {};
    }
    if (!known_statement(k)) return error(line_no, "unknown statement '" + std::string(k) + "'");
    return {};
  }

  std::string source_;
  std::size_t v_ = 0, vn_ = 0, vt_ = 0, face_count_ = 0;
};

// Calls fn(corner_a, corner_b, corner_c) for the fan triangles of every face, in file order.
template <class Fn>
void for_each_fan_triangle(const std::vector<tinyobj::shape_t>& shapes, Fn fn) {
  for (const auto& shape : shapes) {
    const auto& idx = shape.mesh.indices;
    std::size_t offset = 0;
    for (const unsigned int corners : shape.mesh.num_face_vertices) {
      if (offset + corners > idx.size()) return;  // inconsistent counts: stop rather than read past
      for (unsigned int k = 1; k + 1 < corners; ++k) fn(idx[offset], idx[offset + k], idx[offset + k + 1]);
      offset += corners;
    }
  }
}

Result<Mesh> build_mesh(const tinyobj::attrib_t& attrib, const std::vector<tinyobj::shape_t>& shapes,
                        const ObjOptions& options, const std::string& source_name) {
  // The check before parsing makes these impossible; a disagreement between it and tinyobjloader
  // must still never index out of bounds.
  const auto positions = static_cast<long long>(attrib.vertices.size() / 3);
  const auto normals = static_cast<long long>(attrib.normals.size() / 3);
  for (const auto& shape : shapes) {
    for (const auto& i : shape.mesh.indices) {
      if (i.vertex_index < 0 || i.vertex_index >= positions || i.normal_index >= normals) {
        return Status{ErrorCode::parse_error, "", source_name + ": a face index is out of range"};
      }
    }
  }
  bool all_have_normals = true;
  for (const auto& shape : shapes)
    for (const auto& idx : shape.mesh.indices) all_have_normals &= idx.normal_index >= 0;

  Mesh mesh;
  auto position = [&](int i) {
    return Vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
  };
  if (all_have_normals) {
    // The file decides: one vertex per distinct (position, normal) pair.
    std::unordered_map<long long, std::uint32_t> vertex_of;
    auto vertex = [&](const tinyobj::index_t& i) {
      const long long key = static_cast<long long>(i.vertex_index) << 32 | static_cast<std::uint32_t>(i.normal_index);
      auto [it, inserted] = vertex_of.try_emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
      if (inserted) {
        mesh.positions.push_back(position(i.vertex_index));
        const Vec3 n(attrib.normals[3 * i.normal_index], attrib.normals[3 * i.normal_index + 1],
                     attrib.normals[3 * i.normal_index + 2]);
        const float len = n.norm();
        mesh.normals.push_back(len > 0.0f && std::isfinite(len) ? Vec3(n / len) : Vec3::Zero());
      }
      return it->second;
    };
    for_each_fan_triangle(shapes, [&](const tinyobj::index_t& a, const tinyobj::index_t& b, const tinyobj::index_t& c) {
      const std::uint32_t ia = vertex(a), ib = vertex(b), ic = vertex(c);
      mesh.triangles.push_back({ia, ib, ic});
    });
    return mesh;
  }
  // Vertices no face uses are dropped (the bunny has 1,113): lighting them would be wasted work.
  const std::size_t n = attrib.vertices.size() / 3;
  constexpr std::uint32_t kUnused = ~0u;
  std::vector<std::uint32_t> new_index(n, kUnused);
  for (const auto& shape : shapes)
    for (const auto& idx : shape.mesh.indices) new_index[static_cast<std::size_t>(idx.vertex_index)] = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (new_index[i] == kUnused) continue;
    new_index[i] = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.push_back(position(static_cast<int>(i)));
  }
  for_each_fan_triangle(shapes, [&](const tinyobj::index_t& a, const tinyobj::index_t& b, const tinyobj::index_t& c) {
    mesh.triangles.push_back({new_index[static_cast<std::size_t>(a.vertex_index)],
                              new_index[static_cast<std::size_t>(b.vertex_index)],
                              new_index[static_cast<std::size_t>(c.vertex_index)]});
  });
  mesh.normals.assign(mesh.positions.size(), Vec3::Zero());
  compute_vertex_normals(mesh, options.crease_angle_deg);
  return mesh;
}

}  // namespace

Result<Mesh> parse_obj(const std::string& text, const std::string& source_name, const ObjOptions& options) {
  try {
    if (!(options.crease_angle_deg >= 0.0f && options.crease_angle_deg <= 180.0f)) {
      return Status{ErrorCode::invalid_argument, "crease_angle_deg",
                    "crease_angle_deg: expected a number in [0, 180], found " + format_number(options.crease_angle_deg)};
    }
    if (text.find('\0') != std::string::npos) {
      return Status{ErrorCode::parse_error, "", source_name + ": not a text file (contains NUL bytes)"};
    }
    std::string checked;
    if (Status s = ObjChecker(source_name).check(text, checked); !s.ok()) return s;

    tinyobj::ObjReaderConfig config;
    config.triangulate = false;  // see the top of this file
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    const bool parsed = reader.ParseFromString(checked, "", config);
    if (!parsed || !reader.Error().empty()) {
      return Status{ErrorCode::parse_error, "", source_name + ": " + std::string(trim(reader.Error()))};
    }
    // Index warnings mean tinyobjloader kept out-of-range indices; the check above should have
    // caught them, so treat any that remain as errors rather than trust the data.
    if (reader.Warning().find("out of bounds") != std::string::npos) {
      return Status{ErrorCode::parse_error, "", source_name + ": " + std::string(trim(reader.Warning()))};
    }
    return build_mesh(reader.GetAttrib(), reader.GetShapes(), options, source_name);
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::io_error, "", source_name + ": out of memory while loading"};
  } catch (const std::exception& e) {
    return Status{ErrorCode::parse_error, "", source_name + ": " + e.what()};
  }
}

Result<Mesh> load_obj(const std::string& path, const ObjOptions& options) {
  Result<std::string> text = read_text_file(path, "OBJ file");
  if (!text) return text.status();
  return parse_obj(*text, path, options);
}

}  // namespace facet
