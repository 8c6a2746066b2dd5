// Errors as values. Every fallible facet call returns a Status or a Result<T>; nothing throws
// across the API and nothing aborts the host. A failed Status carries a category, the field or
// argument it is about (e.g. "lights[2].position") and a complete human-readable message.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace facet {

enum class ErrorCode {
  ok = 0,
  invalid_argument,  // a value is outside its documented domain (NaN, negative size, bad index…)
  parse_error,       // a file is not well-formed (JSON syntax, OBJ line)
  io_error,          // a file cannot be opened or read
  unsupported,       // well-formed but not something this build can do
  out_of_memory,     // an allocation failed, or the work would exceed the memory budget it was given
  cancelled,         // the caller's progress callback asked to stop
};

const char* to_string(ErrorCode code) noexcept;

class [[nodiscard]] Status {
 public:
  Status() = default;  // success
  Status(ErrorCode code, std::string field, std::string message)
      : code_(code), field_(std::move(field)), message_(std::move(message)) {}

  static Status success() { return {}; }

  bool ok() const noexcept { return code_ == ErrorCode::ok; }
  explicit operator bool() const noexcept { return ok(); }
  ErrorCode code() const noexcept { return code_; }
  // The field or argument the error is about, in scene-file path form; empty when not applicable.
  const std::string& field() const noexcept { return field_; }
  // The complete message, ready to show a user (it already names the file, line and field).
  const std::string& message() const noexcept { return message_; }

 private:
  ErrorCode code_ = ErrorCode::ok;
  std::string field_;
  std::string message_;
};

// A value or the Status that explains why there is none.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::move(value)) {}                   // NOLINT: implicit on purpose
  Result(Status error) : state_(std::move(error)) {}              // NOLINT: implicit on purpose

  bool ok() const noexcept { return std::holds_alternative<T>(state_); }
  explicit operator bool() const noexcept { return ok(); }

  T& value() & { return std::get<T>(state_); }
  const T& value() const& { return std::get<T>(state_); }
  T&& value() && { return std::get<T>(std::move(state_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  // Success when ok(), else the error. A reference, so `r.status().message()` can be kept by
  // reference for as long as `r` lives.
  const Status& status() const noexcept {
    static const Status kSuccess;  // immutable; shared by every Result
    return ok() ? kSuccess : std::get<Status>(state_);
  }

 private:
  std::variant<T, Status> state_;
};

}  // namespace facet
