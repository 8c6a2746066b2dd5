// A folder a command writes several files into (facet bake -o DIR), kept to itself: it is new or
// empty unless the user asks to overwrite, nothing is written through a symbolic link (neither a
// file's nor a sub-folder's), nothing that exists and is not a regular file is replaced, and no
// file the command read as input is written over.
#pragma once

#include <sys/types.h>

#include <set>
#include <string>
#include <utility>

#include "facet/status.hpp"

namespace facet::cli {

class OutputFolder {
 public:
  // Creates `dir` (and its parents) when missing. An existing `dir` must be a folder (a link to
  // one is followed: the user named it) and empty, unless `overwrite`.
  static Result<OutputFolder> open(const std::string& dir, bool overwrite);

  // Remembers a file read as input: no output may replace it.
  void protect(const std::string& path);

  // DIR/relative, its sub-folders created, after the checks above; `relative` is a normal
  // relative path ("import_0/tex/a.png").
  Result<std::string> path(const std::string& relative) const;

  // Writes `bytes` to DIR/relative (a temporary file renamed over it).
  Status write(const std::string& relative, const std::string& bytes) const;

  const std::string& dir() const noexcept { return dir_; }

 private:
  std::string dir_;
  std::set<std::pair<dev_t, ino_t>> inputs_;
};

}  // namespace facet::cli
