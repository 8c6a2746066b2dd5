#include "output_folder.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "common/format.hpp"
#include "io/file_access.hpp"

namespace facet::cli {
namespace {

Status refuse(const std::string& path, const std::string& why) {
  return {ErrorCode::io_error, "output", "cannot write " + quote(path, 200) + ": " + why};
}

}  // namespace

Result<OutputFolder> OutputFolder::open(const std::string& dir, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) {
    if (errno != ENOENT) return refuse(dir, std::strerror(errno));
    fs::create_directories(dir, ec);
    if (ec) return refuse(dir, "cannot create the folder: " + ec.message());
  } else if (!S_ISDIR(st.st_mode)) {
    return refuse(dir, "it exists and is not a folder");
  } else if (!overwrite) {
    fs::directory_iterator it(dir, ec);
    if (ec) return refuse(dir, ec.message());
    if (it != fs::directory_iterator()) {
      return refuse(dir, "the folder is not empty (write into a new or empty folder, or pass --overwrite to replace the "
                         "files of an earlier bake)");
    }
  }
  OutputFolder out;
  out.dir_ = dir;
  return out;
}

void OutputFolder::protect(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) inputs_.insert({st.st_dev, st.st_ino});
}

Result<std::string> OutputFolder::path(const std::string& relative) const {
  if (relative.empty() || relative[0] == '/') return refuse(relative, "not a relative path");
  std::string at = dir_;
  std::size_t b = 0;
  while (true) {
    const std::size_t e = relative.find('/', b);
    const std::string part = relative.substr(b, e == std::string::npos ? std::string::npos : e - b);
    if (part.empty() || part == "." || part == "..") return refuse(dir_ + "/" + relative, "not a normal relative path");
    at += "/" + part;
    struct stat st {};
    const bool exists = ::lstat(at.c_str(), &st) == 0;
    if (!exists && errno != ENOENT) return refuse(at, std::strerror(errno));
    if (exists && S_ISLNK(st.st_mode)) return refuse(at, "it is a symbolic link (facet writes through no link)");
    if (e == std::string::npos) {
      if (exists && !S_ISREG(st.st_mode)) return refuse(at, "it exists and is not a regular file");
      if (exists && inputs_.count({st.st_dev, st.st_ino})) return refuse(at, "it is a file this command reads");
      return at;
    }
    if (!exists && ::mkdir(at.c_str(), 0755) != 0) return refuse(at, std::string("cannot create the folder: ") + std::strerror(errno));
    if (exists && !S_ISDIR(st.st_mode)) return refuse(at, "it exists and is not a folder");
    b = e + 1;
  }
}

Status OutputFolder::write(const std::string& relative, const std::string& bytes) const {
  Result<std::string> p = path(relative);
  if (!p) return p.status();
  return io::write_file_atomically(*p, "file", [&](std::FILE* f) -> Status {
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) {
      return {ErrorCode::io_error, "output", "cannot write " + quote(*p, 200) + ": " + std::strerror(errno)};
    }
    return {};
  });
}

}  // namespace facet::cli
