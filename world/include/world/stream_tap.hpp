#pragma once
// StreamTap: a ByteStream decorator that watches the bytes a vehicle client receives and
// decodes the control messages in them with the libocp codec, so a test can assert what
// actually reached the vehicle (not only what the Streamer meant to send). Bytes pass through
// unchanged and in the same chunks.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "ocp/byte_stream.hpp"
#include "ocp/frame.hpp"
#include "ocp/messages.hpp"
#include "ocp/time.hpp"

namespace ocp {

class Executor;

class StreamTap {
 public:
  explicit StreamTap(const Executor& executor) : executor_(executor) {}

  // Wraps `inner`: the returned stream behaves like `inner` for its user.
  std::shared_ptr<ByteStream> wrap(std::shared_ptr<ByteStream> inner);

  std::uint64_t control_messages() const { return control_messages_; }
  std::uint64_t undecodable_frames() const { return undecodable_frames_; }
  // The latest control message received (nullopt before the first).
  const std::optional<OcpControlMessage>& last_control() const { return last_control_; }
  std::optional<SimTime> last_control_time() const { return last_control_time_; }

 private:
  class Stream;
  void observe(std::string_view bytes);

  const Executor& executor_;
  FrameDecoder decoder_;
  std::uint64_t control_messages_ = 0;
  std::uint64_t undecodable_frames_ = 0;
  std::optional<OcpControlMessage> last_control_;
  std::optional<SimTime> last_control_time_;
};

}  // namespace ocp
