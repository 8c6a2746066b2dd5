// Which files a scene or a model may make facet read. A scene file, an OBJ (its `mtllib` and
// texture names) and a glTF (its buffer and image `uri`s) name other files. By default every such
// name is resolved against the folder of the file that names it, and nothing outside that folder
// is opened: no absolute path, no `..` that climbs out of it, no `file:` or other URI scheme, no
// symbolic link that leads out of it. Errors name the file and the field, never the bytes of a
// file that was refused.
//
// A host widens this on purpose, never a file: `allowed_roots` adds folders whose files may be
// named too (facet --allow-path DIR), and `resolver` replaces the file system altogether.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "facet/status.hpp"

namespace facet {

struct AssetAccess {
  // Folders from which a named file may also be read, besides the naming file's own folder.
  std::vector<std::string> allowed_roots;
  // When set, facet opens no file at all: every file a load needs, the one passed to
  // load_model / load_scene_file included, is asked of the resolver by name. The name is the
  // naming file's folder joined with the name as written, normalised ("models/tex/wood.png"; no
  // "." or ".." left in it), after the same confinement checks. Return the file's bytes, or a
  // Status saying why not (its message is shown after facet's own, which names the file and field).
  std::function<Result<std::string>(const std::string& name)> resolver;
  // When set, told of every file a load read, once it was read whole: its name (the file the host
  // named as given; any other as the resolver would be asked for it, confined as above) and its
  // bytes. A host that packs a model with what it needs (facet bake) copies exactly these bytes,
  // never reading the folder again by rules of its own. Called on the loading thread.
  std::function<void(const std::string& name, const std::string& bytes)> on_read;
};

}  // namespace facet
