#include "ocp/link_messages.hpp"

namespace ocp {
namespace {

// An estimate of a compact binary encoding; the real com channel is proprietary, so only
// the order of magnitude matters (bandwidth caps, byte counters). Nothing is encoded.
constexpr std::size_t header_bytes = 16;         // type, length, link sequence, checksum
constexpr std::size_t u64_bytes = 8;
constexpr std::size_t ack_pair_bytes = 12;       // u64 ack_time + u32 mac
constexpr std::size_t controller_bytes = 2 + 6 * 4;  // 15 button bits, six f32 axes
constexpr std::size_t position_bytes = 16;
constexpr std::size_t presence_flags_bytes = 1;  // which optionals are present
constexpr std::size_t string_length_bytes = 2;
constexpr std::size_t fault_bytes = 1;

std::size_t string_size(const std::string& text) { return string_length_bytes + text.size(); }

struct SizeOf {
  std::size_t operator()(const OperatorControl& message) const {
    std::size_t size = header_bytes + presence_flags_bytes + u64_bytes;
    size += message.controller ? controller_bytes : 0;
    size += message.client_user_data ? string_size(message.client_user_data->text) : 0;
    size += message.returned_ack ? ack_pair_bytes : 0;
    size += 1 + message.sender_faults.size() * fault_bytes;
    return size;
  }
  std::size_t operator()(const StreamerFeedback& message) const {
    std::size_t size = header_bytes + presence_flags_bytes + u64_bytes;
    size += 1 + message.receiver_faults.size() * fault_bytes;
    size += message.latency_ms ? u64_bytes : 0;
    size += 1;
    for (const std::string& camera : message.missing_cameras) {
      size += string_size(camera);
    }
    if (message.vehicle_data) {
      size += (message.vehicle_data->pos ? position_bytes : 0) + string_size(message.vehicle_data->user_data.text);
    }
    size += message.vehicle_data_age ? u64_bytes : 0;
    size += message.last_remote_input ? controller_bytes : 0;
    return size;
  }
  std::size_t operator()(const VideoFrame& message) const {
    // The encoded picture dominates; the SEI pair rides inside it as metadata.
    return header_bytes + string_size(message.camera) + u64_bytes + (message.sei ? ack_pair_bytes : 0) +
           message.size_bytes;
  }
  std::size_t operator()(const Ping&) const { return header_bytes + 2 * u64_bytes; }
  std::size_t operator()(const Pong&) const { return header_bytes + 2 * u64_bytes; }
};

}  // namespace

std::size_t wire_size_bytes(const LinkMessage& message) { return std::visit(SizeOf{}, message); }

}  // namespace ocp
