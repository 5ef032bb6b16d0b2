#pragma once
// Telling a peer that does not speak OCP framing from one that sent a big frame. Every OCP
// frame starts with a uint32 LE length ≤ 16 KiB; text read as such a length is huge ("GET "
// reads as 542 393 671 bytes), so a first header with a non-zero top byte (≥ 16 MiB) is not
// an oversized frame but someone speaking something else: HTTP, plain text, JSON without the
// length prefix. Both ends use this: the Streamer (:4000) and the Player (:4001) about their
// clients, the vehicle client about its server.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ocp/frame.hpp"

namespace ocp {

// Declared lengths from here up have a non-zero top byte: no OCP peer sends them.
inline constexpr std::uint32_t implausible_frame_length = 0x0100'0000;  // 16 MiB

// The first bytes as a short quote: printable ASCII kept, others as '.', at most 8 characters
// then '…' ("GET / HT…").
std::string quote_first_bytes(std::string_view first_bytes);

// "this does not look like OCP framing (got 'GET / HT…': an HTTP client?)". The guess is
// HTTP (request or response), TLS, SSH, JSON without the length prefix, plain text, or else
// the declared length against the limit.
std::string describe_non_ocp_bytes(std::string_view first_bytes,
                                   std::size_t payload_limit_bytes = max_payload_bytes);

// Watches the first bytes of one connection. observe() returns the description once, as soon
// as 4 bytes declare an implausible length; afterwards diagnosis() keeps it (for the reason a
// connection is finally closed with). A plausible first header ends the watch.
// A server's sniffer (FramedConnection) takes lengths from implausible_frame_length up as
// implausible: below that a first frame is only oversized, drained like any other. The vehicle
// client is stricter — a server's first frame is a small control message, so one over the
// payload limit already means the peer is no OCP server — and says so with
// FramingSniffer(max_payload_bytes + 1).
class FramingSniffer {
 public:
  explicit FramingSniffer(std::uint32_t implausible_from = implausible_frame_length)
      : implausible_from_(implausible_from) {}

  std::optional<std::string> observe(std::string_view bytes);
  const std::optional<std::string>& diagnosis() const { return diagnosis_; }
  // The length the first header declared (nullopt until 4 bytes came).
  std::optional<std::uint32_t> declared_length() const { return read_length_prefix(first_bytes_); }

 private:
  std::uint32_t implausible_from_;
  std::string first_bytes_;
  bool done_ = false;
  std::optional<std::string> diagnosis_;
};

}  // namespace ocp
