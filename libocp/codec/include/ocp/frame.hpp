#pragma once
// Length-prefixed framing shared by both TCP APIs (SPEC §2):
//   uint32 little-endian payload length, then that many bytes of UTF-8 JSON.
//
// FrameDecoder is push-based (like Beast's basic_parser): call `put` with whatever bytes
// arrived; it consumes some of them and reports at most one event per call. Call `put`
// again with the unconsumed rest until it reports need_more (or let `put_all` run that loop).
// Inbound frames longer than the limit are drained (exactly `length` bytes are skipped) and
// reported, not treated as errors.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "ocp/error.hpp"

namespace ocp {

inline constexpr std::size_t max_payload_bytes = 16384;  // 16 KiB
inline constexpr std::size_t frame_header_bytes = 4;

// The length prefix on its own: the one encoder and the one decoder of it. FrameDecoder,
// append_frame, the framing diagnosis, the raw conformance writes and their WireFrame events,
// and the vehicle client's deliberately oversized frames all go through these two.
//
// Appends the 4 bytes declaring `length` to `out`. Checks no limit — append_frame does, for
// protocol frames; a bare header is for what must break the limit on purpose.
void append_length_prefix(std::uint32_t length, std::string& out);
// The length the first 4 bytes of `bytes` declare; nullopt when there are fewer than 4.
std::optional<std::uint32_t> read_length_prefix(std::string_view bytes);

struct FrameEvent {
  enum class Kind {
    need_more,          // every given byte was consumed; no complete event yet
    frame,              // `payload` holds one complete payload
    oversized_dropped,  // a frame of `declared_length` bytes (> limit) was fully drained
  };
  Kind kind = Kind::need_more;
  // For `frame`: valid until the next call to put() or reset(). Points either into the
  // caller's input (zero-copy when a frame arrives whole) or into the decoder's buffer.
  std::string_view payload;
  std::uint32_t declared_length = 0;
};

class FrameDecoder {
 public:
  explicit FrameDecoder(std::size_t payload_limit_bytes = max_payload_bytes);

  // Consumes bytes from `input` until one event completes or input runs out.
  // Returns the number of bytes consumed; `event` says what happened.
  std::size_t put(std::string_view input, FrameEvent& event);

  // The deframing loop every reader shares: feeds all of `input` through put() and hands each
  // event on, in order — on_frame(payload) for a complete payload (valid during the call only),
  // on_oversized(declared_length) for a drained one. Each returns whether to go on; after false
  // (say the handler closed the connection) the rest of `input` is left unread. Inline, so a
  // reader's handlers cost no indirect call.
  template <typename OnFrame, typename OnOversized>
  void put_all(std::string_view input, OnFrame&& on_frame, OnOversized&& on_oversized) {
    while (!input.empty()) {
      FrameEvent event;
      input.remove_prefix(put(input, event));
      switch (event.kind) {
        case FrameEvent::Kind::frame:
          if (!on_frame(event.payload)) return;
          break;
        case FrameEvent::Kind::oversized_dropped:
          if (!on_oversized(event.declared_length)) return;
          break;
        case FrameEvent::Kind::need_more:
          return;  // put() consumed every byte
      }
    }
  }
  // The same for a reader that ignores drained frames.
  template <typename OnFrame>
  void put_all(std::string_view input, OnFrame&& on_frame) {
    put_all(input, std::forward<OnFrame>(on_frame), [](std::uint32_t) { return true; });
  }

  // Call at end of stream. Ok between frames; truncated_frame (with how many bytes of which
  // part were missing) when the stream ended inside a header, payload or drained frame.
  Status finish() const;

  bool mid_frame() const;
  void reset();

 private:
  enum class State { header, payload, drain };
  std::size_t payload_limit_bytes_;
  State state_ = State::header;
  char header_[frame_header_bytes] = {};
  std::size_t header_filled_ = 0;
  std::uint32_t length_ = 0;
  std::size_t remaining_ = 0;  // payload or drain bytes still expected
  std::string buffer_;         // partial payload, only when a frame arrives in pieces
  bool buffer_delivered_ = false;  // buffer_ holds the last delivered payload: clear on next put
};

// Appends one frame (header + payload) to `out`. Fails with frame_too_large, leaving `out`
// untouched, when the payload exceeds `payload_limit_bytes`.
Status append_frame(std::string_view payload, std::string& out,
                    std::size_t payload_limit_bytes = max_payload_bytes);

}  // namespace ocp
