#pragma once
// Result<T>: a value or a message saying what went wrong with external input.
//
// The error type shared by every atmoglobe library (it lives in globe because globe is
// the bottom of the dependency graph). Bad input (files, scene descriptions, tiles,
// out-of-range coordinates) is reported through Result, never by throwing; the CLI
// prints the message and exits non-zero. Programmer misuse is an assert.
//
// Passing a failure on unchanged, whatever the caller's own Result type:
//   auto grid = readGrid(path);
//   if (!grid) return grid.forwardError();
// Adding context is spelled out: `return makeError(path + ": " + grid.error());`.
#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace atmoglobe {

struct Error {
  std::string message;  ///< What went wrong, naming the file/argument and the problem.
};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : m_(std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : m_(std::move(error)) {}  // NOLINT: implicit by design

  bool ok() const { return std::holds_alternative<T>(m_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& {
    assert(ok());
    return std::get<T>(m_);
  }
  T& value() & {
    assert(ok());
    return std::get<T>(m_);
  }
  T&& value() && {
    assert(ok());
    return std::get<T>(std::move(m_));
  }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  const std::string& error() const {
    assert(!ok());
    return std::get<Error>(m_).message;
  }

  /// The error, to return as-is from a function with any Result type (the message is not
  /// touched). Copies from an lvalue; moves from an rvalue. Only for a failed Result.
  Error forwardError() const& {
    assert(!ok());
    return std::get<Error>(m_);
  }
  Error forwardError() && {
    assert(!ok());
    return std::get<Error>(std::move(m_));
  }

 private:
  std::variant<T, Error> m_;
};

/// Result for operations that produce nothing but may fail.
struct Ok {};
using Status = Result<Ok>;

inline Error makeError(std::string message) { return Error{std::move(message)}; }

}  // namespace atmoglobe
