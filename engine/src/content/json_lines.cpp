#include "content/json_lines.hpp"

#include <algorithm>
#include <set>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

namespace facet {
namespace {

using json = nlohmann::json;

// Offsets of line starts, for byte offset -> (line, column).
class LineIndex {
 public:
  explicit LineIndex(const std::string& text) {
    starts_.push_back(0);
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') starts_.push_back(i + 1);
  }
  std::size_t line(std::size_t offset) const {
    return static_cast<std::size_t>(std::upper_bound(starts_.begin(), starts_.end(), offset) - starts_.begin());
  }
  std::size_t column(std::size_t offset) const { return offset - starts_[line(offset) - 1] + 1; }

 private:
  std::vector<std::size_t> starts_;
};

class LineRecorder final : public nlohmann::json_sax<json> {
 public:
  LineRecorder(std::istringstream& in, const LineIndex& index, std::unordered_map<std::string, std::size_t>& out)
      : in_(in), index_(index), out_(out) {}

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }

  bool key(string_t& k) override {
    Frame& f = stack_.back();
    if (!f.keys.insert(k).second) {
      fail("duplicate key '" + k + "' in " + (f.path.empty() ? std::string("the top-level object") : f.path));
      return false;
    }
    f.pending = f.path.empty() ? k : f.path + "." + k;
    return true;
  }

  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& ex) override {
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line L, column C: what".
    std::string what = ex.what();
    if (const auto colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
    const std::size_t offset = position > 0 ? position - 1 : 0;
    error_line_ = index_.line(offset);
    error_column_ = index_.column(offset);
    error_ = "invalid JSON: " + what;
    return false;
  }

  const std::string& error() const { return error_; }
  std::size_t error_line() const { return error_line_; }
  std::size_t error_column() const { return error_column_; }

 private:
  struct Frame {
    bool is_array = false;
    std::string path;
    std::size_t next_index = 0;
    std::string pending;
    std::set<std::string> keys;
  };

  std::size_t offset() {
    const auto pos = static_cast<std::size_t>(in_.rdbuf()->pubseekoff(0, std::ios_base::cur, std::ios_base::in));
    return pos > 0 ? pos - 1 : 0;  // the last character the lexer consumed
  }

  void fail(std::string what) {
    error_ = std::move(what);
    error_line_ = index_.line(offset());
    error_column_ = 0;
  }

  std::string next_path() {
    if (stack_.empty()) return "";
    Frame& f = stack_.back();
    if (f.is_array) return f.path + "[" + std::to_string(f.next_index++) + "]";
    return f.pending;
  }

  bool value() {
    out_.try_emplace(next_path(), index_.line(offset()));
    return true;
  }

  bool open(bool is_array) {
    if (stack_.size() >= kMaxJsonDepth) {
      fail("nesting deeper than " + std::to_string(kMaxJsonDepth) + " levels");
      return false;
    }
    std::string path = next_path();
    out_.try_emplace(path, index_.line(offset()));
    stack_.push_back(Frame{is_array, std::move(path), 0, {}, {}});
    return true;
  }

  bool close() {
    stack_.pop_back();
    return true;
  }

  std::istringstream& in_;
  const LineIndex& index_;
  std::unordered_map<std::string, std::size_t>& out_;
  std::vector<Frame> stack_;
  std::string error_;
  std::size_t error_line_ = 0, error_column_ = 0;
};

}  // namespace

Status JsonLines::scan(const std::string& text, const std::string& source_name) {
  line_of_path_.clear();
  const LineIndex index(text);
  std::istringstream in(text);
  LineRecorder recorder(in, index, line_of_path_);
  const bool ok = json::sax_parse(in, &recorder);
  if (ok) return {};
  std::string where = source_name + ":" + std::to_string(recorder.error_line());
  if (recorder.error_column() > 0) where += ":" + std::to_string(recorder.error_column());
  const std::string what = recorder.error().empty() ? "invalid JSON" : recorder.error();
  return {ErrorCode::parse_error, "", where + ": " + what};
}

std::size_t JsonLines::line_of(std::string path) const {
  while (true) {
    if (auto it = line_of_path_.find(path); it != line_of_path_.end()) return it->second;
    if (path.empty()) return 0;
    const auto cut = path.find_last_of(".[");
    path = cut == std::string::npos ? std::string() : path.substr(0, cut);
  }
}

}  // namespace facet
