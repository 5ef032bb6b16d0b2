#pragma once
// Errors a peer can cause. Every bad input has its own code plus a human-readable detail
// (e.g. "telemetry.fault: expected boolean"); they are values, never exceptions.
#include <iosfwd>
#include <string>
#include <system_error>
#include <utility>
#include <variant>

namespace ocp {

// Two kinds of error, as in h11: what the PEER did wrong (remote: bad bytes, silence, going
// away) and what OUR OWN code asked for that the protocol forbids (local: sending an
// oversized frame, writing to a closed connection). Each kind is its own enum with its own
// error category, so a test or a tool compares values (`reason.code == PeerError::read_timeout`)
// and never parses text. The detail string says where and what, for a person.

// The peer violated the protocol or went away. Every close of a connection caused by the other
// side carries one of these.
enum class PeerError {
  truncated_frame = 1,   // the stream ended inside a frame
  malformed_json,        // not parseable JSON (or not UTF-8)
  not_an_object,         // valid JSON whose top level is not an object
  missing_field,         // a required field is absent
  wrong_type,            // a field has the wrong JSON type
  out_of_range,          // a number outside its type (negative u64, u32 overflow, fractional integer)
  too_deep,              // nesting beyond the decoder's depth limit
  read_timeout,          // no byte for the read timeout (SPEC §2: 2 000 ms)
  closed_by_peer,        // the peer closed the connection cleanly (or the transport failed)
  not_reading,           // the peer stopped reading: our write queue for it hit its limit
};

// Our own code misused the connection, or closed it on purpose. Never the peer's fault.
enum class LocalError {
  frame_too_large = 1,   // asked to send a payload over the frame limit (SPEC §2: never sent)
  not_connected,         // asked to send on a closed connection
  shut_down,             // the component stopped (stop(), restart) and closed the connection
  already_connected,     // a second connection while one is active (SPEC §3.1 Decision): refused
  stream_closed,         // handed a stream that was already closed
};

const std::error_category& peer_category() noexcept;
const std::error_category& local_category() noexcept;
inline std::error_code make_error_code(PeerError e) noexcept { return {static_cast<int>(e), peer_category()}; }
inline std::error_code make_error_code(LocalError e) noexcept { return {static_cast<int>(e), local_category()}; }
// Stable lower-case identifiers for machine-readable output (traces, reports):
// "peer.read_timeout", "local.frame_too_large"; other categories give "<category>.<value>".
std::string error_code_id(const std::error_code& code);

struct Error {
  std::error_code code;
  std::string detail;  // what was wrong and where, ready for a log line

  std::string message() const { return code.message() + ": " + detail; }
  bool is_peer_error() const { return code.category() == peer_category(); }
  bool is_local_error() const { return code.category() == local_category(); }
  bool operator==(const Error&) const = default;
};

// Why a connection closed: a PeerError or LocalError value plus its detail.
using CloseReason = Error;

// "peer closed: closed by peer" — for logs and test failure messages.
std::ostream& operator<<(std::ostream& out, const Error& error);

// Minimal expected<T, Error> (C++23's std::expected is not in GCC 12). [[nodiscard]]: a
// result dropped unread is an error ignored; a caller that means it says so with a cast.
template <class T>
class [[nodiscard]] Result {
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
struct std::is_error_code_enum<ocp::PeerError> : std::true_type {};
template <>
struct std::is_error_code_enum<ocp::LocalError> : std::true_type {};
