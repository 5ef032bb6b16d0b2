// `ocp_conformance operator`, the connection: keep-alives while the Player is silent, reconnect
// after the Player closes the connection or restarts (and no stale pair after it), and one
// connection at a time — the single client-data source (SPEC §2, §4.2, §4.3).
#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"
#include "operator_observations.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

constexpr milliseconds silence_ms{2300};  // longer than the Player's 2 s read timeout

// The client's longest silence since `from` (a close ends it), graded at the product's line.
Outcome grade_client_silence(CaseContext& context, std::int64_t from, const std::string& during) {
  const OperatorObservations observed = OperatorObservations::from(context.entries(), from);
  std::int64_t longest = 0, last = from;
  for (std::int64_t t : observed.client_frames_us) {
    if (!observed.closed_us.empty() && t > observed.closed_us.front()) break;
    longest = std::max(longest, t - last);
    last = t;
  }
  // A closed connection's silence ends at the close.
  longest = std::max(longest, (observed.closed_us.empty() ? context.now_us() : observed.closed_us.front()) - last);
  const std::string counts = fmt::format("{} frames from the client during {}; longest silence {} ms",
                                         observed.client_frames_us.size(), during, longest / 1000);
  if (!observed.closed_us.empty()) return failed(counts + "; the connection closed: " + observed.close_codes.front());
  return grade_longest_silence(counts + "; connection kept", longest);
}

Outcome keeps_connection_alive(CaseContext& context) {
  context.run_for(milliseconds(300));
  const std::int64_t from = context.now_us();
  context.note("Player output paused: no VehicleOcpShared for 2.3 s");
  context.host().player().set_client_output_paused(true);
  context.run_for(silence_ms);
  context.host().player().set_client_output_paused(false);
  context.note("Player output resumed");
  return grade_client_silence(context, from, "the 2.3 s pause");
}

// The Player keeps sending, but the pair in its frames stays the same for 2.3 s: the vehicle's
// video is stalled (no SEI, so no new pair), as when a camera stalls or the vehicle is gone. A
// client that answers only a changed pair goes silent, and the 2 s read timeout closes it.
Outcome keeps_sending_on_an_unchanged_pair(CaseContext& context) {
  context.run_for(milliseconds(300));
  StreamerCore& streamer = context.host().streamer();
  const std::vector<CameraConfig> cameras = streamer.config().cameras;
  const std::int64_t from = context.now_us();
  context.note("video stalled: the Player keeps sending, the pair stays unchanged for 2.3 s");
  for (const CameraConfig& camera : cameras) streamer.set_camera_stalled(camera.name, true);
  context.run_for(silence_ms);
  for (const CameraConfig& camera : cameras) streamer.set_camera_stalled(camera.name, false);
  context.note("video resumed");
  return grade_client_silence(context, from, "2.3 s of an unchanged pair");
}

// Closes (or restarts the Player), then grades the new connection: reconnected, and every pair
// it returns was published on the new connection (none remembered from before).
Outcome reconnects(CaseContext& context, const std::function<void()>& cut, const std::string& what) {
  context.run_for(milliseconds(500));
  const std::int64_t cut_us = context.now_us();
  cut();
  std::int64_t reopened_us = -1;
  const auto reopened = [&] {
    for (const WireLogEntry& e : context.entries()) {
      if (e.kind == WireEntryKind::opened && e.time_us >= cut_us && reopened_us < 0) reopened_us = e.time_us;
    }
    return reopened_us >= 0;
  };
  if (!context.wait_until(reopened, milliseconds(5000))) return failed("no reconnect within 5 s after " + what);
  context.run_for(milliseconds(800));
  const OperatorObservations after = OperatorObservations::from(context.entries(), reopened_us);
  const PairReturns returns = pair_returns(after, host_vehicle_name);
  const std::string counts = fmt::format("reconnected {} ms after {}; then {}", (reopened_us - cut_us) / 1000, what,
                                         returns.describe(host_vehicle_name));
  if (!returns.altered.empty()) {
    return failed_with_cause(counts + "; pairs not published on the new connection: " + list_pairs(returns.altered),
                             returns.altered, returns.published);
  }
  if (returns.count < 5) return failed(counts + "; fewer than 5 returned pairs in 0.8 s after the reconnect");
  return ok(counts);
}

// One connection at a time (SPEC §4.2): a second one is refused, so an application that opens
// two (a dashboard next to the control connection) has two would-be sources, one of them cut off.
Outcome single_connection(CaseContext& context) {
  context.run_for(milliseconds(1000));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  bool locked = false;
  for (const WireLogEntry& e : context.entries())
    locked = locked || (e.kind == WireEntryKind::note && e.text.find("source locked: tcp") != std::string::npos);
  const std::string lock =
      locked ? "its client data locked the tcp source" : "it sent no client data (keep-alives only: no lock)";
  if (observed.refused > 0) {
    return failed(fmt::format("{} more connection(s) opened while one was up, refused by the Player; {}",
                              observed.refused, lock));
  }
  return ok("one connection; " + lock);
}

}  // namespace

namespace {

// The Player silent or its pair unchanged: the client must still send.
void add_keep_alive_cases(std::vector<VehicleCase>& cases, const StreamerSetup& op) {
  cases.push_back(
      {{{"operator/2/2",
         "keeps the connection alive while the Player is silent (2 s read timeout never fires)",
         "SPEC §2, §4.2",
         "\"Read timeout: … the timer runs whenever the connection is open and no byte has arrived for 2 000 ms … same "
         "rule "
         "on :4001.\" — \"[a keep-alive] resets the :4001 read timer … A read-only operator client (a dashboard) sends "
         "it "
         "about once a second to stay connected\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: while the Player sends nothing for 2.3 s the client still sends (keep-alives {} or data), never silent "
          "for more than 1 s; connection kept",
          "NON-STRICT: its longest silence is over 1 s but under the product's 2 000 ms line (the margin is named)"},
         "broken_client.py op-no-keepalive"},
        keeps_connection_alive},
       op});
  cases.push_back(
      {{{"operator/2/6",
         "keeps sending while the pair stays unchanged (a stalled video)",
         "SPEC §2, §4.1, §4.2",
         "\"ack_time/ack_time_mac are the latest pair extracted from that vehicle's video SEI\" (no new video, no new "
         "pair, while the Player sends on) — \"the timer runs whenever the connection is open and no byte has arrived "
         "for 2 000 ms … same rule on :4001\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: while the vehicle's video is stalled for 2.3 s (the Player sends on, the pair unchanged) the client "
          "still sends, never silent for more than 1 s; connection kept",
          "NON-STRICT: its longest silence is over 1 s but under the product's 2 000 ms line (the margin is named)"},
         "broken_client.py op-answer-on-change"},
        keeps_sending_on_an_unchanged_pair},
       op});
}

// The Player closes or restarts: reconnect after a short delay, with no stale pair; and one
// connection at a time.
void add_reconnect_cases(std::vector<VehicleCase>& cases, const StreamerSetup& op) {
  cases.push_back(
      {{{"operator/4.2/3",
         "reconnects after the Player closes the connection; no stale pair",
         "SPEC §4.2, seed 000",
         "\"Treat disconnects as normal lifecycle events and reconnect after a short delay.\" (seed 000, for the "
         "vehicle "
         "side; the :4001 server follows the same rules: \"same bind rule and framing as §2, one client at a time\")",
         Tier::must,
         milliseconds(12'000),
         {"OK: reconnects within 5 s, then returns ≥ 5 pairs in 0.8 s, each published on the new connection (none "
          "remembered from the old one)"},
         "broken_client.py op-no-reconnect (or op-sticky)"},
        [](CaseContext& context) {
          return reconnects(
              context, [&] { context.host().player().close_client_connection(); }, "the Player closed the connection");
        }},
       op});
  cases.push_back(
      {{{"operator/4.2/7",
         "reconnects after a short delay: not at once, not after seconds",
         "seed 000 (Practical connection rules; the Rust example's 100 ms sleep), SPEC §4.2",
         "\"Treat disconnects as normal lifecycle events and reconnect after a short delay.\" (seed 000, for the "
         "vehicle "
         "side; the :4001 server follows the same rules)",
         Tier::should,
         milliseconds(15'000),
         {"OK: after each of 3 Player closes the client reconnects 20 ms to 1 s later",
          "NON-STRICT: it reconnects in under 20 ms (a tight loop) or after more than 1 s (a practical rule: SHOULD)"},
         "broken_client.py op-reconnect-at-once (NON-STRICT); broken_client.py op-reconnect-slowly (NON-STRICT)"},
        [](CaseContext& context) {
          return grade_reconnect_delays(context, [&context] { context.host().player().close_client_connection(); });
        }},
       op});
  cases.push_back(
      {{{"operator/4.2/4",
         "reconnects after a Player restart (new Streamer keys); no stale pair",
         "SPEC §4.2, §5, seed 000",
         "\"Treat disconnects as normal lifecycle events and reconnect after a short delay.\" — \"The 32-byte key is "
         "drawn "
         "from a CSPRNG at Streamer start and never leaves it.\" (pairs from before the restart never validate again)",
         Tier::must,
         milliseconds(12'000),
         {"OK: reconnects to the restarted Player within 5 s, then returns ≥ 5 pairs in 0.8 s, each published after "
          "the "
          "restart"},
         "broken_client.py op-sticky (or op-no-reconnect)"},
        [op](CaseContext& context) {
          return reconnects(
              context, [&] { context.restart_streamer(op); }, "the Player restarted");
        }},
       op});
  cases.push_back({{{"operator/4.3/1",
                     "one connection at a time: a single client-data source",
                     "SPEC §4.2, §4.3, seed 002",
                     "\"Only one operator-side client data source may be active in a session.\" — Player TCP server: "
                     "\"one client at "
                     "a time (same Decision as §3.1)\": a second connection is accepted and closed at once",
                     Tier::must,
                     milliseconds(10'000),
                     {"OK: the client keeps one connection for 1 s; no second connection is refused"},
                     "broken_client.py op-second-connection"},
                    single_connection},
                   op});
}

}  // namespace

void add_operator_connection_cases(std::vector<VehicleCase>& cases) {
  const StreamerSetup op = operator_setup();
  add_keep_alive_cases(cases, op);
  add_reconnect_cases(cases, op);
}

}  // namespace ocp::conformance
