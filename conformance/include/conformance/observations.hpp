#pragma once
// The facts cases grade, read off a wire log: pairs sent, responses received, connections.
//
// The window rule (applied here, once, for every vehicle case): a case grades what the client
// sent on a connection from the client's first control message on that connection onward.
// Responses the client wrote before it had read a control message belong to vehicle/3.3/4
// (and, after a reconnect, to the stale-pair checks of vehicle/3.1/*), never to other cases.
// From the Streamer's side, a response is "before control" when
//  * no control frame had been sent on its connection when it arrived, or
//  * it precedes, in the connection's byte order, the client's first echo of a pair sent on
//    that connection: such a response was written before the client had read our first frame
//    and crossed it on the wire. On a slow machine it can even arrive in the same read as that
//    first echo, with the same time stamp, which is why the order, not the time, decides.
// A connection on which the client never echoes a sent pair has no crossing allowance: its
// window opens at the first control frame sent on it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "conformance/wire_log.hpp"

namespace ocp::conformance {

struct SentPair {
  std::int64_t time_us = 0;
  AckPair ack;
};

struct Response {
  std::int64_t time_us = 0;
  std::optional<AckPair> ack;  // nullopt: drained, or did not decode
  bool drained = false;
  std::uint32_t length_prefix = 0;
  std::string_view payload;  // points into the wire log
};

struct Observations {
  std::vector<SentPair> sent;
  std::vector<Response> responses;       // in the window (see above): what cases grade
  std::vector<Response> before_control;  // written before the client read a control message
  // Every response, in or out of the window, in arrival order: for the rules that hold for
  // every frame the client sends (framing, the response schema).
  std::vector<Response> all_responses;
  std::vector<std::int64_t> opened_us;
  std::vector<std::string> close_codes;  // every close, in order ("peer.read_timeout", …)
  std::vector<std::int64_t> closed_us;

  // Entries at or after `since_us`; the window is worked out on the whole log first, so a
  // `since_us` inside a connection does not move that connection's window.
  static Observations from(const std::vector<WireLogEntry>& entries, std::int64_t since_us = 0);

  // Index in `sent` of the pair `ack` (exact u64 + u32 match), or -1: never sent.
  std::int64_t find_sent(const AckPair& ack) const;
  // Index in `sent` of the last pair sent at or before `time_us`, or -1.
  std::int64_t latest_sent_before(std::int64_t time_us) const;
  // Responses (in the window) that decoded to a pair.
  std::size_t responses_with_pair() const;
  // Was the connection closed by a peer error (read timeout, malformed, …)?
  bool closed_by_peer_error() const;
};

// Percentile (0..100) of a list of values (sorted copy); 0 for an empty list.
double percentile(std::vector<double> values, double p);

}  // namespace ocp::conformance
