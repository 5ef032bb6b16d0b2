#include "ocp/error.hpp"

#include <ostream>
#include <string>

namespace ocp {
namespace {

// Names double as the stable machine-readable identifiers (error_code_id).
const char* peer_error_name(PeerError value) {
  switch (value) {
    case PeerError::truncated_frame: return "truncated_frame";
    case PeerError::malformed_json: return "malformed_json";
    case PeerError::not_an_object: return "not_an_object";
    case PeerError::missing_field: return "missing_field";
    case PeerError::wrong_type: return "wrong_type";
    case PeerError::out_of_range: return "out_of_range";
    case PeerError::too_deep: return "too_deep";
    case PeerError::read_timeout: return "read_timeout";
    case PeerError::closed_by_peer: return "closed_by_peer";
    case PeerError::not_reading: return "not_reading";
  }
  return nullptr;
}

const char* local_error_name(LocalError value) {
  switch (value) {
    case LocalError::frame_too_large: return "frame_too_large";
    case LocalError::not_connected: return "not_connected";
    case LocalError::shut_down: return "shut_down";
    case LocalError::already_connected: return "already_connected";
    case LocalError::stream_closed: return "stream_closed";
  }
  return nullptr;
}

class PeerCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "peer"; }
  std::string message(int value) const override {
    switch (static_cast<PeerError>(value)) {
      case PeerError::truncated_frame: return "truncated frame";
      case PeerError::malformed_json: return "malformed JSON";
      case PeerError::not_an_object: return "not a JSON object";
      case PeerError::missing_field: return "missing field";
      case PeerError::wrong_type: return "wrong type";
      case PeerError::out_of_range: return "out of range";
      case PeerError::too_deep: return "nesting too deep";
      case PeerError::read_timeout: return "read timeout";
      case PeerError::closed_by_peer: return "peer closed";
      case PeerError::not_reading: return "peer not reading";
    }
    return "unknown peer error";
  }
};

class LocalCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "local"; }
  std::string message(int value) const override {
    switch (static_cast<LocalError>(value)) {
      case LocalError::frame_too_large: return "frame too large";
      case LocalError::not_connected: return "not connected";
      case LocalError::shut_down: return "shut down";
      case LocalError::already_connected: return "already connected";
      case LocalError::stream_closed: return "stream closed";
    }
    return "unknown local error";
  }
};

}  // namespace

const std::error_category& peer_category() noexcept {
  static const PeerCategory category;
  return category;
}

const std::error_category& local_category() noexcept {
  static const LocalCategory category;
  return category;
}

std::string error_code_id(const std::error_code& code) {
  const char* name = nullptr;
  if (code.category() == peer_category()) name = peer_error_name(static_cast<PeerError>(code.value()));
  if (code.category() == local_category()) name = local_error_name(static_cast<LocalError>(code.value()));
  if (name != nullptr) return std::string(code.category().name()) + "." + name;
  return std::string(code.category().name()) + "." + std::to_string(code.value());
}

std::ostream& operator<<(std::ostream& out, const Error& error) { return out << error.message(); }

}  // namespace ocp
