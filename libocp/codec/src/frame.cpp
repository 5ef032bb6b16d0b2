#include "ocp/frame.hpp"

#include <algorithm>
#include <limits>

namespace ocp {

void append_length_prefix(std::uint32_t length, std::string& out) {
  char header[frame_header_bytes];
  for (std::size_t index = 0; index < frame_header_bytes; ++index) {
    header[index] = static_cast<char>((length >> (8 * index)) & 0xFFu);  // little-endian (SPEC §2)
  }
  out.append(header, frame_header_bytes);
}

std::optional<std::uint32_t> read_length_prefix(std::string_view bytes) {
  if (bytes.size() < frame_header_bytes) return std::nullopt;
  std::uint32_t length = 0;
  for (std::size_t index = 0; index < frame_header_bytes; ++index) {
    length |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[index])) << (8 * index);
  }
  return length;
}

FrameDecoder::FrameDecoder(std::size_t payload_limit_bytes)
    : payload_limit_bytes_(payload_limit_bytes) {}

std::size_t FrameDecoder::put(std::string_view input, FrameEvent& event) {
  event = FrameEvent{};
  if (buffer_delivered_) {  // the previous payload's lifetime ends with this call
    buffer_.clear();
    buffer_delivered_ = false;
  }
  std::size_t consumed = 0;
  while (consumed < input.size()) {
    const std::string_view rest = input.substr(consumed);
    switch (state_) {
      case State::header: {
        const std::size_t take = std::min(frame_header_bytes - header_filled_, rest.size());
        std::copy_n(rest.data(), take, header_ + header_filled_);
        header_filled_ += take;
        consumed += take;
        if (header_filled_ < frame_header_bytes) break;
        header_filled_ = 0;
        length_ = *read_length_prefix(std::string_view(header_, frame_header_bytes));
        remaining_ = length_;
        if (length_ > payload_limit_bytes_) {
          state_ = State::drain;
        } else if (length_ == 0) {
          event.kind = FrameEvent::Kind::frame;
          event.payload = std::string_view();
          return consumed;
        } else {
          state_ = State::payload;
        }
        break;
      }
      case State::payload: {
        if (buffer_.empty() && rest.size() >= remaining_) {
          // The whole payload is in this input: hand it out without copying.
          event.kind = FrameEvent::Kind::frame;
          event.payload = rest.substr(0, remaining_);
          consumed += remaining_;
          remaining_ = 0;
          state_ = State::header;
          return consumed;
        }
        const std::size_t take = std::min(remaining_, rest.size());
        if (buffer_.empty()) buffer_.reserve(length_);
        buffer_.append(rest.data(), take);
        consumed += take;
        remaining_ -= take;
        if (remaining_ == 0) {
          event.kind = FrameEvent::Kind::frame;
          event.payload = buffer_;
          buffer_delivered_ = true;
          state_ = State::header;
          return consumed;
        }
        break;
      }
      case State::drain: {
        const std::size_t take = std::min(remaining_, rest.size());
        consumed += take;
        remaining_ -= take;
        if (remaining_ == 0) {
          event.kind = FrameEvent::Kind::oversized_dropped;
          event.declared_length = length_;
          state_ = State::header;
          return consumed;
        }
        break;
      }
    }
  }
  return consumed;
}

Status FrameDecoder::finish() const {
  const auto truncated = [](std::string detail) {
    return Error{make_error_code(PeerError::truncated_frame), std::move(detail)};
  };
  switch (state_) {
    case State::header:
      if (header_filled_ == 0) return Ok{};
      return truncated("stream ended inside a frame header: " +
                       std::to_string(frame_header_bytes - header_filled_) + " of " +
                       std::to_string(frame_header_bytes) + " header bytes missing");
    case State::payload:
      return truncated("stream ended inside a " + std::to_string(length_) + "-byte payload: " +
                       std::to_string(remaining_) + " payload bytes missing");
    case State::drain:
      return truncated("stream ended while draining an oversized " + std::to_string(length_) +
                       "-byte frame: " + std::to_string(remaining_) + " bytes missing");
  }
  return Ok{};
}

bool FrameDecoder::mid_frame() const { return state_ != State::header || header_filled_ != 0; }

void FrameDecoder::reset() {
  state_ = State::header;
  header_filled_ = 0;
  length_ = 0;
  remaining_ = 0;
  buffer_.clear();
  buffer_delivered_ = false;
}

Status append_frame(std::string_view payload, std::string& out, std::size_t payload_limit_bytes) {
  const std::size_t limit =
      std::min<std::size_t>(payload_limit_bytes, std::numeric_limits<std::uint32_t>::max());
  if (payload.size() > limit) {
    return Error{make_error_code(LocalError::frame_too_large),
                 "payload of " + std::to_string(payload.size()) + " bytes exceeds the limit of " +
                     std::to_string(limit) + " bytes"};
  }
  append_length_prefix(static_cast<std::uint32_t>(payload.size()), out);
  out.append(payload);
  return Ok{};
}

}  // namespace ocp
