// Connection lifecycle (SPEC §3.1, seed 000 "Connect from the vehicle process"): reconnect
// after the server closes and after a Streamer restart, and never echo a stale pair.
#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

// After the break at `break_us`: reconnected, echoes pairs of the new session only.
Outcome grade_reconnect(CaseContext& context, std::int64_t break_us, const std::vector<AckPair>& old_pairs) {
  const bool back = context.wait_until(
      [&] {
        const Observations observed = Observations::from(context.entries(), break_us);
        return !observed.opened_us.empty() && context.host().has_streamer() && context.streamer().vehicle_connected();
      },
      milliseconds(5000));
  if (!back) return failed("the client did not reconnect within 5 s");
  const Observations reopen = Observations::from(context.entries(), break_us);
  const std::int64_t opened = reopen.opened_us.front();
  context.run_for(milliseconds(500));
  const Observations observed = Observations::from(context.entries(), opened);
  std::vector<AckPair> stale;
  std::size_t fresh = 0;
  // Every response of the new connection, also those written before the client read a control
  // message there: a pair kept from the old connection is exactly what this case is about.
  for (const Response& response : observed.all_responses) {
    if (!response.ack) continue;
    bool is_old = false;
    for (const AckPair& p : old_pairs) is_old = is_old || p == *response.ack;
    if (is_old) stale.push_back(*response.ack);
    fresh += observed.find_sent(*response.ack) >= 0;
  }
  const std::string counts = fmt::format("reconnected {:.0f} ms after the break; {} echoes of new pairs, {} stale",
                                         static_cast<double>(opened - break_us) / 1000.0, fresh, stale.size());
  if (!stale.empty()) return failed(counts + "; stale pairs from before the break: " + list_pairs(stale));
  if (fresh == 0) return failed(counts + "; no new pair echoed within 500 ms");
  return ok(counts);
}

Outcome after_server_close(CaseContext& context) {
  context.run_for(milliseconds(400));
  const auto old_pairs = sent_pairs(Observations::from(context.entries()));
  const std::int64_t break_us = context.now_us();
  context.note("server closes the vehicle connection");
  context.streamer().close_vehicle_connection();
  return grade_reconnect(context, break_us, old_pairs);
}

Outcome after_restart(CaseContext& context) {
  context.run_for(milliseconds(400));
  const auto old_pairs = sent_pairs(Observations::from(context.entries()));
  const std::int64_t break_us = context.now_us();
  StreamerSetup fresh;
  fresh.ack_time_offset = (std::uint64_t{1} << 53) + (std::uint64_t{1} << 44);
  context.restart_streamer(fresh);
  return grade_reconnect(context, break_us, old_pairs);
}

// One connection at a time (SPEC §3.1, seed 000): the Streamer accepts a second connection
// and closes it at once, so a client that opens one next to the working connection (a
// "health probe", a second thread) has half of its traffic cut off.
Outcome single_vehicle_connection(CaseContext& context) {
  context.run_for(milliseconds(1000));
  std::size_t refused = 0;
  std::string first;
  for (const WireLogEntry& entry : context.entries()) {
    if (entry.kind != WireEntryKind::refused) continue;
    if (refused++ == 0)
      first = fmt::format(" (the first at {:.0f} ms: {})", static_cast<double>(entry.time_us) / 1000.0, entry.text);
  }
  const Observations observed = Observations::from(context.entries());
  if (refused > 0) {
    return failed(
        fmt::format("{} more connection(s) opened while one was up, refused by the Streamer{}", refused, first));
  }
  if (observed.opened_us.size() > 1)
    return failed(fmt::format("{} connections in 1 s; the Streamer closed none", observed.opened_us.size()));
  return ok("one connection for 1 s; no second connection opened");
}

Outcome reconnect_delay(CaseContext& context) {
  return grade_reconnect_delays(context, [&context] { context.streamer().close_vehicle_connection(); });
}

}  // namespace

void add_connection_cases(std::vector<VehicleCase>& cases) {
  cases.push_back(
      {{{"vehicle/3.1/1",
         "reconnects after the server closes; no stale pair",
         "seed 000 (Connect from the vehicle process), SPEC §3.1",
         "\"If the connection drops, reconnect from your process; when OCP accepts the next connection it clears old "
         "queued control messages\" — "
         "\"Treat disconnects as normal lifecycle events and reconnect after a short delay.\"",
         Tier::must,
         milliseconds(15'000),
         {"OK: reconnects within 5 s, then echoes pairs of the new connection only (none sent before the close)"},
         "broken_client.py no-reconnect (or sticky-pair)"},
        after_server_close},
       {}});
  cases.push_back({{{"vehicle/3.1/2",
                     "reconnects after a Streamer restart with a new MAC key; no stale pair",
                     "SPEC §3.1, §5",
                     "\"The 32-byte key is drawn from a CSPRNG at Streamer start\" — \"reconnect after a short "
                     "delay\"; a pair of the old Streamer never validates again",
                     Tier::must,
                     milliseconds(15'000),
                     {"OK: reconnects to the restarted Streamer within 5 s and echoes only its pairs"},
                     "broken_client.py sticky-pair (or no-reconnect)"},
                    after_restart},
                   {}});
  cases.push_back({{{"vehicle/3.1/3",
                     "one connection at a time",
                     "SPEC §3.1, seed 000 (Connect from the vehicle process)",
                     "\"OCP accepts one active vehicle-side TCP connection at a time.\" — \"One active vehicle "
                     "connection at a time. "
                     "Decision: a second connection arriving while one is active is accepted and closed at once\"",
                     Tier::must,
                     milliseconds(10'000),
                     {"OK: the client keeps one connection for 1 s; no second connection is refused"},
                     "broken_client.py second-connection"},
                    single_vehicle_connection},
                   {}});
  cases.push_back(
      {{{"vehicle/3.1/4",
         "reconnects after a short delay: not at once, not after seconds",
         "seed 000 (Practical connection rules; the Rust example's 100 ms sleep)",
         "\"Treat disconnects as normal lifecycle events and reconnect after a short delay.\"",
         Tier::should,
         milliseconds(15'000),
         {"OK: after each of 3 server closes the client reconnects 20 ms to 1 s later",
          "NON-STRICT: it reconnects in under 20 ms (a tight loop) or after more than 1 s (a practical rule: SHOULD)"},
         "broken_client.py reconnect-at-once (NON-STRICT); broken_client.py reconnect-slowly (NON-STRICT)"},
        reconnect_delay},
       {}});
}

}  // namespace ocp::conformance
