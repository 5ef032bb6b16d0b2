#pragma once
// The com channel over UDP (issue #22), sans-IO: what a LinkMessage looks like as datagrams,
// and the checks every received datagram passes before it becomes a LinkMessage again. No
// socket and no clock here: the app layer (apps/sim_app/src/udp_com_link.cpp) moves the bytes.
//
// One datagram (at most 1 200 bytes, all integers little-endian):
//
//   0  magic "OC"        2  version (2)        3  kind (LinkKind; 6 and 7: the handshake, com_session.hpp)
//   4  session  u64      the Player's random id for this session (com_session.hpp): a new one per handshake
//   12 sequence u64      per session, from 1, one per datagram: checked against a replay window
//   20 message  u32      per session, from 1, one per LinkMessage: groups its fragments
//   24 fragment u16      index of this piece        26 fragments u16  pieces of the message
//   28 body length u16   30 reserved u16 (0)
//   32 body              ≤ 1 136 bytes: the piece of the message's encoding
//   …  tag               HMAC-SHA256(key, header + body), 32 bytes
//
// A message longer than one body is cut into pieces; every piece but the last is full. A
// message that lost a piece is lost (as RTP video is): at most `max_partial_messages` wait for
// their missing pieces; starting another evicts the oldest, counted in `messages_lost`.
// A VideoFrame's encoding is padded to its size_bytes, so the wire carries the frame's bytes.
//
// Who may send what: Player → Streamer carries OperatorControl and Ping, Streamer → Player the
// rest. An opener refuses the other direction's kinds, so a datagram reflected back to its
// sender (same key on both sides) is not accepted.
#include <array>
#include <bitset>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/link_messages.hpp"

namespace ocp::com {

inline constexpr std::size_t max_datagram_bytes = 1200;
inline constexpr std::size_t header_bytes = 32;
inline constexpr std::size_t tag_bytes = 32;
inline constexpr std::size_t max_body_bytes = max_datagram_bytes - header_bytes - tag_bytes;   // 1 136
inline constexpr std::size_t max_fragments = 256;
inline constexpr std::size_t max_message_bytes = max_fragments * max_body_bytes;             // ~290 kB
inline constexpr std::size_t max_partial_messages = 8;
inline constexpr std::size_t replay_window = 1024;
// 2: sessions with keys of their own, from a handshake (com_session.hpp, issue #36).
inline constexpr std::uint8_t protocol_version = 2;
// A key file's bytes are the key (apps/sim_app/src/com_key_file.cpp checks this range).
inline constexpr std::size_t min_key_bytes = 16;
inline constexpr std::size_t max_key_bytes = 1024;

enum class LinkKind : std::uint8_t { operator_control = 1, streamer_feedback, video_frame, ping, pong };
LinkKind kind_of(const LinkMessage& message);
// True for the kinds the Player sends (OperatorControl, Ping).
bool travels_to_streamer(LinkKind kind);

// The body codec: a message as bytes and back. Pure; decode never trusts a length and returns
// nullopt for anything malformed (bad length, unknown fault, non-finite axis, invalid JSON …).
std::string encode_body(const LinkMessage& message);
std::optional<LinkMessage> decode_body(LinkKind kind, std::string_view body);

// The key: empty only with --com-insecure (loopback), which MACs with an empty key — that
// authenticates nothing, it only keeps one code path.
using ComKey = std::vector<std::uint8_t>;

// Cuts messages into sealed datagrams.
class DatagramSealer {
 public:
  DatagramSealer(ComKey key, std::uint64_t session);
  // Appends the message's datagrams (each ≤ max_datagram_bytes) to `out`. A message whose
  // encoding exceeds max_message_bytes is not sent (false); a VideoFrame's padding is capped.
  bool seal(const LinkMessage& message, std::vector<std::string>& out);
  std::uint64_t session() const { return session_; }

 private:
  ComKey key_;
  std::uint64_t session_;
  std::uint64_t next_sequence_ = 1;
  std::uint32_t next_message_ = 1;
};

enum class Drop : std::uint8_t {
  none,            // accepted (a piece of a message, or a whole one)
  truncated,       // shorter than header + tag, or than the body length says
  oversized,       // longer than max_datagram_bytes, or than the body length says
  bad_header,      // wrong magic, version, reserved, kind, fragment numbers
  bad_mac,         // the tag does not match: another key, or tampered
  replayed,        // sequence already seen in its session, or too old for its window
  wrong_direction, // a kind the other side sends (a reflected datagram)
  malformed,       // authenticated, but the reassembled body does not decode
};
std::string_view drop_name(Drop drop);

struct OpenerCounters {
  std::uint64_t accepted = 0;        // datagrams that passed every check
  std::uint64_t messages = 0;        // LinkMessages delivered
  std::uint64_t truncated = 0, oversized = 0, bad_header = 0, bad_mac = 0, replayed = 0,
                wrong_direction = 0, malformed = 0;
  std::uint64_t messages_lost = 0;   // partial messages evicted before their last piece
  std::uint64_t sessions = 0;        // sessions adopted (1 + the peer's restarts)
  std::uint64_t dropped() const {
    return truncated + oversized + bad_header + bad_mac + replayed + wrong_direction + malformed;
  }
  OpenerCounters& operator+=(const OpenerCounters& other);
};

// The 32-byte header of a datagram, and the HMAC-SHA256 tag of `length` bytes under `key`
// (the handshake's datagrams, com_session.cpp, use the same layout).
std::string datagram_header(std::uint8_t kind, std::uint64_t session, std::uint64_t sequence, std::uint32_t message,
                            std::size_t fragment, std::size_t fragments, std::size_t body_length);
// A little-endian field of `bytes` bytes at `at` (the caller checked the length).
std::uint64_t datagram_field(std::span<const std::uint8_t> datagram, std::size_t at, std::size_t bytes);
std::array<std::uint8_t, tag_bytes> datagram_tag(const ComKey& key, const std::uint8_t* data, std::size_t length);

// A sliding window over sequence numbers (RFC 4303 §3.4.3 style): a number is new once.
class ReplayWindow {
 public:
  // True (and remembered) when `sequence` was not seen and is not older than the window.
  bool check_and_mark(std::uint64_t sequence);
  // Read-only check, before the MAC is verified the window must not change.
  bool is_fresh(std::uint64_t sequence) const;
  void reset();

 private:
  std::bitset<replay_window> seen_;   // bit sequence % window
  std::uint64_t highest_ = 0;
};

// Checks and reassembles received datagrams. State is bounded: at most `remembered_sessions`
// sessions, each with its replay window (so a replayed datagram of the peer's previous run is
// still caught by that run's window, and the current run is not disturbed by it), and at most
// max_partial_messages partial messages (of the current session).
class DatagramOpener {
 public:
  // `to_streamer`: this opener is the Streamer's (accepts OperatorControl and Ping).
  DatagramOpener(ComKey key, bool to_streamer);
  struct Opened {
    Drop drop = Drop::none;
    std::optional<LinkMessage> message;   // a whole message, when this piece completed one
    bool new_session = false;             // the peer (re)started: first datagram of an unknown session
  };
  Opened open(std::span<const std::uint8_t> datagram);
  const OpenerCounters& counters() const { return counters_; }

  static constexpr std::size_t remembered_sessions = 8;

 private:
  struct Partial {
    std::uint32_t message = 0;
    LinkKind kind{};
    std::uint16_t fragments = 0;
    std::uint16_t received = 0;
    std::size_t last_length = 0;
    std::vector<bool> have;
    std::string bytes;
  };
  Opened reject(Drop drop);
  Opened finish(LinkKind kind, std::string_view body, bool new_session);
  Opened add_fragment(LinkKind kind, std::uint32_t message, std::uint16_t index, std::uint16_t fragments,
                      std::string_view body, bool new_session);
  // The session's window (adopting a session not seen before); partials from another session
  // are dropped.
  ReplayWindow& window_for(std::uint64_t session, bool& new_session);

  ComKey key_;
  bool to_streamer_;
  struct Session {
    std::uint64_t id = 0;
    ReplayWindow window;
  };
  std::vector<Session> sessions_;   // the most recently used last
  std::vector<Partial> partials_;
  OpenerCounters counters_;
};

}  // namespace ocp::com
