// `ocp_conformance operator` (SPEC §2, §4, §7): the suite plays the Player on its :4001
// operator API, with real Streamers and the reference vehicle client in-process behind it,
// and grades the operator client. This file: the suite's order and the echo cases (valid
// frames, the latest pair per vehicle returned unchanged, byte-exact above 2^53, every control
// vehicle's pair once the client holds the source, the return delay distribution).
#include <rapidjson/document.h>

#include <algorithm>
#include <limits>

#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"
#include "operator_observations.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

Outcome valid_frames(CaseContext& context) {
  context.run_for(milliseconds(1500));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  const std::string counts = fmt::format("{} frames from the client, {} oversized (drained)",
                                         observed.client_frames_us.size(), observed.drained);
  if (observed.closed_by_peer_error())
    return failed(counts + "; the Player closed the connection: " + observed.close_codes.back());
  if (observed.drained > 0) return failed(counts);
  if (observed.client_frames_us.empty()) return failed(counts + "; nothing sent in 1.5 s");
  return ok(counts);
}

Outcome grade_pairs(const PairReturns& returns, const std::string& vehicle, std::size_t at_least) {
  const std::string counts = returns.describe(vehicle);
  if (!returns.altered.empty()) {
    return failed_with_cause(counts + "; never published for it: " + list_pairs(returns.altered), returns.altered,
                             returns.published);
  }
  if (returns.count < at_least) return failed(fmt::format("{}; fewer than {} returned pairs", counts, at_least));
  if (static_cast<double>(returns.stale) > 0.05 * static_cast<double>(returns.count)) return failed(counts);
  return ok(counts);
}

Outcome returns_pairs_over(CaseContext& context, milliseconds window) {
  context.run_for(window);
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  return grade_pairs(pair_returns(observed, host_vehicle_name), host_vehicle_name, 10);
}

// One connection held 10.5 s (issue #35): a client that freezes its returned pairs after a few
// seconds must not pass.
Outcome returns_latest_pair(CaseContext& context) { return returns_pairs_over(context, milliseconds(10'500)); }

// Once the client's data locked the tcp source the Player echoes nothing itself (SPEC §4.3):
// a vehicle whose pair the client leaves out has a broken latency loop.
Outcome returns_every_vehicle_pair(CaseContext& context) {
  context.run_for(milliseconds(1500));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  std::string actual;
  for (const HostedVehicle& vehicle : context.host().vehicles()) {
    if (vehicle.monitor) continue;
    const Outcome one = grade_pairs(pair_returns(observed, vehicle.name), vehicle.name, 10);
    if (one.verdict == Verdict::failed) return one;
    actual += (actual.empty() ? "" : "; ") + one.actual;
  }
  Outcome reordered = grade_reordered_vehicles(context);
  reordered.actual = actual + "; then " + reordered.actual;
  return reordered;
}

// INFO: how long after the Player first published a pair the client first returned it.
Outcome return_delay(CaseContext& context) {
  context.run_for(milliseconds(1500));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  const auto published = observed.published.find(host_vehicle_name);
  const auto returned = observed.returned.find(host_vehicle_name);
  std::vector<double> delays_ms;
  std::size_t pairs = 0;
  if (published != observed.published.end() && returned != observed.returned.end()) {
    std::vector<AckPair> seen;
    for (const SentPair& p : published->second) {
      if (std::find(seen.begin(), seen.end(), p.ack) != seen.end()) continue;
      seen.push_back(p.ack);
      ++pairs;
      for (const SentPair& back : returned->second) {
        if (back.time_us >= p.time_us && back.ack == p.ack) {
          delays_ms.push_back(static_cast<double>(back.time_us - p.time_us) / 1000.0);
          break;
        }
      }
    }
  }
  if (delays_ms.empty()) {
    return informational(fmt::format("{} pairs published, none returned: no delay to measure", pairs));
  }
  return informational(fmt::format(
      "{} of {} published pairs returned; delay from publication to return: median {:.1f} ms, p90 {:.1f} ms, "
      "p99 {:.1f} ms, max {:.1f} ms",
      delays_ms.size(), pairs, percentile(delays_ms, 50), percentile(delays_ms, 90), percentile(delays_ms, 99),
      percentile(delays_ms, 100)));
}

// operator/2/1 as a standing rule: every frame of every case is a JSON object ≤ 16 KiB.
std::optional<StandingFinding> client_frame_rule(const WireLogEntry& entry) {
  if (entry.drained)
    return StandingFinding{Verdict::failed,
                           fmt::format("an oversized frame (length prefix {} > 16 384)", entry.length_prefix)};
  rapidjson::Document doc;
  doc.Parse(entry.text.data(), entry.text.size());
  if (doc.HasParseError() || !doc.IsObject())
    return StandingFinding{Verdict::failed, "a frame that is not a JSON object"};
  return std::nullopt;
}

void add_operator_echo_cases(std::vector<VehicleCase>& cases) {
  const StreamerSetup op = operator_setup();
  StreamerSetup big = op;
  big.ack_time_offset = std::numeric_limits<std::uint64_t>::max() - ocp_ack_time_headroom_us;
  cases.push_back(
      {{{"operator/2/1",
         "client frames are valid and within 16 KiB",
         "SPEC §2, §4.2",
         "\"Frame = uint32 little-endian payload length, then that many bytes of UTF-8 JSON. Maximum payload: 16 384 "
         "bytes\" (same framing as §2 on :4001)",
         Tier::must,
         milliseconds(10'000),
         {"OK: the client sends frames in 1.5 s, none oversized, the Player never closes the connection for bad input; "
          "and every frame of every other case of the run is valid too (a standing rule: the first offending frame is "
          "named)"},
         "broken_client.py op-oversized; broken_client.py op-malformed; broken_client.py op-once-oversized (with "
         "operator/4.2/1)"},
        valid_frames,
        client_frame_rule},
       op});
  cases.push_back(
      {{{"operator/4.2/1",
         "returns the latest pair per vehicle, unchanged",
         "SPEC §4.1, §4.2",
         "\"ack_time/ack_time_mac are the latest pair extracted from that vehicle's video SEI; the client must echo "
         "them back.\" — "
         "\"TCP clients and plugins must fill ack_time_returned/ack_time_mac_returned\"",
         Tier::must,
         milliseconds(20'000),
         {"OK: over one connection held 10.5 s, ≥ 10 returned pairs, every one published by the Player, ≤ 5 % more "
          "than 500 ms behind"},
         "broken_client.py op-corrupt (or op-stale, op-tires)"},
        returns_latest_pair},
       op});
  cases.push_back({{{"operator/4.2/2",
                     "returned pairs above 2^53 survive byte-exact",
                     "SPEC §2",
                     "\"Integers ack_time (u64) and ack_time_mac (u32) must survive byte-exact: never pass them "
                     "through a double.\"",
                     Tier::must,
                     milliseconds(10'000),
                     {"OK: with ack_time near 2^64-1, every returned pair is exactly one the Player published"},
                     "broken_client.py op-double"},
                    [](CaseContext& context) { return returns_pairs_over(context, milliseconds(1500)); }},
                   big});
  cases.push_back(
      {{{"operator/4.2/6",
         "pair return delay distribution",
         "SPEC §5",
         "\"Echo (self, web view, plugin or TCP client) puts it into the next control message as returned pair.\" "
         "(the client's share of the measured latency)",
         Tier::info,
         milliseconds(10'000),
         {"INFORMATIONAL: median, p90, p99 and max of the delay from the Player's first publication of a pair to "
          "the client's first return of it, over 1.5 s"},
         "never fails (INFO)"},
        return_delay},
       op});
  cases.push_back(
      {{{"operator/4.3/2",
         "returns the pair of every control vehicle",
         "SPEC §4.3, §4.1, seed 003",
         "\"With no source, the Player itself echoes the SEI pair (self-echo)\" — \"The first source that sends client "
         "data "
         "to OCP becomes the locked source. Once locked, OCP only accepts data from that source.\" (so the locked "
         "client "
         "must return every control vehicle's pair)",
         Tier::must,
         milliseconds(10'000),
         {"OK: with two control vehicles and a monitor linked, ≥ 10 returned pairs in 1.5 s for each control vehicle, "
          "every one published for that vehicle, ≤ 5 % more than 500 ms behind; then, with the vehicles listed in "
          "another order every other frame (seed 004: a hashmap), each vehicle's own pair returned, never another's"},
         "broken_client.py op-active-only; broken_client.py op-by-position"},
        returns_every_vehicle_pair},
       fleet_setup()});
}

}  // namespace

std::vector<VehicleCase> operator_cases() {
  std::vector<VehicleCase> cases;
  add_operator_echo_cases(cases);
  add_operator_framing_cases(cases);
  add_operator_connection_cases(cases);
  add_operator_data_cases(cases);
  add_operator_product_shape_cases(cases);
  // Stable order by id (section, then number) whatever the files add.
  std::stable_sort(cases.begin(), cases.end(), [](const VehicleCase& a, const VehicleCase& b) {
    return case_id_before(a.body.info.id, b.body.info.id);
  });
  return cases;
}

}  // namespace ocp::conformance
