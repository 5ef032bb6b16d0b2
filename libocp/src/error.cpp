#include "ocp/error.hpp"

namespace ocp {
namespace {

class ProtocolCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "ocp.protocol"; }
  std::string message(int value) const override {
    switch (static_cast<ProtocolError>(value)) {
      case ProtocolError::frame_too_large: return "frame too large";
      case ProtocolError::truncated_frame: return "truncated frame";
      case ProtocolError::malformed_json: return "malformed JSON";
      case ProtocolError::not_an_object: return "not a JSON object";
      case ProtocolError::missing_field: return "missing field";
      case ProtocolError::wrong_type: return "wrong type";
      case ProtocolError::out_of_range: return "out of range";
      case ProtocolError::too_deep: return "nesting too deep";
    }
    return "unknown protocol error";
  }
};

}  // namespace

const std::error_category& protocol_category() noexcept {
  static const ProtocolCategory category;
  return category;
}

}  // namespace ocp
