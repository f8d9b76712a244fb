// Result<T>: a value or an Error. The core never throws across its interface and never crashes
// on bad input: loaders and validators return a Result whose Error names the thing (input,
// field, body, link, joint) and the rule it broke.
//
// An Error is structured: `input` (what was refused: "apply_wrench", "set_body_state",
// "config", …), `field` (the field within it, a dotted path such as "f.x" or "pose.rotation")
// and `rule` (the rule broken, in words). Callers that present errors under other names (the
// node speaks of message fields, not of the core's) rename `input` and `field` and keep `rule`:
// nobody parses message text. Loaders whose messages already name a file, a line and a link
// build an Error from the whole message (input and field empty).
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace cga_rigid_sim {

struct Error {
  std::string input;  ///< what was refused; may be empty
  std::string field;  ///< the field within it (dotted path); may be empty
  std::string rule;   ///< the rule it broke (or the whole message when input is empty)

  /// A complete message (input and field empty).
  Error(std::string message) : rule(std::move(message)) {}  // NOLINT: implicit by design
  Error(std::string input_name, std::string field_path, std::string broken_rule)
      : input(std::move(input_name)), field(std::move(field_path)), rule(std::move(broken_rule)) {}

  /// "input.field: rule", "input: rule" (no field) or "rule" (no input).
  std::string message() const {
    if (input.empty()) return rule;
    return input + (field.empty() ? "" : "." + field) + ": " + rule;
  }
};

template <class T>
class Result {
 public:
  Result(T value) : value_(std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : error_(std::move(error)) {}  // NOLINT
  bool ok() const { return value_.has_value(); }
  explicit operator bool() const { return ok(); }
  const T& value() const& { return *value_; }
  T& value() & { return *value_; }
  T&& value() && { return std::move(*value_); }
  const T& operator*() const& { return *value_; }
  T& operator*() & { return *value_; }
  const T* operator->() const { return &*value_; }
  T* operator->() { return &*value_; }
  /// The error as one line of text (Error::message()); empty when ok().
  std::string error() const { return error_ ? error_->message() : std::string(); }
  /// The structured error; only when !ok().
  const Error& failure() const { return *error_; }

 private:
  std::optional<T> value_;
  std::optional<Error> error_;
};

}  // namespace cga_rigid_sim
