// Internal: every file facet reads or writes goes through here.
//
// Reading: the file is opened without blocking and refused unless fstat says it is a regular
// file (a FIFO, a device or a directory would block, never end or mean nothing), refused if it
// is larger than the caller's limit, then read whole; a read either returns every byte or an
// error (out_of_memory when the buffer cannot be had).
// Writing: into a temporary file in the same directory, renamed over the target only when every
// byte was written and the file closed, so a failed or interrupted write (disk full, ulimit -f,
// a crash) leaves the old file as it was. A missing directory is an error, never created. A name
// that leads to anything but a regular file (a FIFO, a device, a socket, a folder; through a link
// or not) is refused; a link to a regular file is replaced by the new file, not written through.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

#include "facet/status.hpp"

namespace facet::io {

inline constexpr std::uint64_t kNoSizeLimit = ~std::uint64_t{0};

// `what` names the kind of file in messages ("scene file", "OBJ file").
Result<std::string> read_file(const std::string& path, const char* what, std::uint64_t max_bytes = kNoSizeLimit);

// Calls write(file) on a temporary file beside `path`; on success (write returned ok and every
// byte reached the file) renames it to `path`, else removes it. `what` as above.
Status write_file_atomically(const std::string& path, const char* what,
                             const std::function<Status(std::FILE*)>& write);

}  // namespace facet::io
