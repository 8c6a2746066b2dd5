// Internal: the files that one file names (facet/assets.hpp states the rules). An AssetFolder is
// the folder of the naming file; every name is resolved against it, confined to it or to the
// host's allowed roots, and read through the host's resolver when there is one.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "facet/assets.hpp"
#include "facet/status.hpp"
#include "io/file_access.hpp"

namespace facet::io {

class AssetFolder {
 public:
  // `folder`: the naming file's folder ("" = the current directory); `root`: the folder nothing
  // may leave (the folder of the file the host named: a scene's, or a model's), by default the
  // naming file's own.
  AssetFolder(const AssetAccess& access, std::string folder)
      : access_(access), folder_(std::move(folder)), root_(folder_) {}
  AssetFolder(const AssetAccess& access, std::string folder, std::string root)
      : access_(access), folder_(std::move(folder)), root_(std::move(root)) {}

  struct Resolved {
    std::string name;  // the folder joined with the name, normalised: for messages and sub-folders
    std::string path;  // what is opened (every link followed), or what the resolver is asked for
  };
  // Where the name leads, or why facet may not read it. `where` starts the message
  // ("scene.json:12: textures[0].file").
  Result<Resolved> resolve(std::string_view name, const std::string& where) const;
  // Resolves and reads the file; `what` names its kind ("texture file"). Over `max_bytes`:
  // ErrorCode::out_of_memory.
  Result<std::string> read(std::string_view name, const std::string& where, const char* what,
                           std::uint64_t max_bytes = kNoSizeLimit) const;
  // The folder of a file this folder names (an MTL names textures beside it), with the same root.
  AssetFolder folder_of(const Resolved& file) const;

  const AssetAccess& access() const noexcept { return access_; }

 private:
  const AssetAccess& access_;
  std::string folder_;
  std::string root_;
};

// The file a host names itself (load_model, load_scene_file): read as it is, or asked of the
// resolver when there is one.
Result<std::string> read_named_by_host(const AssetAccess& access, const std::string& path, const char* what,
                                       std::uint64_t max_bytes = kNoSizeLimit);

}  // namespace facet::io
