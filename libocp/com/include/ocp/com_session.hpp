#pragma once
// The com channel's sessions (issue #36): a handshake to which both ends contribute fresh
// randomness, so that no datagram of another session (an earlier run, an evicted session, a
// capture) ever authenticates, whatever either end remembers or forgets.
//
//   Player → Streamer   hello    (kind 6)  session S, body: nonce_p (32 random bytes)
//   Streamer → Player   welcome  (kind 7)  session S, body: nonce_p ‖ nonce_s (32 fresh random bytes)
//
// Both are tagged with the long-term key (the key file). Each end then derives the session's
// two keys with HKDF-SHA256 (OpenSSL 3): salt nonce_p ‖ nonce_s, input the long-term key, info
// "ocp com v2 to_streamer" / "ocp com v2 to_player". Every data datagram of session S is tagged
// with its direction's session key, and checked against the session's replay window.
//
// The Streamer moves its peer (where video and feedback go) only when the first data datagram
// under a new session's key arrives: a completed handshake proves the sender knew the long-term
// key *and* saw this Streamer's fresh nonce. A replayed hello costs the Streamer one welcome and
// one of `max_pending` slots, never the current session. A datagram that is rejected changes no
// state at all. The Player sends hellos until a welcome answers (UdpComEndpoint retries them),
// and starts a new handshake when it has heard nothing authentic for a while (the Streamer
// restarted, or the path changed).
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ocp/com_datagram.hpp"

namespace ocp::com {

inline constexpr std::size_t nonce_bytes = 32;
using Nonce = std::array<std::uint8_t, nonce_bytes>;

struct SessionKeys {
  ComKey to_streamer;
  ComKey to_player;
};
// HKDF-SHA256 over the long-term key, salted with both nonces.
SessionKeys derive_session_keys(const ComKey& long_term, const Nonce& player, const Nonce& streamer);

std::string seal_hello(const ComKey& long_term, std::uint64_t session, const Nonce& player);
std::string seal_welcome(const ComKey& long_term, std::uint64_t session, const Nonce& player, const Nonce& streamer);

struct SessionCounters {
  std::uint64_t hellos = 0, welcomes = 0;      // authentic handshake datagrams received
  std::uint64_t handshakes = 0;                // sessions established
  std::uint64_t unknown_session = 0;           // data of no session this end has keys for: dropped
  std::uint64_t stale_handshake = 0;           // a welcome for no hello of ours (replayed): dropped
};

// One end of the channel: its handshake, its current session's sealer and opener.
class ComSessionEnd {
 public:
  using Random = std::function<void(std::uint8_t* bytes, std::size_t count)>;
  // `streamer_side`: the responder (accepts hellos, OperatorControl and Ping).
  ComSessionEnd(ComKey long_term, bool streamer_side, Random random);
  ~ComSessionEnd();

  // Player: a hello to send. `fresh`: a new handshake (new session, new nonce); otherwise the
  // pending one again (a retry), or a new one when none is pending.
  std::string hello(bool fresh);
  bool handshake_pending() const { return pending_hello_.has_value(); }

  struct Received {
    Drop drop = Drop::none;
    std::optional<LinkMessage> message;
    bool established = false;             // this datagram completed a handshake (a new session)
    std::optional<std::string> reply;     // Streamer: the welcome to send back to the sender
  };
  Received receive(std::span<const std::uint8_t> datagram);

  // False while no session is established (nothing is sent), or the message is too large.
  bool seal(const LinkMessage& message, std::vector<std::string>& out);
  bool established() const { return current_ != nullptr; }
  std::uint64_t session() const;

  // The current session's opener counters plus every earlier session's, and the handshake's.
  OpenerCounters counters() const;
  const SessionCounters& session_counters() const { return session_counters_; }

  static constexpr std::size_t max_pending = 4;   // Streamer: handshakes answered, not completed

 private:
  struct Session;
  struct Pending {
    std::uint64_t session = 0;
    Nonce player{}, streamer{};
    SessionKeys keys;
  };
  Received handshake(std::span<const std::uint8_t> datagram);
  Received reject(Drop drop);
  void adopt(std::uint64_t session, const SessionKeys& keys, std::unique_ptr<DatagramOpener> opener);

  ComKey long_term_;
  bool streamer_side_;
  Random random_;
  std::unique_ptr<Session> current_;
  std::vector<Pending> pending_;                 // Streamer side
  struct PendingHello {
    std::uint64_t session = 0;
    Nonce player{};
  };
  std::optional<PendingHello> pending_hello_;    // Player side
  OpenerCounters earlier_;                       // counters of sessions replaced
  OpenerCounters own_;                           // drops decided before any session's opener
  SessionCounters session_counters_;
};

}  // namespace ocp::com
