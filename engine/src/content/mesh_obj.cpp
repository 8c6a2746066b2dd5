// Wavefront OBJ loading. tinyobjloader parses; before it runs, a line-by-line check rejects what it
// would accept silently (unknown statements, non-numeric coordinates, bad or out-of-range face
// indices), so every error names the file and line. tinyobjloader then reads the *checked* text
// (comments and blank lines removed), not the original: it does not treat a '#' in the middle of
// a line as a comment, so it once resolved indices the check never saw (found by fuzz_obj; the
// input is in tests/data/fuzz/obj/). Every index it returns is bounds-checked again all the same.
// Polygons are triangulated here: convex ones as fans from their first corner, concave ones by ear
// clipping in their plane (scene/polygon.hpp), as Blender and assimp do.
// Texture coordinates (`vt`), vertex colours (`v x y z r g b`) and material groups (`usemtl`) are
// kept. Colours are all-or-nothing (every `v` has one, or none), and a file that mixes is refused
// with the line of the first vertex that breaks the rule; a corner without a `vt` in a file whose
// other corners have one reads (0, 0).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <tiny_obj_loader.h>

#include "common/format.hpp"
#include "common/text.hpp"
#include "common/try.hpp"
#include "facet/mesh.hpp"
#include "io/file_access.hpp"
#include "scene/polygon.hpp"

namespace facet {
namespace {

using text::split_ws;
using text::trim;

enum class NumberKind { ok, not_a_number, not_finite, out_of_range };

// facet decides every number of an OBJ file (std::from_chars: correctly rounded, any length of
// mantissa); tinyobjloader's own reading of them is never used (build_mesh), so the two cannot
// disagree. NaN and infinities, and values a float cannot hold (overflow, or a non-zero value
// below the smallest subnormal), are errors.
NumberKind parse_float(std::string_view tok, float& out) {
  tok = text::without_plus(tok);
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  if (r.ptr != tok.data() + tok.size() || tok.empty()) return NumberKind::not_a_number;
  if (r.ec == std::errc::result_out_of_range) return NumberKind::out_of_range;
  if (r.ec != std::errc()) return NumberKind::not_a_number;
  if (!std::isfinite(out)) return NumberKind::not_finite;
  return NumberKind::ok;
}

bool parse_int(std::string_view tok, long long& out) {
  tok = text::without_plus(tok);
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

  // Checks `text` and writes the lines it checked, without comments, to `clean` (faces of more
  // than kMaxCorners corners split into fans of the same triangles). Keeps the values of `v` and
  // `vn` lines, and for each line of `clean` the line of `text` it came from.
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
      const std::vector<std::string_view> tok = split_ws(line);
      if (Status s = check_line(line_no, tok); !s.ok()) return s;
      if (tok[0] == "f" && tok.size() - 1 > kMaxCorners) {
        append_split_face(tok, line_no, clean);
      } else {
        clean.append(line);
        clean.push_back('\n');
        origin_.push_back(line_no);
        if (tok[0] == "f") face_group_.push_back(group_);
      }
      if (end == text.size()) break;
    }
    if (face_count_ == 0) return error(line_no, "no faces: the file defines no triangle or polygon");
    return {};
  }

  const std::vector<float>& positions() const { return positions_; }
  const std::vector<float>& normals() const { return normals_; }
  const std::vector<float>& texcoords() const { return texcoords_; }  // u v per `vt` line
  const std::vector<float>& colors() const { return colors_; }        // r g b per `v` line, if any has one
  // The material group of each face of the checked text, in order (an index into group_names());
  // faces before any `usemtl` are in group 0, named "".
  const std::vector<std::uint32_t>& face_groups() const { return face_group_; }
  const std::vector<std::string>& group_names() const { return group_names_; }
  bool has_texcoords() const { return corners_with_vt_ > 0; }
  // The line of the original text that line `clean_line` (1-based) of the checked text came from.
  std::size_t origin(std::size_t clean_line) const {
    return clean_line >= 1 && clean_line <= origin_.size() ? origin_[clean_line - 1] : 0;
  }

 private:
  Status error(std::size_t line, const std::string& what) const {
    return {ErrorCode::parse_error, "line " + std::to_string(line),
            source_ + ":" + std::to_string(line) + ": " + what};
  }

  // tinyobjloader 1.0.6 keeps a face's corner count in an unsigned char: a face of 256 or more
  // corners would corrupt every face after it. Longer faces go to it as fans of at most this many.
  static constexpr std::size_t kMaxCorners = 255;

  // Corners c0 c1 ... cn-1 as faces (c0, c[a] .. c[b]) of at most kMaxCorners corners: the fan
  // triangles from c0 are the same, in the same order.
  void append_split_face(const std::vector<std::string_view>& tok, std::size_t line_no, std::string& clean) {
    const std::size_t corners = tok.size() - 1;
    for (std::size_t a = 1; a + 1 < corners; a += kMaxCorners - 2) {
      const std::size_t b = std::min(corners - 1, a + kMaxCorners - 2);
      clean.append("f ");
      clean.append(tok[1]);
      for (std::size_t k = a; k <= b; ++k) {
        clean.push_back(' ');
        clean.append(tok[k + 1]);
      }
      clean.push_back('\n');
      origin_.push_back(line_no);
      face_group_.push_back(group_);
    }
  }

  // Checks that `tok` holds lo..hi numbers and keeps the first `keep_count` of them in `keep`.
  Status check_numbers(std::size_t line_no, const std::vector<std::string_view>& tok, std::size_t lo,
                       std::size_t hi, std::vector<float>* keep = nullptr, std::size_t keep_count = 0) {
    const std::size_t n = tok.size() - 1;
    if (n < lo || n > hi) {
      return error(line_no, quote(tok[0], 16) + " expects " + std::to_string(lo) +
                                (lo == hi ? "" : " to " + std::to_string(hi)) + " numbers, found " +
                                std::to_string(n));
    }
    for (std::size_t i = 1; i < tok.size(); ++i) {
      float value = 0.0f;
      const NumberKind kind = parse_float(tok[i], value);
      if (kind != NumberKind::ok) {
        const char* why = kind == NumberKind::not_finite     ? " is not finite: "
                          : kind == NumberKind::out_of_range ? " is outside the range of a float: "
                                                             : " is not a number: ";
        return error(line_no, quote(tok[0], 16) + " value " + std::to_string(i) + why + quote(tok[i], 32));
      }
      if (keep && i <= keep_count) keep->push_back(value);
    }
    return {};
  }

  // One index of a face corner; `count` is how many elements of that kind exist so far.
  Status check_index(std::size_t line_no, std::string_view part, const char* kind, std::size_t count) const {
    long long idx = 0;
    if (!parse_int(part, idx) || idx == 0) {
      return error(line_no, std::string("bad ") + kind + " index " + quote(part, 24) + " (indices start at 1)");
    }
    const long long resolved = idx > 0 ? idx : static_cast<long long>(count) + idx + 1;
    if (resolved < 1 || resolved > static_cast<long long>(count)) {
      return error(line_no, std::string(kind) + " index " + std::to_string(idx) + " is out of range (" +
                                std::to_string(count) + " defined so far)");
    }
    return {};
  }

  Status check_line(std::size_t line_no, const std::vector<std::string_view>& tok) {
    Status s = check_statement(line_no, tok);
    ++statements_;
    return s;
  }

  Status check_statement(std::size_t line_no, const std::vector<std::string_view>& tok) {
    const std::string_view k = tok[0];
    if (k == "v") {
      ++v_;
      // x y z, x y z w (w ignored) or x y z r g b.
      const std::size_t n = tok.size() - 1;
      if (n != 3 && n != 4 && n != 6) {
        return error(line_no, "'v' expects 3 (x y z), 4 (x y z w) or 6 (x y z r g b) numbers, found " + std::to_string(n));
      }
      FACET_TRY(check_numbers(line_no, tok, n, n, &positions_, 3));
      const bool colored = n == 6;
      if (v_ == 1) first_v_colored_ = colored;
      if (colored != first_v_colored_) {
        return error(line_no, std::string("vertex ") + std::to_string(v_) + (colored ? " has" : " has no") +
                                  " colour (r g b) but vertex 1 " + (colored ? "has none" : "has one") +
                                  ": give every vertex a colour, or none");
      }
      for (std::size_t c = 4; colored && c <= 6; ++c) {
        float value = 0.0f;
        parse_float(tok[c], value);  // checked above
        if (!(value >= 0.0f && value <= 1.0f)) {
          return error(line_no, "'v' colour value " + std::to_string(c - 3) + " is outside [0, 1]: " + quote(tok[c], 32));
        }
        colors_.push_back(value);
      }
      return {};
    }
    if (k == "vn") {
      ++vn_;
      return check_numbers(line_no, tok, 3, 3, &normals_, 3);
    }
    if (k == "vt") {
      ++vt_;
      const std::size_t at = texcoords_.size();
      FACET_TRY(check_numbers(line_no, tok, 1, 3, &texcoords_, 2));  // u [v [w]]: w is ignored
      if (texcoords_.size() == at + 1) texcoords_.push_back(0.0f);  // v defaults to 0
      return {};
    }
    if (k == "usemtl") {
      // The rest of the line, as 'newmtl' reads it: a material name may hold spaces.
      if (tok.size() < 2) return error(line_no, "'usemtl' expects a material name");
      const std::string name(tok[1].data(), static_cast<std::size_t>(tok.back().data() + tok.back().size() - tok[1].data()));
      const auto it = std::find(group_names_.begin(), group_names_.end(), name);
      group_ = static_cast<std::uint32_t>(it - group_names_.begin());
      if (it == group_names_.end()) group_names_.push_back(name);
      return {};
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
        if (!tpart.empty()) {
          if (Status s = check_index(line_no, tpart, "texture coordinate", vt_); !s.ok()) return s;
          ++corners_with_vt_;
        }
        if (s2 == std::string_view::npos) continue;
        const std::string_view npart = rest.substr(s2 + 1);
        if (Status s = check_index(line_no, npart, "normal", vn_); !s.ok()) return s;
      }
      ++face_count_;
      return {};
    }
    if (!known_statement(k)) {
      // A file whose first statement is not OBJ is probably not an OBJ file at all: say so, and
      // quote none of it (it may be any file at all).
      if (statements_ == 0) return error(line_no, "not an OBJ file: its first statement is not an OBJ statement");
      return error(line_no, "unknown statement " + quote(k, 16));
    }
    return {};
  }

  std::string source_;
  std::size_t v_ = 0, vn_ = 0, vt_ = 0, face_count_ = 0, statements_ = 0;
  std::size_t corners_with_vt_ = 0;
  bool first_v_colored_ = false;
  std::uint32_t group_ = 0;
  std::vector<std::string> group_names_{""};
  std::vector<std::uint32_t> face_group_;
  std::vector<float> positions_, normals_, texcoords_, colors_;
  std::vector<std::size_t> origin_;
};

// Calls fn(face, corner_a, corner_b, corner_c) for the triangles of every face, in file order
// (`face` counts the faces of all shapes): a triangle as it is, a polygon by triangulate_polygon
// (a fan when convex, ear clipping when concave) over the positions `xyz` (x y z per vertex).
template <class Fn>
void for_each_triangle(const std::vector<tinyobj::shape_t>& shapes, const std::vector<float>& xyz, Fn fn) {
  std::size_t face = 0;
  std::vector<Eigen::Vector3d> corners;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (const auto& shape : shapes) {
    const auto& idx = shape.mesh.indices;
    std::size_t offset = 0;
    for (const unsigned int count : shape.mesh.num_face_vertices) {
      if (offset + count > idx.size()) return;  // inconsistent counts: stop rather than read past
      corners.clear();
      triangles.clear();
      bool known = true;  // every corner's position is in range (checked again when the mesh is built)
      for (unsigned int k = 0; k < count && known; ++k) {
        const long long v = idx[offset + k].vertex_index;
        known = v >= 0 && static_cast<std::size_t>(v) < xyz.size() / 3;
        if (known) {
          const std::size_t i = 3 * static_cast<std::size_t>(v);
          corners.emplace_back(double(xyz[i]), double(xyz[i + 1]), double(xyz[i + 2]));
        }
      }
      if (known) {
        triangulate_polygon(corners, triangles);
      } else {
        for (std::uint32_t k = 1; k + 1 < count; ++k) triangles.push_back({0, k, k + 1});
      }
      for (const auto& t : triangles) fn(face, idx[offset + t[0]], idx[offset + t[1]], idx[offset + t[2]]);
      offset += count;
      ++face;
    }
  }
}

// A unit normal from any finite vector: scaled by its largest component first, so that neither
// 1e30 (whose square overflows) nor 1e-30 (whose square underflows) becomes a zero normal.
Vec3 unit_normal(const Vec3& n) {
  const float scale = n.cwiseAbs().maxCoeff();
  if (!(scale > 0.0f) || !std::isfinite(scale)) return Vec3::Zero();
  const Vec3 m = n / scale;
  return m / m.norm();
}

struct CornerKey {
  int v, t, n;
  bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (int x : {k.v, k.t, k.n}) h = (h ^ static_cast<std::uint32_t>(x)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

// Faces come from tinyobjloader, every number from the checker (xyz per `v` and `vn` line, uv per
// `vt` line, rgb per `v` line, in file order), so tinyobjloader's reading of numbers is never used.
Result<Mesh> build_mesh(const ObjChecker& checked, const tinyobj::attrib_t& attrib,
                        const std::vector<tinyobj::shape_t>& shapes, const ObjOptions& options,
                        const std::string& source_name) {
  const std::vector<float>& vertex_xyz = checked.positions();
  const std::vector<float>& normal_xyz = checked.normals();
  const std::vector<float>& texcoord_uv = checked.texcoords();
  const std::vector<float>& vertex_rgb = checked.colors();
  if (vertex_xyz.size() != attrib.vertices.size() || normal_xyz.size() != attrib.normals.size() ||
      texcoord_uv.size() / 2 != attrib.texcoords.size() / 2) {
    return Status{ErrorCode::parse_error, "", source_name + ": tinyobjloader read " +
                                                  std::to_string(attrib.vertices.size() / 3) + " vertices, " +
                                                  std::to_string(attrib.normals.size() / 3) + " normals and " +
                                                  std::to_string(attrib.texcoords.size() / 2) +
                                                  " texture coordinates where facet read " +
                                                  std::to_string(vertex_xyz.size() / 3) + ", " +
                                                  std::to_string(normal_xyz.size() / 3) + " and " +
                                                  std::to_string(texcoord_uv.size() / 2)};
  }
  // The check before parsing makes these impossible; a disagreement between it and tinyobjloader
  // must still never index out of bounds.
  const auto positions = static_cast<long long>(vertex_xyz.size() / 3);
  const auto normals = static_cast<long long>(normal_xyz.size() / 3);
  const auto texcoords = static_cast<long long>(texcoord_uv.size() / 2);
  const bool with_uv = checked.has_texcoords();
  std::size_t faces = 0;
  for (const auto& shape : shapes) {
    faces += shape.mesh.num_face_vertices.size();
    for (const auto& i : shape.mesh.indices) {
      if (i.vertex_index < 0 || i.vertex_index >= positions || i.normal_index >= normals ||
          i.texcoord_index >= texcoords) {
        return Status{ErrorCode::parse_error, "", source_name + ": a face index is out of range"};
      }
    }
  }
  if (faces != checked.face_groups().size()) {
    return Status{ErrorCode::parse_error, "", source_name + ": tinyobjloader read " + std::to_string(faces) +
                                                  " faces where facet read " + std::to_string(checked.face_groups().size())};
  }
  bool all_have_normals = true;
  for (const auto& shape : shapes)
    for (const auto& idx : shape.mesh.indices) all_have_normals &= idx.normal_index >= 0;

  Mesh mesh;
  // One vertex per distinct (position, texture coordinate, normal) triple the faces use, in order of
  // first use; without texture coordinates or normals, in the order of the `v` lines (vertices no
  // face uses are dropped: the bunny has 1,113, and lighting them would be wasted work).
  const bool keyed = all_have_normals || with_uv;
  std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> vertex_of;
  std::vector<std::uint32_t> new_index;
  auto add_vertex = [&](const tinyobj::index_t& i) {
    const auto v = static_cast<std::size_t>(i.vertex_index);
    mesh.positions.push_back(Vec3(vertex_xyz[3 * v], vertex_xyz[3 * v + 1], vertex_xyz[3 * v + 2]));
    if (!vertex_rgb.empty()) mesh.colors.push_back(Color3(vertex_rgb[3 * v], vertex_rgb[3 * v + 1], vertex_rgb[3 * v + 2]));
    if (with_uv) {
      // A corner without a `vt` in a file whose other corners have one reads (0, 0), as Blender
      // and three.js read it.
      const auto t = static_cast<std::size_t>(i.texcoord_index);
      mesh.uvs.push_back(i.texcoord_index < 0 ? Vec2(0.0f, 0.0f) : Vec2(texcoord_uv[2 * t], texcoord_uv[2 * t + 1]));
    }
    if (all_have_normals) {
      const auto n = static_cast<std::size_t>(i.normal_index);
      mesh.normals.push_back(unit_normal(Vec3(normal_xyz[3 * n], normal_xyz[3 * n + 1], normal_xyz[3 * n + 2])));
    }
  };
  auto vertex = [&](const tinyobj::index_t& i) -> std::uint32_t {
    if (!keyed) return new_index[static_cast<std::size_t>(i.vertex_index)];
    auto [it, inserted] = vertex_of.try_emplace(CornerKey{i.vertex_index, i.texcoord_index, i.normal_index}, static_cast<std::uint32_t>(mesh.positions.size()));
    if (inserted) add_vertex(i);
    return it->second;
  };
  if (!keyed) {
    constexpr std::uint32_t kUnused = ~0u;
    new_index.assign(vertex_xyz.size() / 3, kUnused);
    for (const auto& shape : shapes)
      for (const auto& idx : shape.mesh.indices) new_index[static_cast<std::size_t>(idx.vertex_index)] = 0;
    for (std::size_t i = 0; i < new_index.size(); ++i) {
      if (new_index[i] == kUnused) continue;
      new_index[i] = static_cast<std::uint32_t>(mesh.positions.size());
      add_vertex(tinyobj::index_t{static_cast<int>(i), -1, -1});
    }
  }
  const std::vector<std::uint32_t>& face_group = checked.face_groups();
  const std::vector<std::string>& group_names = checked.group_names();
  for_each_triangle(shapes, vertex_xyz, [&](std::size_t face, const tinyobj::index_t& a, const tinyobj::index_t& b,
                                    const tinyobj::index_t& c) {
    const std::uint32_t ia = vertex(a), ib = vertex(b), ic = vertex(c);
    const auto t = static_cast<std::uint32_t>(mesh.triangles.size());
    mesh.triangles.push_back({ia, ib, ic});
    const std::string& name = group_names[face_group[face]];
    if (mesh.groups.empty() || mesh.groups.back().material != name) mesh.groups.push_back({name, t, 0});
    ++mesh.groups.back().triangle_count;
  });
  // One group named "" (no usemtl): the mesh has no groups.
  if (mesh.groups.size() == 1 && mesh.groups[0].material.empty()) mesh.groups.clear();
  for (const MaterialGroup& g : mesh.groups) {
    if (g.material.empty()) {
      return Status{ErrorCode::parse_error, "", source_name + ": faces before the first 'usemtl' have no material, "
                                                              "while later faces do: put a 'usemtl' before the first face"};
    }
  }
  if (!all_have_normals) {
    mesh.normals.assign(mesh.positions.size(), Vec3::Zero());
    compute_vertex_normals(mesh, options.crease_angle_deg);
  }
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
    ObjChecker checker(source_name);
    if (Status s = checker.check(text, checked); !s.ok()) return s;
    // tinyobjloader read the checked text: a line number in its messages is one of that text.
    auto from_tinyobj = [&](std::string_view message) {
      std::string what(trim(message));
      std::size_t line = 0;
      if (const auto at = what.find("line "); at != std::string::npos) {
        line = checker.origin(std::strtoul(what.c_str() + at + 5, nullptr, 10));
      }
      return Status{ErrorCode::parse_error, line ? "line " + std::to_string(line) : "",
                    source_name + ":" + (line ? std::to_string(line) + ":" : "") + " tinyobjloader: " + quote(what, 120)};
    };

    tinyobj::ObjReaderConfig config;
    config.triangulate = false;  // see the top of this file
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    const bool parsed = reader.ParseFromString(checked, "", config);
    if (!parsed || !reader.Error().empty()) return from_tinyobj(reader.Error());
    // Index warnings mean tinyobjloader kept out-of-range indices; the check above should have
    // caught them, so treat any that remain as errors rather than trust the data.
    if (reader.Warning().find("out of bounds") != std::string::npos) return from_tinyobj(reader.Warning());
    return build_mesh(checker, reader.GetAttrib(), reader.GetShapes(), options, source_name);
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", source_name + ": out of memory while loading"};
  } catch (const std::exception& e) {
    return Status{ErrorCode::parse_error, "", source_name + ": " + e.what()};
  }
}

Result<Mesh> load_obj(const std::string& path, const ObjOptions& options) {
  Result<std::string> text =
      io::read_file(path, "OBJ file", options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes);
  if (!text) return text.status();
  return parse_obj(*text, path, options);
}

}  // namespace facet
