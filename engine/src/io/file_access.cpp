#include "io/file_access.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>

#include "common/format.hpp"

namespace facet::io {
namespace {

Status fail(ErrorCode code, const char* verb, const char* what, const std::string& path, const std::string& why) {
  return {code, "path", std::string(verb) + " " + what + " " + quote(path, 200) + ": " + why};
}

struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

Result<std::string> read_file(const std::string& path, const char* what, std::uint64_t max_bytes) {
  Fd f;
  // O_NONBLOCK: opening a FIFO with no writer would otherwise wait forever; it is refused below.
  f.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (f.fd < 0) {
    const int err = errno;
    return fail(ErrorCode::io_error, "cannot open", what, path, err == ENOENT ? "no such file" : std::strerror(err));
  }
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) return fail(ErrorCode::io_error, "cannot read", what, path, std::strerror(errno));
  if (!S_ISREG(st.st_mode)) return fail(ErrorCode::io_error, "cannot open", what, path, "not a regular file");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes) {
    return fail(ErrorCode::out_of_memory, "cannot read", what, path,
                std::to_string(size) + " bytes, over the limit of " + std::to_string(max_bytes) +
                    " bytes (the memory budget; raise LoadOptions::memory_budget_bytes)");
  }
  std::string text;
  try {
    text.resize(static_cast<std::size_t>(size));
  } catch (const std::bad_alloc&) {
    return fail(ErrorCode::out_of_memory, "cannot read", what, path,
                "out of memory for its " + std::to_string(size) + " bytes");
  }
  std::size_t done = 0;
  while (true) {
    if (done == text.size()) {
      // The file may have grown since fstat: read until end of file, within the limit.
      char probe[4096];
      const ssize_t n = ::read(f.fd, probe, sizeof probe);
      if (n == 0) break;
      if (n < 0) {
        if (errno == EINTR) continue;
        return fail(ErrorCode::io_error, "error while reading", what, path, std::strerror(errno));
      }
      if (text.size() + static_cast<std::size_t>(n) > max_bytes) {
        return fail(ErrorCode::out_of_memory, "cannot read", what, path,
                    "it grew over the limit of " + std::to_string(max_bytes) + " bytes while being read");
      }
      try {
        text.append(probe, static_cast<std::size_t>(n));
      } catch (const std::bad_alloc&) {
        return fail(ErrorCode::out_of_memory, "cannot read", what, path, "out of memory");
      }
      done = text.size();
      continue;
    }
    const ssize_t n = ::read(f.fd, text.data() + done, text.size() - done);
    if (n == 0) {  // shrank since fstat
      text.resize(done);
      break;
    }
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail(ErrorCode::io_error, "error while reading", what, path, std::strerror(errno));
    }
    done += static_cast<std::size_t>(n);
  }
  return text;
}

Status write_file_atomically(const std::string& path, const char* what,
                             const std::function<Status(std::FILE*)>& write) {
  // What the name leads to now: a regular file is replaced, a link is replaced (not written
  // through); a FIFO, a device, a socket or a folder is refused, never replaced by a file.
  struct stat target {};
  if (::stat(path.c_str(), &target) == 0 && !S_ISREG(target.st_mode)) {
    return fail(ErrorCode::io_error, "cannot write", what, path,
                S_ISDIR(target.st_mode) ? "it is a folder" : "it exists and is not a regular file (a FIFO, a device or a socket)");
  }
  std::string temp = path + ".XXXXXX";
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) {
    const int err = errno;
    return fail(ErrorCode::io_error, "cannot write", what, path, std::strerror(err));
  }
  ::fchmod(fd, 0644);  // mkstemp makes 0600; an image is meant to be read by others
  std::FILE* file = ::fdopen(fd, "wb");
  if (!file) {
    const int err = errno;
    ::close(fd);
    ::unlink(temp.c_str());
    return fail(ErrorCode::io_error, "cannot write", what, path, std::strerror(err));
  }
  Status written = write(file);
  if (written.ok() && (std::fflush(file) != 0 || std::ferror(file))) {
    written = fail(ErrorCode::io_error, "cannot write", what, path, std::strerror(errno));
  }
  if (std::fclose(file) != 0 && written.ok()) {
    written = fail(ErrorCode::io_error, "cannot write", what, path, std::strerror(errno));
  }
  if (written.ok() && ::rename(temp.c_str(), path.c_str()) != 0) {
    written = fail(ErrorCode::io_error, "cannot write", what, path, std::strerror(errno));
  }
  if (!written.ok()) ::unlink(temp.c_str());
  return written;
}

}  // namespace facet::io
