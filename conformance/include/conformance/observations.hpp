#pragma once
// The facts cases grade, read off a wire log: pairs sent, responses received, connections.
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
  std::optional<AckPair> ack;      // nullopt: drained, or did not decode
  bool drained = false;
  std::uint32_t length_prefix = 0;
  std::string_view payload;        // points into the wire log
};

struct Observations {
  std::vector<SentPair> sent;
  std::vector<Response> responses;
  std::vector<std::int64_t> opened_us;
  std::vector<std::string> close_codes;   // every close, in order ("peer.read_timeout", …)
  std::vector<std::int64_t> closed_us;

  // Entries at or after `since_us`.
  static Observations from(const std::vector<WireLogEntry>& entries, std::int64_t since_us = 0);

  // Index in `sent` of the pair `ack` (exact u64 + u32 match), or -1: never sent.
  std::int64_t find_sent(const AckPair& ack) const;
  // Index in `sent` of the last pair sent at or before `time_us`, or -1.
  std::int64_t latest_sent_before(std::int64_t time_us) const;
  // Responses that decoded to a pair.
  std::size_t responses_with_pair() const;
  // Was the connection closed by a peer error (read timeout, malformed, …)?
  bool closed_by_peer_error() const;
};

// Percentile (0..100) of a list of values (sorted copy); 0 for an empty list.
double percentile(std::vector<double> values, double p);

}  // namespace ocp::conformance
