// OBJ + MTL import: the OBJ through load_obj (mesh_obj.cpp), its `mtllib` files through facet's
// MTL reader below. MTL is a small line format; facet reads every statement itself so that each
// error names the file and line, and lists what it ignores in Model::warnings.
#include <algorithm>
#include <optional>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "content/import.hpp"
#include "common/format.hpp"
#include "common/text.hpp"
#include "common/try.hpp"
#include "facet/model.hpp"
#include "io/assets.hpp"
#include "io/file_access.hpp"
#include "texture/texture_file.hpp"

namespace facet {
namespace {

using text::split_ws;
using text::trim;

bool to_float(std::string_view tok, float& out) {
  tok = text::without_plus(tok);
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return !tok.empty() && r.ec == std::errc() && r.ptr == tok.data() + tok.size() && std::isfinite(out);
}

// Each line of `text` without its comment, trimmed, with its number; empty lines skipped.
template <class Fn>
Status for_each_line(const std::string& text, Fn fn) {
  std::size_t line_no = 0, pos = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (!line.empty()) FACET_TRY(fn(line_no, line));
    if (end == text.size()) break;
  }
  return {};
}

// Statements read by facet, and those it knows and ignores (with a warning).
constexpr std::string_view kIgnored[] = {"Ni", "Tf", "sharpness", "map_Ka", "map_Ks", "map_Ns", "disp", "decal", "refl", "map_Pr", "map_Pm",
                                         "map_Ps", "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor", "map_aat"};

class MtlReader {
 public:
  MtlReader(std::string source, io::AssetFolder folder, const ModelOptions& options, Scene& scene,
            std::vector<std::string>& warnings)
      : source_(std::move(source)), folder_(std::move(folder)), options_(options), scene_(scene), warnings_(warnings) {}

  Status read(const std::string& text) {
    FACET_TRY(for_each_line(text, [&](std::size_t line, std::string_view s) { return statement(line, s); }));
    FACET_TRY(finish_material());
    for (const auto& [what, lines] : ignored_) {
      warnings_.push_back(source_ + ": " + what + " (line " + lines + "): not supported; ignored");
    }
    return {};
  }

 private:
  Status error(std::size_t line, const std::string& what, ErrorCode code = ErrorCode::parse_error) const {
    return {code, "line " + std::to_string(line), source_ + ":" + std::to_string(line) + ": " + what};
  }
  void ignore(std::size_t line, std::string_view what) {
    std::string& lines = ignored_[std::string(what)];
    if (std::count(lines.begin(), lines.end(), ',') < 3) lines += (lines.empty() ? "" : ", ") + std::to_string(line);
    else if (lines.back() != '.') lines += ", ...";
  }

  Status statement(std::size_t line, std::string_view s) {
    const std::vector<std::string_view> tok = split_ws(s);
    const std::string_view key = tok[0];
    if (key == "newmtl") {
      FACET_TRY(finish_material());
      const std::string_view name = trim(s.substr(6));
      if (name.empty()) return error(line, "newmtl: expected a material name");
      current_ = Material{};
      current_.name = std::string(name);
      open_ = true;
      has_d_ = has_tr_ = false;
      map_kd_.clear();
      map_d_.clear();
      map_ke_.clear();
      map_norm_.clear();
      map_bump_.clear();
      has_ke_ = false;
      return {};
    }
    if (!open_) {
      // Before the first material, only what an MTL file may say is quoted: anything else may be
      // the first bytes of a file that is not an MTL file at all.
      bool known = key == "Ka" || key == "Kd" || key == "Ks" || key == "Ke" || key == "map_Kd" || key == "map_d" ||
                   key == "map_Ke" || key == "norm" || key == "bump" || key == "map_Bump" || key == "map_bump" || key == "d" ||
                   key == "Tr" || key == "Ns";
      for (std::string_view i : kIgnored) known |= key == i;
      if (!known) return error(line, "not an MTL file: its first statement is neither 'newmtl' nor another MTL statement");
      return error(line, quote(key, 24) + " before any 'newmtl'");
    }
    if (key == "Ka" || key == "Kd" || key == "Ks" || key == "Ke") {
      Color3 c;
      FACET_TRY(color(line, tok, c));
      (key == "Ka" ? current_.ambient : key == "Kd" ? current_.diffuse : key == "Ks" ? current_.specular : current_.emissive) = c;
      has_ke_ |= key == "Ke";
      return {};
    }
    if (key == "Ns") {
      float v = 0;
      FACET_TRY(number(line, tok, 1, v));
      if (v < 0.0f) return error(line, "Ns: expected a number >= 0");
      if (v > kMaxShininess) warnings_.push_back(source_ + ":" + std::to_string(line) + ": Ns " + format_number(v) +
                                                 " is clamped to " + format_number(kMaxShininess));
      current_.shininess = std::min(v, kMaxShininess);
      return {};
    }
    if (key == "d" || key == "Tr") {
      std::size_t first = 1;
      if (key == "d" && tok.size() > 1 && tok[1] == "-halo") {
        ignore(line, "d -halo");
        first = 2;
      }
      float v = 0;
      if (tok.size() != first + 1 || !to_float(tok[first], v) || v < 0.0f || v > 1.0f) {
        return error(line, std::string(key) + ": expected one number in [0, 1]");
      }
      if (key == "d") {
        d_ = v;
        has_d_ = true;
      } else {
        tr_ = v;
        has_tr_ = true;
      }
      return {};
    }
    if (key == "illum") {
      float v = 0;
      FACET_TRY(number(line, tok, 1, v));
      if (v != std::floor(v) || v < 0.0f || v > 10.0f) return error(line, "illum: expected an integer in [0, 10]");
      illum_ = static_cast<int>(v);
      illum_line_ = line;
      return {};
    }
    if (key == "map_Kd" || key == "map_d" || key == "map_Ke" || key == "norm") return texture_statement(line, s, key);
    if (key == "bump" || key == "map_Bump" || key == "map_bump") return texture_statement(line, s, "bump");
    for (std::string_view i : kIgnored) {
      if (key == i) {
        ignore(line, key);
        return {};
      }
    }
    ignore(line, "unknown statement " + quote(key, 24));
    return {};
  }

  Status number(std::size_t line, const std::vector<std::string_view>& tok, std::size_t count, float& out) const {
    if (tok.size() != count + 1 || !to_float(tok[1], out)) {
      return error(line, std::string(tok[0]) + ": expected " + std::to_string(count) + " number" + (count > 1 ? "s" : "") +
                             ", found " + quote(tok.size() > 1 ? tok[1] : std::string_view("nothing"), 24));
    }
    return {};
  }

  Status color(std::size_t line, const std::vector<std::string_view>& tok, Color3& out) const {
    const std::string key(tok[0]);
    if (tok.size() > 1 && (tok[1] == "spectral" || tok[1] == "xyz")) {
      return error(line, key + ": " + std::string(tok[1]) + " colours are not supported (give r g b)", ErrorCode::unsupported);
    }
    if (tok.size() != 2 && tok.size() != 4) return error(line, key + ": expected r g b (or one number for a grey)");
    for (std::size_t i = 1; i < tok.size(); ++i) {
      float v = 0;
      if (!to_float(tok[i], v)) return error(line, key + ": " + quote(tok[i], 24) + " is not a number");
      if (v < 0.0f) return error(line, key + ": colour components must be >= 0");
      out[static_cast<Eigen::Index>(i - 1)] = v;
    }
    if (tok.size() == 2) out = Color3::Constant(out[0]);
    return {};
  }

  // map_Kd / map_d / map_Ke / norm [options] file: -s (uv_scale) and -clamp are read, and norm's
  // -bm (the normal map's scale); the other options are ignored.
  Status texture_statement(std::size_t line, std::string_view s, std::string_view key) {
    std::vector<std::string_view> tok = split_ws(s);
    std::size_t i = 1;
    TextureRef ref;
    ref.line = line;
    auto numbers = [&](std::size_t at, std::size_t most, std::vector<float>& out) {
      out.clear();
      float v = 0;
      while (at < tok.size() && out.size() < most && to_float(tok[at], v)) {
        out.push_back(v);
        ++at;
      }
      return at;
    };
    std::vector<float> nums;
    while (i < tok.size() && tok[i].size() > 1 && tok[i][0] == '-') {
      const std::string_view opt = tok[i];
      if (opt == "-s") {
        i = numbers(i + 1, 3, nums);
        if (nums.empty()) return error(line, std::string(key) + " -s: expected 1 to 3 numbers");
        ref.scale = Vec2(nums[0], nums.size() > 1 ? nums[1] : 1.0f);
        if (!(ref.scale.x() != 0.0f && ref.scale.y() != 0.0f)) return error(line, std::string(key) + " -s: scale factors must be non-zero");
      } else if (opt == "-o" || opt == "-t") {
        i = numbers(i + 1, 3, nums);
        if (nums.empty()) return error(line, std::string(key) + " " + std::string(opt) + ": expected 1 to 3 numbers");
        ignore(line, std::string(key) + " " + std::string(opt));
      } else if (opt == "-clamp") {
        if (i + 1 >= tok.size() || (tok[i + 1] != "on" && tok[i + 1] != "off")) return error(line, std::string(key) + " -clamp: expected on or off");
        ref.clamp = tok[i + 1] == "on";
        i += 2;
      } else if (opt == "-blendu" || opt == "-blendv" || opt == "-cc") {
        if (i + 1 >= tok.size() || (tok[i + 1] != "on" && tok[i + 1] != "off")) return error(line, std::string(key) + " " + std::string(opt) + ": expected on or off");
        ignore(line, std::string(key) + " " + std::string(opt));
        i += 2;
      } else if (opt == "-bm" && (key == "norm" || key == "bump")) {
        i = numbers(i + 1, 1, nums);
        if (nums.size() != 1 || !(std::abs(nums[0]) <= 1e6f)) {
          return error(line, std::string(key) + " -bm: expected a number in [-1e6, 1e6]");
        }
        ref.bump = nums[0];
      } else if (opt == "-bm" || opt == "-boost" || opt == "-texres" || opt == "-imfchan") {
        if (i + 1 >= tok.size()) return error(line, std::string(key) + " " + std::string(opt) + ": expected a value");
        ignore(line, std::string(key) + " " + std::string(opt));
        i += 2;
      } else if (opt == "-mm") {
        i = numbers(i + 1, 2, nums);
        if (nums.size() != 2) return error(line, std::string(key) + " -mm: expected 2 numbers");
        ignore(line, std::string(key) + " -mm");
      } else {
        return error(line, std::string(key) + ": unknown option " + quote(opt, 24));
      }
    }
    if (i >= tok.size()) return error(line, std::string(key) + ": expected a file name");
    // The file name is the rest of the line (it may contain spaces); Windows separators become '/'.
    const std::size_t at = static_cast<std::size_t>(tok[i].data() - s.data());
    ref.file = std::string(trim(s.substr(at)));
    std::replace(ref.file.begin(), ref.file.end(), '\\', '/');
    (key == "map_Kd" ? map_kd_ : key == "map_d" ? map_d_ : key == "norm" ? map_norm_ : key == "bump" ? map_bump_ : map_ke_) = ref;
    return {};
  }

  struct TextureRef {
    std::string file;
    std::size_t line = 0;
    Vec2 scale{1.0f, 1.0f};
    bool clamp = false;
    float bump = 1.0f;  // norm -bm
    bool empty() const { return file.empty(); }
    void clear() { file.clear(); }
  };

  Status finish_material() {
    if (!open_) return {};
    open_ = false;
    if (has_d_) {
      current_.alpha = d_;
      if (has_tr_ && std::abs((1.0f - tr_) - d_) > 1e-6f) {
        warnings_.push_back(source_ + ": material " + quote(current_.name, 40) + ": d " + format_number(d_) + " and Tr " +
                            format_number(tr_) + " disagree; d is used");
      }
    } else if (has_tr_) {
      current_.alpha = 1.0f - tr_;
    }
    if (illum_ == 0) {  // colour on, ambient off: the diffuse colour, unlit
      current_.emissive = current_.diffuse;
      current_.ambient = current_.diffuse = current_.specular = Color3::Zero();
    } else if (illum_ == 1) {
      current_.specular = Color3::Zero();
    } else if (illum_ > 2) {
      ignore(illum_line_, "illum " + std::to_string(illum_) + " (reflection, refraction; drawn as illum 2)");
    }
    illum_ = 2;
    if (!map_kd_.empty() || !map_d_.empty()) FACET_TRY(attach_texture());
    if (!map_ke_.empty()) FACET_TRY(attach_emissive_texture());
    if (!map_norm_.empty()) FACET_TRY(attach_map(map_norm_, "norm", current_.normal_texture, current_.normal_scale));
    if (!map_bump_.empty()) FACET_TRY(attach_map(map_bump_, "bump", current_.bump_texture, current_.bump_scale));
    if (current_.alpha < 1.0f || !map_d_.empty()) current_.blend = BlendMode::alpha;
    scene_.materials.push_back(current_);
    return {};
  }

  Status attach_texture() {
    // map_Kd and map_Ke are colour, sRGB-encoded (as Blender's and three.js's OBJ readers take
    // them); the alpha of map_d is linear either way (alpha is never sRGB-encoded).
    Result<Texture> kd = map_kd_.empty() ? Result<Texture>(Texture{}) : load(map_kd_, TextureEncoding::srgb);
    if (!kd) return kd.status();
    const bool kd_ok = !map_kd_.empty() && kd->width() > 0;
    Texture result;
    if (!map_d_.empty() && map_d_.file != map_kd_.file) {
      // A separate alpha map: its alpha where it has one, else its luminance, becomes the alpha
      // of the colour texture (which must have the same size), or of a white texture.
      Result<Texture> d = load(map_d_);
      if (!d) return d.status();
      if (d->width() == 0) {
        if (kd_ok) result = std::move(*kd);
      } else {
        if (kd_ok && (kd->width() != d->width() || kd->height() != d->height())) {
          return error(map_d_.line, "map_d: " + quote(map_d_.file, 80) + " is " + std::to_string(d->width()) + "x" +
                                        std::to_string(d->height()) + " but map_Kd's texture is " +
                                        std::to_string(kd->width()) + "x" + std::to_string(kd->height()) +
                                        "; facet combines them into one texture of one size",
                       ErrorCode::unsupported);
        }
        const int w = d->width(), h = d->height();
        std::vector<std::uint8_t> rgba(std::size_t(w) * std::size_t(h) * 4);
        bool has_alpha = false;
        for (std::size_t t = 0; t < std::size_t(w) * std::size_t(h); ++t) has_alpha |= (d->texels[t] >> 24) != 255;
        for (int y = 0; y < h; ++y) {
          for (int x = 0; x < w; ++x) {
            const std::size_t stored = std::size_t(y) * std::size_t(w) + std::size_t(x);  // bottom row first
            const std::size_t out = (std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x)) * 4;  // top row first
            const std::uint32_t c = kd_ok ? kd->texels[stored] : 0xffffffffu;
            const std::uint32_t a = d->texels[stored];
            const unsigned alpha = has_alpha ? (a >> 24) : ((a & 255) + ((a >> 8) & 255) + ((a >> 16) & 255) + 1) / 3;
            rgba[out] = std::uint8_t(c & 255), rgba[out + 1] = std::uint8_t((c >> 8) & 255);
            rgba[out + 2] = std::uint8_t((c >> 16) & 255), rgba[out + 3] = std::uint8_t(std::min(alpha, 255u));
          }
        }
        TextureOptions topt;
        topt.encoding = TextureEncoding::srgb;
        topt.wrap = (kd_ok ? map_kd_ : map_d_).clamp ? TextureWrap::clamp : TextureWrap::repeat;
        topt.memory_budget_bytes = left();
        Result<Texture> made = make_texture(map_kd_.file + "+" + map_d_.file, w, h, rgba, topt);
        if (!made) return error(map_d_.line, made.status().message(), made.status().code());
        result = std::move(*made);
      }
    } else if (kd_ok) {
      result = std::move(*kd);
    }
    if (result.width() == 0) return {};
    const TextureRef& ref = map_kd_.empty() ? map_d_ : map_kd_;
    current_.uv_scale = ref.scale;
    scene_.textures.push_back(std::move(result));
    current_.diffuse_texture = static_cast<std::int32_t>(scene_.textures.size() - 1);
    current_.texture_mode = TextureMode::modulate;
    return {};
  }

  // map_Ke: the emissive texture, times Ke (1 when the material gives no Ke), added after the
  // diffuse texture (Material::emissive_texture). One uv scale per material: map_Kd's wins.
  Status attach_emissive_texture() {
    Result<Texture> ke = load(map_ke_, TextureEncoding::srgb);
    if (!ke) return ke.status();
    if (ke->width() == 0) return {};  // missing and allowed: warned by load()
    if (current_.diffuse_texture == kNoTexture) {
      current_.uv_scale = map_ke_.scale;
    } else if (map_ke_.scale != current_.uv_scale) {
      warnings_.push_back(source_ + ":" + std::to_string(map_ke_.line) + ": map_Ke -s differs from map_Kd's; facet has "
                                                                          "one uv scale per material, map_Kd's is used");
    }
    scene_.textures.push_back(std::move(*ke));
    current_.emissive_texture = static_cast<std::int32_t>(scene_.textures.size() - 1);
    if (!has_ke_) current_.emissive = Color3::Ones();
    return {};
  }

  // norm (a tangent-space normal map) and bump / map_Bump (a height map): linear, scaled by -bm,
  // at the material's one set of coordinates (the first texture's uv scale wins).
  Status attach_map(const TextureRef& ref, const char* key, std::int32_t& texture, float& scale) {
    Result<Texture> t = load(ref, TextureEncoding::linear);
    if (!t) return t.status();
    if (t->width() == 0) return {};
    if (!uses_textures(current_)) {
      current_.uv_scale = ref.scale;
    } else if (ref.scale != current_.uv_scale) {
      warnings_.push_back(source_ + ":" + std::to_string(ref.line) + ": " + key +
                          " -s differs from map_Kd's; facet has one uv scale per material, map_Kd's is used");
    }
    scene_.textures.push_back(std::move(*t));
    texture = static_cast<std::int32_t>(scene_.textures.size() - 1);
    scale = ref.bump;
    return {};
  }

  // A texture file, or an empty texture (and a warning) when it is missing and that is allowed.
  Result<Texture> load(const TextureRef& ref, std::optional<TextureEncoding> encoding = std::nullopt) {
    TextureOptions topt;
    topt.encoding = encoding;
    topt.wrap = ref.clamp ? TextureWrap::clamp : TextureWrap::repeat;
    topt.memory_budget_bytes = left();
    const std::string where = source_ + ":" + std::to_string(ref.line) + ": texture";
    Result<Texture> t = read_texture(folder_, ref.file, where, ref.file, topt);
    if (t) return t;
    // A name written on another machine (D:\models\tex.jpg, ..\LWO\x.png): its base name in the
    // material library's folder, as Blender and assimp look for it; never outside the folder.
    const std::size_t slash = ref.file.find_last_of("/:");
    if (t.status().code() != ErrorCode::out_of_memory && t.status().code() != ErrorCode::cancelled &&
        slash != std::string::npos && slash + 1 < ref.file.size()) {
      const std::string base = ref.file.substr(slash + 1);
      Result<Texture> found = read_texture(folder_, base, where, base, topt);
      if (found) {
        warnings_.push_back(where + ": " + quote(ref.file, 120) + " cannot be read (" + t.status().message() +
                            "); the file of its base name " + quote(base, 80) + " beside the material library is used");
        return found;
      }
    }
    const bool missing = skippable(t.status());
    if (missing && options_.allow_missing) {
      warnings_.push_back(t.status().message() + "; drawn untextured");
      return Texture{};
    }
    return Status{t.status().code(), "line " + std::to_string(ref.line),
                  t.status().message() + (missing ? kStrictNote
                                          : t.status().code() == ErrorCode::out_of_memory
                                              ? " (what the model's mesh and textures before it leave of ModelOptions::memory_budget_bytes, facet --memory-budget-mb)"
                                              : "")};
  }

  // What the model's textures so far leave of the memory budget (never 0, which would mean no
  // limit); 0 when there is no budget. The caller's budget has the mesh taken off already.
  std::uint64_t left() const {
    const std::uint64_t budget = options_.memory_budget_bytes;
    if (budget == 0) return 0;
    std::uint64_t used = 0;
    for (const Texture& t : scene_.textures) used += t.texels.size() * sizeof(std::uint32_t);
    return std::max<std::uint64_t>(1, budget - std::min(used, budget));
  }

  std::string source_;
  io::AssetFolder folder_;
  const ModelOptions& options_;
  Scene& scene_;
  std::vector<std::string>& warnings_;
  Material current_;
  bool open_ = false;
  float d_ = 1.0f, tr_ = 0.0f;
  bool has_d_ = false, has_tr_ = false;
  int illum_ = 2;
  std::size_t illum_line_ = 0;
  TextureRef map_kd_, map_d_, map_ke_, map_norm_, map_bump_;
  bool has_ke_ = false;
  std::map<std::string, std::string> ignored_;  // what -> the first lines it was on
};

Status parse_mtl_in(const std::string& text, const std::string& source_name, const io::AssetFolder& folder,
                    const ModelOptions& options, Scene& scene, std::vector<std::string>& warnings) {
  try {
    MtlReader reader(source_name, folder, options, scene, warnings);
    return reader.read(text);
  } catch (const std::bad_alloc&) {
    return {ErrorCode::out_of_memory, "", source_name + ": out of memory while reading the materials"};
  }
}

}  // namespace

Status parse_mtl(const std::string& text, const std::string& source_name, const std::string& base_dir,
                 const ModelOptions& options, Scene& scene, std::vector<std::string>& warnings) {
  return parse_mtl_in(text, source_name, io::AssetFolder(options.assets, base_dir), options, scene, warnings);
}

Result<Model> load_obj_model(const std::string& path, const ModelOptions& options) {
  try {
    const std::uint64_t limit = options.memory_budget_bytes == 0 ? io::kNoSizeLimit : options.memory_budget_bytes;
    Result<std::string> text = io::read_named_by_host(options.assets, path, "OBJ file", limit);
    if (!text) return text.status();
    ObjOptions oo;
    oo.crease_angle_deg = options.crease_angle_deg;
    oo.memory_budget_bytes = options.memory_budget_bytes;
    Result<Mesh> mesh = parse_obj(*text, path, oo);
    if (!mesh) return mesh.status();
    // The materials' textures get what the mesh leaves of the budget.
    ModelOptions mtl_options = options;
    if (options.memory_budget_bytes != 0) {
      const std::uint64_t mesh_bytes = mesh->vertex_count() * (2 * sizeof(Vec3) + sizeof(Vec2)) + mesh->triangle_count() * 12;
      mtl_options.memory_budget_bytes = std::max<std::uint64_t>(1, options.memory_budget_bytes - std::min(mesh_bytes, options.memory_budget_bytes));
    }
    Model model;
    model.scene.transparent_order = TransparentOrder::back_to_front;  // as glTF models (docs/content.md)
    model.scene.display.tone_mapping = ToneMapping::neutral;            // as glTF models (docs/color.md)
    Scene& scene = model.scene;
    const std::string base = std::filesystem::path(path).parent_path().string();
    // mtllib statements: each names one or more files (names without spaces, as tinyobjloader reads them).
    std::vector<std::string> libraries;
    const Status libraries_read = for_each_line(*text, [&](std::size_t line, std::string_view s) -> Status {
      const std::vector<std::string_view> tok = split_ws(s);
      if (tok[0] != "mtllib") return {};
      if (tok.size() < 2) return {ErrorCode::parse_error, "line " + std::to_string(line), path + ":" + std::to_string(line) + ": mtllib: expected a file name"};
      for (std::size_t i = 1; i < tok.size(); ++i) {
        std::string file(tok[i]);
        std::replace(file.begin(), file.end(), '\\', '/');
        const io::AssetFolder folder(options.assets, base);
        const std::string where = path + ":" + std::to_string(line) + ": mtllib";
        Result<io::AssetFolder::Resolved> resolved = folder.resolve(file, where);
        Result<std::string> mtl = resolved ? folder.read(file, where, "MTL file", limit) : Result<std::string>(resolved.status());
        if (!mtl) {
          if (options.allow_missing && skippable(mtl.status())) {
            model.warnings.push_back(mtl.status().message() + "; its materials are facet's default");
            continue;
          }
          return {mtl.status().code(), "line " + std::to_string(line),
                  mtl.status().message() + (skippable(mtl.status()) ? kStrictNote : "")};
        }
        const std::string full = resolved->name;
        libraries.push_back(file);
        FACET_TRY(parse_mtl_in(*mtl, full, folder.folder_of(*resolved), mtl_options, scene, model.warnings));
      }
      return {};
    });
    if (!libraries_read.ok()) return libraries_read;
    // Every group's material must exist; faces before any `usemtl` use the group named "".
    std::set<std::string> missing;
    for (MaterialGroup& g : mesh->groups) {
      if (find_material(scene, g.material) >= 0) continue;
      if (g.material.empty() || missing.count(g.material)) continue;
      if (!options.allow_missing && !libraries.empty()) {
        std::string libs;
        for (const auto& l : libraries) libs += (libs.empty() ? "" : ", ") + quote(l, 60);
        return Status{ErrorCode::invalid_argument, "usemtl",
                      path + ": usemtl " + quote(g.material, 40) + ": no material of that name in " + libs +
                          kStrictNote};
      }
      if (!libraries.empty()) {
        model.warnings.push_back(path + ": usemtl " + quote(g.material, 40) + ": no such material; facet's default is used");
      }
      missing.insert(g.material);
    }
    for (const MaterialGroup& g : mesh->groups) {
      if (find_material(scene, g.material) >= 0) continue;
      Material m = model_default_material();
      m.name = g.material;
      scene.materials.push_back(m);
    }
    if (libraries.empty() && !mesh->groups.empty()) {
      model.warnings.push_back(path + ": usemtl without mtllib: every material is facet's default");
    }
    // A textured material on a mesh without texture coordinates: drawn untextured.
    if (mesh->uvs.empty()) {
      std::set<std::string> used;
      for (const MaterialGroup& g : mesh->groups) used.insert(g.material);
      for (Material& m : scene.materials) {
        if (uses_textures(m) && (used.count(m.name) || mesh->groups.empty())) {
          model.warnings.push_back(path + ": material " + quote(m.name, 40) +
                                   " is textured but the mesh has no texture coordinates (vt); drawn untextured");
          m.diffuse_texture = m.emissive_texture = m.normal_texture = m.occlusion_texture = m.bump_texture = kNoTexture;
        }
      }
    }
    NamedMesh named;
    named.name = std::filesystem::path(path).stem().string();
    named.mesh = std::move(*mesh);
    const bool groups = !named.mesh.groups.empty();
    scene.meshes.push_back(std::move(named));
    Instance inst;
    inst.mesh = 0;
    inst.mesh_materials = groups;
    if (!groups) {
      // No usemtl: the only material of the libraries if there is exactly one, else facet's default.
      if (scene.materials.size() != 1) scene.materials.push_back(model_default_material());
      inst.material = static_cast<std::uint32_t>(scene.materials.size() - 1);
    }
    scene.objects.push_back(inst);
    if (Status s = generate_missing_tangents(scene); !s.ok()) return Status{s.code(), s.field(), path + ": " + s.message()};
    if (Status s = validate_scene(scene); !s.ok()) {
      return Status{s.code(), s.field(), path + ": the imported scene is not valid: " + s.message()};
    }
    return model;
  } catch (const std::bad_alloc&) {
    return Status{ErrorCode::out_of_memory, "", path + ": out of memory while reading the model"};
  }
}

}  // namespace facet
