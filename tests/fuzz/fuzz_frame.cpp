// libFuzzer target: the frame decoder. The first input byte picks the chunk size and the
// second the payload limit; the rest is the stream. Property: chunked decoding reports exactly
// the events of one-shot decoding, `put` never over-consumes, and need_more consumes all.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/frame.hpp"

namespace {

struct Event {
  ocp::FrameEvent::Kind kind;
  std::string payload;
  std::uint32_t declared_length;
  bool operator==(const Event&) const = default;
};

void feed(ocp::FrameDecoder& decoder, std::string_view input, std::vector<Event>& events) {
  while (true) {
    ocp::FrameEvent event;
    const std::size_t consumed = decoder.put(input, event);
    if (consumed > input.size()) __builtin_trap();
    input.remove_prefix(consumed);
    if (event.kind == ocp::FrameEvent::Kind::need_more) {
      if (!input.empty()) __builtin_trap();
      return;
    }
    events.push_back({event.kind, std::string(event.payload), event.declared_length});
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t chunk = 1 + data[0] % 64;
  const std::size_t limit = data[1] < 128 ? data[1] : ocp::max_payload_bytes;
  const std::string_view stream(reinterpret_cast<const char*>(data + 2), size - 2);

  ocp::FrameDecoder whole_decoder(limit);
  std::vector<Event> whole;
  feed(whole_decoder, stream, whole);

  ocp::FrameDecoder chunked_decoder(limit);
  std::vector<Event> chunked;
  for (std::size_t at = 0; at < stream.size(); at += chunk) {
    const std::string copy(stream.substr(at, chunk));  // views must not outlive their chunk
    feed(chunked_decoder, copy, chunked);
  }
  if (whole != chunked) __builtin_trap();
  if (whole_decoder.finish().ok() != chunked_decoder.finish().ok()) __builtin_trap();
  if (whole_decoder.mid_frame() == whole_decoder.finish().ok()) __builtin_trap();

  for (const Event& event : whole) {
    if (event.kind == ocp::FrameEvent::Kind::frame) {
      std::string framed;
      if (!ocp::append_frame(event.payload, framed, limit).ok()) __builtin_trap();
    }
  }
  return 0;
}
