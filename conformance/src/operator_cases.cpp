// `ocp_conformance operator` (SPEC §4.1, §4.2, §2): the suite plays the Player on its :4001
// operator API, with a real Streamer and the reference vehicle client in-process behind it,
// and grades the operator client: valid frames, the latest pair per vehicle returned
// unchanged, byte-exact above 2^53.
#include <limits>
#include <map>

#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

// Pairs the Player published for our vehicle, and the pairs the client returned.
struct OperatorObservations {
  std::vector<SentPair> published;
  std::vector<SentPair> returned;
  std::size_t inbound = 0, drained = 0;
};

OperatorObservations observe(const std::vector<WireLogEntry>& entries) {
  OperatorObservations o;
  for (const WireLogEntry& e : entries) {
    if (e.kind == WireEntryKind::out) {
      if (auto shared = decode_vehicle_ocp_shared(e.text)) {
        const auto it = shared->vehicle_feedback.find(host_vehicle_name);
        if (it != shared->vehicle_feedback.end()) o.published.push_back({e.time_us, it->second.ack});
      }
    } else if (e.kind == WireEntryKind::in) {
      ++o.inbound;
      o.drained += e.drained;
      if (auto data = decode_client_ocp_shared(e.text)) {
        const auto it = data->client_user_data.find(host_vehicle_name);
        if (it != data->client_user_data.end() && it->second.ack_time_returned && it->second.ack_time_mac_returned) {
          o.returned.push_back({e.time_us, AckPair{*it->second.ack_time_returned, *it->second.ack_time_mac_returned}});
        }
      }
    }
  }
  return o;
}

std::int64_t find_published(const OperatorObservations& o, const AckPair& pair) {
  for (std::size_t i = o.published.size(); i-- > 0;) {
    if (o.published[i].ack == pair) return static_cast<std::int64_t>(i);
  }
  return -1;
}

Outcome valid_frames(CaseContext& ctx) {
  Outcome outcome;
  if (!connected(ctx, outcome)) return outcome;
  ctx.run_for(milliseconds(1500));
  const OperatorObservations o = observe(ctx.entries());
  const Observations obs = Observations::from(ctx.entries());
  const std::string counts = fmt::format("{} frames from the client, {} oversized (drained)", o.inbound, o.drained);
  if (obs.closed_by_peer_error()) return failed(counts + "; the Player closed the connection: " + last_close(obs));
  if (o.drained > 0) return failed(counts);
  if (o.inbound == 0) return failed(counts + "; nothing sent in 1.5 s");
  return ok(counts);
}

Outcome returns_latest_pair(CaseContext& ctx) {
  Outcome outcome;
  if (!connected(ctx, outcome)) return outcome;
  ctx.run_for(milliseconds(1500));
  const OperatorObservations o = observe(ctx.entries());
  std::size_t stale = 0, altered = 0;
  std::vector<AckPair> altered_pairs;
  for (const SentPair& r : o.returned) {
    const std::int64_t index = find_published(o, r.ack);
    if (index < 0) {
      ++altered;
      altered_pairs.push_back(r.ack);
      continue;
    }
    // Behind = how long before this return a newer pair had already been published.
    for (std::size_t i = static_cast<std::size_t>(index) + 1; i < o.published.size() && o.published[i].time_us <= r.time_us; ++i) {
      if (!(o.published[i].ack == r.ack)) {
        if (r.time_us - o.published[i].time_us > 500'000) ++stale;
        break;
      }
    }
  }
  const std::string counts = fmt::format("{} VehicleOcpShared frames, {} returned pairs, {} altered, {} stale (> 500 ms behind)",
                                         o.published.size(), o.returned.size(), altered, stale);
  if (altered > 0) return failed(counts + "; never published: " + list_pairs(altered_pairs));
  if (o.returned.size() < 10) return failed(counts + "; fewer than 10 returned pairs in 1.5 s");
  if (static_cast<double>(stale) > 0.05 * static_cast<double>(o.returned.size())) return failed(counts);
  return ok(counts);
}

}  // namespace

std::vector<VehicleCase> operator_cases() {
  StreamerSetup op;
  op.operator_side = true;
  StreamerSetup big = op;
  big.ack_time_offset = std::numeric_limits<std::uint64_t>::max() - 3'000'000;
  std::vector<VehicleCase> cases;
  cases.push_back({{{"operator/2/1", "client frames are valid and within 16 KiB", "SPEC §2, §4.2",
                     "\"Frame = uint32 little-endian payload length, then that many bytes of UTF-8 JSON. Maximum payload: 16 384 bytes\" (same framing as §2 on :4001)",
                     Tier::must, milliseconds(10'000),
                     {"OK: the client sends frames in 1.5 s, none oversized, the Player never closes the connection for bad input"},
                     "broken_client.py op-oversized"},
                    valid_frames},
                   op});
  cases.push_back({{{"operator/4.2/1", "returns the latest pair per vehicle, unchanged", "SPEC §4.1, §4.2",
                     "\"ack_time/ack_time_mac are the latest pair extracted from that vehicle's video SEI; the client must echo them back.\" — "
                     "\"TCP clients and plugins must fill ack_time_returned/ack_time_mac_returned\"",
                     Tier::must, milliseconds(10'000),
                     {"OK: ≥ 10 returned pairs in 1.5 s, every one published by the Player, ≤ 5 % more than 500 ms behind"},
                     "broken_client.py op-corrupt (or op-stale)"},
                    returns_latest_pair},
                   op});
  cases.push_back({{{"operator/4.2/2", "returned pairs above 2^53 survive byte-exact", "SPEC §2",
                     "\"Integers ack_time (u64) and ack_time_mac (u32) must survive byte-exact: never pass them through a double.\"",
                     Tier::must, milliseconds(10'000),
                     {"OK: with ack_time near 2^64-1, every returned pair is exactly one the Player published"},
                     "broken_client.py op-double"},
                    returns_latest_pair},
                   big});
  return cases;
}

}  // namespace ocp::conformance
