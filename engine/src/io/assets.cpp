#include "io/assets.hpp"

#include <cctype>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "common/format.hpp"

namespace facet::io {
namespace {

namespace fs = std::filesystem;

// `path` split at '/', "." dropped and ".." applied; nullopt when ".." climbs above the start.
std::optional<std::vector<std::string>> normal_parts(std::string_view path) {
  std::vector<std::string> parts;
  std::size_t b = 0;
  while (b <= path.size()) {
    std::size_t e = path.find('/', b);
    if (e == std::string_view::npos) e = path.size();
    const std::string_view part = path.substr(b, e - b);
    if (part == "..") {
      if (parts.empty()) return std::nullopt;
      parts.pop_back();
    } else if (!part.empty() && part != ".") {
      parts.emplace_back(part);
    }
    b = e + 1;
  }
  return parts;
}

std::string join_parts(const std::vector<std::string>& parts, bool absolute) {
  std::string out = absolute ? "/" : "";
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? "/" : "") + parts[i];
  return out;
}

// `inner` lies in folder `root` (both absolute and normal, or both relative and normal).
bool inside(const std::string& inner, const std::string& root) {
  if (root.empty() || root == ".") return !inner.empty() && inner[0] != '/';
  if (root == "/") return !inner.empty() && inner[0] == '/';
  return inner.size() > root.size() && inner.compare(0, root.size(), root) == 0 && inner[root.size()] == '/';
}

std::string absolute_normal(const std::string& path) {
  std::error_code ec;
  const fs::path a = fs::absolute(path.empty() ? fs::path(".") : fs::path(path), ec);
  if (ec) return {};
  const auto parts = normal_parts(a.string());
  return parts ? join_parts(*parts, true) : std::string("/");
}

// The path with every symbolic link followed, or empty when it does not exist.
std::string real(const std::string& path) {
  std::unique_ptr<char, decltype(&std::free)> r(::realpath(path.c_str(), nullptr), &std::free);
  return r ? std::string(r.get()) : std::string();
}

// "file:", "http:", "C:": a URI scheme (or a drive letter), which is never a relative file name.
bool has_scheme(std::string_view name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  for (std::size_t i = 1; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (c == ':') return true;
    if (!std::isalnum(c) && c != '+' && c != '-' && c != '.') return false;
  }
  return false;
}

Status refuse(const std::string& where, std::string_view name, const std::string& why,
              ErrorCode code = ErrorCode::io_error) {
  return {code, "path", where + " " + quote(name, 200) + ": " + why};
}

// The resolver's bytes for `name`; `head` starts a message ("file.mtl:3: texture 'a.png'").
Result<std::string> from_resolver(const AssetAccess& access, const std::string& name, const std::string& head,
                                  std::uint64_t max_bytes) {
  Result<std::string> bytes = access.resolver(name);
  if (!bytes) {
    return Status{bytes.status().code(), "path", head + ": the host's resolver did not give it: " + bytes.status().message()};
  }
  if (bytes->size() > max_bytes) {
    return Status{ErrorCode::out_of_memory, "path",
                  head + ": " + std::to_string(bytes->size()) + " bytes, over the limit of " + std::to_string(max_bytes) + " bytes"};
  }
  return bytes;
}

}  // namespace

Result<AssetFolder::Resolved> AssetFolder::resolve(std::string_view name, const std::string& where) const {
  if (name.empty()) return refuse(where, name, "an empty file name", ErrorCode::parse_error);
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return refuse(where, name, "a file name with control characters", ErrorCode::parse_error);
  }
  if (has_scheme(name)) {
    return refuse(where, name, "a URI or drive letter, not a file name relative to the naming file's folder (facet reads "
                               "no URI but data: in glTF)", ErrorCode::invalid_argument);
  }
  const bool absolute = name[0] == '/';
  // Lexically, from a virtual "/" for relative folders (a resolver's names stay relative).
  auto rooted = [](const std::string& folder) { return folder.empty() ? std::string("/") : folder[0] == '/' ? folder : "/" + folder; };
  bool relative_folder = folder_.empty() || folder_[0] != '/';
  std::string folder = rooted(folder_), root = rooted(root_);
  if (!access_.resolver && relative_folder && (!normal_parts(folder) || !normal_parts(root))) {
    // A folder given as "../models": worked out from the current directory instead.
    folder = absolute_normal(folder_);
    root = absolute_normal(root_);
    relative_folder = false;
  }
  const auto joined = normal_parts(absolute ? std::string(name) : folder + "/" + std::string(name));
  const auto root_parts = normal_parts(root);
  std::string candidate = joined ? join_parts(*joined, true) : std::string();
  const std::string root_path = root_parts ? join_parts(*root_parts, true) : std::string("/");
  Resolved out;
  std::string real_root_of;  // the folder whose real path must contain the file's
  if (!absolute && joined && inside(candidate, root_path)) {
    out.name = relative_folder ? candidate.substr(1) : candidate;
    real_root_of = relative_folder ? (root_.empty() ? std::string(".") : root_) : root;
  } else {
    // Else within one of the host's allowed roots.
    const std::string full = absolute ? absolute_normal(std::string(name))
                                      : absolute_normal(folder_.empty() ? std::string(name) : folder_ + "/" + std::string(name));
    for (const std::string& r : access_.allowed_roots) {
      const std::string ar = absolute_normal(r);
      if (!ar.empty() && inside(full, ar)) {
        out.name = full;
        real_root_of = ar;
        break;
      }
    }
    if (out.name.empty()) {
      return refuse(where, name,
                    std::string(absolute ? "an absolute path" : "it leads out of the folder of the file facet was given") +
                        "; facet reads only files in that folder (a host may allow more: "
                        "AssetAccess::allowed_roots, facet --allow-path DIR)",
                    ErrorCode::invalid_argument);
    }
  }
  if (access_.resolver) {
    out.path = out.name;
    return out;
  }
  // Symbolic links: the file itself, followed, must lie in the root, followed.
  out.path = real(out.name);
  if (out.path.empty()) {
    return refuse(where, name, out.name == name ? std::string("no such file") : "no such file (looked for " + quote(out.name, 200) + ")");
  }
  const std::string real_root = real(real_root_of);
  if (real_root.empty() || !inside(out.path, real_root)) {
    return refuse(where, name, "a symbolic link leads out of the folder facet may read from", ErrorCode::invalid_argument);
  }
  return out;
}

Result<std::string> AssetFolder::read(std::string_view name, const std::string& where, const char* what,
                                      std::uint64_t max_bytes) const {
  Result<Resolved> file = resolve(name, where);
  if (!file) return file.status();
  Result<std::string> bytes = access_.resolver ? from_resolver(access_, file->path, where + " " + quote(name, 200), max_bytes)
                                               : read_file(file->path, what, max_bytes);
  if (!bytes) {
    if (access_.resolver) return bytes;
    return Status{bytes.status().code(), "path", where + ": " + bytes.status().message()};
  }
  if (access_.on_read) access_.on_read(file->name, *bytes);
  return bytes;
}

AssetFolder AssetFolder::folder_of(const Resolved& file) const {
  const std::size_t slash = file.name.rfind('/');
  return AssetFolder(access_, slash == std::string::npos ? std::string() : file.name.substr(0, slash == 0 ? 1 : slash), root_);
}

Result<std::string> read_named_by_host(const AssetAccess& access, const std::string& path, const char* what,
                                       std::uint64_t max_bytes) {
  Result<std::string> bytes = access.resolver ? from_resolver(access, path, std::string(what) + " " + quote(path, 200), max_bytes)
                                              : read_file(path, what, max_bytes);
  if (bytes && access.on_read) access.on_read(path, *bytes);
  return bytes;
}

}  // namespace facet::io
