#include "io/read_file.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace facet {

Result<std::string> read_text_file(const std::string& path, const char* what) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) {
    return Status{ErrorCode::io_error, "path", std::string("cannot open ") + what + " '" + path + "': no such file"};
  }
  if (!std::filesystem::is_regular_file(status)) {
    return Status{ErrorCode::io_error, "path",
                  std::string("cannot open ") + what + " '" + path + "': not a regular file"};
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return Status{ErrorCode::io_error, "path", std::string("cannot open ") + what + " '" + path + "'"};
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    return Status{ErrorCode::io_error, "path", std::string("error while reading ") + what + " '" + path + "'"};
  }
  return text.str();
}

}  // namespace facet
