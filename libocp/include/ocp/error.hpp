#pragma once
// Errors a peer can cause. Every bad input has its own code plus a human-readable detail
// (e.g. "telemetry.fault: expected boolean"); they are values, never exceptions.
#include <string>
#include <system_error>
#include <utility>
#include <variant>

namespace ocp {

enum class ProtocolError {
  frame_too_large = 1,   // outbound payload over the limit (inbound ones are drained, see frame.hpp)
  truncated_frame,       // the stream ended inside a frame
  malformed_json,        // not parseable JSON (or not UTF-8)
  not_an_object,         // valid JSON whose top level is not an object
  missing_field,         // a required field is absent
  wrong_type,            // a field has the wrong JSON type
  out_of_range,          // a number outside its type (negative u64, u32 overflow, fractional integer)
  too_deep,              // nesting beyond the decoder's depth limit
};

const std::error_category& protocol_category() noexcept;
inline std::error_code make_error_code(ProtocolError e) noexcept {
  return {static_cast<int>(e), protocol_category()};
}

struct Error {
  std::error_code code;
  std::string detail;  // what was wrong and where, ready for a log line

  std::string message() const { return code.message() + ": " + detail; }
};

// Minimal expected<T, Error> (C++23's std::expected is not in GCC 12).
template <class T>
class Result {
 public:
  Result(T value) : state_(std::move(value)) {}          // NOLINT(google-explicit-constructor)
  Result(Error error) : state_(std::move(error)) {}      // NOLINT(google-explicit-constructor)

  bool ok() const noexcept { return state_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }
  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  T&& value() && { return std::get<0>(std::move(state_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  const Error& error() const { return std::get<1>(state_); }

 private:
  std::variant<T, Error> state_;
};

struct Ok {};
using Status = Result<Ok>;

}  // namespace ocp

template <>
struct std::is_error_code_enum<ocp::ProtocolError> : std::true_type {};
